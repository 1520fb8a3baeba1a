// render_options.cpp — the shared render options and the RenderConfig fields they set.
#include "app/render_options.h"

#include <algorithm>
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

// The options of the table's settings in `group` (gpu/render_settings_table.h),
// each bound to its RenderConfig field; `after(name)` runs after each one (to
// keep an option outside the table in its place in --help).
void declare_table_options(CLI::App& app, RenderConfig& c, SettingGroup group,
                           const std::function<void(const std::string&)>& after = nullptr) {
  visit_render_settings([&](const auto& info, auto config_field, auto) {
    if (info.group != group) return;
    using T = std::decay_t<decltype(info.dflt)>;
    T& value = config_field(c);
    if constexpr (kWordSetting<T>) {
      const std::vector<std::string> words = setting_words(info.value),
                                     shown = shown_setting_words(info.value);
      std::string value_name;
      for (const std::string& w : shown) value_name += (value_name.empty() ? "" : "|") + w;
      setter<std::string>(
          app, info.flag, info.name,
          [&value, words](const std::string& w) {
            const size_t i = size_t(std::find(words.begin(), words.end(), w) - words.begin());
            value = frame_value<T>(i);  // one_of() let only the words through
          },
          value_name, info.help)
          ->check(cli::one_of(shown))
          ->default_str(words[size_t(frame_value<int>(info.dflt))]);
    } else {
      field(app, info.flag, info.name, value, info.value, info.help)->capture_default_str();
    }
    if (after) after(info.name);
  });
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
  declare_table_options(app, c, SettingGroup::Image);

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
  if (cache_flags == CacheFlags::All) declare_table_options(app, c, SettingGroup::CacheSwitch);
  if (cache_flags != CacheFlags::None) {
    setter<int64_t>(
        app, "--cache-cells", "cache_cells", [&c](const int64_t& v) { c.cache_cells = v; }, "N",
        "cache cells (with --cache-entries; a cell of 8 entries is one 64-byte line)")
        ->default_str("sized from the scene");
    declare_table_options(app, c, SettingGroup::Cache, [&](const std::string& name) {
      if (name != "cache_eval") return;
      // Optional (unset, it follows --cache-eval): declared here, listed after --cache-eval.
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
    });
  }

  app.option_defaults()->group("machine");
  setter<int>(
      app, "--threads", "threads", [&c](const int& v) { c.threads = v; }, "T",
      "host and PoCL worker threads, T of each; with two waves in flight (--waves-in-flight) the two kinds "
      "work at the same time, so up to about 2T threads are busy: --waves-in-flight 1 keeps it to T")
      ->default_str("all cores");
  field(app, "--device", "device", c.device, "NAME",
        "OpenCL device or platform name substring (see 'pmc info --devices')")
      ->default_str("first GPU, else CPU");
  setter<std::string>(
      app, "--trace-mode", "trace_mode", [&c](const std::string& v) { c.trace_mode = parse_trace_mode(v); },
      "MODE", "Embree query style: single, stream or packet16")
      ->check(cli::one_of({"single", "stream", "packet16"}))
      ->default_str("stream");
  declare_table_options(app, c, SettingGroup::Machine);
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
