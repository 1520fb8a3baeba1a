// wavefront_renderer.cpp — the wave loop, stage by stage.
#include "gpu/wavefront_renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <future>
#include <mutex>
#include <vector>

#include "core/device/pmc_cache.h"
#include "core/error.h"
#include "gpu/adaptive_sampling.h"
#include "gpu/cache_trace.h"
#include "gpu/material_sort.h"
#include "gpu/render_config.h"
#include "gpu/scene_buffers.h"
#include "gpu/stage_timer.h"
#include "gpu/wave_buffers.h"
#include "gpu/wave_kernels.h"

namespace pmc {

struct WavefrontRenderer::Impl {
  const ClContext& cl;
  const Scene& scene;
  const EmbreeTracer& tracer;
  std::unique_ptr<WaveKernels> built;
  WaveKernels& kernels;
  SceneBuffers scene_buffers;
  MaterialSorter sorter;
  bool warmed_up = false;
  // The second wave in flight's queue and kernel objects (made by the first
  // render that has two), kept, like the first's, warm across renders.
  struct SecondWave {
    ClQueue queue;
    WaveKernels kernels;
    bool warmed_up = false;
    SecondWave(const ClContext& cl, const WaveKernels& first)
        : queue(cl.new_queue()), kernels(first, queue.get()) {}
  };
  std::unique_ptr<SecondWave> second;
  // The lights of the table the last render uploaded: a render with the same
  // lights and sampler keeps it (pmc compare, sweeps), as a tree over a
  // million emissive triangles takes a second to build.
  std::unique_ptr<SceneLights> uploaded_lights;
  LightSampler uploaded_sampler = LightSampler::Tree;

  Impl(const ClContext& c, const Scene& s, const MaterialSet& mats, const EmbreeTracer& t,
       std::unique_ptr<WaveKernels> k)
      : cl(c),
        scene(s),
        tracer(t),
        built(std::move(k)),
        kernels(*built),
        scene_buffers(c, s, mats),
        sorter(scene_buffers.triangle_material, scene_buffers.material_count, kernels.lanes()) {}
};

namespace {

// One render's waves: the pipeline's stages over the buffers of `wave`.
class WaveLoop {
 public:
  WaveLoop(cl_command_queue queue, HostLink& link, WaveKernels& kernels, const SceneBuffers& scene,
           const EmbreeTracer& tracer, MaterialSorter& sorter, WaveBuffers& wave, size_t chunk,
           RenderStats& stats)
      : q_(queue),
        link_(link),
        kernels_(kernels),
        scene_(scene),
        tracer_(tracer),
        sorter_(sorter),
        wave_(wave),
        chunk_(chunk),
        st_(stats) {}

  // Renders the `frame.path_count` paths of one wave (wave_samples samples of
  // wave_pixels pixels) and adds them to the film.
  void run(const PmcFrame& frame) {
    const size_t n = frame.path_count;
    queue_write(q_, wave_.frame, 0, sizeof(frame), &frame, true);
    generate_camera_rays(n);
    int queue = 0;  // the ray queue being traced
    size_t count = n;
    bool coherent = true;  // camera rays
    while (count > 0) {
      intersect_and_shade(queue, count, coherent);
      const PmcCounters counts = read_counters();
      PMC_CHECK(counts.next_rays <= count && counts.shadow_rays <= count, "queue overflow");
      trace_shadow_rays(counts.shadow_rays);
      st_.rays += count + counts.shadow_rays;
      st_.shadow_rays += counts.shadow_rays;
      queue = 1 - queue;
      count = counts.next_rays;
      coherent = false;
    }
    accumulate(frame.wave_pixels);
  }

 private:
  // 1. One camera ray and a fresh path state per pixel of the wave.
  void generate_camera_rays(size_t n) {
    kernels_.camera_rays(wave_, 0, n, events_.add(st_.stages.camera));
    st_.paths += n;
  }

