// render_settings_table.h — the plain render settings, declared once.
//
// Each line of PMC_RENDER_SETTINGS is one setting of RenderConfig
// (gpu/render_config.h), and everything about it that is the same for every
// setting comes from that line:
//   * the RenderConfig field and its default (render_config.h expands it);
//   * its flag, value name, help and default in `--help` (app/render_options.cpp);
//   * the range validate() checks, with the error text (gpu/render_config.cpp),
//     and the same range on its RenderSettings copy (validate_render_settings,
//     which the renderer and `pmc sweep`'s rows run);
//   * its copy into RenderSettings (base_render_settings), and for a setting
//     only the table and the kernels read, that copy's CacheSettings member
//     itself (CACHE(member) below, declared by PMC_CACHE_TABLE_MEMBERS);
//   * its copy into the kernels' PmcFrame (fill_frame_settings, which
//     make_frame in gpu/wavefront_renderer.cpp calls; what make_frame writes
//     out by hand combines several values: the level bias, the table size);
//   * its key in `pmc render --stats` (app/stats_json.cpp);
//   * whether it enters the part's settings hash (gpu/part_identity.cpp);
//   * `pmc info --settings` (app/info_command.cpp), which scripts/farm reads.
//
// The columns of X(field, name, flag, type, dflt, lo, hi, check, group, hash, frame, kernel, stats, value,
// help):
//   field  the RenderConfig member.
//   name   its name in ConfigError messages (app/ shows it as `flag`).
//   flag   its command-line option.
//   type   int, int64_t, float, double: a number; bool or an enum: a word
//          setting, whose `value` lists its words in value order (false|true,
//          the enum's 0|1|...). On/off switches list "off|on" (shown "on|off").
//   dflt   the default.
//   lo hi  numbers: the valid range, inclusive (kNone: no bound; NaN is out).
//   check  numbers: the error after "NAME: " when out of range, "{}" standing
//          for the value ("" when validate() checks the setting with others).
//   group  where --help lists it, and which subcommands take it:
//          Image, CacheSwitch (--cache: `pmc render` only), Cache (not sweep,
//          which takes lists), Machine.
//   hash   how it enters the part EXR's settings hash (gpu/part_identity.h):
//          TAG("word"): by the table, the word and the value whenever the
//            value differs from the default (Cache settings: with the cache
//            on), so parts rendered before the setting existed keep their
//            hash; a new setting that changes the image takes this;
//          FIXED: in part_identity.cpp's fixed sequence (the settings hashed
//            before this table, in their historical order, so old parts keep
//            their hashes);
//          PROGRAM: it changes the compiled materials, so the scene hash
//            (the program's code) covers it;
//          NO: it changes speed, not the image (or, like cache_fit, only
//            through a resolved value that is hashed: fit_levels).
//          tests/gpu/render_settings_table_test.cpp checks that changing any
//          TAG or FIXED setting changes the hash and that NO ones do not.
//   frame  where RenderSettings holds it (converted: an enum to its index):
//          S(member), a member declared by hand (the host reads it too), or
//          CACHE(member), a member of CacheSettings this line declares (with
//          the line's type and default; for settings that only the table's
//          expansions and the kernels read); NONE when the session uses it
//          (a table size, the compiler's options).
//   kernel K(member, conversion): fill_frame_settings copies the RenderSettings
//          value into PmcFrame.member (core/abi/pmc_types.h), AS_IS (an enum
//          or bool as its index) or IF_CACHE (0 unless the cache is on); NONE:
//          the kernels do not read it from the frame.
//   stats  its key in the stats JSON, written from the RenderSettings member
//          (`frame`) ("" for none; cache settings go in the "cache" object).
//   value  the value's name in --help, or the words of a word setting.
//   help   the --help text (the default is appended).
//
// Not in the table (each has a reason a line cannot say): the scene and
// material files and search paths (strings, repeatable), the camera, the
// lights and environment (three numbers, optional values, combinations),
// --samples and --crop (ranges checked against spp and the image), --aov
// (a list of render passes; it does not change the beauty image), the
// optional settings whose default is "decided later" (--cache-cells,
// --cache-filter, --threads, --fov, --env-scale, --env-rotate),
// --shade-lanes (a power of two, its default depends on the device),
// --trace-mode and --transfer (parsed by their own layers), and cache_audit
// (tests only, no flag).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "materials/cache_plan.h"

