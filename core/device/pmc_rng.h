/* pmc_rng.h — the numbers a path draws, shared by host and kernels.
 *
 * Every number is a pure function of (seed, pixel, sample index, bounce,
 * dimension): no generator state travels with a path, so the image does not
 * depend on thread count, queue order, wave shape or chunking, sample i of a
 * pixel is the same sample in any process (farm parts merge exactly), and
 * cache-on / cache-off renders consume identical streams sample for sample.
 *
 * Two samplers (PmcFrame.sampler):
 *   PMC_SAMPLER_SOBOL  (the default) Owen-scrambled Sobol points, Burley 2020
 *     (pmc_sobol.h). The dimensions of a bounce come in sets (PMC_SET_*): a 2D
 *     set (pixel jitter, light uv, BSDF uv, cache jitter) is one 2D Sobol
 *     (0,2)-sequence, a 1D set (light pick, lobe, roulette) a scrambled van
 *     der Corput sequence. Each (pixel, bounce, set) has its own index shuffle
 *     and scramble seeds, hashed from the seed and pixel: pixels are
 *     decorrelated, and sets are "padded" together as independent
 *     low-discrepancy sequences, as Burley does. The first 2^k samples of any
 *     pixel put one point in every elementary interval of area 2^-k of each
 *     2D set (tests/core/sobol_sampler_test.cpp).
 *   PMC_SAMPLER_RANDOM independent hashed numbers (the sampler before Sobol):
 *     Chris Wellons' "lowbias32" integer hash of the path key and the
 *     dimension; kept to compare against (scripts/bench/sampler.py).
 */
#ifndef PMC_RNG_H
#define PMC_RNG_H

#include "../abi/pmc_vec.h"
#include "pmc_sobol.h"

#define PMC_SAMPLER_SOBOL 0u
#define PMC_SAMPLER_RANDOM 1u

