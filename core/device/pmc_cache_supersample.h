/* pmc_cache_supersample.h — where a supersampled cache miss evaluates.
 *
 * In cache_eval center a texel (a position cell) stores one value for its
 * whole area. Evaluated at its centre alone, that value point-samples any
 * pattern finer than the texel (threads, mortar lines, pores), where the
 * cacheless render averages it over the pixel. With K > 1 sub-samples a miss
 * runs the group's sub-graphs at K points spread over the texel and stores
 * their mean: a box filter over the texel (pmc_interp.h replays the group).
 *
 * The points: the first K (a power of two) of a 2D Owen-scrambled Sobol
 * (0,2)-sequence (pmc_sobol2), one in each of K strata of every elementary
 * shape, scrambled by a hash of the key (the texel's hash and the material),
 * so the stored value still depends on the key alone (thread counts and farm
 * parts agree) and a periodic pattern does not lock onto one fixed grid of
 * offsets. Cells take x and y from that sequence and z from an independently
 * shuffled 1D one (padded stratification). A cell's points spread along its
 * own three axes, not in the surface's tangent plane as stochastic selection
 * does (pmc_cache_plane_jitter): the normal belongs to the hit that missed,
 * not to the key, and a value that depended on it would depend on which hit
 * inserted it. The price is that a cell's mean also averages the solid
 * texture up to half a cell in front of and behind a surface.
 *
 * K per key kind travels in the CACHE_LOOKUP skip word as log2 K
 * (PMC_CACHE_SAMPLES_*), so the compiled program carries it and the part hash
 * covers it; K = 1 is the texel's centre, exactly as before.
 */
#ifndef PMC_CACHE_SUPERSAMPLE_H
#define PMC_CACHE_SUPERSAMPLE_H

#include "pmc_cache.h"
#include "pmc_rng.h"

/* The CACHE_LOOKUP skip word's bits 28-30: log2 of the point's sub-samples. */
#define PMC_CACHE_SAMPLES_SHIFT 28u
#define PMC_CACHE_SAMPLES_MASK 0x70000000u
#define PMC_CACHE_SAMPLES_MAX 16u

/* Sub-samples of a point whose lookup word is `word` (1, 2, 4, 8 or 16). */
PMC_FN pmc_u32 pmc_cache_samples_of(pmc_u32 word) {
  const pmc_u32 log2k = (word & PMC_CACHE_SAMPLES_MASK) >> PMC_CACHE_SAMPLES_SHIFT;
  return 1u << (log2k < 4u ? log2k : 4u);
}

/* Sub-sample `s` of `samples` for the texel or cell `t` of material
 * `material`: its offset from the centre in texel widths, each axis in
 * [-0.5, 0.5) (w: 0 for uv texels). A function of the key and s alone. */
PMC_FN float4 pmc_cache_subsample(const PmcCacheTexel* t, pmc_u32 material, pmc_u32 s) {
  const pmc_u32 key =
      pmc_hash_u32((pmc_u32)t->hash ^ pmc_hash_u32((pmc_u32)(t->hash >> 32) ^ pmc_hash_u32(material)));
  const float2 xy = pmc_sobol2(s, key, pmc_hash_u32(key + 1u), pmc_hash_u32(key + 2u));
  const float z = pmc_sobol1(s, pmc_hash_u32(key + 3u), pmc_hash_u32(key + 4u));
  return make_float4(xy.x - 0.5f, xy.y - 0.5f, z - 0.5f, 0.0f);
}

/* A texel's (cell's) coordinate along one axis at sub-sample offset `o`:
 * the centre plus o texel widths; the centre alone for the huge indices that
 * hold a float (pmc_cache_texel_center), whose width means nothing. */
PMC_FN float pmc_cache_subsample_coord(float center, long index, int lambda, float o) {
  if (index >= PMC_CACHE_BIG_INDEX || index <= -PMC_CACHE_BIG_INDEX) return center;
  return center + o * pmc_exp2i(-lambda);
}

#endif /* PMC_CACHE_SUPERSAMPLE_H */