namespace pmc {

// What a cache miss stores for a texel: the value at the inserting hit, or
// at the texel's centre (then the image does not depend on the table).
enum class CacheEval { Hit, Center };
// The texel a lookup reads: the one under the hit, or a neighbour picked at
// random with its bilinear weight (center mode only).
enum class CacheFilter { Nearest, Bilinear };
// When a cell is full: keep the first entries (the paper's rule), or let an
// insert from a camera-ray hit replace an entry from a deeper bounce
// (core/device/pmc_cache.h).
enum class CachePolicy { KeepFirst, Priority };
// Where a path's numbers come from (core/device/pmc_rng.h): Owen-scrambled
// Sobol points, or independent hashed numbers (the sampler before Sobol).
enum class Sampler { Sobol, Random };
// Where level floors (materials/bandwidth.h) apply: nowhere (texels follow the
// footprint), at every hit, or at camera-ray hits only (deeper hits follow the
// footprint: a camera hit's texel shows in its pixel, a deeper hit's value is
// spread over the lobe that reached it).
enum class CacheBandwidth { Off, On, Camera };
// Which nodes become cache points: the node count alone (cache_min_nodes),
// or also whether each pays on the device for the frame (materials/node_costs.h).
enum class CacheModel { Nodes, Cost };

// --cache-lobe-spread's default: how much position cells widen per bounce, C
// of core/device/pmc_raycone.h's pmc_lobe_spread. 0 (the paper's cone): 1/32
// renders the solid room 3-7% faster at the same bias, but its paths part from
// the cacheless render's more often, so same-seed comparisons at low sample
// counts (scripts/ci-compare) lose up to 8 dB (docs/BENCHMARKS.md, "Coarser
// cells after rough bounces").
constexpr float kDefaultCacheLobeSpread = 0.0f;

namespace settings_table {
constexpr double kNone = std::numeric_limits<double>::infinity();
}  // namespace settings_table

// clang-format off
#define PMC_RENDER_SETTINGS(X)                                                                              \
  X(width, "width", "--width", int, 640, 1, settings_table::kNone, "", Image, FIXED, S(width),              \
    K(width, AS_IS), "width", "W", "image width in pixels")                                                 \
  X(height, "height", "--height", int, 360, 1, settings_table::kNone, "", Image, FIXED, S(height),          \
    K(height, AS_IS), "height",                                                                             \
    "H", "image height in pixels")                                                                          \
  X(spp, "spp", "--spp", int, 16, 1, settings_table::kNone,                                                 \
    "samples per pixel must be at least 1, got {}",                                                         \
    Image, FIXED, S(spp), NONE, "spp", "N", "samples per pixel")                                            \
  X(max_depth, "max_depth", "--max-depth", int, 8, 1, 1024, "must be in 1..1024, got {}", Image, FIXED,     \
    S(max_depth), K(max_depth, AS_IS), "max_depth", "D",                                                    \
    "maximum number of surface hits per path, 1..1024")                                                     \
  X(seed, "seed", "--seed", int64_t, 0, 0, 4294967295.0, "must be in 0..4294967295, got {}", Image, FIXED,  \
    S(seed), K(seed, AS_IS), "seed", "S",                                                                   \
    "random seed, 0..4294967295; equal seeds give identical images (with the cache: in --cache-eval "       \
    "center, not hit)")                                                                                     \
  X(light_tree, "light_tree", "--light-tree", bool, true, 0, 0, "", Image, TAG("light_tree"),               \
    S(light_tree), NONE,                                                                                    \
    "light_tree", "off|on",                                                                                 \
    "next-event estimation picks a light by its importance at the shading point (a light tree over the "    \
    "finite lights, lights at infinity by irradiance); off: by power alone, the environment weighted by "   \
    "the scene's size (the old selection, for comparisons)")                                                \
  X(sampler, "sampler", "--sampler", Sampler, Sampler::Sobol, 0, 0, "", Image, FIXED, S(sampler),           \
    K(sampler, AS_IS), "sampler",                                                                           \
    "sobol|random",                                                                                         \
    "the numbers each sample draws: Owen-scrambled Sobol points (stratified: less noise at equal samples) " \
    "or independent hashed numbers (the sampler before Sobol, for comparisons)")                            \
  X(adaptive_threshold, "adaptive_threshold", "--adaptive-threshold", double, 0.0, 0, 1,                    \
    "must be 0..1, got {}", Image, TAG("adaptive"), S(adaptive_threshold), NONE, "adaptive_threshold", "T", \
    "adaptive sampling: a pixel stops drawing samples once the relative standard error of its mean (its "   \
    "grey value's, against mean^2 + 0.01, as bench's relMSE weighs it) is below T at two checks in a "     \
    "row, one every --adaptive-min-spp samples; a stopped pixel equals the same pixel rendered with its "   \
    "sample count. "                                                                                        \
    "Needs each pixel's samples in one process (no --samples part; farm chunks split by --crop). "          \
    "0: every pixel draws --spp samples")                                                                   \
  X(adaptive_min_spp, "adaptive_min_spp", "--adaptive-min-spp", int, 16, 1, settings_table::kNone,          \
    "must be at least 1, got {}", Image, TAG("adaptive_min"), S(adaptive_min_spp), NONE, "adaptive_min_spp", \
    "N", "with --adaptive-threshold: samples every pixel draws before its first check, and between checks") \
  X(clamp_direct, "clamp_direct", "--clamp-direct", float, 0.0f, 0, settings_table::kNone,                 \
    "must be at least 0, got {}", Image, TAG("clamp_direct"), S(clamp_direct), K(clamp_direct, AS_IS),      \
    "clamp_direct", "L",                                                                                    \
    "largest radiance one light sample may add to a pixel sample through the camera's first hit (an "       \
    "emitter seen directly, or light reaching that hit): a larger contribution keeps its hue and is "       \
    "scaled down to L in its largest channel. Removes fireflies at the cost of energy (biased); 0: off")    \
  X(clamp_indirect, "clamp_indirect", "--clamp-indirect", float, 0.0f, 0, settings_table::kNone,           \
    "must be at least 0, got {}", Image, TAG("clamp_indirect"), S(clamp_indirect),                          \
    K(clamp_indirect, AS_IS), "clamp_indirect", "L",                                                        \
    "as --clamp-direct, for light reaching the path's second or a later hit (indirect light: caustics "     \
    "from glossy surfaces, the usual fireflies). Biased: a bright surface seen through another loses "      \
    "energy; 0: off")                                                                                       \
  X(cache, "cache", "--cache", bool, true, 0, 0, "", CacheSwitch, FIXED, S(cache.on), K(cache_on, AS_IS),   \
    "enabled", "off|on",                                                                                    \
    "progressive material cache")                                                                           \
  X(cache_entries, "cache_entries", "--cache-entries", int64_t, 8, 1, 1024, "must be in 1..1024, got {}",   \
    Cache, FIXED, NONE, NONE, "", "N", "entries per cache cell, 1..1024")                                   \
  X(mip_bias, "mip_bias", "--mip-bias", float, 0.0f, -32, 32, "must be within -32..32, got {}", Cache,      \
    FIXED, S(cache.mip_bias), NONE, "mip_bias", "B",                                                        \
    "added to the cache's virtual mip level (higher: finer, more accurate), -32..32")                       \
  X(cache_eval, "cache_eval", "--cache-eval", CacheEval, CacheEval::Center, 0, 0, "", Cache, FIXED,         \
    S(cache.center), K(cache_center, AS_IS), "eval", "hit|center",                                          \
    "values stored for a texel: at the inserting hit, or at the texel centre")                              \
  X(cache_policy, "cache_policy", "--cache-policy", CachePolicy, CachePolicy::KeepFirst, 0, 0, "", Cache,   \
    FIXED, S(cache.priority), K(cache_policy, AS_IS), "policy", "keep-first|priority",                      \
    "when a cache cell is full: keep its first entries (the paper's rule), or let a camera-ray hit "        \
    "replace an entry from a deeper bounce")                                                                \
  X(cache_position_keys, "cache_keys", "--cache-keys", bool, true, 0, 0, "", Cache, PROGRAM, NONE, NONE,    \
    "",                                                                                                     \
    "uv|uv+position",                                                                                       \
    "what cache points are keyed on: uv texels only (the paper), or also 3D position cells for "            \
    "sub-graphs that read the position alone (noise3d, fractal3d, ...)")                                    \
  X(cache_min_nodes, "cache_min_nodes", "--cache-min-nodes", int, kDefaultCacheMinNodes, 1,                 \
    settings_table::kNone, "must be at least 1", Cache, PROGRAM, NONE, NONE, "", "N",                       \
    "smallest sub-graph (in nodes) worth a cache point (with --cache-model cost: the floor under the model)") \
  X(cache_model, "cache_model", "--cache-model", CacheModel, CacheModel::Cost, 0, 0, "", Cache, PROGRAM, NONE, \
    NONE, "", "nodes|cost",                                                                                 \
    "which sub-graphs become cache points: cost: those of at least --cache-min-nodes nodes that also pay "  \
    "on this device for this frame (sub-graph cost x expected hit rate against lookup and miss costs; "   \
    "'pmc info --dump-cache-plan' shows the figures); nodes: the node count alone")                         \
  X(cache_bandwidth, "cache_bandwidth", "--cache-bandwidth", CacheBandwidth, CacheBandwidth::Off, 0, 0,    \
    "", Cache, FIXED, S(cache.bandwidth), K(cache_bandwidth, IF_CACHE), "bandwidth", "off|on|camera",       \
    "on: level floors: a cache point's texels are at most half its pattern's smallest feature (grid "       \
    "lines, tile gaps, a noise's finest octave; see 'pmc info --dump-cache-plan'), finer than the "         \
    "footprint where needed; camera: the floors at camera-ray hits only, which show their texels in "       \
    "the pixel, while later hits follow the footprint (sub-pixel detail exact where the camera sees it, "   \
    "the cache's speed elsewhere); off: texels follow the footprint alone (the paper; faster: on the "      \
    "default scene the floors cost most of the cache's speedup, docs/BENCHMARKS.md)")                       \
  X(cache_feature_texels, "cache_feature_texels", "--cache-feature-texels", double, 2.0, 0.125, 64,         \
    "must be 0.125..64, got {}", Cache, FIXED, S(cache.feature_texels), NONE, "feature_texels", "N",        \
    "with --cache-bandwidth on or camera: texels across a pattern's smallest feature (more: finer "        \
    "texels, less aliasing, fewer hits)")                                                                   \
  X(cache_fit, "cache_fit", "--cache-fit", bool, false, 0, 0, "", Cache, NO, NONE, NONE, "", "off|on",      \
    "on: when the table holds fewer entries than the frame's expected keys need at load factor 1/2 (a "     \
    "--cache-cells below the automatic size, or a table the memory limit shrank), coarsen the texels "      \
    "and cells by half a level per halving, so the keys fit (faster, blurrier material detail); off: "      \
    "texels follow the footprint whatever the table's size (the paper)")                                    \
  X(cache_lobe_spread, "cache_lobe_spread", "--cache-lobe-spread", float, kDefaultCacheLobeSpread, 0, 4,    \
    "must be 0..4, got {}", Cache, TAG("lobe"), CACHE(lobe_spread), K(cache_lobe_spread, IF_CACHE),         \
    "lobe_spread", "C",                                                                                     \
    "after each bounce, position cells follow a cone whose spread grows by C times the angle of the "       \
    "lobe one sample stands for (a diffuse bounce: about 2C radians), so hits after rough bounces "         \
    "share coarser cells, whose detail that lobe averages out (uv texels keep the texture's cone; "         \
    "0.03125: fewer misses at the same bias, but a noisier same-seed match with the cacheless render); "    \
    "0: the texture's cone (the paper), 0..4")                                                              \
  X(cache_max_refine, "cache_max_refine", "--cache-max-refine", int, 2, 0, 16, "must be 0..16, got {}",     \
    Cache, FIXED, CACHE(max_refine), K(cache_max_refine, AS_IS), "max_refine", "LEVELS",                    \
    "how many levels finer than the footprint a pattern may make its texels (each level splits a "          \
    "footprint into 4 texels, 8 cells); a point that needs more is evaluated without the cache there")      \
  X(cache_camera_samples, "cache_camera_samples", "--cache-camera-samples", int, 16, 0,                     \
    settings_table::kNone, "must not be negative, got {}", Cache, TAG("camera_samples"),                    \
    CACHE(camera_samples), K(cache_camera_samples, AS_IS), "camera_samples", "N",                           \
    "camera-ray hits use the cache in each pixel's first N samples and evaluate their materials "           \
    "exactly in later ones (the cache keeps serving the later bounces): the cache's error where the "       \
    "camera sees it falls as N / spp, faster than the noise, so a converged image matches the "             \
    "cacheless one; a frame of at most N spp is cached at every hit (0: never at camera hits; a number "    \
    "above the frame's samples: always, the paper)")                                                        \
  X(cache_supersample, "cache_supersample", "--cache-supersample", int, 0, 0, 16, "",                       \
    Cache, PROGRAM, NONE, NONE, "", "N",                                                                    \
    "with --cache-eval center, a miss evaluates its sub-graphs at N stratified points over its texel "      \
    "(cell) and stores their mean, so a texel stands for its area, not its centre (patterns finer than "    \
    "a texel stop aliasing; a miss costs N times as much): N a power of two 1..16; 0: auto, per key "       \
    "kind the largest power of two up to the frame's expected lookups per key / 4 (1 at 16 spp, 8 for uv "  \
    "texels at 256; 'pmc info --dump-cache-plan' shows it)")                                                \
  X(chunk_rays, "chunk_rays", "--chunk-rays", int64_t, 65536, 0, settings_table::kNone,                     \
    "must not be negative", Machine, NO, S(chunk_rays), NONE, "", "N",                                      \
    "rays per streamed chunk with --transfer copy (0: the whole queue)")                                   \
  X(waves_in_flight, "waves_in_flight", "--waves-in-flight", int, 2, 1, 2, "must be 1 or 2, got {}",        \
    Machine, NO, S(waves_in_flight), NONE, "", "N",                                                         \
    "wave loops at once, each on half of the pixels with its own queue: the host traces one's rays while "  \
    "the device shades the other's, so neither waits for the other (faster on small and simple frames; "   \
    "the same image); 1: one loop, the host and the device taking turns. Adaptive sampling runs one")
// clang-format on

// ---- the table's expansions --------------------------------------------------

enum class SettingGroup { Image, CacheSwitch, Cache, Machine };
enum class SettingHash { Tag, Fixed, Program, No };

// One line of the table, as values (`field`, `type` and `frame` become the
// accessors visit_render_settings passes beside it).
template <typename T>
struct SettingInfo {
  const char* name;
  const char* flag;
  T dflt;
  double lo, hi;
  const char* check;
  SettingGroup group;
  SettingHash hash;
  const char* hash_tag;  // TAG's word, else nullptr
  const char* stats;
  const char* value;
  const char* help;
};

// bool and enum settings take words; numbers take numbers.
template <typename T>
constexpr bool kWordSetting = std::is_same_v<T, bool> || std::is_enum_v<T>;

#define PMC_SETTING_HASH_TAG(word) SettingHash::Tag, word
#define PMC_SETTING_HASH_FIXED SettingHash::Fixed, nullptr
#define PMC_SETTING_HASH_PROGRAM SettingHash::Program, nullptr
#define PMC_SETTING_HASH_NO SettingHash::No, nullptr
#define PMC_SETTING_FRAME_S(member) \
  [](auto& s) -> auto& { return s.member; }
#define PMC_SETTING_FRAME_CACHE(member) \
  [](auto& s) -> auto& { return s.cache.member; }
#define PMC_SETTING_FRAME_NONE nullptr

// Calls visit(info, config_field, frame_field) for each line of the table, in
// order: config_field(config) is the RenderConfig field (a reference),
// frame_field(settings) the RenderSettings member, or frame_field is nullptr.
template <typename Visit>
void visit_render_settings(Visit&& visit) {
#define PMC_VISIT_SETTING(field, name, flag, type, dflt, lo, hi, check, group, hash, frame, kernel, stats, \
                          value, help)                                                                     \
  visit(                                                                                                   \
      SettingInfo<type>{name, flag, dflt, double(lo), double(hi), check, SettingGroup::group,              \
                        PMC_SETTING_HASH_##hash, stats, value, help},                                      \
      [](auto& c) -> auto& { return c.field; }, PMC_SETTING_FRAME_##frame);
  PMC_RENDER_SETTINGS(PMC_VISIT_SETTING)
#undef PMC_VISIT_SETTING
}

// A setting's value as its RenderSettings member holds it (an enum: its index).
template <typename To, typename From>
To frame_value(const From& v) {
  if constexpr (std::is_enum_v<From>)
    return To(static_cast<std::underlying_type_t<From>>(v));
  else
    return To(v);
}

// The CacheSettings members the table's CACHE(member) lines declare, each
// with its line's type and default (expanded inside CacheSettings,
// gpu/wavefront_renderer.h).
#define PMC_TABLE_MEMBER_S(member) PMC_TABLE_SKIP_, ~
#define PMC_TABLE_MEMBER_NONE PMC_TABLE_SKIP_, ~
#define PMC_TABLE_MEMBER_CACHE(member) PMC_TABLE_DECLARE_, member
#define PMC_TABLE_DECLARE_(member, type, dflt) type member = dflt;
#define PMC_TABLE_SKIP_(member, type, dflt)
#define PMC_TABLE_APPLY_(what, member, type, dflt) what(member, type, dflt)
#define PMC_TABLE_APPLY(...) PMC_TABLE_APPLY_(__VA_ARGS__)
#define PMC_CACHE_TABLE_MEMBER_(field, name, flag, type, dflt, lo, hi, check, group, hash, frame, ...) \
  PMC_TABLE_APPLY(PMC_TABLE_MEMBER_##frame, type, dflt)
#define PMC_CACHE_TABLE_MEMBERS PMC_RENDER_SETTINGS(PMC_CACHE_TABLE_MEMBER_)

// How a K(member, conversion) line's value enters PmcFrame.
enum class FrameConversion {
  AsIs,     // the value (bool: 0 or 1, an enum: its index) as the member's type
  IfCache,  // the value with the cache on, else 0
};
#define PMC_SETTING_KERNEL_K(member, conversion) \
  [](auto& f) -> auto& { return f.member; }      \
  , PMC_FRAME_CONVERSION_##conversion
#define PMC_SETTING_KERNEL_NONE nullptr, FrameConversion::AsIs
#define PMC_FRAME_CONVERSION_AS_IS FrameConversion::AsIs
#define PMC_FRAME_CONVERSION_IF_CACHE FrameConversion::IfCache

// Copies every K(...) line's RenderSettings value into the kernels' frame:
// `s` is a RenderSettings, `frame` a PmcFrame (template parameters: this
// header sees neither type).
template <typename Settings, typename Frame>
void fill_frame_settings(const Settings& s, Frame& frame) {
  auto fill = [&](auto host_field, auto frame_field, FrameConversion conversion) {
    if constexpr (!std::is_null_pointer_v<decltype(frame_field)>) {
      static_assert(!std::is_null_pointer_v<decltype(host_field)>,
                    "a setting the kernels read needs its RenderSettings copy (the frame column)");
      auto& out = frame_field(frame);
      using F = std::decay_t<decltype(out)>;
      const bool pass = conversion == FrameConversion::AsIs || s.cache.on;
      out = pass ? frame_value<F>(host_field(s)) : F(0);
    }
  };
#define PMC_FILL_FRAME_SETTING(field, name, flag, type, dflt, lo, hi, check, group, hash, frame, kernel, \
                               ...)                                                                      \
  fill(PMC_SETTING_FRAME_##frame, PMC_SETTING_KERNEL_##kernel);
  PMC_RENDER_SETTINGS(PMC_FILL_FRAME_SETTING)
#undef PMC_FILL_FRAME_SETTING
}

// The words of a word setting, in value order ("hit|center" -> hit, center).
std::vector<std::string> setting_words(const char* value);
// The same words as --help and error messages list them (on before off).
std::vector<std::string> shown_setting_words(const char* value);

}  // namespace pmc
