// wave_buffers.h — the device buffers of one render's waves, in one place.
//
// A wave holds up to `paths` paths (one pixel sample each). Its queues:
// two ray queues that swap roles every bounce (the shade kernel reads one
// and appends continuations to the other), the hit records Embree writes,
// the path states, the shadow-ray queue with the light sample each shadow
// ray carries, the occlusion bytes Embree writes for them, and the queue
// counters, and the order in which the shade kernel takes the hits. The film, the material cache's table and
// its counters live for the whole render. Buffers the host reads or writes between launches are allocated
// with the HostLink's flags (host-visible for zero-copy).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/abi/pmc_types.h"
#include "gpu/cl_context.h"
#include "gpu/host_link.h"

namespace pmc {

struct WaveBuffers {
  size_t paths = 0;  // capacity of every per-path queue
  ClBuffer frame;
  ClBuffer rays[2];  // ray queues: rays[cur] is traced, the shade kernel fills rays[1 - cur]
  ClBuffer hits;
  ClBuffer path_states;
  ClBuffer shadow_rays;
  ClBuffer shadow_loads;
  ClBuffer occluded;
  ClBuffer counters;
  ClBuffer order;  // material-sorted ray indices (gpu/material_sort.h)
  size_t order_capacity = 0;
  ClBuffer film;
  ClBuffer active;  // adaptive sampling: window indices of the pixels still sampled (one per pixel)
  // Render passes (core/device/pmc_passes.h): per path slot, and the pass
  // film for the whole render; one element each when the render has none.
  ClBuffer path_passes;
  ClBuffer pass_film;
  ClBuffer cache_entries;  // cells x ways 64-bit entries (one word when the cache is off)
  ClBuffer cache_stats;    // PMC_CSTAT_COUNT 64-bit counters

  // Host staging for the copy transfer mode, `paths` elements each (empty
  // with zero-copy); never resized during a render.
  std::vector<PmcRay> host_rays;
  std::vector<PmcHit> host_hits;
  std::vector<uint8_t> host_occluded;
  std::vector<uint32_t> host_order;

  size_t film_bytes = 0, cache_bytes = 0, pass_film_bytes = 0;

  // `order_capacity`: entries of the material-sorted order (every chunk of a
  // queue). The film and the cache start uninitialised: WaveKernels::clear
  // zeroes them on the device (the pass film too). `passes`: the render
  // fills the pass buffers (PmcFrame.passes_on).
  WaveBuffers(const ClContext& cl, const HostLink& link, size_t paths, size_t order_capacity, size_t pixels,
              size_t cache_words, bool passes = false);
  // A second wave in flight: queues and path states of its own, and the
  // render-wide buffers of `first` (the film, the active pixels, the pass
  // film, the cache table and its counters), shared.
  WaveBuffers(const ClContext& cl, const HostLink& link, size_t paths, size_t order_capacity, bool passes,
              const WaveBuffers& first);
};

}  // namespace pmc