  // 2-3. Embree intersects the queue on the host and the host orders the hits
  // by material; the device shades them (material against the cache for a
  // batch of hits of one material at a time, emission, a light sample, a
  // BSDF sample) and appends continuations to the other queue and shadow
  // rays to theirs. Zero-copy traces the whole queue in place; copies stream
  // it in chunks.
  void intersect_and_shade(int queue, size_t count, bool coherent) {
    reset_counters();
    const PmcRay* rays;
    {
      ScopedStage t(st_.stages.transfer);
      rays = link_.read(wave_.rays[queue], 0, count, wave_.host_rays);
    }
    const size_t chunk = chunk_size(count);
    size_t order_at = 0;  // each chunk sorts into its own part of the order
    for (size_t c0 = 0; c0 < count; c0 += chunk) {
      const size_t cn = std::min(chunk, count - c0);
      PmcHit* hits = link_.write(wave_.hits, c0, cn, wave_.host_hits);
      {
        ScopedStage t(st_.stages.trace);
        tracer_.intersect(rays + c0, hits, cn, coherent);
      }
      size_t entries;
      {
        ScopedStage t(st_.stages.sort);
        const size_t room = sorter_.capacity(cn);
        PMC_CHECK(order_at + room <= wave_.order_capacity, "material order overflow");
        uint32_t* order = link_.write(wave_.order, order_at, room, wave_.host_order);
        entries = sorter_.sort(hits, cn, uint32_t(c0), order);
      }
      {
        ScopedStage t(st_.stages.transfer);
        link_.publish();
      }
      kernels_.shade(scene_, wave_, queue, order_at, entries / size_t(sorter_.lanes()),
                     events_.add(st_.stages.shade));
      order_at += sorter_.capacity(cn);
      clFlush(q_);
    }
  }

  // 4-5. Embree tests the shadow rays; the device adds the unoccluded light
  // samples to their paths.
  void trace_shadow_rays(size_t count) {
    if (count == 0) return;
    const PmcRay* rays;
    {
      ScopedStage t(st_.stages.transfer);
      rays = link_.read(wave_.shadow_rays, 0, count, wave_.host_rays);
    }
    const size_t chunk = chunk_size(count);
    for (size_t c0 = 0; c0 < count; c0 += chunk) {
      const size_t cn = std::min(chunk, count - c0);
      uint8_t* occluded = link_.write(wave_.occluded, c0, cn, wave_.host_occluded);
      {
        ScopedStage t(st_.stages.shadow);
        tracer_.occluded(rays + c0, occluded, cn);
      }
      {
        ScopedStage t(st_.stages.transfer);
        link_.publish();
      }
      kernels_.resolve_shadows(wave_, c0, c0 + cn, events_.add(st_.stages.resolve));
      clFlush(q_);
    }
  }

  // 6. The wave's path radiance into the film, one work-item per pixel.
  void accumulate(size_t pixels) {
    kernels_.accumulate(wave_, pixels, events_.add(st_.stages.film));
    queue_finish(q_);
    events_.collect();
  }

  size_t chunk_size(size_t count) const { return link_.zero_copy() || chunk_ == 0 ? count : chunk_; }

  void reset_counters() {
    static const PmcCounters zero{};
    queue_write(q_, wave_.counters, 0, sizeof(zero), &zero, false);
  }

  PmcCounters read_counters() {
    ScopedStage t(st_.stages.transfer);  // waits for the shade kernels
    PmcCounters c{};
    queue_read(q_, wave_.counters, 0, sizeof(c), &c);
    return c;
  }

