// render_job.cpp — scene, materials, cache size, BVH and renderer in one place.
#include "app/render_job.h"

#include "app/render_options.h"
#include "core/obj_loader.h"

namespace pmc {

std::unique_ptr<RenderJob> prepare_render(const ArgParser& p, const std::string& obj, const ClContext& cl,
                                          const std::string& cache, bool verbose) {
  auto job = std::make_unique<RenderJob>();
  ObjLoadOptions load;
  load.load_textures = false;  // the material compiler loads what live nodes read
  job->scene = load_obj(obj, load);
  MaterialOptions mo = material_options_from(p);
  if (!cache.empty()) mo.compile.cache = cache == "on";
  job->materials = build_material_set(job->scene, mo);
  job->settings = render_settings_from(p, job->scene, obj);
  size_cache(p, job->materials, job->settings, mo.compile.cache, verbose);
  job->cutout = std::make_unique<CutoutTester>(job->scene, job->materials);
  job->tracer = std::make_unique<EmbreeTracer>(job->scene, parse_trace_mode(p.get("--trace-mode", "single")),
                                               job->cutout->any() ? job->cutout.get() : nullptr);
  job->renderer = std::make_unique<WavefrontRenderer>(cl, job->scene, job->materials, *job->tracer);
  return job;
}

}  // namespace pmc
