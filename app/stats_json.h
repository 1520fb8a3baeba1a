// stats_json.h — render settings and statistics as JSON, one way everywhere.
//
// `pmc render --stats` and `pmc compare`'s metrics.json describe the cache
// with the same object (cache_json), so a key means the same in both.
#pragma once

#include <nlohmann/json.hpp>

#include "core/texture_cache.h"
#include "gpu/render_session.h"
#include "gpu/wavefront_renderer.h"

namespace pmc {

// The cache's settings (the table's with a stats key, gpu/render_settings_table.h)
// and counters: enabled, eval, filter, policy, mip_bias, cells, entries,
// memory_bytes, size_reason (in flag names), each counter of
// PMC_CACHE_COUNTERS (core/device/pmc_cache.h) under its key (lookups, hits,
// misses, inserts, ...), hit_rate, camera_hit_rate, position_hit_rate,
// uv_hit_rate, occupancy.
nlohmann::json cache_json(const RenderSettings& settings, const CacheStats& stats);
// The cost model behind the cache plan (--cache-model cost; null otherwise):
// its costs' source, unit_ns, lookup, miss, miss_per_cost (unit nodes), the
// expected hit rates, and predicted_saving_seconds: the points' gains per
// lookup (materials/node_costs.h) times the lookups this render made (each
// material's shaded hits, all its points), in seconds; with the measured hit
// rates instead of the expected ones: saving_at_measured_hit_rates_seconds;
// shaded_hits: the hits each scene material ran for.
nlohmann::json cache_model_json(const RenderSession& session, const RenderStats& stats);
// Where a session's setup went (gpu/render_session.h): opencl_device (the
// wait for the device), scene, materials, lights, bvh, renderer, total (their
// sum: wall seconds), and background: {opencl_device: seconds opening it
// took on its own thread, overlapping the steps}.
nlohmann::json setup_json(const SetupSeconds& setup);
// What the render holds in memory, in bytes: the mesh (positions, normals,
// uvs, triangle records), the texel pool (every texture's mip chain, as the
// device reads it), the sky map (texels, CDFs and guide tables: 0 without
// one), the cache table, their sum (`listed`), and the process's peak
// resident memory so far (`peak_resident`, from getrusage: the rest is the
// BVH, the wave buffers, the OpenCL runtime and its kernels).
nlohmann::json memory_json(const RenderSession& session, const RenderStats& stats);
// The texture cache's folder and its hits, misses and writes in this process.
nlohmann::json texture_cache_json(const TextureCache& cache);
// A render's settings and statistics (`pmc render --stats`).
nlohmann::json render_json(const RenderSettings& settings, const RenderStats& stats,
                           const std::string& scene);

}  // namespace pmc
