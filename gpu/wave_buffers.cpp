// wave_buffers.cpp — allocation of the per-render buffers.
#include "gpu/wave_buffers.h"

#include <algorithm>

#include "core/device/pmc_cache.h"

namespace pmc {

WaveBuffers::WaveBuffers(const ClContext& cl, const HostLink& link, size_t n, size_t order_entries,
                         size_t pixels, size_t cache_words, bool passes)
    : paths(n), order_capacity(order_entries) {
  const cl_mem_flags host = link.buffer_flags();
  frame = cl.buffer(sizeof(PmcFrame));
  rays[0] = cl.buffer(n * sizeof(PmcRay), nullptr, host);
  rays[1] = cl.buffer(n * sizeof(PmcRay), nullptr, host);
  hits = cl.buffer(n * sizeof(PmcHit), nullptr, host);
  path_states = cl.buffer(n * sizeof(PmcPathState));
  shadow_rays = cl.buffer(n * sizeof(PmcRay), nullptr, host);
  shadow_loads = cl.buffer(n * sizeof(PmcShadowLoad));
  occluded = cl.buffer(n, nullptr, host);
  counters = cl.buffer(sizeof(PmcCounters));
  order = cl.buffer(order_entries * sizeof(uint32_t), nullptr, host);
  film_bytes = pixels * sizeof(PmcFilmPixel);
  cache_bytes = std::max<size_t>(1, cache_words) * sizeof(uint64_t);
  film = cl.buffer(film_bytes);
  active = cl.buffer(std::max<size_t>(1, pixels) * sizeof(uint32_t));
  cache_entries = cl.buffer(cache_bytes);
  cache_stats = cl.buffer(PMC_CSTAT_COUNT * sizeof(uint64_t));
  path_passes = cl.buffer((passes ? n : 1) * sizeof(PmcPathPasses));
  pass_film_bytes = (passes ? pixels : 1) * sizeof(PmcPassPixel);
  pass_film = cl.buffer(pass_film_bytes);
  if (!link.zero_copy()) {  // sized once: pending non-blocking writes read from them
    host_rays.resize(n);
    host_hits.resize(n);
    host_occluded.resize(n);
    host_order.resize(order_entries);
  }
}

WaveBuffers::WaveBuffers(const ClContext& cl, const HostLink& link, size_t n, size_t order_entries,
                         bool passes, const WaveBuffers& first)
    : WaveBuffers(cl, link, n, order_entries, 0, 0, passes) {
  film = first.film.share();
  active = first.active.share();
  pass_film = first.pass_film.share();
  cache_entries = first.cache_entries.share();
  cache_stats = first.cache_stats.share();
  film_bytes = first.film_bytes;
  cache_bytes = first.cache_bytes;
  pass_film_bytes = first.pass_film_bytes;
}

}  // namespace pmc
