/* pmc_cache_point.h — the material cache as one material evaluation uses it:
 * the per-point context and the lookup / store protocol of a cache point.
 *
 * pmc_cache.h holds the table (keys, encodings, lookup, insert); this file
 * holds what the interpreter (pmc_interp.h) does at a CACHE_LOOKUP and a
 * CACHE_STORE for one shading point:
 *  - pmc_cache_point_key: the point's texel (uv points) or cell (position
 *    points), computed once per evaluation and shared by all of its points
 *    of that kind;
 *  - pmc_cache_point_lookup: a hit delivers the stored value; a miss (or a
 *    texel too fine to pay, "bypassed") leaves the point to the group's
 *    sub-graphs;
 *  - pmc_cache_point_store: inserts a missed point's computed value and
 *    returns the value to deliver (in center mode the stored, quantised one).
 * Each counts its events in the context's PMC_CSTAT_* counters.
 */
#ifndef PMC_CACHE_POINT_H
#define PMC_CACHE_POINT_H

#include "pmc_cache.h"

/* The material cache as one evaluation sees it. A null context (the host
 * reference, or the cache off, whose programs have no cache instructions)
 * makes every lookup a miss. */
typedef struct PmcCacheContext {
  PmcCacheTable table;
  float2 g1, g2;            /* ray-cone uv gradients at the hit */
  float bias;               /* mip_bias */
  float4 jitter;            /* added to uv * 2^lambda (x, y) and to the position *
                             * 2^lambda (x, y, z) before flooring, in [-0.5, 0.5): 0 is
                             * the nearest texel; uniform random offsets pick a neighbour
                             * with its bilinear (trilinear) weight (cache_filter) */
  float radius;             /* ray-cone radius at the hit, scene units (position keys) */
  pmc_u32 floors;           /* 0: no level floors (the three fields below are ignored) */
  int level_floor_uv;       /* the material's level floors (pmc_cache_floored_level; */
  int level_floor_position; /* PMC_LEVEL_NO_FLOOR: none) for uv and position points */
  int max_refine;           /* levels a floor may lie above the footprint's before bypass */
  pmc_u32 material;
  pmc_u32 center;      /* cache_eval center: evaluate misses at the texel centre */
  pmc_u32 depth;       /* surface hits before this one (0: a camera-ray hit); the
                        * priority policy tags entries with it, and camera
                        * lookups are counted apart */
  PmcCacheTexel texel; /* the shading point's texel, if the caller computed it
                        * (ready); else the first lookup computes it */
  PmcCacheTexel cell;  /* the same for its position cell */
  pmc_u32 hits;        /* out: cache points found in this evaluation */
#if PMC_CACHE_TRACE_RECORDS
  pmc_u32 trace_pixel, trace_sample; /* PMC_CACHE_TRACE: who looked up (gpu/cache_trace.h) */
#endif
  /* out: PMC_CSTAT_* events, counted privately (no atomics per lookup); the
   * caller adds them up: the shade kernel once per work-group. */
  pmc_u32 counts[PMC_CSTAT_COUNT];
} PmcCacheContext;

/* PMC_CACHE_TRACE (a diagnostic, gpu/cache_trace.h): the shade kernel
 * appends every lookup to a record region behind the cache table: a count
 * word, then two words per lookup (the key's 64-bit cell hash; the pixel, the
 * depth, the sample and whether the key is a position cell). Records past the
 * region's capacity are counted, not written. */
#ifndef PMC_CACHE_TRACE_RECORDS
#define PMC_CACHE_TRACE_RECORDS 0
#endif
#if PMC_CACHE_TRACE_RECORDS && defined(__OPENCL_VERSION__)
PMC_FN void pmc_cache_trace(const PmcCacheContext* cx, PmcCacheKey key, int positional) {
  __global volatile ulong* region = cx->table.entries + cx->table.cells * (ulong)cx->table.ways;
  const ulong slot = atom_inc(region);
  if (slot >= (ulong)PMC_CACHE_TRACE_RECORDS) return;
  region[1ul + 2ul * slot] = key.h1;
  region[2ul + 2ul * slot] = (ulong)cx->trace_pixel | ((ulong)min(cx->depth, 255u) << 32) |
                             ((ulong)(cx->trace_sample & 0xfffffu) << 40) | ((ulong)(positional != 0) << 60);
}
#define PMC_CACHE_TRACE(cx, key, positional) pmc_cache_trace(cx, key, positional)
#else
#define PMC_CACHE_TRACE(cx, key, positional) ((void)0)
#endif

