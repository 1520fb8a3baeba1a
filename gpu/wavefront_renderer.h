// wavefront_renderer.h — the render loop: Embree on the host, shading in OpenCL.
//
// render() runs, for every sample and every block of pixels, waves of
//   camera rays -> intersect (host) -> shade (device) -> shadow rays (host)
//   -> resolve (device) ... until no path is alive, then adds the block to the
// film. Hit records stream to the device in chunks: while the device shades
// chunk k the host already traces chunk k+1 (in-order queue, non-blocking
// enqueues). Stage timers separate host tracing from device work (OpenCL
// event profiling) so the stats say where the time goes.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "core/camera.h"
#include "core/embree_tracer.h"
#include "core/image_io.h"
#include "core/scene.h"
#include "gpu/cl_context.h"
#include "materials/material_set.h"

namespace pmc {

struct RenderSettings {
  int width = 640;
  int height = 360;
  int spp = 16;
  int max_depth = 8;
  uint32_t seed = 0;
  float env[3] = {0.0f, 0.0f, 0.0f};
  Camera camera;
  size_t chunk_rays = 65536;        // rays per streamed chunk (0: whole queue at once)
  size_t max_wave_paths = 1 << 20;  // paths in flight per wave
};

struct StageSeconds {
  double camera = 0, trace = 0, shade = 0, shadow = 0, film = 0, transfer = 0;
};

struct RenderStats {
  double render_seconds = 0;
  double kernel_build_seconds = 0;
  uint64_t paths = 0;
  uint64_t rays = 0;  // camera + continuation + shadow rays traced
  uint64_t shadow_rays = 0;
  uint64_t bad_samples = 0;  // NaN/Inf path samples dropped from the film
  uint64_t nan_pixels = 0;   // non-finite pixels in the final image
  StageSeconds stages;
  std::string device;
};

struct RenderOutput {
  Image image;
  RenderStats stats;
};

// Called after each finished pass: samples done so far, total, rays so far.
using ProgressFn = std::function<void(int samples_done, int samples_total, uint64_t rays)>;

class WavefrontRenderer {
 public:
  WavefrontRenderer(const ClContext& cl, const Scene& scene, const MaterialSet& materials,
                    const EmbreeTracer& tracer);
  ~WavefrontRenderer();
  RenderOutput render(const RenderSettings& settings, const ProgressFn& progress = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pmc
