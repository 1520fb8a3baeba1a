// render_session.h — one scene prepared for rendering from a RenderConfig.
//
// A session validates the config, loads the OBJ (textures are loaded by the
// material compiler, only those live nodes read), binds and compiles its
// materials (with cache instructions when config.cache), resolves the camera
// and the lights (a lights file, SCENE.lights.json, the environment),
// sizes the cache table (config.cache_cells, else from the scene's cache
// points; the cache is turned off, with the reason in settings().cache.reason,
// when no material has a cache point; the reason names settings marked as in
// ConfigError messages: show it through phrase_settings), and builds the cut-out tester, the
// Embree BVH and the OpenCL renderer. render() renders with the resolved
// settings, or with settings derived from them (another spp, seed or cache
// table over the same scene and program: what `compare` and `sweep` vary).
// `pmc render`, `compare`, `sweep` and the tests all render through it, so a
// cached and a cacheless render are always set up the same way.
//
// setup_seconds() says where the session's construction went (wall clock).
//
// A session given no device opens it itself (open_device(config)) on a
// Background job (core/background.h) while the OBJ is parsed and the
// materials compiled, and waits for it once they are. An error opening the
// device surfaces unchanged, and before any error of the scene or its
// materials, as when the device was opened first. The OpenCL program (whose
// build options come from the compiled materials) then builds on another
// Background job while the textures decode and the BVH builds.
//
// Errors: ConfigError for settings (see core/error.h), pmc::Error naming the
// file for bad scenes and materials.
#pragma once

#include <functional>
#include <memory>
#include <optional>

#include "core/embree_tracer.h"
#include "core/scene.h"
#include "gpu/cl_context.h"
#include "gpu/render_config.h"
#include "gpu/wavefront_renderer.h"
#include "materials/cutout.h"
#include "materials/material_set.h"

namespace pmc {

// Wall-clock seconds of each step of a session's setup, on the thread that
// constructs it: the steps follow each other, so they add up to the setup's
// wall time (total()). Work that runs on a background job beside a step is
// in that step only as far as the step waits for it; its own duration is
// reported apart (background_*), overlapping the steps.
struct SetupSeconds {
  double opencl_device = 0;  // a session that opens its device: the wait for it, once the materials are
                             // compiled (0 when given one)
  double scene = 0;          // OBJ + MTL parsing
  double materials = 0;      // binding, MaterialX reading, compiling, texture decoding and mip chains (and
                             // with cache_model cost on a device measured for the first time, its
                             // calibration, gpu/device_calibration.h)
  double lights = 0;         // camera, lights file and environment map, cache sizing
  double bvh = 0;            // cut-out tester and Embree's BVH build
  double renderer = 0;       // the wait for the OpenCL program build, and scene buffer uploads
  double total() const { return opencl_device + scene + materials + lights + bvh + renderer; }
  // Jobs beside the steps (not part of total()): opening the device; the
  // program build (kernel_build_seconds), from the end of material compiling.
  double background_opencl_device = 0;
  double background_kernel_build = 0;
};

class RenderSession {
 public:
  // Renders on `cl`, which must outlive the session.
  RenderSession(const RenderConfig& config, const ClContext& cl);
  // Opens its own device: open_device(config), overlapped with the scene's loading.
  explicit RenderSession(const RenderConfig& config);
  ~RenderSession();
  RenderSession(const RenderSession&) = delete;
  RenderSession& operator=(const RenderSession&) = delete;

  const RenderConfig& config() const { return config_; }
  const ClContext& device() const { return *cl_; }
  const Scene& scene() const { return scene_; }
  const MaterialSet& materials() const { return materials_; }
  // The resolved settings: camera, cache table size and why.
  const RenderSettings& settings() const { return settings_; }
  // Cache points over all compiled materials.
  size_t cache_points() const;
  const SetupSeconds& setup_seconds() const { return setup_; }
  // The cost model the cache plan was made with (cache_model cost), else none.
  const std::optional<CacheCostModel>& cache_model() const { return cache_model_; }
  // The sub-samples a miss evaluates per key kind (cache_supersample resolved; 1 in hit mode).
  const CacheSupersample& cache_supersample() const { return cache_supersample_; }

  RenderOutput render(const ProgressFn& progress = {}) { return render(settings_, progress); }
  // `settings` must keep settings().cache.on (the program was compiled for it).
  RenderOutput render(const RenderSettings& settings, const ProgressFn& progress = {});

 private:
  RenderSession(const RenderConfig& config, const ClContext* cl);
  // Scene, materials, lights and BVH: the steps before the renderer; `lap` ends each.
  // `compiled` runs once the materials are compiled, before their textures decode.
  // `device` returns the device (waiting for it to open) when the cache's
  // cost model needs it before compiling.
  void prepare_scene(const std::function<void(double&)>& lap, const std::function<const ClContext&()>& device,
                     const std::function<void(MaterialSet&)>& compiled);
  RenderConfig config_;
  std::unique_ptr<ClContext> own_cl_;  // before everything that uses it, so destroyed after them
  const ClContext* cl_ = nullptr;
  Scene scene_;
  MaterialSet materials_;
  RenderSettings settings_;
  std::optional<CacheCostModel> cache_model_;
  CacheSupersample cache_supersample_;
  std::unique_ptr<CutoutTester> cutout_;
  std::unique_ptr<EmbreeTracer> tracer_;
  std::unique_ptr<WavefrontRenderer> renderer_;
  SetupSeconds setup_;
};

// Limits the host (TBB) and PoCL worker threads to config.threads when set,
// then opens the OpenCL device config.device names (ClContext's default
// choice when empty). The thread limit must precede any OpenCL use, so
// programs open their device through this (or a session opens it).
// The frame the cache's cost model plans for (materials/node_costs.h): the
// whole frame's samples (a farm part plans as the frame does, so parts merge).
CacheFrame cache_frame(const RenderConfig& config);
std::unique_ptr<ClContext> open_device(const RenderConfig& config);
// The thread limit alone (open_device's first half).
void limit_threads(const RenderConfig& config);

// The camera of `config` for `scene` (see RenderConfig).
Camera resolve_camera(const RenderConfig& config, const Scene& scene);
// The lights of `config`: its lights file (or SCENE.lights.json), and the
// environment from env_map or env with env_scale/env_rotate applied. Loads
// the map. Errors name the file and field, or the setting.
SceneLights resolve_lights(const RenderConfig& config);

// Hits per lookup, 0 without lookups.
inline double hit_rate(const CacheStats& s) { return s.lookups ? double(s.hits) / double(s.lookups) : 0.0; }
// Hits per lookup at camera-ray hits (depth 0), 0 without such lookups.
inline double camera_hit_rate(const CacheStats& s) {
  return s.camera_lookups ? double(s.camera_hits) / double(s.camera_lookups) : 0.0;
}
// The same for position-keyed points, and for uv-keyed ones (the rest).
inline double position_hit_rate(const CacheStats& s) {
  return s.position_lookups ? double(s.position_hits) / double(s.position_lookups) : 0.0;
}
inline double uv_hit_rate(const CacheStats& s) {
  const uint64_t lookups = s.lookups - s.position_lookups, hits = s.hits - s.position_hits;
  return lookups ? double(hits) / double(lookups) : 0.0;
}

}  // namespace pmc
