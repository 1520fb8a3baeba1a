// wavefront_renderer.h — the render loop: Embree on the host, shading in OpenCL.
//
// render() runs the paper's pipeline as a list of stages over waves of paths
// (one pixel sample each; gpu/wavefront_renderer.cpp reads top to bottom):
//   generate camera rays (device) -> intersect (host, Embree)
//   -> shade: material against the cache + light sample + BSDF sample (device)
//   -> trace shadow rays (host) -> resolve shadow rays (device)
//   -> ... next bounce until no path is alive -> accumulate into the film.
// Hits and occlusion bytes reach the device without copies on CPU devices
// (gpu/host_link.h); on discrete GPUs they are uploaded in chunks so the host
// traces chunk k+1 while the device shades chunk k. Stage timers say where
// the time goes; the kernels' first-launch compile is warm-up, not render time.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "core/camera.h"
#include "core/device/pmc_cache.h"
#include "core/device/pmc_rng.h"
#include "core/embree_tracer.h"
#include "core/film_sum.h"
#include "core/image_io.h"
#include "core/lights.h"
#include "core/render_passes.h"
#include "core/scene.h"
#include "gpu/cl_context.h"
#include "gpu/host_link.h"
#include "gpu/render_settings_table.h"
#include "materials/material_set.h"

