// render_options.cpp — validation of the shared render options.
#include "app/render_options.h"

#include <tbb/global_control.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "core/cache_sizing.h"
#include "core/error.h"
#include "core/image_io.h"

namespace pmc {

void declare_render_options(ArgParser& p) {
  p.option("--mtlx", "FILE.mtlx", "MaterialX document; usemtl NAME binds to its material NAME (repeatable)",
           "", true);
  p.option("--material", "NAME", "render every triangle with this MaterialX material");
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
  p.option("--env", "R,G,B", "constant environment radiance", "0,0,0");
  p.option("--trace-mode", "MODE", "Embree query style: single, stream or packet16", "single");
  p.option("--chunk-rays", "N", "rays per streamed chunk (0: whole queue)", "65536");
}

void apply_thread_option(const ArgParser& p) {
  if (!p.has("--threads")) return;
  int threads = p.get_int("--threads", 0);
  if (threads <= 0) fail("--threads: must be at least 1, got ", threads);
  static std::unique_ptr<tbb::global_control> control;
  control =
      std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(threads));
  // PoCL's CPU driver reads these when the platform is first opened.
  std::string t = std::to_string(threads);
  setenv("POCL_MAX_PTHREAD_COUNT", t.c_str(), 1);
  setenv("POCL_CPU_MAX_CU_NUM", t.c_str(), 1);
}

MaterialOptions material_options_from(const ArgParser& p) {
  MaterialOptions m;
  std::string cache = p.get("--cache", "on");
  if (cache != "on" && cache != "off") fail("--cache: expected on or off, got '", cache, "'");
  m.compile.cache = cache == "on";
  m.compile.cache_min_nodes = p.get_int("--cache-min-nodes", kDefaultCacheMinNodes);
  if (m.compile.cache_min_nodes < 1) fail("--cache-min-nodes: must be at least 1");
  m.mtlx_files = p.all("--mtlx");
  m.override_material = p.get("--material");
  if (!m.override_material.empty() && m.mtlx_files.empty())
    fail("--material needs at least one --mtlx document");
  return m;
}

RenderSettings render_settings_from(const ArgParser& p, const Scene& scene, const std::string& obj_path) {
  RenderSettings s;
  s.width = p.get_int("--width", s.width);
  s.height = p.get_int("--height", s.height);
  s.spp = p.get_int("--spp", s.spp);
  s.max_depth = p.get_int("--max-depth", s.max_depth);
  if (s.width <= 0 || s.height <= 0)
    fail("--width/--height: the image size must be positive, got ", s.width, "x", s.height);
  if (size_t(s.width) * size_t(s.height) > (size_t(1) << 28)) fail("--width/--height: image too large");
  if (s.spp <= 0) fail("--spp: samples per pixel must be at least 1, got ", s.spp);
  if (s.max_depth <= 0 || s.max_depth > 1024) fail("--max-depth: must be in 1..1024, got ", s.max_depth);
  long long seed = p.get_int64("--seed", 0);
  if (seed < 0 || seed > 0xffffffffLL) fail("--seed: must be in 0..4294967295");
  s.seed = uint32_t(seed);
  if (p.has("--env")) {
    p.get_vec3("--env", s.env);
    for (float v : s.env)
      if (v < 0.0f) fail("--env: radiance must not be negative");
  }
  long long chunk = p.get_int64("--chunk-rays", (long long)s.chunk_rays);
  if (chunk < 0) fail("--chunk-rays: must not be negative");
  s.chunk_rays = size_t(chunk);

  s.cache.mip_bias = p.get_float("--mip-bias", 0.0f);
  if (std::fabs(s.cache.mip_bias) > 32.0f) fail("--mip-bias: must be within -32..32, got ", s.cache.mip_bias);
  std::string eval = p.get("--cache-eval", "center");
  if (eval != "hit" && eval != "center") fail("--cache-eval: expected hit or center, got '", eval, "'");
  s.cache.center = eval == "center";
  std::string filter = p.get("--cache-filter", s.cache.center ? "bilinear" : "nearest");
  if (filter != "nearest" && filter != "bilinear")
    fail("--cache-filter: expected nearest or bilinear, got '", filter, "'");
  if (filter == "bilinear" && !s.cache.center)
    fail(
        "--cache-filter bilinear needs --cache-eval center (a hit-mode texel holds the value at one "
        "sample's uv, not at its centre, so there is nothing to interpolate)");
  s.cache.bilinear = filter == "bilinear";
  float aspect = float(s.width) / float(s.height);
  float fov = p.get_float("--fov", 45.0f);
  if (!(fov > 0.0f && fov < 180.0f)) fail("--fov: must be in (0, 180) degrees, got ", fov);
  if (p.has("--camera-from") != p.has("--camera-at")) fail("--camera-from and --camera-at go together");
  if (p.has("--camera-from")) {
    p.get_vec3("--camera-from", s.camera.from);
    p.get_vec3("--camera-at", s.camera.at);
    p.get_vec3("--camera-up", s.camera.up);
    s.camera.fov_degrees = fov;
  } else if (auto cam = read_camera_file(replace_extension(obj_path, ".camera"))) {
    s.camera = *cam;
    if (p.has("--fov")) s.camera.fov_degrees = fov;
  } else {
    s.camera = frame_bounds(scene.bounds, fov, aspect);
    p.get_vec3("--camera-up", s.camera.up);
  }
  return s;
}

}  // namespace pmc