PMC_FN_INLINE pmc_u32 pmc_hash_u32(pmc_u32 x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

/* A dimension: its number for the random sampler, and for Sobol the set it
 * belongs to and its axis in the set (0: x, 1: y). */
#define PMC_DIM(number, set, axis) ((number) | ((set) << 8) | ((axis) << 16))
#define PMC_DIM_NUMBER(dim) ((dim)&0xffu)
#define PMC_DIM_SET(dim) (((dim) >> 8) & 0xffu)
#define PMC_DIM_AXIS(dim) ((dim) >> 16)

/* The sets of one bounce; 2D sets draw (x, y) from one Sobol pair. */
#define PMC_SET_PIXEL 0u      /* 2D: jitter in the pixel (camera rays, bounce 0) */
#define PMC_SET_LIGHT_PICK 1u /* 1D: which light */
#define PMC_SET_LIGHT_UV 2u   /* 2D: the point on it */
#define PMC_SET_LOBE 3u       /* 1D: which BSDF lobe */
#define PMC_SET_BSDF_UV 4u    /* 2D: the direction in the lobe */
#define PMC_SET_RR 5u         /* 1D: Russian roulette */
#define PMC_SET_CACHE 6u      /* 2D: the cache's bilinear texel jitter */
#define PMC_SET_COUNT 7u

#define PMC_DIM_PIXEL_X PMC_DIM(0u, PMC_SET_PIXEL, 0u)
#define PMC_DIM_PIXEL_Y PMC_DIM(1u, PMC_SET_PIXEL, 1u)
#define PMC_DIM_LIGHT_PICK PMC_DIM(2u, PMC_SET_LIGHT_PICK, 0u)
#define PMC_DIM_LIGHT_U PMC_DIM(3u, PMC_SET_LIGHT_UV, 0u)
#define PMC_DIM_LIGHT_V PMC_DIM(4u, PMC_SET_LIGHT_UV, 1u)
#define PMC_DIM_LOBE PMC_DIM(5u, PMC_SET_LOBE, 0u)
#define PMC_DIM_BSDF_U PMC_DIM(6u, PMC_SET_BSDF_UV, 0u)
#define PMC_DIM_BSDF_V PMC_DIM(7u, PMC_SET_BSDF_UV, 1u)
#define PMC_DIM_RR PMC_DIM(8u, PMC_SET_RR, 0u)
#define PMC_DIM_CACHE_U PMC_DIM(9u, PMC_SET_CACHE, 0u)
#define PMC_DIM_CACHE_V PMC_DIM(10u, PMC_SET_CACHE, 1u)

/* The 1D sets (the others are 2D). */
#define PMC_SETS_1D ((1u << PMC_SET_LIGHT_PICK) | (1u << PMC_SET_LOBE) | (1u << PMC_SET_RR))

/* The random sampler's key of one path (seed, pixel and sample index). */
PMC_FN_INLINE pmc_u32 pmc_path_key(pmc_u32 seed, pmc_u32 pixel, pmc_u32 sample) {
  return pmc_hash_u32(seed ^ pmc_hash_u32(pixel ^ pmc_hash_u32(sample + 0x9e3779b9u)));
}

/* The random sampler: a uniform float in [0, 1) per (path key, bounce, dimension number). */
PMC_FN_INLINE float pmc_rand_hashed(pmc_u32 path_key, pmc_u32 bounce, pmc_u32 number) {
  pmc_u32 h = pmc_hash_u32(path_key ^ pmc_hash_u32(bounce * 32u + number));
  return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* What a path's numbers are keyed by: its sampler, its sample index and a
 * hash (random: of the seed, pixel and sample, pmc_path_key; Sobol: of the
 * seed and pixel, which every set's seeds start from). */
typedef struct PmcSampler {
  pmc_u32 kind; /* PMC_SAMPLER_* */
  pmc_u32 key;
  pmc_u32 sample;
} PmcSampler;

PMC_FN_INLINE PmcSampler pmc_sampler(pmc_u32 kind, pmc_u32 seed, pmc_u32 pixel, pmc_u32 sample) {
  PmcSampler s;
  s.kind = kind;
  s.key = kind == PMC_SAMPLER_RANDOM ? pmc_path_key(seed, pixel, sample)
                                     : pmc_hash_u32(seed ^ pmc_hash_u32(pixel + 0x6a09e667u));
  s.sample = sample;
  return s;
}

/* The Sobol seed of one (seed, pixel, bounce, set): its index shuffle; axis a
 * of the set scrambles with pmc_hash_u32(set seed + 1 + a). */
PMC_FN pmc_u32 pmc_set_seed(PmcSampler s, pmc_u32 bounce, pmc_u32 set) {
  return pmc_hash_u32(s.key ^ pmc_hash_u32(bounce * PMC_SET_COUNT + set));
}

/* Both numbers of a 2D set, dimensions `dim_x` and `dim_y` (PMC_DIM_*), of
 * bounce `bounce` (0: the camera ray's; d: the d-th surface hit's). */
PMC_FN float2 pmc_rand2(PmcSampler s, pmc_u32 bounce, pmc_u32 dim_x, pmc_u32 dim_y) {
  if (s.kind == PMC_SAMPLER_RANDOM)
    return make_float2(pmc_rand_hashed(s.key, bounce, PMC_DIM_NUMBER(dim_x)),
                       pmc_rand_hashed(s.key, bounce, PMC_DIM_NUMBER(dim_y)));
  const pmc_u32 seed = pmc_set_seed(s, bounce, PMC_DIM_SET(dim_x));
  return pmc_sobol2(s.sample, seed, pmc_hash_u32(seed + 1u), pmc_hash_u32(seed + 2u));
}

/* One number in [0, 1): dimension `dim` of bounce `bounce`. Draw both axes
 * of a 2D set with one pmc_rand2 (each call shuffles the index once). */
PMC_FN float pmc_rand(PmcSampler s, pmc_u32 bounce, pmc_u32 dim) {
  if (s.kind == PMC_SAMPLER_RANDOM) return pmc_rand_hashed(s.key, bounce, PMC_DIM_NUMBER(dim));
  const pmc_u32 set = PMC_DIM_SET(dim);
  const pmc_u32 seed = pmc_set_seed(s, bounce, set);
  if ((PMC_SETS_1D >> set) & 1u) return pmc_sobol1(s.sample, seed, pmc_hash_u32(seed + 1u));
  const float2 p = pmc_sobol2(s.sample, seed, pmc_hash_u32(seed + 1u), pmc_hash_u32(seed + 2u));
  return PMC_DIM_AXIS(dim) == 0u ? p.x : p.y;
}

/* The numbers a surface hit draws after its material: the light pick and
 * the point on the light, the lobe, the direction in it and Russian
 * roulette, all of bounce `bounce`. Each equals its own pmc_rand or
 * pmc_rand2 call (tests/core/sobol_sampler_test.cpp); drawn together, each
 * set's seeds are hashed once, and the shade kernel draws a whole batch's
 * in one loop over its lanes with one sampler kind, straight-line integer
 * code that a CPU compiler vectorises (pmc_draw_hit_numbers in
 * gpu/kernels/shade_surface.cl). */
typedef struct PmcHitNumbers {
  float light_pick, light_u, light_v, lobe, bsdf_u, bsdf_v, rr;
} PmcHitNumbers;

/* Both axes of a 2D Sobol set of bounce `bounce` (key: PmcSampler.key). */
PMC_FN_INLINE float2 pmc_sobol_set2(pmc_u32 key, pmc_u32 sample, pmc_u32 bounce, pmc_u32 set) {
  const pmc_u32 seed = pmc_hash_u32(key ^ pmc_hash_u32(bounce * PMC_SET_COUNT + set));
  return pmc_sobol2(sample, seed, pmc_hash_u32(seed + 1u), pmc_hash_u32(seed + 2u));
}

/* The number of a 1D Sobol set of bounce `bounce`. */
PMC_FN_INLINE float pmc_sobol_set1(pmc_u32 key, pmc_u32 sample, pmc_u32 bounce, pmc_u32 set) {
  const pmc_u32 seed = pmc_hash_u32(key ^ pmc_hash_u32(bounce * PMC_SET_COUNT + set));
  return pmc_sobol1(sample, seed, pmc_hash_u32(seed + 1u));
}

/* PmcHitNumbers of the Sobol sampler (key: PmcSampler.key). */
PMC_FN_INLINE PmcHitNumbers pmc_hit_numbers_sobol(pmc_u32 key, pmc_u32 sample, pmc_u32 bounce) {
  PmcHitNumbers h;
  const float2 light = pmc_sobol_set2(key, sample, bounce, PMC_SET_LIGHT_UV);
  const float2 bsdf = pmc_sobol_set2(key, sample, bounce, PMC_SET_BSDF_UV);
  h.light_pick = pmc_sobol_set1(key, sample, bounce, PMC_SET_LIGHT_PICK);
  h.light_u = light.x;
  h.light_v = light.y;
  h.lobe = pmc_sobol_set1(key, sample, bounce, PMC_SET_LOBE);
  h.bsdf_u = bsdf.x;
  h.bsdf_v = bsdf.y;
  h.rr = pmc_sobol_set1(key, sample, bounce, PMC_SET_RR);
  return h;
}

/* PmcHitNumbers of the random sampler (key: PmcSampler.key). */
PMC_FN_INLINE PmcHitNumbers pmc_hit_numbers_random(pmc_u32 key, pmc_u32 bounce) {
  PmcHitNumbers h;
  h.light_pick = pmc_rand_hashed(key, bounce, PMC_DIM_NUMBER(PMC_DIM_LIGHT_PICK));
  h.light_u = pmc_rand_hashed(key, bounce, PMC_DIM_NUMBER(PMC_DIM_LIGHT_U));
  h.light_v = pmc_rand_hashed(key, bounce, PMC_DIM_NUMBER(PMC_DIM_LIGHT_V));
  h.lobe = pmc_rand_hashed(key, bounce, PMC_DIM_NUMBER(PMC_DIM_LOBE));
  h.bsdf_u = pmc_rand_hashed(key, bounce, PMC_DIM_NUMBER(PMC_DIM_BSDF_U));
  h.bsdf_v = pmc_rand_hashed(key, bounce, PMC_DIM_NUMBER(PMC_DIM_BSDF_V));
  h.rr = pmc_rand_hashed(key, bounce, PMC_DIM_NUMBER(PMC_DIM_RR));
  return h;
}

/* The cache's bilinear texel jitter of bounce `bounce` (the pair
 * pmc_rand2(s, bounce, PMC_DIM_CACHE_U, PMC_DIM_CACHE_V) draws), for the
 * Sobol and the random sampler: the forms the shade kernel's loop over a
 * batch's lanes calls (pmc_draw_cache_jitter). */
PMC_FN_INLINE float2 pmc_cache_jitter_sobol(pmc_u32 key, pmc_u32 sample, pmc_u32 bounce) {
  return pmc_sobol_set2(key, sample, bounce, PMC_SET_CACHE);
}

PMC_FN_INLINE float2 pmc_cache_jitter_random(pmc_u32 key, pmc_u32 bounce) {
  return make_float2(pmc_rand_hashed(key, bounce, PMC_DIM_NUMBER(PMC_DIM_CACHE_U)),
                     pmc_rand_hashed(key, bounce, PMC_DIM_NUMBER(PMC_DIM_CACHE_V)));
}

PMC_FN PmcHitNumbers pmc_hit_numbers(PmcSampler s, pmc_u32 bounce) {
  return s.kind == PMC_SAMPLER_RANDOM ? pmc_hit_numbers_random(s.key, bounce)
                                      : pmc_hit_numbers_sobol(s.key, s.sample, bounce);
}

#endif /* PMC_RNG_H */
