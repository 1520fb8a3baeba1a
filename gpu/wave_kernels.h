// wave_kernels.h — the wavefront program and one typed launcher per kernel.
//
// Builds gpu/kernels/pmc_kernels.cl once per renderer (the interpreter's stack
// size comes from the materials, the shade kernel's batch size `lanes` from
// the device) and launches its kernels with fixed work-groups over an index
// range passed as arguments: kLocalSize items, or for the shade kernel
// kLocalSize / lanes batches of `lanes` hits.
// Each launcher sets every argument of its kernel in one place, from the
// named buffers, so no caller counts positional arguments. warm_up() runs
// every kernel with the render's own launch geometry and no work: PoCL
// compiles a kernel's work-group function at its first launch for a given
// work-group size and grid class (narrower than 65535 work-items, its
// "smallgrid" variant, or wider), and that compile belongs to warm-up, not
// to rendering.
#pragma once

#include <cstddef>
#include <string>

#include "gpu/cl_context.h"
#include "gpu/program.h"
#include "gpu/scene_buffers.h"
#include "gpu/wave_buffers.h"
#include "materials/material_set.h"

namespace pmc {

class WaveKernels {
 public:
  static constexpr size_t kLocalSize = 64;
  // PoCL compiles a second work-group function for grids of this many
  // work-items or more (its grid_width_specialization_limit, USHRT_MAX on
  // every CPU device); other drivers compile one.
  static constexpr size_t kSmallGridItems = 65535;
  // The zeroing kernel's grid: at most this many work-items, striding.
  static constexpr size_t kZeroGridItems = 4096 * kLocalSize;

  // `lanes`: hits per shade work-item (a power of two up to kLocalSize).
  WaveKernels(const ClContext& cl, const MaterialSet& materials, int lanes);
  // The same from wave_program_options(materials, lanes, ...), computed
  // beforehand: the build needs nothing else, so it can run on another thread.
  WaveKernels(const ClContext& cl, int lanes, const std::string& program_options);
  // The same program's kernels launched on another queue (a second wave in
  // flight): kernel objects of their own, so two threads never share one's
  // arguments.
  WaveKernels(const WaveKernels& base, cl_command_queue queue);
  double build_seconds() const { return program_.build_seconds(); }
  int lanes() const { return lanes_; }

  // Every kernel with no rays, at each grid class this render's launches
  // reach (frame.path_count must be 0 and the frame uploaded); returns when
  // they are done.
  void warm_up(const SceneBuffers& scene, WaveBuffers& wave);

  // Pixels [frame.pixel_offset, + count) -> camera rays in rays[queue] and fresh paths.
  void camera_rays(WaveBuffers& wave, int queue, size_t count, cl_event* done);
  // `batches` batches of lanes() hits of rays[queue], read from the
  // material-sorted wave.order starting at order[order_first] -> rays[1 - queue],
  // shadow rays, path updates.
  void shade(const SceneBuffers& scene, WaveBuffers& wave, int queue, size_t order_first, size_t batches,
             cl_event* done);
  // Adds the unoccluded light samples [first, end) to their paths.
  void resolve_shadows(WaveBuffers& wave, size_t first, size_t end, cl_event* done);
  // Adds the radiance of the wave's `count` paths to the film.
  void accumulate(WaveBuffers& wave, size_t count, cl_event* done);
  // Zeroes the film, the cache table and its counters (before a render).
  void clear(WaveBuffers& wave);

 private:
  void launch(cl_kernel k, size_t count, size_t local, cl_event* done);
  void create_kernels();
  const ClContext& cl_;
  cl_command_queue queue_;
  int lanes_;
  ClProgram program_;
  void zero(const ClBuffer& b, size_t bytes);
  size_t warm_up_items_ = 0;  // during warm_up(): the grid of every launch, at least
  cl_kernel camera_ = nullptr, shade_ = nullptr, resolve_ = nullptr, film_ = nullptr, zero_ = nullptr;
};

// -DPMC_STACK_SIZE=...: the materials' peak stack rounded up to a power of
// two (at least 16), so few distinct builds exist across scenes; and
// -DPMC_LANES=lanes; -DPMC_CELL_CHUNK (core/device/pmc_cache.h): 8 on GPUs,
// 1 on CPU devices; on CPU devices -DPMC_CPU_PREFETCH=1 (the shade kernel
// starts its loads with prefetch instructions: PMC_TOUCH, gpu/kernels/shade_surface.cl).
std::string wave_program_options(const MaterialSet& materials, int lanes, bool gpu);

// The shade kernel's batch size for a device when none is asked for: on CPU
// devices 64 hits per work-item (the interpreter's dispatch is paid once per
// batch and its arithmetic vectorises over the batch; 64 renders the default
// scene, Sponza and the cached default scene 11-15% faster than 16, see
// docs/BENCHMARKS.md), fewer when the materials' stack would make a
// work-item's batch larger than 64 KiB (at least 16); 1 on GPUs.
int default_shade_lanes(const ClContext& cl, const MaterialSet& materials);

}  // namespace pmc