namespace pmc {

void size_cache(const ArgParser& p, const MaterialSet& materials, RenderSettings& s, bool cache_on,
                bool verbose) {
  s.cache.on = cache_on;
  // Checked even when this scene will not use the cache: a bad value is bad input either way.
  long long cells = p.get_int64("--cache-cells", 0), entries = p.get_int64("--cache-entries", 8);
  if (p.has("--cache-cells") && cells <= 0) fail("--cache-cells: must be at least 1, got ", cells);
  if (entries <= 0 || entries > 1024) fail("--cache-entries: must be in 1..1024, got ", entries);
  const uint64_t avail = available_memory_bytes();
  auto check_fits = [&](double bytes) {
    if (bytes > double(avail) * 0.8)
      fail("--cache-cells/--cache-entries: a table of ", bytes / double(1 << 20), " MiB does not fit in the ",
           double(avail) / double(1 << 20), " MiB of free memory");
  };
  if (p.has("--cache-cells")) check_fits(double(cells) * double(entries) * 8.0);
  if (!s.cache.on) return;
  size_t points = 0, with_points = 0;
  for (const CompiledMaterial& m : materials.program.materials) {
    points += m.cache_plan.points.size();
    with_points += m.cache_plan.points.empty() ? 0 : 1;
  }
  if (points == 0) {
    s.cache.on = false;  // nothing cacheable: run the cacheless path, allocate nothing
    s.cache.reason =
        "no cacheable nodes in this scene's materials (none depends on uv alone with a sub-graph of at "
        "least --cache-min-nodes nodes): the cacheless program runs and no table is allocated";
    if (verbose) std::fprintf(stderr, "pmc: cache: %s\n", s.cache.reason.c_str());
    return;
  }
  if (p.has("--cache-cells")) {
    s.cache.cells = uint64_t(cells);
    s.cache.ways = uint32_t(entries);
    s.cache.reason = "set by --cache-cells/--cache-entries";
  } else {
    // --cache-entries alone: the cell count follows, so the table holds the same keys.
    double per_material = double(points) / double(std::max<size_t>(1, with_points));
    CacheSize cs = choose_cache_size(s.width, s.height, s.spp, per_material,
                                     std::min<uint64_t>(avail / 4, 4ull << 30), uint32_t(entries));
    s.cache.cells = cs.cells;
    s.cache.ways = cs.entries;
    s.cache.reason = cs.reason;
    check_fits(double(cs.bytes()));
  }
  if (verbose)
    std::fprintf(stderr, "pmc: cache: %llu cells x %u entries = %.1f MiB (%s)\n",
                 (unsigned long long)s.cache.cells, s.cache.ways,
                 double(s.cache.cells) * s.cache.ways * 8.0 / double(1 << 20), s.cache.reason.c_str());
}

uint64_t available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  uint64_t kb = 0;
  while (in >> key) {
    if (key == "MemAvailable:") {
      in >> kb;
      return kb * 1024;
    }
    std::string rest;
    std::getline(in, rest);
  }
  return uint64_t(8) << 30;
}

}  // namespace pmc
