// render_options.cpp — the shared render options and the RenderConfig fields they set.
#include "app/render_options.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "app/cli.h"
#include "core/embree_tracer.h"
#include "gpu/host_link.h"

namespace pmc {
namespace {

// An option bound to `field` of the config, known to ConfigError messages as `setting`.
template <typename T>
CLI::Option* field(CLI::App& app, const std::string& flag, const char* setting, T& value,
                   const std::string& value_name, const std::string& help) {
  cli::name_setting(setting, flag);
  CLI::Option* o = app.add_option(flag, value, help)->type_name(value_name);
  if constexpr (std::is_integral_v<T>) o->check(cli::integer<T>());
  if constexpr (std::is_floating_point_v<T>) o->check(cli::number());
  return o;
}

// An option whose value goes through `set` (optional fields, words).
template <typename T>
CLI::Option* setter(CLI::App& app, const std::string& flag, const char* setting,
                    std::function<void(const T&)> set, const std::string& value_name,
                    const std::string& help) {
  cli::name_setting(setting, flag);
  CLI::Option* o = app.add_option_function<T>(flag, std::move(set), help)->type_name(value_name);
  if constexpr (std::is_integral_v<T>) o->check(cli::integer<T>());
  if constexpr (std::is_floating_point_v<T>) o->check(cli::number());
  return o;
}

CLI::Option* vec3(CLI::App& app, const std::string& flag, const char* setting, std::function<void(Vec3)> set,
                  const std::string& value_name, const std::string& help) {
  cli::name_setting(setting, flag);
  return cli::add_vec3(app, flag, std::move(set), help)->type_name(value_name);
}

}  // namespace

void declare_render_options(CLI::App& app, RenderConfig& c, CacheFlags cache_flags) {
  cli::name_setting("scene", "SCENE.obj");
  app.option_defaults()->group("scene");
  field(app, "--mtlx", "mtlx", c.mtlx, "FILE.mtlx",
        "MaterialX document; usemtl NAME binds to its material NAME (repeatable)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  field(app, "--material", "material", c.material, "NAME",
        "render every triangle with this MaterialX material");
  field(app, "--mtlx-library", "mtlx_library", c.mtlx_library, "DIR",
        "MaterialX data libraries (.../MaterialX/libraries) for nodes pmc expands from their nodegraphs")
      ->default_str("$PMC_MTLX_LIBRARY, else the one found at build time");
  field(app, "--mtlx-search-path", "mtlx_search_paths", c.mtlx_search_paths, "DIR",
        "folder where MaterialX filenames are looked up after fileprefix, the document's folder and "
        "$MATERIALX_SEARCH_PATH (repeatable)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);

  field(app, "--texture-cache", "texture_cache", c.texture_cache, "DIR|off",
        "folder where decoded textures (with their mip chains) are kept between runs, so a scene's "
        "textures decode once; at most 4 GiB, least recently used removed first; 'off' decodes every run")
      ->default_str("$PMC_TEXTURE_CACHE, else $XDG_CACHE_HOME/pmc/textures, else ~/.cache/pmc/textures");

  app.option_defaults()->group("image");
  field(app, "--width", "width", c.width, "W", "image width in pixels")->capture_default_str();
  field(app, "--height", "height", c.height, "H", "image height in pixels")->capture_default_str();
  field(app, "--spp", "spp", c.spp, "N", "samples per pixel")->capture_default_str();
  field(app, "--max-depth", "max_depth", c.max_depth, "D", "maximum number of surface hits per path, 1..1024")
      ->capture_default_str();
  field(app, "--seed", "seed", c.seed, "S",
        "random seed, 0..4294967295; equal seeds give identical images (with the cache: in --cache-eval "
        "center, not hit)")
      ->capture_default_str();

  app.option_defaults()->group("camera");
  vec3(
      app, "--camera-from", "camera_from", [&c](Vec3 v) { c.camera_from = v; }, "x,y,z",
      "camera position (scene units; with --camera-at)")
      ->default_str("SCENE.camera beside the OBJ, else framing the scene");
  vec3(
      app, "--camera-at", "camera_at", [&c](Vec3 v) { c.camera_at = v; }, "x,y,z",
      "point the camera looks at (with --camera-from)");
  vec3(
      app, "--camera-up", "camera_up", [&c](Vec3 v) { c.camera_up = v; }, "x,y,z", "camera up vector")
      ->default_str("0,1,0");
  setter<float>(
      app, "--fov", "fov", [&c](const float& v) { c.fov = v; }, "DEG",
      "vertical field of view in degrees, (0, 180); overrides SCENE.camera's")
      ->default_str("45");

  app.option_defaults()->group("lights");
  field(app, "--lights", "lights", c.lights, "FILE.json|none",
        "lights file: point, spot, directional and quad lights and the environment (README, Lights); "
        "'none' ignores SCENE.lights.json")
      ->default_str("SCENE.lights.json beside the OBJ, if there is one");
  vec3(
      app, "--env", "env", [&c](Vec3 v) { c.env = v; }, "R,G,B",
      "constant environment radiance (W/m^2/sr), sampled as a light; replaces the lights file's environment")
      ->default_str("0,0,0");
  field(app, "--env-map", "env_map", c.env_map, "FILE",
        "environment map, lat-long EXR or Radiance HDR (+Y up, image centre seen looking along -Z, +X at "
        "u = 0.75), importance-sampled; replaces the lights file's environment");
  setter<float>(
      app, "--env-scale", "env_scale", [&c](const float& v) { c.env_scale = v; }, "S",
      "multiplies the environment (--env, --env-map or the lights file's)")
      ->default_str("1");
  setter<float>(
      app, "--env-rotate", "env_rotate", [&c](const float& v) { c.env_rotate = v; }, "DEG",
      "turns the environment about +Y, counter-clockwise seen from above")
      ->default_str("0");

  app.option_defaults()->group("cache");
  if (cache_flags == CacheFlags::All)
    setter<std::string>(
        app, "--cache", "cache", [&c](const std::string& v) { c.cache = v == "on"; }, "on|off",
        "progressive material cache")
        ->check(cli::one_of({"on", "off"}))
        ->default_str("on");
  if (cache_flags != CacheFlags::None) {
    setter<int64_t>(
        app, "--cache-cells", "cache_cells", [&c](const int64_t& v) { c.cache_cells = v; }, "N",
        "cache cells (with --cache-entries; a cell of 8 entries is one 64-byte line)")
        ->default_str("sized from the scene");
    field(app, "--cache-entries", "cache_entries", c.cache_entries, "N", "entries per cache cell, 1..1024")
        ->capture_default_str();
    field(app, "--mip-bias", "mip_bias", c.mip_bias, "B",
          "added to the cache's virtual mip level (higher: finer, more accurate), -32..32")
        ->default_str("0");
    setter<std::string>(
        app, "--cache-eval", "cache_eval",
        [&c](const std::string& v) { c.cache_eval = v == "hit" ? CacheEval::Hit : CacheEval::Center; },
        "hit|center", "values stored for a texel: at the inserting hit, or at the texel centre")
        ->check(cli::one_of({"hit", "center"}))
        ->default_str("center");
    setter<std::string>(
        app, "--cache-filter", "cache_filter",
        [&c](const std::string& v) {
          c.cache_filter = v == "bilinear" ? CacheFilter::Bilinear : CacheFilter::Nearest;
        },
        "nearest|bilinear",
        "texel a lookup reads: the one under the hit, or a neighbour picked at random with its bilinear "
        "weight (center mode only)")
        ->check(cli::one_of({"nearest", "bilinear"}))
        ->default_str("bilinear with center, nearest with hit");
    setter<std::string>(
        app, "--cache-policy", "cache_policy",
        [&c](const std::string& v) {
          c.cache_policy = v == "priority" ? CachePolicy::Priority : CachePolicy::KeepFirst;
        },
        "keep-first|priority",
        "when a cache cell is full: keep its first entries (the paper's rule), or let a camera-ray hit "
        "replace an entry from a deeper bounce")
        ->check(cli::one_of({"keep-first", "priority"}))
        ->default_str("keep-first");
    setter<std::string>(
        app, "--cache-keys", "cache_keys", [&c](const std::string& v) { c.cache_position_keys = v != "uv"; },
        "uv|uv+position",
        "what cache points are keyed on: uv texels only (the paper), or also 3D position cells for "
        "sub-graphs that read the position alone (noise3d, fractal3d, ...)")
        ->check(cli::one_of({"uv", "uv+position"}))
        ->default_str("uv+position");
    field(app, "--cache-min-nodes", "cache_min_nodes", c.cache_min_nodes, "N",
          "smallest sub-graph (in nodes) worth a cache point")
        ->capture_default_str();
    setter<std::string>(
        app, "--cache-bandwidth", "cache_bandwidth",
        [&c](const std::string& v) { c.cache_bandwidth = v == "on"; }, "on|off",
        "on: level floors: a cache point's texels are at most half its pattern's smallest feature (grid "
        "lines, tile gaps, "
        "a noise's finest octave; see 'pmc info --dump-cache-plan'), finer than the footprint where needed; "
        "off: texels follow the footprint alone (the paper; faster: on the default scene the floors cost "
        "most of the cache's speedup, docs/BENCHMARKS.md)")
        ->check(cli::one_of({"on", "off"}))
        ->default_str("off");
    field(app, "--cache-feature-texels", "cache_feature_texels", c.cache_feature_texels, "N",
          "with --cache-bandwidth on: texels across a pattern's smallest feature (more: finer texels, less "
          "aliasing, fewer hits)")
        ->capture_default_str();
    setter<std::string>(
        app, "--cache-fit", "cache_fit", [&c](const std::string& v) { c.cache_fit = v == "on"; }, "on|off",
        "on: when the table holds fewer entries than the frame's expected keys need at load factor 1/2 (a "
        "--cache-cells below the automatic size, or a table the memory limit shrank), coarsen the texels "
        "and cells by half a level per halving, so the keys fit (faster, blurrier material detail); off: "
        "texels follow the footprint whatever the table's size (the paper)")
        ->check(cli::one_of({"on", "off"}))
        ->default_str("off");
    field(app, "--cache-lobe-spread", "cache_lobe_spread", c.cache_lobe_spread, "C",
          "after each bounce, position cells follow a cone whose spread grows by C times the angle of the "
          "lobe one sample stands for (a diffuse bounce: about 2C radians), so hits after rough bounces "
          "share coarser cells, whose detail that lobe averages out (uv texels keep the texture's cone; "
          "0.03125: fewer misses at the same bias, but a noisier same-seed match with the cacheless render); "
          "0: the texture's cone (the paper), 0..4")
        ->capture_default_str();
    field(app, "--cache-max-refine", "cache_max_refine", c.cache_max_refine, "LEVELS",
          "how many levels finer than the footprint a pattern may make its texels (each level splits a "
          "footprint into 4 texels, 8 cells); a point that needs more is evaluated without the cache there")
        ->capture_default_str();
  }

  app.option_defaults()->group("machine");
  setter<int>(
      app, "--threads", "threads", [&c](const int& v) { c.threads = v; }, "T", "host and PoCL worker threads")
      ->default_str("all cores");
  field(app, "--device", "device", c.device, "NAME",
        "OpenCL device or platform name substring (see 'pmc info --devices')")
      ->default_str("first GPU, else CPU");
  setter<std::string>(
      app, "--trace-mode", "trace_mode", [&c](const std::string& v) { c.trace_mode = parse_trace_mode(v); },
      "MODE", "Embree query style: single, stream or packet16")
      ->check(cli::one_of({"single", "stream", "packet16"}))
      ->default_str("stream");
  field(app, "--chunk-rays", "chunk_rays", c.chunk_rays, "N",
        "rays per streamed chunk with --transfer copy (0: the whole queue)")
      ->capture_default_str();
  setter<std::string>(
      app, "--transfer", "transfer", [&c](const std::string& v) { c.transfer = parse_transfer_mode(v); },
      "auto|zero-copy|copy",
      "how hits reach the device: mapped host-visible buffers (no copies; CPU devices) or explicit copies "
      "streamed in chunks (discrete GPUs)")
      ->check(cli::one_of({"auto", "zero-copy", "copy"}))
      ->default_str("auto: zero-copy on CPU devices, copy otherwise");
  field(app, "--shade-lanes", "shade_lanes", c.shade_lanes, "N",
        "hits of one material shaded together by one work-item (a power of two up to 64): the material "
        "interpreter decodes each instruction once per batch")
      ->default_str("64 on CPU devices (fewer for materials with very deep stacks), 1 on GPUs");
  app.option_defaults()->group("options");
}

void declare_display_options(CLI::App& app, ToneMap& tm) {
  app.option_defaults()->group("display");
  app.add_option("--exposure", tm.exposure_ev,
                 "PNG exposure in stops: linear values x 2^EV before the view transform")
      ->type_name("EV")
      ->check(cli::number())
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            return std::fabs(std::strtod(s.c_str(), nullptr)) <= 64.0
                       ? ""
                       : "must be within -64..64 stops, got " + s;
          },
          ""))
      ->default_str("0");
  app.add_option_function<std::string>(
         "--view", [&tm](const std::string& v) { tm.view = parse_view_transform(v, "--view"); },
         "PNG view transform, then sRGB: filmic (ACES fit, highlights roll off) or standard (clip at 1); "
         "the EXR stays linear")
      ->type_name("filmic|standard")
      ->check(cli::one_of({"filmic", "standard"}))
      ->default_str("filmic");
  app.option_defaults()->group("options");
}

CLI::Option* add_quiet_flag(CLI::App& app, bool& quiet, const std::string& what_still_prints) {
  return app.add_flag("--quiet", quiet, "no progress bar and no cache-size line (" + what_still_prints + ")");
}

void print_cache_choice(const RenderSettings& s) {
  const CacheSettings& c = s.cache;
  if (!c.on && !c.reason.empty())
    std::fprintf(stderr, "pmc: cache: %s\n", cli::with_flags(c.reason).c_str());
  else if (c.on)
    std::fprintf(stderr, "pmc: cache: %llu cells x %u entries = %.1f MiB (%s)%s\n",
                 (unsigned long long)c.cells, c.ways, double(c.cells) * c.ways * 8.0 / double(1 << 20),
                 cli::with_flags(c.reason).c_str(), c.priority ? ", --cache-policy priority" : "");
}

}  // namespace pmc
