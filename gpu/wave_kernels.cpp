// wave_kernels.cpp — program build, typed launchers, warm-up.
#include "gpu/wave_kernels.h"

#include <algorithm>

#include "core/device/pmc_cache.h"
#include "core/error.h"
#include "gpu/cache_trace.h"

namespace pmc {

namespace {

// The materials' peak stack (floats per lane), rounded up to a power of two.
uint32_t stack_size(const MaterialSet& mats) {
  uint32_t peak = 0;
  for (const CompiledMaterial& m : mats.program.materials) peak = std::max(peak, m.peak_stack);
  uint32_t size = 16;
  while (size < peak) size *= 2;
  return size;
}

}  // namespace

int default_shade_lanes(const ClContext& cl, const MaterialSet& mats) {
  if (cl.info().is_gpu) return 1;
  // 64 lanes while a work-item's stack stays within 64 KiB (256 floats per
  // lane); larger programs halve the batch per doubling, down to 16.
  int lanes = int(WaveKernels::kLocalSize);
  for (uint32_t size = stack_size(mats); lanes > 16 && size * uint32_t(lanes) * 4u > 65536u;) lanes /= 2;
  return lanes;
}

std::string wave_program_options(const MaterialSet& mats, int lanes, bool gpu) {
  return "-DPMC_STACK_SIZE=" + std::to_string(stack_size(mats)) + " -DPMC_LANES=" + std::to_string(lanes) +
         " -DPMC_CELL_CHUNK=" + (gpu ? "8" : "1") + (gpu ? "" : " -DPMC_CPU_PREFETCH=1 -DPMC_CELL_VECTOR=1") +
         cache_trace_program_option(cache_trace_config());
}

WaveKernels::WaveKernels(const ClContext& cl, const MaterialSet& materials, int lanes)
    : WaveKernels(cl, lanes, wave_program_options(materials, lanes, cl.info().is_gpu)) {}

WaveKernels::WaveKernels(const ClContext& cl, int lanes, const std::string& program_options)
    : cl_(cl), queue_(cl.queue()), lanes_(lanes), program_(cl, "pmc_kernels.cl", program_options) {
  PMC_CHECK(lanes >= 1 && size_t(lanes) <= kLocalSize && (lanes & (lanes - 1)) == 0, "shade lanes ", lanes);
  create_kernels();
}

WaveKernels::WaveKernels(const WaveKernels& base, cl_command_queue queue)
    : cl_(base.cl_), queue_(queue), lanes_(base.lanes_), program_(base.program_.share()) {
  create_kernels();
}

void WaveKernels::create_kernels() {
  camera_ = program_.kernel("pmc_camera_rays");
  shade_ = program_.kernel("pmc_shade");
  resolve_ = program_.kernel("pmc_resolve_shadows");
  film_ = program_.kernel("pmc_film_accumulate");
  zero_ = program_.kernel("pmc_zero_words");
  check_kernel_arg_count(shade_, 1 + kSceneBufferCount + 13);
}

void WaveKernels::launch(cl_kernel k, size_t count, size_t local, cl_event* done) {
  const size_t items = std::max<size_t>({count, warm_up_items_, 1});
  const size_t global = (items + local - 1) / local * local;
  cl_check(clEnqueueNDRangeKernel(queue_, k, 1, nullptr, &global, &local, 0, nullptr, done),
           "clEnqueueNDRangeKernel");
}

void WaveKernels::warm_up(const SceneBuffers& scene, WaveBuffers& wave) {
  // The largest grid (work-items) each kernel can get in this render: a
  // wave's paths (shadow rays: at most one per path), the material order's
  // batches of `lanes` hits (all chunks': an upper bound), the zeroing
  // kernel's capped grid over the largest buffer.
  const size_t paths = wave.paths;
  const size_t batches = wave.order_capacity / size_t(lanes_);
  const size_t zero_items = std::min<size_t>(
      std::max({wave.film_bytes, wave.pass_film_bytes, wave.cache_bytes}) / 4, kZeroGridItems);
  // Every kernel with no work (the kernels do nothing beyond their index
  // range), once in one work-group and, where the render's grids reach
  // PoCL's limit, once more at full width: the two compiled variants.
  for (int pass = 0; pass < 2; ++pass) {
    auto at = [&](size_t largest) {
      warm_up_items_ = pass == 0 ? 0 : largest;
      return pass == 0 || largest >= kSmallGridItems;
    };
    if (at((paths + size_t(lanes_) - 1) / size_t(lanes_))) camera_rays(wave, 0, 0, nullptr);
    if (at(batches)) shade(scene, wave, 0, 0, 0, nullptr);
    if (at(paths)) resolve_shadows(wave, 0, 0, nullptr);
    if (at(paths)) accumulate(wave, 0, nullptr);
    if (at(zero_items)) zero(wave.cache_stats, 0);
  }
  warm_up_items_ = 0;
  queue_finish(queue_);
}

void WaveKernels::camera_rays(WaveBuffers& w, int queue, size_t count, cl_event* done) {
  set_kernel_args(camera_, w.frame, w.rays[queue], w.path_states, w.path_passes, w.active);
  // `lanes_` consecutive paths a work-item (pmc_camera_rays)
  launch(camera_, (count + size_t(lanes_) - 1) / size_t(lanes_), kLocalSize / size_t(lanes_), done);
}

void WaveKernels::shade(const SceneBuffers& scene, WaveBuffers& w, int queue, size_t order_first,
                        size_t batches, cl_event* done) {
  cl_uint arg = 0;
  set_kernel_arg(shade_, arg++, w.frame);
  for (const ClBuffer& b : scene.buffers) set_kernel_arg(shade_, arg++, b);
  set_kernel_arg(shade_, arg++, w.rays[queue]);
  set_kernel_arg(shade_, arg++, w.hits);
  set_kernel_arg(shade_, arg++, w.path_states);
  set_kernel_arg(shade_, arg++, w.rays[1 - queue]);
  set_kernel_arg(shade_, arg++, w.shadow_rays);
  set_kernel_arg(shade_, arg++, w.shadow_loads);
  set_kernel_arg(shade_, arg++, w.counters);
  set_kernel_arg(shade_, arg++, w.cache_entries);
  set_kernel_arg(shade_, arg++, w.cache_stats);
  set_kernel_arg(shade_, arg++, w.order);
  set_kernel_arg(shade_, arg++, cl_uint(order_first));
  set_kernel_arg(shade_, arg++, cl_uint(batches));
  set_kernel_arg(shade_, arg++, w.path_passes);
  launch(shade_, batches, kLocalSize / size_t(lanes_), done);
}

void WaveKernels::resolve_shadows(WaveBuffers& w, size_t first, size_t end, cl_event* done) {
  set_kernel_args(resolve_, w.shadow_loads, w.occluded, w.path_states, cl_uint(first), cl_uint(end));
  launch(resolve_, end - first, kLocalSize, done);
}

void WaveKernels::accumulate(WaveBuffers& w, size_t count, cl_event* done) {
  set_kernel_args(film_, w.frame, w.path_states, w.film, w.path_passes, w.pass_film);
  launch(film_, count, kLocalSize, done);
}

void WaveKernels::clear(WaveBuffers& w) {
  zero(w.film, w.film_bytes);
  zero(w.pass_film, w.pass_film_bytes);
  zero(w.cache_entries, w.cache_bytes);
  zero(w.cache_stats, PMC_CSTAT_COUNT * sizeof(uint64_t));
  queue_finish(queue_);
}

void WaveKernels::zero(const ClBuffer& b, size_t bytes) {
  PMC_CHECK(bytes % sizeof(uint32_t) == 0, "zeroing ", bytes, " bytes");
  const cl_ulong words = bytes / sizeof(uint32_t);
  set_kernel_args(zero_, b, words);
  // A fixed grid (at most 4096 groups) that strides over the words.
  launch(zero_, std::min<size_t>(words, kZeroGridItems), kLocalSize, nullptr);
}

}  // namespace pmc
