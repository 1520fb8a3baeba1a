// render_job.h — everything one render needs, prepared from the command line.
//
// prepare_render() loads the OBJ, compiles its materials (with or without
// cache instructions), sizes the cache, builds the cut-out tester, the Embree
// BVH and the OpenCL renderer. `render`, `compare` and `sweep` share it so the
// cached and cacheless renders they compare are set up identically.
#pragma once

#include <memory>
#include <string>

#include "app/cli_args.h"
#include "core/embree_tracer.h"
#include "core/scene.h"
#include "gpu/wavefront_renderer.h"
#include "materials/cutout.h"
#include "materials/material_set.h"

namespace pmc {

struct RenderJob {
  Scene scene;
  MaterialSet materials;
  RenderSettings settings;
  std::unique_ptr<CutoutTester> cutout;
  std::unique_ptr<EmbreeTracer> tracer;
  std::unique_ptr<WavefrontRenderer> renderer;
};

// `cache`: "on", "off", or "" to follow --cache.
std::unique_ptr<RenderJob> prepare_render(const ArgParser& p, const std::string& obj, const ClContext& cl,
                                          const std::string& cache, bool verbose);

}  // namespace pmc
