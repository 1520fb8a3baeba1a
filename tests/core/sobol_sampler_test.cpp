// sobol_sampler_test.cpp — the Owen-scrambled Sobol sampler (core/device/pmc_sobol.h, pmc_rng.h).
//
// Independent answers: Sobol's second dimension from its generator matrix,
// whose columns come from Sobol's recurrence for the polynomial x + 1 (not from
// the superset-sum shortcut the sampler uses); the definition of a (0,k,2)-net
// (every elementary interval of area 2^-k holds exactly one of 2^k points),
// checked by counting; sample correlations against their standard error; and
// the analytic integral of a smooth function, whose error must fall faster
// with the sample count than the random sampler's N^-1/2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/device/pmc_rng.h"

namespace pmc {
namespace {

// Columns of Sobol's generator matrix for a primitive polynomial of degree s
// with inner coefficients a and initial direction numbers m (Joe and Kuo's
// recurrence); column j, digits as bits from the top (bit 31: 1/2).
std::vector<uint32_t> sobol_columns(int s, uint32_t a, const std::vector<uint32_t>& m) {
  std::vector<uint32_t> v(32);
  for (int i = 0; i < s; ++i) v[i] = m[i] << (31 - i);
  for (int i = s; i < 32; ++i) {
    uint32_t x = v[i - s] ^ (v[i - s] >> s);
    for (int k = 1; k < s; ++k)
      if ((a >> (s - 1 - k)) & 1u) x ^= v[i - k];
    v[i] = x;
  }
  return v;
}

uint32_t matrix_times(const std::vector<uint32_t>& columns, uint32_t index) {
  uint32_t x = 0;
  for (int j = 0; j < 32; ++j)
    if ((index >> j) & 1u) x ^= columns[j];
  return x;
}

TEST(SobolSampler, SecondDimensionMatchesItsGeneratorMatrix) {
  const std::vector<uint32_t> columns = sobol_columns(1, 0, {1});
  uint32_t state = 12345;
  for (int n = 0; n < 20000; ++n) {
    const uint32_t index = n < 64 ? uint32_t(n) : (state = pmc_hash_u32(state));
    ASSERT_EQ(pmc_reverse_bits(pmc_sobol_dim1_reversed(index)), matrix_times(columns, index)) << index;
  }
}

TEST(SobolSampler, OwenHashBitsDependOnlyOnLowerBits) {
  uint32_t state = 99;
  for (int n = 0; n < 2000; ++n) {
    const uint32_t x = state = pmc_hash_u32(state), seed = pmc_hash_u32(state + 7u);
    for (int b = 0; b < 32; ++b) {
      const uint32_t flipped = pmc_lk_hash(x ^ (1u << b), seed), base = pmc_lk_hash(x, seed);
      const uint32_t below = b == 0 ? 0u : (1u << b) - 1u;
      ASSERT_EQ(flipped & below, base & below) << "bit " << b;
      ASSERT_NE(flipped & (1u << b), base & (1u << b)) << "bit " << b;  // a bijection flips its own bit
    }
  }
}

// The samples [first, first + count) of one pixel's 2D set.
std::vector<float2> set_points(uint32_t kind, uint32_t seed, uint32_t pixel, uint32_t bounce, uint32_t dim_x,
                               uint32_t dim_y, uint32_t first, uint32_t count) {
  std::vector<float2> p(count);
  for (uint32_t i = 0; i < count; ++i)
    p[i] = pmc_rand2(pmc_sampler(kind, seed, pixel, first + i), bounce, dim_x, dim_y);
  return p;
}

// Every elementary interval [a/2^i, (a+1)/2^i) x [b/2^j, (b+1)/2^j) with
// i + j = k holds exactly one of the 2^k points.
::testing::AssertionResult is_0k2_net(const std::vector<float2>& p, int k) {
  for (int i = 0; i <= k; ++i) {
    const int j = k - i;
    std::vector<int> count(size_t(1) << k, 0);
    for (const float2& q : p) {
      const uint32_t a = uint32_t(q.x * float(1u << i)), b = uint32_t(q.y * float(1u << j));
      ++count[(size_t(a) << j) | b];
    }
    for (size_t c = 0; c < count.size(); ++c)
      if (count[c] != 1)
        return ::testing::AssertionFailure()
               << "intervals 2^-" << i << " x 2^-" << j << ": cell " << c << " holds " << count[c];
  }
  return ::testing::AssertionSuccess();
}

const uint32_t kSets2D[][2] = {{PMC_DIM_PIXEL_X, PMC_DIM_PIXEL_Y},
                               {PMC_DIM_LIGHT_U, PMC_DIM_LIGHT_V},
                               {PMC_DIM_BSDF_U, PMC_DIM_BSDF_V},
                               {PMC_DIM_CACHE_U, PMC_DIM_CACHE_V}};

TEST(SobolSampler, PowerOfTwoPrefixesOfEveryPixelAre0k2Nets) {
  for (uint32_t pixel : {0u, 1u, 777u, 123456u, 2073599u})
    for (uint32_t bounce : {0u, 1u, 5u})
      for (const auto& set : kSets2D)
        for (int k = 0; k <= 12; ++k) {
          const auto p = set_points(PMC_SAMPLER_SOBOL, 3u, pixel, bounce, set[0], set[1], 0, 1u << k);
          ASSERT_TRUE(is_0k2_net(p, k))
              << "pixel " << pixel << " bounce " << bounce << " dim " << set[0] << " k " << k;
        }
}

TEST(SobolSampler, AlignedBlocksAreNetsSoFarmPartsStayStratified) {
  // A farm part of samples [m 2^k, (m+1) 2^k) is itself stratified.
  for (uint32_t m : {1u, 2u, 7u, 100u})
    for (int k : {2, 6, 9}) {
      const auto p =
          set_points(PMC_SAMPLER_SOBOL, 0u, 4242u, 2u, PMC_DIM_BSDF_U, PMC_DIM_BSDF_V, m << k, 1u << k);
      ASSERT_TRUE(is_0k2_net(p, k)) << "block " << m << " of 2^" << k;
    }
}

TEST(SobolSampler, OneDimensionalSetsAreStratified) {
  for (uint32_t dim : {PMC_DIM_LIGHT_PICK, PMC_DIM_LOBE, PMC_DIM_RR})
    for (uint32_t pixel : {0u, 31u, 99999u})
      for (int k = 0; k <= 12; ++k) {
        std::vector<int> count(size_t(1) << k, 0);
        for (uint32_t i = 0; i < (1u << k); ++i) {
          const float u = pmc_rand(pmc_sampler(PMC_SAMPLER_SOBOL, 1u, pixel, i), 3u, dim);
          ++count[size_t(u * float(1u << k))];
        }
        for (int c : count) ASSERT_EQ(c, 1) << "dim " << dim << " pixel " << pixel << " k " << k;
      }
}

TEST(SobolSampler, ValuesLieInTheUnitInterval) {
  uint32_t state = 5;
  for (uint32_t kind : {PMC_SAMPLER_SOBOL, PMC_SAMPLER_RANDOM})
    for (int n = 0; n < 20000; ++n) {
      state = pmc_hash_u32(state);
      const uint32_t sample = n % 3 == 0 ? 0xffffffffu - uint32_t(n) : state;
      const PmcSampler s = pmc_sampler(kind, state >> 7, state % 100003u, sample);
      for (const auto& set : kSets2D) {
        const float2 p = pmc_rand2(s, uint32_t(n % 9), set[0], set[1]);
        ASSERT_TRUE(p.x >= 0.0f && p.x < 1.0f && p.y >= 0.0f && p.y < 1.0f) << p.x << " " << p.y;
        // the scalar form draws the same numbers
        ASSERT_EQ(pmc_rand(s, uint32_t(n % 9), set[0]), p.x);
        ASSERT_EQ(pmc_rand(s, uint32_t(n % 9), set[1]), p.y);
      }
      for (uint32_t dim : {PMC_DIM_LIGHT_PICK, PMC_DIM_LOBE, PMC_DIM_RR}) {
        const float u = pmc_rand(s, 1u, dim);
        ASSERT_TRUE(u >= 0.0f && u < 1.0f) << u;
      }
    }
}

// The shade kernel draws a hit's numbers together (pmc_hit_numbers, one
// loop over a batch's lanes), and the cache's texel jitter in another
// (pmc_cache_jitter_*); each must be the number its own pmc_rand or
// pmc_rand2 call draws, so that images do not change.
TEST(SobolSampler, HitNumbersDrawnTogetherAreTheSingleDraws) {
  uint32_t state = 11;
  for (uint32_t kind : {PMC_SAMPLER_SOBOL, PMC_SAMPLER_RANDOM})
    for (int n = 0; n < 20000; ++n) {
      state = pmc_hash_u32(state);
      const uint32_t sample = n % 3 == 0 ? 0xffffffffu - uint32_t(n) : state % 4096u;
      const PmcSampler s = pmc_sampler(kind, state >> 7, state % 100003u, sample);
      const uint32_t bounce = 1u + uint32_t(n % 9);
      const PmcHitNumbers h = pmc_hit_numbers(s, bounce);
      const float2 light = pmc_rand2(s, bounce, PMC_DIM_LIGHT_U, PMC_DIM_LIGHT_V);
      const float2 bsdf = pmc_rand2(s, bounce, PMC_DIM_BSDF_U, PMC_DIM_BSDF_V);
      ASSERT_EQ(h.light_pick, pmc_rand(s, bounce, PMC_DIM_LIGHT_PICK));
      ASSERT_EQ(h.light_u, light.x);
      ASSERT_EQ(h.light_v, light.y);
      ASSERT_EQ(h.lobe, pmc_rand(s, bounce, PMC_DIM_LOBE));
      ASSERT_EQ(h.bsdf_u, bsdf.x);
      ASSERT_EQ(h.bsdf_v, bsdf.y);
      ASSERT_EQ(h.rr, pmc_rand(s, bounce, PMC_DIM_RR));
      // the cache's texel jitter, which the kernel also draws in a loop over the lanes
      const float2 jitter = pmc_rand2(s, bounce, PMC_DIM_CACHE_U, PMC_DIM_CACHE_V);
      const float2 drawn = kind == PMC_SAMPLER_SOBOL ? pmc_cache_jitter_sobol(s.key, s.sample, bounce)
                                                     : pmc_cache_jitter_random(s.key, bounce);
      ASSERT_EQ(drawn.x, jitter.x);
      ASSERT_EQ(drawn.y, jitter.y);
    }
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
  ma /= double(a.size());
  mb /= double(b.size());
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

TEST(SobolSampler, PixelsSetsAndBouncesAreDecorrelated) {
  // Sample i of two streams, over 4096 samples: independent streams have a
  // correlation of about N^-1/2 = 0.016; the bound is 5 standard errors.
  const uint32_t n = 4096;
  const double bound = 5.0 / std::sqrt(double(n));
  auto stream = [&](uint32_t seed, uint32_t pixel, uint32_t bounce, uint32_t dim) {
    std::vector<double> v(n);
    for (uint32_t i = 0; i < n; ++i)
      v[i] = pmc_rand(pmc_sampler(PMC_SAMPLER_SOBOL, seed, pixel, i), bounce, dim);
    return v;
  };
  const uint32_t dims[] = {PMC_DIM_PIXEL_X, PMC_DIM_PIXEL_Y, PMC_DIM_LIGHT_PICK, PMC_DIM_LIGHT_U,
                           PMC_DIM_LIGHT_V, PMC_DIM_LOBE,    PMC_DIM_BSDF_U,     PMC_DIM_BSDF_V,
                           PMC_DIM_RR,      PMC_DIM_CACHE_U, PMC_DIM_CACHE_V};
  // Every pair of dimensions of one pixel, in one bounce and across bounces.
  std::vector<std::vector<double>> streams;
  std::vector<std::string> names;
  for (uint32_t bounce : {1u, 2u})
    for (uint32_t dim : dims) {
      streams.push_back(stream(11u, 1000u, bounce, dim));
      names.push_back("bounce " + std::to_string(bounce) + " dim " + std::to_string(PMC_DIM_NUMBER(dim)));
    }
  for (size_t a = 0; a < streams.size(); ++a)
    for (size_t b = a + 1; b < streams.size(); ++b)
      EXPECT_LT(std::abs(correlation(streams[a], streams[b])), bound) << names[a] << " vs " << names[b];
  // One dimension across pixels (neighbours in x and y, far ones) and seeds.
  for (uint32_t dim : dims) {
    const auto base = stream(11u, 1000u, 1u, dim);
    for (uint32_t pixel : {1001u, 1640u, 0u, 77777u})
      EXPECT_LT(std::abs(correlation(base, stream(11u, pixel, 1u, dim))), bound) << "pixel " << pixel;
    EXPECT_LT(std::abs(correlation(base, stream(12u, 1000u, 1u, dim))), bound) << "seed 12";
  }
}

// RMS error, over `pixels` pixels, of the N-sample estimate of the integral
// of f(x, y) = exp(x) sin(pi y) over the unit square: (e - 1) 2 / pi.
double rms_error(uint32_t kind, uint32_t samples, uint32_t pixels) {
  const double pi = 3.14159265358979323846, exact = (std::exp(1.0) - 1.0) * 2.0 / pi;
  double sq = 0;
  for (uint32_t pixel = 0; pixel < pixels; ++pixel) {
    double sum = 0;
    for (uint32_t i = 0; i < samples; ++i) {
      const float2 p = pmc_rand2(pmc_sampler(kind, 0u, pixel * 7919u, i), 1u, PMC_DIM_BSDF_U, PMC_DIM_BSDF_V);
      sum += std::exp(double(p.x)) * std::sin(pi * double(p.y));
    }
    const double e = sum / samples - exact;
    sq += e * e;
  }
  return std::sqrt(sq / pixels);
}

// Least-squares slope of log(error) against log(N) for N = 2^4 .. 2^11.
double error_slope(uint32_t kind) {
  std::vector<double> lx, ly;
  for (int k = 4; k <= 11; ++k) {
    lx.push_back(std::log(double(1u << k)));
    ly.push_back(std::log(rms_error(kind, 1u << k, 64)));
  }
  double mx = 0, my = 0;
  for (size_t i = 0; i < lx.size(); ++i) mx += lx[i], my += ly[i];
  mx /= double(lx.size());
  my /= double(ly.size());
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < lx.size(); ++i) {
    sxy += (lx[i] - mx) * (ly[i] - my);
    sxx += (lx[i] - mx) * (lx[i] - mx);
  }
  return sxy / sxx;
}

TEST(SobolSampler, IntegrationErrorFallsFasterThanRandom) {
  // Owen-scrambled nets converge as N^-3/2 on smooth integrands; independent
  // numbers as N^-1/2.
  const double sobol = error_slope(PMC_SAMPLER_SOBOL), random = error_slope(PMC_SAMPLER_RANDOM);
  EXPECT_LT(sobol, -1.0) << "random: " << random;
  EXPECT_GT(random, -0.7);
  EXPECT_LT(random, -0.3);
  EXPECT_LT(rms_error(PMC_SAMPLER_SOBOL, 1024, 64), 0.1 * rms_error(PMC_SAMPLER_RANDOM, 1024, 64));
}

}  // namespace
}  // namespace pmc
