/* device_calibration.cl — tiny kernels that time the material cache's
 * operations and one unit node on a device, once per device
 * (gpu/device_calibration.h). Each work-item runs `iterations` operations on
 * keys of its own (one texel per work-item and iteration, as a frame's hits
 * spread over the table); the host times whole launches. */
#include "../../core/device/pmc_cache.h"
#include "../../core/device/pmc_noise.h"

PmcCacheKey pmc_calibration_key(uint gid, uint i) { return pmc_cache_key(1u, 7u, 0u, 3, (long)gid, (long)i); }

PmcCacheTable pmc_calibration_table(__global ulong* entries, ulong cells, uint ways) {
  PmcCacheTable t;
  t.entries = entries;
  t.cells = cells;
  t.ways = ways;
  t.policy = PMC_CACHE_KEEP_FIRST;
  return t;
}

/* A miss: the lookup that does not find the key, then its insert. */
__kernel void pmc_calibrate_miss(__global ulong* entries, ulong cells, uint ways, uint iterations,
                                 __global uint* out) {
  const PmcCacheTable t = pmc_calibration_table(entries, cells, ways);
  const uint gid = (uint)get_global_id(0);
  uint acc = 0u;
  for (uint i = 0u; i < iterations; ++i) {
    const PmcCacheKey k = pmc_calibration_key(gid, i);
    uint v = 0u;
    if (!pmc_cache_lookup(&t, k, &v)) acc += (uint)pmc_cache_insert(&t, k, gid ^ i, 0u);
  }
  out[gid] = acc;
}

/* A hit: the lookup of a key the miss kernel inserted. */
__kernel void pmc_calibrate_lookup(__global ulong* entries, ulong cells, uint ways, uint iterations,
                                   __global uint* out) {
  const PmcCacheTable t = pmc_calibration_table(entries, cells, ways);
  const uint gid = (uint)get_global_id(0);
  uint acc = 0u;
  for (uint i = 0u; i < iterations; ++i) {
    uint v = 0u;
    if (pmc_cache_lookup(&t, pmc_calibration_key(gid, i), &v)) acc += v;
  }
  out[gid] = acc;
}

/* A unit node: one 2D Perlin noise (1.0 average floor node on PoCL,
 * docs/BENCHMARKS.md "Node costs"). */
__kernel void pmc_calibrate_unit(uint iterations, __global float* out) {
  const uint gid = (uint)get_global_id(0);
  float acc = 0.0f;
  for (uint i = 0u; i < iterations; ++i)
    acc += pmc_op_noise2d((float2)((float)gid * 0.37f + (float)i * 0.11f, (float)i * 0.23f), 1u).x;
  out[gid] = acc;
}
