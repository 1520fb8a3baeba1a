// stats_json.cpp — the JSON objects of stats_json.h.
#include "app/stats_json.h"

#include <sys/resource.h>

#include "app/cli.h"
#include "gpu/render_config.h"
#include "gpu/render_session.h"

namespace pmc {
namespace {

bool cache_group(SettingGroup g) { return g == SettingGroup::Cache || g == SettingGroup::CacheSwitch; }

// The table's settings that have a stats key (gpu/render_settings_table.h),
// from their RenderSettings copies: a word setting as its word, a number as
// itself; the cache's settings (`cache`) or the others.
void table_stats(const RenderSettings& s, bool cache, nlohmann::json& j) {
  visit_render_settings([&](const auto& info, auto, auto frame_field) {
    using T = std::decay_t<decltype(info.dflt)>;
    if constexpr (!std::is_null_pointer_v<decltype(frame_field)>) {
      if (!*info.stats || cache_group(info.group) != cache) return;
      const auto& v = frame_field(s);
      if constexpr (std::is_enum_v<T>)
        j[info.stats] = setting_words(info.value).at(size_t(v));
      else
        j[info.stats] = v;
    }
  });
}

}  // namespace

nlohmann::json cache_json(const RenderSettings& settings, const CacheStats& st) {
  const CacheSettings& s = settings.cache;
  nlohmann::json c;
  table_stats(settings, true, c);  // enabled, eval, policy, bandwidth, max_refine, lobe_spread, ...
  c["filter"] = s.bilinear ? "bilinear" : "nearest";
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

nlohmann::json cache_model_json(const RenderSession& session, const RenderStats& st) {
  const std::optional<CacheCostModel>& model = session.cache_model();
  if (!model || !st.cache.lookups) return nullptr;
  const CacheCosts& c = model->costs;
  const double measured[2] = {uv_hit_rate(st.cache), position_hit_rate(st.cache)};
  double predicted = 0.0, at_measured = 0.0;
  // Shaded hits are counted per scene material; each runs its compiled
  // program (MaterialSet::compiled, -1 for an unused one).
  const MaterialSet& set = session.materials();
  for (size_t m = 0; m < set.compiled.size() && m < st.material_hits.size(); ++m) {
    if (set.compiled[m] < 0) continue;
    for (const CachePoint& p : set.program.materials[size_t(set.compiled[m])].cache_plan.points) {
      const PointEconomics& e = p.economics;
      const double h = measured[p.key == CacheKey::Position ? 1 : 0];
      predicted += double(st.material_hits[m]) * e.gain;
      at_measured += double(st.material_hits[m]) * (h * e.cost - e.lookup - (1.0 - h) * e.miss);
    }
  }
  nlohmann::json j;
  j["costs"] = c.source;
  j["unit_ns"] = c.unit_ns;
  j["lookup"] = c.lookup;
  j["miss"] = c.miss;
  j["miss_per_cost"] = c.miss_per_cost;
  j["expected_uv_hit_rate"] = expected_hit_rate(model->frame, false);
  j["expected_position_hit_rate"] = expected_hit_rate(model->frame, true);
  j["supersample"] = {{"uv", session.cache_supersample().uv},
                      {"position", session.cache_supersample().position}};
  j["shaded_hits"] = st.material_hits;
  j["predicted_saving_seconds"] = predicted * c.unit_ns * 1e-9;
  j["saving_at_measured_hit_rates_seconds"] = at_measured * c.unit_ns * 1e-9;
  return j;
}

nlohmann::json texture_cache_json(const TextureCache& cache) {
  const TextureCacheStats st = cache.stats();
  return {{"folder", cache.enabled() ? cache.folder() : "off"},
          {"hits", st.hits},
          {"misses", st.misses},
          {"writes", st.writes}};
}

nlohmann::json memory_json(const RenderSession& session, const RenderStats& st) {
  const Scene& scene = session.scene();
  const uint64_t mesh = (scene.positions.size() + scene.normals.size() + scene.uvs.size()) * sizeof(float) +
                        scene.triangles.size() * sizeof(PmcTriangle);
  const uint64_t texels = session.materials().texel_words->size() * sizeof(uint32_t);
  const EnvironmentSpec& env = session.settings().lights.environment;
  const uint64_t sky = env.map ? env.map->data.size() * sizeof(float) : 0;
  const uint64_t cache = st.cache.memory_bytes;
  struct rusage usage {};
  const uint64_t peak = getrusage(RUSAGE_SELF, &usage) == 0 ? uint64_t(usage.ru_maxrss) * 1024u : 0u;  // KiB
  return {{"mesh", mesh},
          {"texels", texels},
          {"sky_map", sky},
          {"cache_table", cache},
          {"listed", mesh + texels + sky + cache},
          {"peak_resident", peak}};
}

nlohmann::json render_json(const RenderSettings& s, const RenderStats& st, const std::string& scene) {
  nlohmann::json j;
  j["scene"] = scene;
  j["render_seconds"] = st.render_seconds;
  j["kernel_build_seconds"] = st.kernel_build_seconds;
  j["kernel_warmup_seconds"] = st.kernel_warmup_seconds;
  table_stats(s, false, j);  // width, height, spp, max_depth, seed
  j["samples"] = {s.sample_begin, s.sample_end > 0 ? s.sample_end : s.spp};
  if (s.crop[2] > 0) j["crop"] = {s.crop[0], s.crop[1], s.crop[2], s.crop[3]};
  j["paths"] = st.paths;
  j["rays"] = st.rays;
  j["shadow_rays"] = st.shadow_rays;
  j["rays_per_second"] = st.render_seconds > 0 ? double(st.rays) / st.render_seconds : 0.0;
  j["nan_pixels"] = st.nan_pixels;
  j["bad_samples"] = st.bad_samples;
  if (s.adaptive_threshold > 0.0)
    j["adaptive"] = {{"mean_spp", st.adaptive_mean_spp}, {"stopped_pixels", st.adaptive_stopped_pixels}};
  j["stage_seconds"] = {{"camera", st.stages.camera}, {"trace", st.stages.trace},
                        {"sort", st.stages.sort},     {"shade", st.stages.shade},
                        {"shadow", st.stages.shadow}, {"resolve", st.stages.resolve},
                        {"film", st.stages.film},     {"transfer", st.stages.transfer}};
  j["transfer_mode"] = st.transfer;
  j["shade_lanes"] = st.shade_lanes;
  j["waves_in_flight"] = st.waves_in_flight;
  j["device"] = st.device;
  j["cache"] = cache_json(s, st.cache);
  j["lights"] = {{"count", st.lights.count},
                 {"emissive_triangles", st.lights.emissive_triangles},
                 {"sampler", st.lights.tree ? "tree" : "power"},
                 {"tree_nodes", st.lights.tree_nodes},
                 {"tree_depth", st.lights.tree_depth},
                 {"tree_build_seconds", st.lights.build_seconds},
                 {"table_reused", st.lights.reused}};
  return j;
}

}  // namespace pmc
