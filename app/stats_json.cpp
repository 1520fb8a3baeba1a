// stats_json.cpp — the JSON objects of stats_json.h.
#include "app/stats_json.h"

#include "app/cli.h"
#include "gpu/render_session.h"

namespace pmc {

nlohmann::json cache_json(const CacheSettings& s, const CacheStats& st) {
  nlohmann::json c;
  c["enabled"] = s.on;
  c["eval"] = s.center ? "center" : "hit";
  c["filter"] = s.bilinear ? "bilinear" : "nearest";
  c["policy"] = s.priority ? "priority" : "keep-first";
  c["bandwidth"] = s.bandwidth;
  c["max_refine"] = s.max_refine;
  c["lobe_spread"] = s.lobe_spread;
  c["feature_texels"] = s.feature_texels;
  c["mip_bias"] = s.mip_bias;
  c["fit_levels"] = s.fit_levels;
  c["cells"] = st.cells;
  c["entries"] = st.ways;
  c["memory_bytes"] = st.memory_bytes;
  c["size_reason"] = s.on || !s.reason.empty() ? cli::with_flags(s.reason) : std::string("--cache off");
  for (const CacheCounter& k : kCacheCounters) c[k.key] = st.*k.field;
  c["hit_rate"] = hit_rate(st);
  c["camera_hit_rate"] = camera_hit_rate(st);
  c["position_hit_rate"] = position_hit_rate(st);
  c["uv_hit_rate"] = uv_hit_rate(st);
  c["occupancy"] = st.occupancy();
  return c;
}

nlohmann::json setup_json(const SetupSeconds& setup) {
  return {
      {"opencl_device", setup.opencl_device},
      {"scene", setup.scene},
      {"materials", setup.materials},
      {"lights", setup.lights},
      {"bvh", setup.bvh},
      {"renderer", setup.renderer},
      {"total", setup.total()},
      {"background",
       {{"opencl_device", setup.background_opencl_device}, {"kernel_build", setup.background_kernel_build}}}};
}

nlohmann::json texture_cache_json(const TextureCache& cache) {
  const TextureCacheStats st = cache.stats();
  return {{"folder", cache.enabled() ? cache.folder() : "off"},
          {"hits", st.hits},
          {"misses", st.misses},
          {"writes", st.writes}};
}

nlohmann::json render_json(const RenderSettings& s, const RenderStats& st, const std::string& scene) {
  nlohmann::json j;
  j["scene"] = scene;
  j["render_seconds"] = st.render_seconds;
  j["kernel_build_seconds"] = st.kernel_build_seconds;
  j["kernel_warmup_seconds"] = st.kernel_warmup_seconds;
  j["width"] = s.width;
  j["height"] = s.height;
  j["spp"] = s.spp;
  j["samples"] = {s.sample_begin, s.sample_end > 0 ? s.sample_end : s.spp};
  if (s.crop[2] > 0) j["crop"] = {s.crop[0], s.crop[1], s.crop[2], s.crop[3]};
  j["max_depth"] = s.max_depth;
  j["seed"] = s.seed;
  j["paths"] = st.paths;
  j["rays"] = st.rays;
  j["shadow_rays"] = st.shadow_rays;
  j["rays_per_second"] = st.render_seconds > 0 ? double(st.rays) / st.render_seconds : 0.0;
  j["nan_pixels"] = st.nan_pixels;
  j["bad_samples"] = st.bad_samples;
  j["stage_seconds"] = {{"camera", st.stages.camera}, {"trace", st.stages.trace},
                        {"sort", st.stages.sort},     {"shade", st.stages.shade},
                        {"shadow", st.stages.shadow}, {"resolve", st.stages.resolve},
                        {"film", st.stages.film},     {"transfer", st.stages.transfer}};
  j["transfer_mode"] = st.transfer;
  j["shade_lanes"] = st.shade_lanes;
  j["device"] = st.device;
  j["cache"] = cache_json(s.cache, st.cache);
  return j;
}

}  // namespace pmc