  cl_command_queue q_;
  HostLink& link_;
  WaveKernels& kernels_;
  const SceneBuffers& scene_;
  const EmbreeTracer& tracer_;
  MaterialSorter& sorter_;
  WaveBuffers& wave_;
  const size_t chunk_;
  RenderStats& st_;
  DeviceStageLog events_;
};

// The paths a wave of several samples per pixel aims for. At 160x120 with the
// random sampler on the shared 2-core machine (3 interleaved rounds of 256
// spp), waves of 2^16 paths (3 samples) took the least wall time in every
// round: 7-15 s against 13-20 s with one sample per wave (19200 paths) and
// 9-17 s with 2^18 (13 samples), at the same CPU time; larger waves leave
// the caches, smaller ones pay per-wave costs more often.
constexpr size_t kWaveTargetPaths = size_t(1) << 16;

// The samples each pixel draws in the next round of waves: at most `left`,
// enough to fill the small frames' target, within a wave's `wave_paths`.
int round_samples(size_t left, size_t block, int wave_samples, size_t target, size_t wave_paths) {
  return int(
      std::min<size_t>({left, std::max<size_t>(size_t(wave_samples), std::min(target, wave_paths) / block),
                        wave_paths / block}));
}

// One round: waves over the window's pixels [lo, hi) (or the active list's
// entries), `block` pixels and `samples` samples from `sample` each.
void run_round(WaveLoop& loop, PmcFrame frame, int sample, int samples, size_t lo, size_t hi, size_t block,
               const std::atomic<bool>& stop) {
  for (size_t at = lo; at < hi && !stop; at += block) {
    frame.sample = uint32_t(sample);
    frame.pixel_offset = uint32_t(at);
    frame.wave_pixels = uint32_t(std::min(block, hi - at));
    frame.wave_samples = uint32_t(samples);
    frame.path_count = frame.wave_pixels * frame.wave_samples;
    loop.run(frame);
  }
}

// Renders every sample in [first_sample, end_sample) of the window's pixels
// [lo, hi) (no active list) in rounds of waves of up to `block_pixels`
// pixels. After each round: done(samples so far). Stops early when `stop` is
// set (the other wave loop failed).
void run_window_part(WaveLoop& loop, const PmcFrame& frame, size_t lo, size_t hi, int first_sample,
                     int end_sample, size_t block_pixels, int wave_samples, size_t target, size_t wave_paths,
                     const std::atomic<bool>& stop, const std::function<void(int)>& done) {
  const size_t block = std::min(hi - lo, block_pixels);
  for (int sample = first_sample; sample < end_sample && !stop;) {
    const int samples = round_samples(size_t(end_sample - sample), block, wave_samples, target, wave_paths);
    run_round(loop, frame, sample, samples, lo, hi, block, stop);
    sample += samples;
    done(sample - first_sample);
  }
}

// Progress of two wave loops: the samples both have finished, the rays both traced.
class SlotProgress {
 public:
  SlotProgress(const ProgressFn& fn, int total) : fn_(fn), total_(total) {}
  // Calls the render's progress function when both have finished more samples than before.
  void report(int slot, int done, uint64_t rays) {
    std::lock_guard<std::mutex> lock(mutex_);
    done_[slot] = done;
    rays_[slot] = rays;
    const int both = std::min(done_[0], done_[1]);
    if (fn_ && both > reported_) fn_(both, total_, rays_[0] + rays_[1]);
    reported_ = std::max(reported_, both);
  }

