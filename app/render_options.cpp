// render_options.cpp — the shared render options and their RenderConfig fields.
#include "app/render_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.h"

namespace pmc {

void declare_render_options(ArgParser& p) {
  p.option("--mtlx", "FILE.mtlx", "MaterialX document; usemtl NAME binds to its material NAME (repeatable)",
           "", true);
  p.option("--material", "NAME", "render every triangle with this MaterialX material");
  p.option("--mtlx-library", "DIR",
           "MaterialX data libraries (.../MaterialX/libraries) for nodes pmc expands from their nodegraphs",
           "$PMC_MTLX_LIBRARY, else the one found at build time");
  p.option("--mtlx-search-path", "DIR",
           "folder where MaterialX filenames are looked up after fileprefix, the document's folder and "
           "$MATERIALX_SEARCH_PATH (repeatable)",
           "", true);
  p.option("--cache", "on|off", "progressive material cache", "on");
  p.option("--cache-cells", "N", "cache cells (with --cache-entries)", "sized from the scene");
  p.option("--cache-entries", "N", "entries per cache cell", "8");
  p.option("--mip-bias", "B", "added to the cache's virtual mip level (higher: finer, more accurate)", "0");
  p.option("--cache-eval", "hit|center",
           "values stored for a texel: at the inserting hit, or at the texel centre", "center");
  p.option("--cache-filter", "nearest|bilinear",
           "texel a lookup reads: the one under the hit, or a neighbour picked at random with its "
           "bilinear weight (center mode only)",
           "bilinear with center, nearest with hit");
  p.option("--cache-min-nodes", "N", "smallest sub-graph worth a cache point",
           std::to_string(kDefaultCacheMinNodes));
  p.option("--width", "W", "image width in pixels", "640");
  p.option("--height", "H", "image height in pixels", "360");
  p.option("--spp", "N", "samples per pixel", "16");
  p.option("--max-depth", "D", "maximum number of surface hits per path", "8");
  p.option("--seed", "S",
           "random seed; equal seeds give identical images (with the cache: in --cache-eval center, not hit)",
           "0");
  p.option("--threads", "T", "host and PoCL worker threads", "all cores");
  p.option("--device", "NAME", "OpenCL device or platform name substring (see 'pmc info --devices')",
           "first GPU, else CPU");
  p.option("--camera-from", "x,y,z", "camera position", "SCENE.camera, else framing the scene");
  p.option("--camera-at", "x,y,z", "point the camera looks at");
  p.option("--camera-up", "x,y,z", "camera up vector", "0,1,0");
  p.option("--fov", "DEG", "vertical field of view in degrees", "45");
  p.option("--env", "R,G,B",
           "constant environment radiance (W/m^2/sr), sampled as a light; replaces the lights file's "
           "environment",
           "0,0,0");
  p.option("--env-map", "FILE",
           "environment map, lat-long EXR or Radiance HDR (+Y up, image centre seen looking along -Z, +X at "
           "u = 0.75), importance-sampled; replaces the lights file's environment");
  p.option("--env-scale", "S", "multiplies the environment (--env, --env-map or the lights file's)", "1");
  p.option("--env-rotate", "DEG", "turns the environment about +Y, counter-clockwise seen from above", "0");
  p.option("--lights", "FILE.json|none",
           "lights file: point, spot, directional and quad lights and the environment (README, Lights); "
           "'none' ignores SCENE.lights.json",
           "SCENE.lights.json beside the OBJ, if there is one");
  p.option("--trace-mode", "MODE", "Embree query style: single, stream or packet16", "single");
  p.option("--chunk-rays", "N", "rays per streamed chunk with --transfer copy (0: whole queue)", "65536");
  p.option("--transfer", "auto|zero-copy|copy",
           "how hits reach the device: mapped host-visible buffers (no copies; CPU devices) or explicit "
           "copies streamed in chunks (discrete GPUs)",
           "auto: zero-copy on CPU devices, copy otherwise");
  p.option("--shade-lanes", "N",
           "hits of one material shaded together by one work-item (a power of two up to 64): the "
           "material interpreter decodes each instruction once per batch",
           "16 on CPU devices, 1 on GPUs");
}

namespace {

std::optional<Vec3> vec3_of(const ArgParser& p, const std::string& name) {
  float v[3];
  if (!p.get_vec3(name, v)) return std::nullopt;
  return Vec3{v[0], v[1], v[2]};
}

}  // namespace

RenderConfig render_config_from(const ArgParser& p, const std::string& obj) {
  RenderConfig c;
  c.scene = obj;
  c.mtlx = p.all("--mtlx");
  c.material = p.get("--material");
  c.mtlx_library = p.get("--mtlx-library");
  c.mtlx_search_paths = p.all("--mtlx-search-path");
  c.width = p.get_int("--width", c.width);
  c.height = p.get_int("--height", c.height);
  c.spp = p.get_int("--spp", c.spp);
  c.max_depth = p.get_int("--max-depth", c.max_depth);
  c.seed = p.get_int64("--seed", c.seed);
  if (auto env = vec3_of(p, "--env")) c.env = *env;
  c.lights = p.get("--lights");
  c.env_map = p.get("--env-map");
  if (p.has("--env-scale")) c.env_scale = p.get_float("--env-scale", 1.0f);
  if (p.has("--env-rotate")) c.env_rotate = p.get_float("--env-rotate", 0.0f);
  c.camera_from = vec3_of(p, "--camera-from");
  c.camera_at = vec3_of(p, "--camera-at");
  c.camera_up = vec3_of(p, "--camera-up");
  if (p.has("--fov")) c.fov = p.get_float("--fov", 45.0f);
  const std::string cache = p.get("--cache", "on");
  if (cache != "on" && cache != "off") fail("--cache: expected on or off, got '", cache, "'");
  c.cache = cache == "on";
  if (p.has("--cache-cells")) c.cache_cells = p.get_int64("--cache-cells", 0);
  c.cache_entries = p.get_int64("--cache-entries", c.cache_entries);
  c.mip_bias = p.get_float("--mip-bias", c.mip_bias);
  const std::string eval = p.get("--cache-eval", "center");
  if (eval != "hit" && eval != "center") fail("--cache-eval: expected hit or center, got '", eval, "'");
  c.cache_eval = eval == "center" ? CacheEval::Center : CacheEval::Hit;
  if (p.has("--cache-filter")) {
    const std::string filter = p.get("--cache-filter");
    if (filter != "nearest" && filter != "bilinear")
      fail("--cache-filter: expected nearest or bilinear, got '", filter, "'");
    c.cache_filter = filter == "bilinear" ? CacheFilter::Bilinear : CacheFilter::Nearest;
  }
  c.cache_min_nodes = p.get_int("--cache-min-nodes", c.cache_min_nodes);
  c.device = p.get("--device");
  if (p.has("--threads")) c.threads = p.get_int("--threads", 0);
  c.trace_mode = parse_trace_mode(p.get("--trace-mode", "single"));
  c.chunk_rays = p.get_int64("--chunk-rays", c.chunk_rays);
  c.transfer = parse_transfer_mode(p.get("--transfer", "auto"));
  c.shade_lanes = p.get_int("--shade-lanes", c.shade_lanes);
  c.validate();
  return c;
}

void declare_display_options(ArgParser& p) {
  p.option("--exposure", "EV", "PNG exposure in stops: linear values x 2^EV before the view transform", "0");
  p.option("--view", "filmic|standard",
           "PNG view transform, then sRGB: filmic (ACES fit, highlights roll off) or standard (clip at 1); "
           "the EXR stays linear",
           "filmic");
}

DisplaySettings display_settings_from(const ArgParser& p) {
  DisplaySettings d;
  d.exposure_ev = p.get_float("--exposure", 0.0f);
  if (!(std::fabs(d.exposure_ev) <= 64.0f))
    fail("--exposure: must be within -64..64 stops, got ", d.exposure_ev);
  d.view = parse_view_transform(p.get("--view", "filmic"), "--view");
  return d;
}

std::string flag_name(const std::string& setting) {
  if (setting == "scene") return "SCENE.obj";
  std::string flag = "--" + setting;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

std::string with_flags(const std::string& marked) { return phrase_settings(marked, flag_name); }

void print_cache_choice(const RenderSettings& s) {
  const CacheSettings& c = s.cache;
  if (!c.on && !c.reason.empty())
    std::fprintf(stderr, "pmc: cache: %s\n", with_flags(c.reason).c_str());
  else if (c.on)
    std::fprintf(stderr, "pmc: cache: %llu cells x %u entries = %.1f MiB (%s)\n", (unsigned long long)c.cells,
                 c.ways, double(c.cells) * c.ways * 8.0 / double(1 << 20), with_flags(c.reason).c_str());
}

}  // namespace pmc
