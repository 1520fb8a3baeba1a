// film_sum_test.cpp — exact film sums (core/device/pmc_film.h, core/film_sum.h).
//
// The independent answer is long double arithmetic: a float's value times
// 2^64 is an integer held exactly by a long double (64-bit mantissa) for
// |v| >= 2^-41, so pmc_fixed_of_float must give exactly that integer; and a
// film is exact, so splitting samples into parts in any order must give the
// same words, whose mean is the long double mean of the samples.
#include "core/film_sum.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/device/pmc_film.h"

namespace pmc {
namespace {

__int128 words_value(const uint32_t w[4]) {
  unsigned __int128 u = 0;
  for (int k = 3; k >= 0; --k) u = (u << 32) | w[k];
  return __int128(u);
}

TEST(FilmFixed, ConvertsFloatsToTheirExactQ64Value) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> mant(1.0f, 2.0f);
  std::uniform_int_distribution<int> expo(-41, 61);
  for (int i = 0; i < 20000; ++i) {
    float v = std::ldexp(mant(rng), expo(rng));
    if (i % 2) v = -v;
    uint32_t w[4];
    ASSERT_TRUE(pmc_fixed_of_float(v, w)) << v;
    const long double exact = std::ldexp((long double)v, 64);  // an integer
    ASSERT_EQ(words_value(w), (__int128)exact) << v;
  }
  uint32_t w[4];
  ASSERT_TRUE(pmc_fixed_of_float(0.0f, w));
  EXPECT_EQ(words_value(w), 0);
  ASSERT_TRUE(pmc_fixed_of_float(-0.0f, w));
  EXPECT_EQ(words_value(w), 0);
  ASSERT_TRUE(pmc_fixed_of_float(1.0f, w));
  EXPECT_EQ(words_value(w), (__int128)1 << 64);
  // Below 2^-64 nothing is left (truncation towards zero, both signs).
  ASSERT_TRUE(pmc_fixed_of_float(std::ldexp(1.0f, -70), w));
  EXPECT_EQ(words_value(w), 0);
  ASSERT_TRUE(pmc_fixed_of_float(-std::ldexp(1.5f, -64), w));
  EXPECT_EQ(words_value(w), -1);  // -1.5 units truncated to -1
}

TEST(FilmFixed, RefusesNonFiniteAndHugeValues) {
  uint32_t w[4];
  EXPECT_FALSE(pmc_fixed_of_float(std::numeric_limits<float>::infinity(), w));
  EXPECT_FALSE(pmc_fixed_of_float(-std::numeric_limits<float>::infinity(), w));
  EXPECT_FALSE(pmc_fixed_of_float(std::numeric_limits<float>::quiet_NaN(), w));
  EXPECT_FALSE(pmc_fixed_of_float(std::ldexp(1.0f, 62), w));
  EXPECT_FALSE(pmc_fixed_of_float(-std::ldexp(1.0f, 62), w));
  EXPECT_TRUE(pmc_fixed_of_float(std::nextafter(std::ldexp(1.0f, 62), 0.0f), w));
}

// Random samples of wildly different sizes, as one film and as parts added
// in two different orders.
// The film kernel's two-word form (pmc_fixed2_of_float, pmc_fixed2_add) is
// the four-word form's integer, for every exponent (subnormals, the smallest
// kept magnitudes, the largest), both signs and zeros, and sums alike with
// the carries between the words.
TEST(FilmFixed, TwoWordFormIsTheFourWordIntegerAndAddsAlike) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<uint32_t> any_bits;
  std::vector<float> values = {0.0f,
                               -0.0f,
                               1.0f,
                               -1.0f,
                               std::ldexp(1.0f, -64),
                               std::ldexp(1.0f, -65),
                               std::numeric_limits<float>::denorm_min(),
                               -std::numeric_limits<float>::min(),
                               std::nextafter(std::ldexp(1.0f, 62), 0.0f),
                               std::ldexp(-1.0f, 61)};
  for (int i = 0; i < 200000; ++i) {
    uint32_t bits = any_bits(rng);
    float v;
    std::memcpy(&v, &bits, sizeof v);
    values.push_back(v);
  }
  uint32_t acc4[4] = {0, 0, 0, 0};
  uint64_t lo = 0, hi = 0;
  size_t converted = 0;
  for (float v : values) {
    uint32_t w[4] = {0, 0, 0, 0};
    uint64_t l = 0, h = 0;
    const int ok4 = pmc_fixed_of_float(v, w), ok2 = pmc_fixed2_of_float(v, &l, &h);
    ASSERT_EQ(ok2, ok4) << v;
    if (!ok4) continue;
    ++converted;
    ASSERT_EQ(l, uint64_t(w[0]) | uint64_t(w[1]) << 32) << v;
    ASSERT_EQ(h, uint64_t(w[2]) | uint64_t(w[3]) << 32) << v;
    pmc_fixed_add(acc4, w);
    pmc_fixed2_add(&lo, &hi, l, h);
    ASSERT_EQ(lo, uint64_t(acc4[0]) | uint64_t(acc4[1]) << 32) << v;
    ASSERT_EQ(hi, uint64_t(acc4[2]) | uint64_t(acc4[3]) << 32) << v;
  }
  EXPECT_GT(converted, values.size() / 3);  // random bits: about half are below 2^62 and finite
}