 private:
  const ProgressFn& fn_;
  const int total_;
  std::mutex mutex_;
  int done_[2] = {0, 0};
  uint64_t rays_[2] = {0, 0};
  int reported_ = 0;
};

// The wave loop counts of `from` added to `to`.
void add_wave_stats(const RenderStats& from, RenderStats& to) {
  to.paths += from.paths;
  to.rays += from.rays;
  to.shadow_rays += from.shadow_rays;
  StageSeconds& a = to.stages;
  const StageSeconds& b = from.stages;
  a.camera += b.camera, a.trace += b.trace, a.sort += b.sort, a.shade += b.shade;
  a.shadow += b.shadow, a.resolve += b.resolve, a.film += b.film, a.transfer += b.transfer;
}

// The kernels' frame: the table's settings (fill_frame_settings,
// gpu/render_settings_table.h), then what combines several values.
PmcFrame make_frame(const RenderSettings& s, const SceneBuffers& scene) {
  PmcFrame frame{};
  fill_frame_settings(s, frame);
  frame.lights = scene.lights.header;
  frame.lights.env_uniform = s.env_importance ? 0u : 1u;
  frame.texture_count = scene.texture_count;
  fill_frame_camera(s.camera, frame);
  const CacheSettings& cs = s.cache;
  frame.cache_ways = cs.ways;
  frame.cache_cells_lo = uint32_t(cs.cells & 0xffffffffu);
  frame.cache_cells_hi = uint32_t(cs.cells >> 32);
  frame.mip_bias = cs.mip_bias - cs.fit_levels;
  frame.cache_bilinear = cs.on && cs.bilinear ? 1u : 0u;
  frame.passes_on = s.passes != 0 ? 1u : 0u;
  // The table copies these as their index (AS_IS).
  static_assert(uint32_t(Sampler::Sobol) == PMC_SAMPLER_SOBOL &&
                uint32_t(Sampler::Random) == PMC_SAMPLER_RANDOM);
  static_assert(uint32_t(false) == PMC_CACHE_KEEP_FIRST && uint32_t(true) == PMC_CACHE_PRIORITY);
  static_assert(uint32_t(CacheBandwidth::On) == PMC_CACHE_FLOORS_EVERY_HIT &&
                uint32_t(CacheBandwidth::Camera) == PMC_CACHE_FLOORS_CAMERA);
  frame.wave_pixels = 1u;  // set per wave
  frame.wave_samples = 1u;
  return frame;
}

// The window's film (each pixel drew samples[i] samples) -> its exact sums, the image (mean of the
// good samples) and the hit map.
void resolve_film(const std::vector<PmcFilmPixel>& film, const std::vector<PmcPassPixel>& pass_film,
                  int width, int height, const std::vector<uint32_t>& samples, RenderOutput& out) {
  RenderStats& st = out.stats;
  FilmSums& f = out.film;
  f = FilmSums::zero(width, height, !pass_film.empty());
  for (size_t i = 0; i < pass_film.size(); ++i) {
    const PmcPassPixel& p = pass_film[i];
    std::copy(p.sum, p.sum + FilmSums::kPassWords, &f.pass_sum[i * FilmSums::kPassWords]);
    f.pass_hits[i] = p.hit_samples;
    f.pass_material_inv[i] = p.material_inv;
  }
  for (size_t i = 0; i < film.size(); ++i) {
    const PmcFilmPixel& p = film[i];
    std::copy(p.sum, p.sum + FilmSums::kWords, &f.sum[i * FilmSums::kWords]);
    f.samples[i] = samples[i];
    f.bad[i] = p.bad_samples;
    f.hits[i] = p.cache_hits;
    st.bad_samples += p.bad_samples;
  }
  out.image = film_mean(f);
  out.hitmap = film_hitmap(f);
  if (f.has_passes()) out.passes = film_passes(f);
  for (float v : out.image.pixels) st.nan_pixels += std::isfinite(v) ? 0 : 1;  // sums are finite: stays 0
}

void read_cache_stats(const ClContext& cl, const WaveBuffers& wave, const CacheSettings& cs, CacheStats& c) {
  uint64_t counts[PMC_CSTAT_COUNT];
  cl.read(wave.cache_stats, 0, sizeof(counts), counts);
  for (const CacheCounter& k : kCacheCounters) c.*k.field = counts[k.index];
  const size_t words = size_t(cs.cells) * cs.ways;
  c.occupied = c.inserts;
  if (cs.audit) {
    std::vector<uint64_t> table(words);
    cl.read(wave.cache_entries, 0, words * sizeof(uint64_t), table.data());
    c.occupied = 0;
    for (uint64_t e : table) c.occupied += e != 0 ? 1 : 0;
  }
  c.cells = cs.cells;
  c.ways = cs.ways;
  c.memory_bytes = words * sizeof(uint64_t);
}

}  // namespace

WavefrontRenderer::WavefrontRenderer(const ClContext& cl, const Scene& scene, const MaterialSet& materials,
                                     const EmbreeTracer& tracer, int shade_lanes)
    : WavefrontRenderer(
          cl, scene, materials, tracer,
          std::make_unique<WaveKernels>(
              cl, materials, shade_lanes > 0 ? shade_lanes : default_shade_lanes(cl, materials))) {}

WavefrontRenderer::WavefrontRenderer(const ClContext& cl, const Scene& scene, const MaterialSet& materials,
                                     const EmbreeTracer& tracer, std::unique_ptr<WaveKernels> kernels)
    : impl_(std::make_unique<Impl>(cl, scene, materials, tracer, std::move(kernels))) {}
WavefrontRenderer::~WavefrontRenderer() = default;

RenderOutput WavefrontRenderer::render(const RenderSettings& s, const ProgressFn& progress) {
  Impl& m = *impl_;
  validate_render_settings(s);  // gpu/render_config.h: the table's ranges, the samples, window and table
  const CacheSettings& cs = s.cache;
  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();

  RenderOutput out;
  RenderStats& st = out.stats;
  st.device = m.cl.description();
  st.kernel_build_seconds = m.kernels.build_seconds();
  const int first_sample = s.sample_begin, end_sample = s.sample_end > 0 ? s.sample_end : s.spp;
  const bool cropped = s.crop[2] > 0;
  const int x0 = cropped ? s.crop[0] : 0, y0 = cropped ? s.crop[1] : 0;
  const int x1 = cropped ? s.crop[2] : s.width, y1 = cropped ? s.crop[3] : s.height;
  const size_t pixels = size_t(x1 - x0) * size_t(y1 - y0);  // of the window
  // Waves in flight: with two, the window's pixels split in two halves, each
  // rendered by its own wave loop on its own thread, queue and buffers, so
  // that the host traces one wave's rays while the device shades the other's
  // (one loop leaves the cores idle at every hand-over between host and
  // device). Both share the film (disjoint pixels) and the cache table. Every
  // path is the same path either way, so the image is too. Adaptive sampling
  // checks the whole window between waves: it keeps one loop.
  const bool adaptive_on = s.adaptive_threshold > 0.0;
  const int slots = s.waves_in_flight >= 2 && !adaptive_on && pixels >= 2 ? 2 : 1;
  // A wave: every pixel of a block of the window, `wave_samples` samples each
  // (several when the window has fewer pixels than kWaveTargetPaths, so small
  // frames keep waves large and per-wave costs small). With two in flight,
  // each holds at most half of max_wave_paths (the memory bound) but keeps
  // the small frames' target: on the shared 2-core machine, two waves of
  // 2^16 paths rendered small frames 1.08-1.16x faster than two of 2^15.
  const size_t slot_max_paths = std::max<size_t>(1, s.max_wave_paths / size_t(slots));
  const size_t slot_pixels = (pixels + size_t(slots) - 1) / size_t(slots);
  const size_t block_pixels = std::min(slot_pixels, slot_max_paths);
  const size_t target = std::min(slot_max_paths, kWaveTargetPaths);
  const int wave_samples =
      int(std::min<size_t>(size_t(end_sample - first_sample), std::max<size_t>(1, target / block_pixels)));
  const size_t wave_paths = block_pixels * size_t(wave_samples);
  const size_t table_words = cs.on ? size_t(cs.cells) * cs.ways : 0;
  // The lookup trace (a diagnostic, gpu/cache_trace.h) lives behind the table.
  const CacheTraceConfig trace = cache_trace_config();
  const size_t cache_words = table_words + (cs.on ? trace.words() : 0);

  m.sorter.reset_counts();
  HostLink link(m.cl, s.transfer);
  st.transfer = link.zero_copy() ? "zero-copy" : "copy";
  st.shade_lanes = m.kernels.lanes();
  st.waves_in_flight = slots;
  // Every chunk of a queue sorts into its own part of the material order.
  const size_t chunk =
      link.zero_copy() || s.chunk_rays == 0 ? wave_paths : std::min(wave_paths, s.chunk_rays);
  const size_t chunks = (wave_paths + chunk - 1) / chunk;
  const size_t order_entries = chunks * m.sorter.capacity(chunk);
  // The cache table lives for the whole render: all samples, all bounces.
  WaveBuffers wave(m.cl, link, wave_paths, order_entries, pixels, cache_words, s.passes != 0);
  // The second wave in flight: its own queue, kernels, buffers and sorter.
  if (slots == 2 && !m.second) m.second = std::make_unique<Impl::SecondWave>(m.cl, m.kernels);
  std::unique_ptr<HostLink> link2;
  std::unique_ptr<WaveBuffers> wave2;
  std::unique_ptr<MaterialSorter> sorter2;
  if (slots == 2) {
    link2 = std::make_unique<HostLink>(m.cl, s.transfer, m.second->queue.get());
    wave2 = std::make_unique<WaveBuffers>(m.cl, *link2, wave_paths, order_entries, s.passes != 0, wave);
    sorter2 = std::make_unique<MaterialSorter>(m.sorter);
  }
  // The lights of this render: its lights file and environment (else the
  // constant s.env) plus the scene's emissive triangles (core/lights.h).
  SceneLights lights = s.lights;
  if (!lights.environment.present) lights.environment = constant_environment(s.env);
  const LightSampler sampler = s.light_tree ? LightSampler::Tree : LightSampler::Power;
  const bool reuse =
      m.uploaded_lights && m.uploaded_sampler == sampler && same_lights(*m.uploaded_lights, lights);
  if (!reuse) {
    m.uploaded_lights.reset();  // (a failed build leaves no table claimed)
    m.scene_buffers.upload_lights(m.cl,
                                  build_light_table(m.scene, m.scene_buffers.emission, lights, sampler));
    m.uploaded_lights = std::make_unique<SceneLights>(lights);
    m.uploaded_sampler = sampler;
  }
  const LightTable& table = m.scene_buffers.lights;
  st.lights = {table.header.count,
               table.emissive_triangles,
               table.header.sampler == PMC_LIGHT_SAMPLER_TREE,
               table.header.tree_nodes,
               table.tree_depth,
               reuse ? 0.0 : table.tree_build_seconds,
               reuse};
  PmcFrame frame = make_frame(s, m.scene_buffers);
  frame.crop_x0 = uint32_t(x0);
  frame.crop_y0 = uint32_t(y0);
  frame.crop_width = uint32_t(x1 - x0);

  const auto t_warm = Clock::now();
  if (!m.warmed_up || (slots == 2 && !m.second->warmed_up)) {  // compile time is warm-up, not rendering
    PmcFrame empty = frame;
    empty.path_count = 0;
    if (!m.warmed_up) {
      m.cl.write(wave.frame, 0, sizeof(empty), &empty, true);
      m.kernels.warm_up(m.scene_buffers, wave);
      m.warmed_up = true;
    }
    if (slots == 2 && !m.second->warmed_up) {
      queue_write(m.second->queue.get(), wave2->frame, 0, sizeof(empty), &empty, true);
      m.second->kernels.warm_up(m.scene_buffers, *wave2);
      m.second->warmed_up = true;
    }
  }
  st.kernel_warmup_seconds = std::chrono::duration<double>(Clock::now() - t_warm).count();
  if (progress) progress(0, end_sample - first_sample, 0);  // warmed up: rendering starts
  m.kernels.clear(wave);

  WaveLoop loop(m.cl.queue(), link, m.kernels, m.scene_buffers, m.tracer, m.sorter, wave, s.chunk_rays, st);
  // Adaptive sampling: the waves run over the pixels still active (all of them without it).
  AdaptiveSampler adaptive(pixels, s.adaptive_threshold, s.adaptive_min_spp);
  std::vector<PmcFilmPixel> film(pixels);
  frame.active_list = adaptive.on() ? 1u : 0u;
  if (adaptive.on()) m.cl.write(wave.active, 0, pixels * sizeof(uint32_t), adaptive.active().data(), true);
  if (slots == 2) {
    // Pixels [0, half) on this thread, [half, pixels) on the other.
    RenderStats st2;
    WaveLoop loop2(m.second->queue.get(), *link2, m.second->kernels, m.scene_buffers, m.tracer, *sorter2,
                   *wave2, s.chunk_rays, st2);
    SlotProgress shared(progress, end_sample - first_sample);
    std::atomic<bool> stop{false};
    auto run = [&](WaveLoop& l, RenderStats& ls, int slot, size_t lo, size_t hi) {
      run_window_part(l, frame, lo, hi, first_sample, end_sample, block_pixels, wave_samples, target,
                      wave_paths, stop, [&](int done) { shared.report(slot, done, ls.rays); });
    };
    auto other = std::async(std::launch::async, [&] {
      try {
        run(loop2, st2, 1, slot_pixels, pixels);
      } catch (...) {
        stop = true;
        throw;
      }
    });
    try {
      run(loop, st, 0, 0, slot_pixels);
    } catch (...) {
      stop = true;
      other.wait();
      throw;
    }
    other.get();
    add_wave_stats(st2, st);
    const std::vector<uint64_t>& hits2 = sorter2->material_hits();
    m.sorter.add_counts(hits2);
    adaptive.add_samples(end_sample - first_sample);
  }
  const std::atomic<bool> no_stop{false};
  for (int sample = first_sample; slots == 1 && sample < end_sample && !adaptive.active().empty();) {
    const size_t active = adaptive.active().size();
    // Fewer active pixels leave room for more samples of each in a wave (within the buffers).
    const size_t block = std::min(active, block_pixels);
    const int samples =
        round_samples(std::min<size_t>(size_t(end_sample - sample),
                                       size_t(adaptive.samples_to_next_check(sample - first_sample))),
                      block, wave_samples, target, wave_paths);
    run_round(loop, frame, sample, samples, 0, active, block, no_stop);
    adaptive.add_samples(samples);
    sample += samples;
    if (adaptive.on() && sample < end_sample &&
        adaptive.samples_to_next_check(sample - first_sample) ==
            s.adaptive_min_spp) {  // a check: the film decides
      m.cl.read(wave.film, 0, pixels * sizeof(PmcFilmPixel), film.data());
      if (adaptive.check(film) > 0 && !adaptive.active().empty())
        m.cl.write(wave.active, 0, adaptive.active().size() * sizeof(uint32_t), adaptive.active().data(),
                   true);
    }
    if (progress) progress(sample - first_sample, end_sample - first_sample, st.rays);
  }
  if (progress && adaptive.active().empty())
    progress(end_sample - first_sample, end_sample - first_sample, st.rays);

  m.cl.read(wave.film, 0, pixels * sizeof(PmcFilmPixel), film.data());
  std::vector<PmcPassPixel> pass_film(s.passes != 0 ? pixels : 0);
  if (!pass_film.empty()) m.cl.read(wave.pass_film, 0, pixels * sizeof(PmcPassPixel), pass_film.data());
  resolve_film(film, pass_film, x1 - x0, y1 - y0, adaptive.samples(), out);
  if (adaptive.on()) {
    uint64_t drawn = 0;
    for (uint32_t n : adaptive.samples()) {
      drawn += n;
      st.adaptive_stopped_pixels += n < uint32_t(end_sample - first_sample) ? 1 : 0;
    }
    st.adaptive_mean_spp = pixels > 0 ? double(drawn) / double(pixels) : 0.0;
  }
  if (cs.on) read_cache_stats(m.cl, wave, cs, st.cache);
  st.material_hits = m.sorter.material_hits();
  if (trace.on())
    write_cache_trace(
        m.cl, cs.on ? &wave.cache_entries : nullptr, table_words, trace,
        {uint32_t(s.width), uint32_t(s.height), cs.on ? uint64_t(cs.cells) : 0, cs.on ? cs.ways : 0});
  st.render_seconds =
      std::chrono::duration<double>(Clock::now() - t_start).count() - st.kernel_warmup_seconds;
  return out;
}

}  // namespace pmc