namespace pmc {

// The progressive material cache of one render (the programs must have been
// compiled with cache instructions for `on` to matter).
struct CacheSettings {
  bool on = false;
  uint64_t cells = 0;
  uint32_t ways = 0;  // entries per cell
  float mip_bias = 0.0f;
  // cache_fit on: levels the texels are coarsened by so the frame's keys fit
  // the table (0 when they fit or with fit off); the kernels' level bias is
  // mip_bias - fit_levels.
  float fit_levels = 0.0f;
  bool center = false;    // cache_eval center
  bool bilinear = false;  // cache_filter bilinear (center mode)
  bool priority = false;  // cache_policy priority: camera inserts may replace deeper entries
  CacheBandwidth bandwidth = CacheBandwidth::Off;  // on/camera: materials carry level floors (bandwidth.h)
  float feature_texels = 2.0f;  // cache_feature_texels: texels across a pattern's smallest feature
  std::string reason;           // why this size (printed, and written to stats)
  // Count the occupied entries by reading the table back after the render
  // (tests check that this equals `inserts`). Otherwise occupied = inserts:
  // entries start empty and only an insert's CAS from 0 fills one, and the
  // table (256 MiB at 1080p) is not copied back.
  bool audit = false;
  // The settings the table declares here (its CACHE(member) lines: max_refine,
  // floor levels above the footprint's before bypass; lobe_spread, position
  // cells' widening per bounce), each with the table's type and default.
  PMC_CACHE_TABLE_MEMBERS
};

// The counters of core/device/pmc_cache.h, one field each, named by its
// PMC_CACHE_COUNTERS key (lookups, hits, misses, inserts, ...: see there for
// what each counts), then the table's size and occupancy.
struct CacheStats {
#define PMC_CSTAT_FIELD_(NAME, key, meaning) uint64_t key = 0;
  PMC_CACHE_COUNTERS(PMC_CSTAT_FIELD_)
#undef PMC_CSTAT_FIELD_
  uint64_t occupied = 0;  // non-empty entries after the render
  uint64_t cells = 0, ways = 0, memory_bytes = 0;
  double occupancy() const { return cells * ways > 0 ? double(occupied) / double(cells * ways) : 0.0; }
};

// Each PMC_CACHE_COUNTERS counter: its buffer index, CacheStats field, stats
// key and meaning, for code that handles them all alike (read back, JSON).
struct CacheCounter {
  int index;  // PMC_CSTAT_*
  uint64_t CacheStats::*field;
  const char* key;
  const char* meaning;
};
inline constexpr CacheCounter kCacheCounters[] = {
#define PMC_CSTAT_ROW_(NAME, key, meaning) {PMC_CSTAT_##NAME, &CacheStats::key, #key, meaning},
    PMC_CACHE_COUNTERS(PMC_CSTAT_ROW_)
#undef PMC_CSTAT_ROW_
};
static_assert(sizeof(kCacheCounters) / sizeof(kCacheCounters[0]) == PMC_CSTAT_COUNT);

struct RenderSettings {
  int width = 640;
  int height = 360;
  int spp = 16;  // the frame's samples per pixel
  // The samples rendered: indices [sample_begin, sample_end) of the frame's
  // spp (sample_end 0: spp). The RNG is keyed by the index, so a range draws
  // the same samples in any process (the samples setting, farm chunks).
  int sample_begin = 0, sample_end = 0;
  // The window rendered, pixels [x0, x1) x [y0, y1) of the frame (crop);
  // x1 == 0: the whole frame. Pixels keep their frame coordinates (camera
  // ray, RNG key), so a window equals the same pixels of the full render.
  int crop[4] = {0, 0, 0, 0};
  int max_depth = 8;
  uint32_t seed = 0;
  float env[3] = {0.0f, 0.0f, 0.0f};  // constant environment radiance, unless lights.environment is set
  SceneLights lights;                 // lights file and environment (emissive triangles come from the scene)
  bool env_importance = true;         // false: sample an environment map uniformly (comparisons)
  bool light_tree = true;             // the light tree sampler; false: by power (core/lights.h)
  // Adaptive sampling (gpu/adaptive_sampling.h): 0 off; else a pixel stops once the relative
  // standard error of its mean is below the threshold, checked every adaptive_min_spp samples.
  double adaptive_threshold = 0.0;
  int adaptive_min_spp = 16;
  // Largest radiance one light sample may add to a sample (0: off), through
  // the first hit (direct) and later hits (indirect): pmc_clamp_light.
  float clamp_direct = 0.0f, clamp_indirect = 0.0f;
  Camera camera;
  size_t chunk_rays = 65536;        // copy transfers: rays per streamed chunk (0: whole queue at once)
  size_t max_wave_paths = 1 << 20;  // paths in flight per wave (several samples of each pixel when it can)
  int waves_in_flight =
      2;  // wave loops at once (two: host and device work overlap; gpu/wavefront_renderer.cpp)
  TransferMode transfer = TransferMode::Auto;
  uint32_t sampler = PMC_SAMPLER_SOBOL;  // PMC_SAMPLER_* (core/device/pmc_rng.h)
  CacheSettings cache;
  // Render passes to fill (PassBit, core/render_passes.h); any bit fills them
  // all (PmcFrame.passes_on), the bits choose what is written.
  uint32_t passes = 0;
};

// Seconds per stage: host stages are wall time, device stages kernel time.
struct StageSeconds {
  double camera = 0;    // device: camera rays
  double trace = 0;     // host: Embree intersect
  double sort = 0;      // host: hits ordered by material
  double shade = 0;     // device: materials, lights, BSDF
  double shadow = 0;    // host: Embree occlusion
  double resolve = 0;   // device: shadow-ray results into paths
  double film = 0;      // device: accumulate
  double transfer = 0;  // host: maps/reads/writes, including waits for kernels
};

// The render's lights as next-event estimation sees them (core/lights.h).
struct LightStats {
  int count = 0;  // lights in the table: emissive triangles, lights file, environment
  uint64_t emissive_triangles = 0;
  bool tree = false;  // picked by the light tree (else by power)
  int tree_nodes = 0;
  int tree_depth = 0;        // levels below the root
  double build_seconds = 0;  // the tree's build (part of render_seconds; 0 when reused)
  bool reused = false;       // the previous render's table, whose lights were the same
};

struct RenderStats {
  double render_seconds = 0;         // excludes the kernel build and warm-up below
  double kernel_build_seconds = 0;   // clBuildProgram
  double kernel_warmup_seconds = 0;  // first (empty) launches: PoCL compiles work-group code there
  std::string transfer;              // "zero-copy" or "copy"
  int shade_lanes = 1;               // hits per shade work-item
  int waves_in_flight = 1;           // wave loops run at once (RenderSettings::waves_in_flight)
  uint64_t paths = 0;
  uint64_t rays = 0;  // camera + continuation + shadow rays traced
  uint64_t shadow_rays = 0;
  uint64_t bad_samples = 0;  // NaN/Inf path samples dropped from the film
  uint64_t nan_pixels = 0;   // non-finite pixels in the final image
  StageSeconds stages;
  std::string device;
  CacheStats cache;
  LightStats lights;
  std::vector<uint64_t> material_hits;  // hits shaded per material (MaterialSet::program order)
  // Adaptive sampling: samples drawn per pixel on average, and the pixels that stopped before spp.
  double adaptive_mean_spp = 0;
  uint64_t adaptive_stopped_pixels = 0;
};

struct RenderOutput {
  Image image;        // the window's pixels (the whole frame without a crop)
  Image hitmap;       // cache points found per sample, per pixel (1 channel)
  FilmSums film;      // the exact sums `image` was resolved from (core/film_sum.h), with pass sums
  PassImages passes;  // resolved from the film's pass sums (when settings.passes)
  RenderStats stats;
};

// Called with 0 samples done once the kernels are warmed up and rendering starts, then after
// each finished pass: samples done so far, total (of this render's range), rays so far.
using ProgressFn = std::function<void(int samples_done, int samples_total, uint64_t rays)>;

class WaveKernels;

class WavefrontRenderer {
 public:
  // `shade_lanes`: hits per shade work-item (a power of two, at most 64;
  // 0: the device's default, see default_shade_lanes in gpu/wave_kernels.h).
  WavefrontRenderer(const ClContext& cl, const Scene& scene, const MaterialSet& materials,
                    const EmbreeTracer& tracer, int shade_lanes = 0);
  // With its program built already (for these materials: see RenderSession).
  WavefrontRenderer(const ClContext& cl, const Scene& scene, const MaterialSet& materials,
                    const EmbreeTracer& tracer, std::unique_ptr<WaveKernels> kernels);
  ~WavefrontRenderer();
  RenderOutput render(const RenderSettings& settings, const ProgressFn& progress = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pmc
