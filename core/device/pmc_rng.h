/* pmc_rng.h — counter-based random numbers shared by host and kernels.
 *
 * Every random number is a pure function of (seed, pixel, sample, bounce,
 * dimension): no generator state travels with a path, so the image does not
 * depend on thread count, queue order or chunking, and cache-on / cache-off
 * renders consume identical random streams sample for sample. The mixer is
 * Chris Wellons' "lowbias32" integer hash (a published constant pair with very
 * low avalanche bias); a path key is hashed once, each dimension once more.
 */
#ifndef PMC_RNG_H
#define PMC_RNG_H

#include "../abi/pmc_vec.h"

PMC_FN pmc_u32 pmc_hash_u32(pmc_u32 x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

/* Key of one path: seed, pixel and sample index. */
PMC_FN pmc_u32 pmc_path_key(pmc_u32 seed, pmc_u32 pixel, pmc_u32 sample) {
  return pmc_hash_u32(seed ^ pmc_hash_u32(pixel ^ pmc_hash_u32(sample + 0x9e3779b9u)));
}

/* Uniform float in [0, 1) for dimension `dim` of bounce `bounce` of a path. */
PMC_FN float pmc_rand(pmc_u32 path_key, pmc_u32 bounce, pmc_u32 dim) {
  pmc_u32 h = pmc_hash_u32(path_key ^ pmc_hash_u32(bounce * 32u + dim));
  return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* Dimensions used at each bounce (keep them distinct). */
#define PMC_DIM_PIXEL_X 0u
#define PMC_DIM_PIXEL_Y 1u
#define PMC_DIM_LIGHT_PICK 2u
#define PMC_DIM_LIGHT_U 3u
#define PMC_DIM_LIGHT_V 4u
#define PMC_DIM_LOBE 5u
#define PMC_DIM_BSDF_U 6u
#define PMC_DIM_BSDF_V 7u
#define PMC_DIM_RR 8u
#define PMC_DIM_CACHE_U 9u
#define PMC_DIM_CACHE_V 10u

#endif /* PMC_RNG_H */
