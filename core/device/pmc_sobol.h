/* pmc_sobol.h — shuffled, Owen-scrambled Sobol points (Burley 2020,
 * "Practical Hash-based Owen Scrambling"), shared by host and kernels.
 *
 * Everything happens in 32-bit integers, in the "reversed" bit order in which
 * bit i of a word is the (i+1)-th binary digit of a fraction (bit 0 the most
 * significant, worth 1/2). In that order:
 *   - Owen scrambling (flipping each digit by a random function of the digits
 *     before it) is a hash whose output bit b depends only on input bits
 *     <= b: Laine and Karras' construction, with the constants of Vegdahl's
 *     "Building a Better LK Hash" (2021), pmc_lk_hash;
 *   - Sobol's first dimension (van der Corput) of index i is i itself;
 *   - Sobol's second dimension is the upper Pascal matrix mod 2 times i: digit
 *     d is the parity of the index bits j with d a bit-subset of j (Lucas), a
 *     superset-sum transform done in five shift-and-mask steps
 *     (pmc_sobol_dim1_reversed) instead of a loop over the generator matrix's
 *     32 columns (tests/core/sobol_sampler_test.cpp checks it against the
 *     columns from Sobol's recurrence).
 * The sample index is shuffled by a nested uniform scramble of its bits
 * (pmc_nested_uniform_scramble): the first 2^k shuffled indices are one
 * aligned block of 2^k Sobol indices, in a hashed order, so every power-of-two
 * prefix of a pixel's samples is still a (0,k,2)-net, and pixels (each with
 * its own shuffle) draw different blocks.
 */
#ifndef PMC_SOBOL_H
#define PMC_SOBOL_H

#include "../abi/pmc_vec.h"

/* Bit i <-> bit 31 - i. */
PMC_FN_INLINE pmc_u32 pmc_reverse_bits(pmc_u32 x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

/* A seeded bijection of 32-bit words whose output bit b depends only on input
 * bits 0..b: applied to reversed digits, an Owen scramble. */
PMC_FN_INLINE pmc_u32 pmc_lk_hash(pmc_u32 x, pmc_u32 seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

/* Owen scramble of a 32-bit integer's bits from the top down (bit b flipped
 * by a function of the bits above it): used on sample indices, it keeps each
 * aligned block of 2^k indices together and shuffles the blocks' order and
 * the order within them. */
PMC_FN_INLINE pmc_u32 pmc_nested_uniform_scramble(pmc_u32 x, pmc_u32 seed) {
  return pmc_reverse_bits(pmc_lk_hash(pmc_reverse_bits(x), seed));
}

/* Sobol's second dimension of `index`, digits reversed (bit 0 the first). */
PMC_FN_INLINE pmc_u32 pmc_sobol_dim1_reversed(pmc_u32 index) {
  pmc_u32 x = index;
  x ^= (x >> 1) & 0x55555555u;
  x ^= (x >> 2) & 0x33333333u;
  x ^= (x >> 4) & 0x0f0f0f0fu;
  x ^= (x >> 8) & 0x00ff00ffu;
  x ^= (x >> 16) & 0x0000ffffu;
  return x;
}

/* The top 24 bits of a fraction's digits as a float in [0, 1). */
PMC_FN_INLINE float pmc_unit_float(pmc_u32 fraction) { return (float)(fraction >> 8) * (1.0f / 16777216.0f); }

/* Point `index` of the 2D Owen-scrambled Sobol (0,2)-sequence with shuffle
 * seed `shuffle` and per-axis scramble seeds `seed_x`, `seed_y`. */
PMC_FN_INLINE float2 pmc_sobol2(pmc_u32 index, pmc_u32 shuffle, pmc_u32 seed_x, pmc_u32 seed_y) {
  const pmc_u32 i = pmc_nested_uniform_scramble(index, shuffle);
  const pmc_u32 x = pmc_reverse_bits(pmc_lk_hash(i, seed_x));
  const pmc_u32 y = pmc_reverse_bits(pmc_lk_hash(pmc_sobol_dim1_reversed(i), seed_y));
  return make_float2(pmc_unit_float(x), pmc_unit_float(y));
}

/* Point `index` of the 1D Owen-scrambled van der Corput sequence with shuffle
 * seed `shuffle` and scramble seed `seed`: every aligned block of 2^k indices
 * falls one in each interval [j/2^k, (j+1)/2^k). The shuffle matters: without
 * it, every 1D sequence's first digit would be the index's lowest bit
 * flipped by a constant, the same for all sequences up to sign. */
PMC_FN_INLINE float pmc_sobol1(pmc_u32 index, pmc_u32 shuffle, pmc_u32 seed) {
  return pmc_unit_float(pmc_reverse_bits(pmc_lk_hash(pmc_nested_uniform_scramble(index, shuffle), seed)));
}

#endif /* PMC_SOBOL_H */