TEST(FilmSum, PartsAddToTheSameWordsInAnyOrderAndResolveToTheExactMean) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> mant(0.0f, 1.0f);
  std::uniform_int_distribution<int> expo(-30, 20);
  const int w = 3, h = 2, spp = 40;
  std::vector<std::vector<float>> samples(size_t(w * h) * 3);
  for (auto& s : samples)
    for (int k = 0; k < spp; ++k) s.push_back(std::ldexp(mant(rng), expo(rng)));

  // Film of samples [a, b) of every pixel.
  auto film_of = [&](int a, int b) -> FilmSums {
    FilmSums f = FilmSums::zero(w, h);
    for (size_t p = 0; p < f.pixels(); ++p) {
      f.samples[p] = uint32_t(b - a);
      for (int c = 0; c < 3; ++c)
        for (int k = a; k < b; ++k) {
          uint32_t v[4];
          EXPECT_TRUE(pmc_fixed_of_float(samples[3 * p + size_t(c)][size_t(k)], v));
          pmc_fixed_add(&f.sum[p * FilmSums::kWords + size_t(4 * c)], v);
        }
    }
    return f;
  };
  const FilmSums whole = film_of(0, spp);
  const int cuts[] = {0, 1, 7, 8, 23, 40};
  FilmSums forward = FilmSums::zero(w, h), backward = FilmSums::zero(w, h);
  for (int i = 0; i < 5; ++i) add_film(forward, film_of(cuts[i], cuts[i + 1]), 0, 0);
  for (int i = 4; i >= 0; --i) add_film(backward, film_of(cuts[i], cuts[i + 1]), 0, 0);
  EXPECT_EQ(forward.sum, whole.sum);
  EXPECT_EQ(backward.sum, whole.sum);
  EXPECT_EQ(forward.samples, whole.samples);

  const Image mean = film_mean(forward);
  for (size_t p = 0; p < whole.pixels(); ++p)
    for (int c = 0; c < 3; ++c) {
      long double exact = 0;
      for (float v : samples[3 * p + size_t(c)]) exact += (long double)v;  // exact: 64-bit mantissa suffices
      EXPECT_EQ(mean.pixels[3 * p + size_t(c)], float(exact / spp)) << p << " " << c;
    }
}

TEST(FilmSum, AddsAWindowAtItsPlaceAndCountsBadSamples) {
  FilmSums frame = FilmSums::zero(4, 3);
  FilmSums tile = FilmSums::zero(2, 1);
  uint32_t v[4];
  ASSERT_TRUE(pmc_fixed_of_float(2.0f, v));
  for (int c = 0; c < 3; ++c) pmc_fixed_add(&tile.sum[FilmSums::kWords + size_t(4 * c)], v);
  tile.samples = {2, 2};
  tile.bad = {0, 1};
  tile.hits = {3, 4};
  add_film(frame, tile, 2, 1);  // pixels (2,1) and (3,1)
  const Image mean = film_mean(frame);
  const Image hits = film_hitmap(frame);
  const size_t p = 1 * 4 + 3;
  EXPECT_EQ(mean.pixels[3 * p], 2.0f);  // one good sample of 2
  EXPECT_EQ(mean.pixels[3 * (p - 1)], 0.0f);
  EXPECT_EQ(hits.pixels[p], 2.0f);  // 4 hits over 2 samples
  EXPECT_EQ(frame.samples[0], 0u);
  EXPECT_EQ(mean.pixels[0], 0.0f);  // no samples: black
}

}  // namespace
}  // namespace pmc
