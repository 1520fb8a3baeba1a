/* pmc_film.h — exact film sums: each float sample added as a 128-bit fixed-point number.
 *
 * The film kernel adds every path sample's radiance to its pixel. A float sum
 * depends on the order of the additions, so a frame rendered in parts (sample
 * ranges on several machines, `pmc merge`) would differ in the last bits from
 * the one-process render. Here a finite float v is converted exactly to the
 * integer N = v * 2^64 (Q63.64, two's complement, four little-endian 32-bit
 * words; bits below 2^-64 are truncated towards zero, i.e. only magnitudes
 * below 2^-41 lose anything) and the film adds integers: exact, so
 * associative, and the sum of any split of the samples is the same integer.
 * A sample with |v| >= 2^62 in any channel is counted as a bad sample (like
 * NaN/Inf), so no 128-bit sum can overflow for fewer than 2^64 samples.
 * The host (core/film_sum.h) turns the integer sum into the pixel's mean.
 * Written here rather than taken from a library: it must compile as OpenCL C
 * and C++ alike and do exactly these integer operations on both.
 */
#ifndef PMC_FILM_H
#define PMC_FILM_H

#include "../abi/pmc_vec.h"

#define PMC_FIXED_WORDS 4u

/* The exact Q63.64 value of `v` as two 64-bit words (lo: the low 64 bits,
 * hi: the high ones, two's complement); 0 (lo and hi untouched) when v is
 * not finite or |v| >= 2^62. Shifts, no store at a run-time index: the film
 * kernel keeps a pixel's three sums in registers across the wave's samples
 * (pmc_film_accumulate). */
PMC_FN int pmc_fixed2_of_float(float v, pmc_u64* lo, pmc_u64* hi) {
  const pmc_u32 bits = (pmc_u32)as_int(v);
  const pmc_u32 e = (bits >> 23) & 0xffu;
  if (e >= 189u) return 0; /* |v| >= 2^62, Inf or NaN */
  /* v = m * 2^(e - 150), N = m * 2^shift with shift = e - 86 <= 102 (subnormals: e = 1) */
  const pmc_u64 m = e == 0u ? (pmc_u64)(bits & 0x7fffffu) : (pmc_u64)((bits & 0x7fffffu) | 0x800000u);
  const int shift = e == 0u ? 1 - 86 : (int)e - 86;
  pmc_u64 l, h;
  if (shift < 0) {
    l = shift <= -24 ? 0ul : m >> (pmc_u32)(-shift);
    h = 0ul;
  } else if (shift < 64) {
    l = m << (pmc_u32)shift;
    h = shift == 0 ? 0ul : m >> (pmc_u32)(64 - shift);
  } else {
    l = 0ul;
    h = m << (pmc_u32)(shift - 64);
  }
  if (bits >> 31) { /* negate: invert and add one */
    l = ~l + 1ul;
    h = ~h + (l == 0ul ? 1ul : 0ul);
  }
  *lo = l;
  *hi = h;
  return 1;
}

/* (acc_lo, acc_hi) += (lo, hi), two's complement, the top carry dropped. */
PMC_FN void pmc_fixed2_add(pmc_u64* acc_lo, pmc_u64* acc_hi, pmc_u64 lo, pmc_u64 hi) {
  const pmc_u64 s = *acc_lo + lo;
  *acc_hi = *acc_hi + hi + (s < lo ? 1ul : 0ul);
  *acc_lo = s;
}

/* The same number as four little-endian 32-bit words w[0..3] (the film's
 * and the pass film's layout); 0 (w untouched) as pmc_fixed2_of_float. */
PMC_FN int pmc_fixed_of_float(float v, pmc_u32* w) {
  pmc_u64 lo, hi;
  if (!pmc_fixed2_of_float(v, &lo, &hi)) return 0;
  w[0] = (pmc_u32)lo;
  w[1] = (pmc_u32)(lo >> 32);
  w[2] = (pmc_u32)hi;
  w[3] = (pmc_u32)(hi >> 32);
  return 1;
}

/* acc += x, both four-word two's complement numbers (the carry out of the
 * top word is dropped, as two's complement addition does). */
PMC_FN void pmc_fixed_add(pmc_u32* acc, const pmc_u32* x) {
  pmc_u64 lo = (pmc_u64)acc[0] | ((pmc_u64)acc[1] << 32), hi = (pmc_u64)acc[2] | ((pmc_u64)acc[3] << 32);
  pmc_fixed2_add(&lo, &hi, (pmc_u64)x[0] | ((pmc_u64)x[1] << 32), (pmc_u64)x[2] | ((pmc_u64)x[3] << 32));
  acc[0] = (pmc_u32)lo;
  acc[1] = (pmc_u32)(lo >> 32);
  acc[2] = (pmc_u32)hi;
  acc[3] = (pmc_u32)(hi >> 32);
}

#endif /* PMC_FILM_H */
