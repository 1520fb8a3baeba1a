// render_options.cpp — validation of the shared render options.
#include "app/render_options.h"

#include <tbb/global_control.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "core/error.h"
#include "core/image_io.h"

namespace pmc {

void declare_render_options(ArgParser& p) {
  p.option("--mtlx", "FILE.mtlx", "MaterialX document; usemtl NAME binds to its material NAME (repeatable)",
           "", true);
  p.option("--material", "NAME", "render every triangle with this MaterialX material");
  p.option("--width", "W", "image width in pixels", "640");
  p.option("--height", "H", "image height in pixels", "360");
  p.option("--spp", "N", "samples per pixel", "16");
  p.option("--max-depth", "D", "maximum number of surface hits per path", "8");
  p.option("--seed", "S", "random seed; equal seeds give identical images", "0");
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