/* The key of a cache point at (uv, position): the point's cell when
 * `positional`, else its texel; computed into *texel or *cell the first time
 * a point of that kind asks (every point of a kind shares it). */
PMC_FN const PmcCacheTexel* pmc_cache_point_key(const PmcCacheContext* cx, float2 uv, float3 position,
                                                int positional, PmcCacheTexel* texel, PmcCacheTexel* cell) {
  if (positional) {
    if (!cell->ready)
      *cell =
          pmc_cache_cell_floored(position, cx->radius, cx->bias, cx->jitter, cx->material,
                                 cx->floors ? cx->level_floor_position : PMC_LEVEL_NO_FLOOR, cx->max_refine);
    return cell;
  }
  if (!texel->ready)
    *texel = pmc_cache_texel_floored(uv, cx->g1, cx->g2, cx->bias, make_float2(cx->jitter.x, cx->jitter.y),
                                     cx->material, cx->floors ? cx->level_floor_uv : PMC_LEVEL_NO_FLOOR,
                                     cx->max_refine);
  return texel;
}

/* What a cache point's lookup found. */
#define PMC_CACHE_POINT_MISS 0
#define PMC_CACHE_POINT_HIT 1
#define PMC_CACHE_POINT_BYPASS 2 /* too fine a texel to pay: evaluate, never insert */

/* Looks up the group's `rank`-th cache point (node `node`, encoding `enc`)
 * at key `t`; a hit decodes its value into *value. */
PMC_FN int pmc_cache_point_lookup(PmcCacheContext* cx, const PmcCacheTexel* t, int positional, pmc_u32 node,
                                  pmc_u32 rank, pmc_u32 enc, float4* value) {
  if (t->bypass) {
    cx->counts[PMC_CSTAT_BYPASSED] += 1u;
    return PMC_CACHE_POINT_BYPASS;
  }
  PmcCacheKey key = pmc_cache_key_at(t->hash, t->base, cx->material, node, rank);
  PMC_CACHE_TRACE(cx, key, positional);
  pmc_u32 bits;
  const pmc_u32 camera = cx->depth == 0u ? 1u : 0u;
  cx->counts[PMC_CSTAT_LOOKUPS] += 1u;
  cx->counts[PMC_CSTAT_CAMERA_LOOKUPS] += camera;
  cx->counts[PMC_CSTAT_POSITION_LOOKUPS] += (pmc_u32)positional;
  if (!pmc_cache_lookup(&cx->table, key, &bits)) {
    cx->counts[PMC_CSTAT_MISSES] += 1u;
    return PMC_CACHE_POINT_MISS;
  }
  *value = pmc_cache_decode(bits, enc);
  cx->hits += 1u;
  cx->counts[PMC_CSTAT_HITS] += 1u;
  cx->counts[PMC_CSTAT_CAMERA_HITS] += camera;
  cx->counts[PMC_CSTAT_POSITION_HITS] += (pmc_u32)positional;
  return PMC_CACHE_POINT_HIT;
}

/* Inserts the value `v` computed for the group's `rank`-th cache point that
 * missed at key `t` (nothing for a bypassed key or a value the encoding
 * cannot hold) and returns the value to deliver: `v`, or in center mode the
 * stored, quantised value, so that a texel's value is the same whether this
 * sample missed or a later one hits (center-mode renders then do not depend
 * on who inserts). */
PMC_FN float4 pmc_cache_point_store(PmcCacheContext* cx, const PmcCacheTexel* t, pmc_u32 node, pmc_u32 rank,
                                    pmc_u32 enc, float4 v) {
  pmc_u32 bits;
  if (t->bypass) return v; /* evaluated without the cache: nothing to insert */
  if (!pmc_cache_encode(v, enc, &bits)) {
    cx->counts[PMC_CSTAT_NOT_ENCODABLE] += 1u;
    return v;
  }
  if (cx->center) v = pmc_cache_decode(bits, enc);
  PmcCacheKey key = pmc_cache_key_at(t->hash, t->base, cx->material, node, rank);
  int result = pmc_cache_insert(&cx->table, key, bits, cx->depth);
  if (result == 1) cx->counts[PMC_CSTAT_INSERTS] += 1u;
  if (result == 2) cx->counts[PMC_CSTAT_REPLACED] += 1u;
  if (result == 0) cx->counts[PMC_CSTAT_ALREADY_PRESENT] += 1u;
  if (result < 0) cx->counts[PMC_CSTAT_DROPPED_FULL] += 1u;
  return v;
}

#endif /* PMC_CACHE_POINT_H */
