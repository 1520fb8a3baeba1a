// cache_encoding_test.cpp — the 32-bit value encodings of the material cache
// (core/device/pmc_cache.h, host C++ compile of the header the kernels use).
//
// A cache hit returns decode(encode(v)) instead of v, so the encodings bound
// the error a hit can add. Checked on random values (a fresh seed each run,
// printed, so a failure can be replayed with PMC_TEST_SEED=<seed>) and on
// extremes (0, -0, denormals, 1e-30, 1e30, 65408, 65409, negatives, NaN, Inf):
//  * float: raw bits, bit-identical for every finite value; NaN and Inf are
//    refused (a cached NaN would poison every later hit of the texel);
//  * RGB9E5: every channel within the bound derived below; negative, NaN,
//    Inf and > 65408 refused;
//  * half2: bit-exact against a brute-force nearest-even reference over all
//    finite halves, so relative error <= 2^-11 in the normal range and the
//    subnormal range rounds on the 2^-24 grid (absolute error <= 2^-25);
//  * decode(encode(x)) is a fixed point: encoding a decoded value again
//    gives the same bits back (a value re-stored from a hit does not drift).
//
// RGB9E5 bound (derivation). Let M be the largest channel. The encoder picks
// e = floor(log2 M), shared exponent E = e + 1, step s = 2^(E-9) = 2^(e-8),
// so M/s lies in [256, 512) and each channel rounds to the nearest step:
// error <= s/2 = 2^(e-9) <= 2^-9 M. But when M/s rounds up to 512 (M >=
// 511.5 s) the exponent is bumped and the step doubles: the error of the
// other channels is then up to s = 2^(e-8) while M can be as small as
// 511.5 * 2^(e-8): error <= M/511.5 = 2^-9 M * 1024/1023, i.e. slightly MORE
// than 2^-9 M (example: r = 511.75/256, g = 2^-8 -> g decodes to 2^-7). At
// the bottom, the exponent cannot go below E = -15 (step 2^-24): for
// M < 2^-16 the error is bounded absolutely by 2^-25, and M < 2^-25 encodes
// as black. So the real bound is  |err| <= max(M / 511.5, 2^-25)  per
// channel, and the largest channel alone is within 2^-9 M for M >= 2^-16.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/device/pmc_cache.h"

namespace pmc {
namespace {

uint32_t bits_of(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

// A fresh seed per run (printed), or PMC_TEST_SEED to replay one.
uint64_t test_seed() {
  static uint64_t seed = [] {
    const char* env = std::getenv("PMC_TEST_SEED");
    uint64_t s = env ? std::strtoull(env, nullptr, 10)
                     : (uint64_t(std::random_device{}()) << 32) ^ std::random_device{}();
    std::printf("cache_encoding_test: seed %llu (replay with PMC_TEST_SEED=%llu)\n", (unsigned long long)s,
                (unsigned long long)s);
    return s;
  }();
  return seed;
}

const float kInf = std::numeric_limits<float>::infinity();
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kDenormMin = std::numeric_limits<float>::denorm_min();  // 1.4e-45
const float kExtremes[] = {0.0f,    -0.0f, kDenormMin, 1e-40f,   -1e-40f,  1.1754942e-38f, 1e-30f,
                           -1e-30f, 1e30f, -1e30f,     65408.0f, 65409.0f, 65504.0f,       65505.0f,
                           1.0f,    -1.0f, 0.5f,       kNaN,     -kNaN,    kInf,           -kInf};

// Random magnitudes spread over many binades (a uniform draw would almost
// never hit the small exponents).
float random_magnitude(std::mt19937_64& rng, int lo_exp, int hi_exp) {
  std::uniform_real_distribution<float> mant(1.0f, 2.0f);
  std::uniform_int_distribution<int> ex(lo_exp, hi_exp);
  return std::ldexp(mant(rng), ex(rng));
}

// ---- float -------------------------------------------------------------------

TEST(CacheEncoding, FloatIsBitExactAndRefusesNaNAndInf) {
  std::mt19937_64 rng(test_seed());
  std::vector<float> values(std::begin(kExtremes), std::end(kExtremes));
  std::uniform_int_distribution<uint32_t> any;
  for (int i = 0; i < 200000; ++i) {
    uint32_t u = any(rng);
    float f;
    std::memcpy(&f, &u, 4);
    values.push_back(f);  // every bit pattern: denormals, NaN payloads, Inf included
  }
  for (float f : values) {
    pmc_u32 out = 0x12345678u;
    int ok = pmc_cache_encode(make_float4(f, 9.0f, 9.0f, 9.0f), PMC_ENC_FLOAT, &out);
    if (!std::isfinite(f)) {
      EXPECT_EQ(ok, 0) << f;
      EXPECT_EQ(out, 0x12345678u) << "a refused value leaves the output untouched";
      continue;
    }
    ASSERT_EQ(ok, 1) << f;
    float4 d = pmc_cache_decode(out, PMC_ENC_FLOAT);
    ASSERT_EQ(bits_of(d.x), bits_of(f)) << f;
    EXPECT_EQ(bits_of(d.y), bits_of(f)) << "a float decodes broadcast";
    // Idempotent.
    pmc_u32 again = 0;
    ASSERT_EQ(pmc_cache_encode(d, PMC_ENC_FLOAT, &again), 1);
    EXPECT_EQ(again, out);
  }
}

// ---- RGB9E5 ------------------------------------------------------------------

// The bound derived in the file comment.
double rgb9e5_bound(double max_channel) { return std::max(max_channel / 511.5, std::ldexp(1.0, -25)); }

void check_rgb9e5(float r, float g, float b, double* worst_ratio) {
  pmc_u32 e = 0xdeadbeefu;
  int ok = pmc_cache_encode(make_float4(r, g, b, 0.0f), PMC_ENC_RGB9E5, &e);
  bool encodable = r >= 0 && g >= 0 && b >= 0 && std::max(r, std::max(g, b)) <= 65408.0f;  // false for NaN
  ASSERT_EQ(ok, encodable ? 1 : 0) << r << " " << g << " " << b;
  if (!ok) {
    EXPECT_EQ(e, 0xdeadbeefu);
    return;
  }
  float4 d = pmc_cache_decode(e, PMC_ENC_RGB9E5);
  const double m = std::max<double>(r, std::max<double>(g, b));
  const double bound = rgb9e5_bound(m);
  const float in[3] = {r, g, b}, out[3] = {d.x, d.y, d.z};
  for (int c = 0; c < 3; ++c) {
    double err = std::fabs(double(out[c]) - double(in[c]));
    ASSERT_LE(err, bound * (1 + 1e-12)) << "channel " << c << " of (" << r << ", " << g << ", " << b
                                        << ") decodes to " << out[c] << " (bits " << std::hex << e << ")";
    ASSERT_GE(out[c], 0.0f);
    if (m >= std::ldexp(1.0, -16)) *worst_ratio = std::max(*worst_ratio, err / m);
  }
  if (m >= std::ldexp(1.0, -16)) {
    int k = r == float(m) ? 0 : g == float(m) ? 1 : 2;
    double err_max = std::fabs(double(out[k]) - m);
    EXPECT_LE(err_max, std::ldexp(m, -9)) << "the largest channel is within 2^-9 relative";
  }
  // Idempotent: the decoded value encodes to itself.
  pmc_u32 again = 0;
  ASSERT_EQ(pmc_cache_encode(d, PMC_ENC_RGB9E5, &again), 1);
  float4 d2 = pmc_cache_decode(again, PMC_ENC_RGB9E5);
  EXPECT_EQ(bits_of(d2.x), bits_of(d.x));
  EXPECT_EQ(bits_of(d2.y), bits_of(d.y));
  EXPECT_EQ(bits_of(d2.z), bits_of(d.z));
}

TEST(CacheEncoding, Rgb9e5RandomValuesStayWithinTheDerivedBound) {
  std::mt19937_64 rng(test_seed() + 1);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  double worst = 0.0;
  for (int i = 0; i < 300000; ++i) {
    float m = random_magnitude(rng, -30, 15);
    // Channels relative to the largest: equal, spread out, or tiny.
    float c[3];
    for (float& x : c) {
      int kind = int(rng() % 4);
      x = kind == 0 ? m : kind == 1 ? m * unit(rng) : kind == 2 ? m * std::ldexp(unit(rng), -12) : 0.0f;
    }
    c[rng() % 3] = m;
    check_rgb9e5(c[0], c[1], c[2], &worst);
    if (HasFatalFailure()) return;
  }
  // Also the [0,1] colours materials mostly produce.
  for (int i = 0; i < 100000; ++i) {
    check_rgb9e5(unit(rng), unit(rng), unit(rng), &worst);
    if (HasFatalFailure()) return;
  }
  std::printf("rgb9e5: worst error / largest channel = %.6g (2^-9 = %.6g, 1/511.5 = %.6g)\n", worst,
              std::ldexp(1.0, -9), 1.0 / 511.5);
  EXPECT_LE(worst, 1.0 / 511.5 + 1e-12);
}

TEST(CacheEncoding, Rgb9e5BoundIsSlightlyAbove2ToTheMinus9WhenTheExponentBumps) {
  // The header's old claim (error <= 2^-9 * max) fails here; the real bound holds.
  const float r = 511.75f / 256.0f, g = 1.0f / 256.0f;
  pmc_u32 e = 0;
  ASSERT_EQ(pmc_cache_encode(make_float4(r, g, 0.0f, 0.0f), PMC_ENC_RGB9E5, &e), 1);
  float4 d = pmc_cache_decode(e, PMC_ENC_RGB9E5);
  EXPECT_EQ(d.x, 2.0f);
  EXPECT_EQ(d.y, 1.0f / 128.0f);
  double err = std::fabs(double(d.y) - g);
  EXPECT_GT(err, std::ldexp(double(r), -9));
  EXPECT_LE(err, rgb9e5_bound(r));
}

TEST(CacheEncoding, Rgb9e5ExtremeValues) {
  double worst = 0.0;
  for (float a : kExtremes)
    for (float b : {0.0f, 0.25f, 1.0f, 65408.0f, -1.0f, kNaN, kInf})
      for (float c : {0.0f, 1e-30f, kDenormMin}) {
        check_rgb9e5(a, b, c, &worst);
        check_rgb9e5(c, a, b, &worst);
        check_rgb9e5(b, c, a, &worst);
        if (HasFatalFailure()) return;
      }
  auto enc = [](float r, float g, float b, pmc_u32* out) {
    return pmc_cache_encode(make_float4(r, g, b, 0.0f), PMC_ENC_RGB9E5, out);
  };
  pmc_u32 e = 0;
  ASSERT_EQ(enc(0, 0, 0, &e), 1);
  EXPECT_EQ(e, 0u) << "black is the all-zero word (the fingerprint keeps the entry non-empty)";
  ASSERT_EQ(enc(65408.0f, 0, 1, &e), 1);
  EXPECT_EQ(pmc_cache_decode(e, PMC_ENC_RGB9E5).x, 65408.0f) << "the largest value is exact";
  // The brightest grey encodes as all ones (mantissas 511, top exponent):
  // the same word as the encoder's "invalid" marker, yet a valid value.
  ASSERT_EQ(enc(65408.0f, 65408.0f, 65365.3f, &e), 1);
  EXPECT_EQ(e, 0xffffffffu);
  EXPECT_EQ(pmc_cache_decode(e, PMC_ENC_RGB9E5).z, 65408.0f);
  EXPECT_EQ(enc(65409.0f, 0, 0, &e), 0);
  EXPECT_EQ(enc(1e30f, 0, 0, &e), 0);
  EXPECT_EQ(enc(0.5f, -1e-30f, 0, &e), 0) << "any negative channel";
  EXPECT_EQ(enc(0.5f, 0.5f, kNaN, &e), 0);
  EXPECT_EQ(enc(kInf, 0.5f, 0.5f, &e), 0);
  ASSERT_EQ(enc(1e-30f, kDenormMin, 0, &e), 1);
  EXPECT_EQ(e, 0u) << "below half the smallest step: black";
  // Smallest step 2^-24: exactly representable, and its neighbours round to it.
  ASSERT_EQ(enc(std::ldexp(1.0f, -24), 0, 0, &e), 1);
  EXPECT_EQ(pmc_cache_decode(e, PMC_ENC_RGB9E5).x, std::ldexp(1.0f, -24));
}

// ---- half2 -------------------------------------------------------------------

// All finite non-negative halves, by bit pattern (monotonic in value),
// decoded exactly from the IEEE definition (independently of the header).
const std::vector<double>& half_values() {
  static std::vector<double> v = [] {
    std::vector<double> out;
    for (uint32_t h = 0; h <= 0x7bffu; ++h) {
      uint32_t e = h >> 10, m = h & 1023u;
      out.push_back(e == 0 ? std::ldexp(double(m), -24) : std::ldexp(double(1024 + m), int(e) - 25));
    }
    return out;
  }();
  return v;
}

// Nearest half, ties to even; magnitudes above 65504 clamp to 65504.
uint32_t reference_half(float f) {
  const std::vector<double>& v = half_values();
  double a = std::fabs(double(f));
  uint32_t sign = std::signbit(f) ? 0x8000u : 0u;
  if (a >= 65504.0) return sign | 0x7bffu;
  size_t hi = size_t(std::lower_bound(v.begin(), v.end(), a) - v.begin());
  if (v[hi] == a || hi == 0) return sign | uint32_t(hi);
  size_t lo = hi - 1;
  double dl = a - v[lo], dh = v[hi] - a;
  size_t pick = dl < dh ? lo : dh < dl ? hi : ((lo & 1u) ? hi : lo);
  return sign | uint32_t(pick);
}

TEST(CacheEncoding, HalfMatchesNearestEvenReferenceAndDecodesExactly) {
  // Decoding: every finite half, both signs.
  const std::vector<double>& v = half_values();
  for (uint32_t h = 0; h <= 0x7bffu; ++h) {
    ASSERT_EQ(double(pmc_half_to_float(h)), v[h]) << std::hex << h;
    ASSERT_EQ(double(pmc_half_to_float(h | 0x8000u)), -v[h]) << std::hex << h;
  }
  EXPECT_TRUE(std::signbit(pmc_half_to_float(0x8000u))) << "-0 keeps its sign";
  std::mt19937_64 rng(test_seed() + 2);
  std::vector<float> values;
  for (int i = 0; i < 300000; ++i) {
    float m = random_magnitude(rng, -30, 16);
    values.push_back(rng() & 1 ? -m : m);
  }
  // Exact ties and their neighbours in the subnormal and normal ranges.
  for (uint32_t h : {0u, 1u, 2u, 3u, 0x3ffu, 0x400u, 0x401u, 0x3c00u, 0x3c01u, 0x7bfeu}) {
    double mid = (v[h] + v[h + 1]) / 2;
    for (double x : {mid, std::nextafter(mid, 0.0), std::nextafter(mid, 1e9)}) values.push_back(float(x));
  }
  for (float f : kExtremes)
    if (std::isfinite(f)) values.push_back(f);
  for (float f : values) {
    ASSERT_EQ(pmc_float_to_half(f), reference_half(f)) << f;
  }
}

TEST(CacheEncoding, Half2ErrorBoundsSubnormalsAndRefusals) {
  std::mt19937_64 rng(test_seed() + 3);
  const double min_normal = std::ldexp(1.0, -14), sub_step = std::ldexp(1.0, -24);
  for (int i = 0; i < 300000; ++i) {
    float x = random_magnitude(rng, -30, 15), y = -random_magnitude(rng, -30, 15);
    if (std::fabs(x) > 65504.0f || std::fabs(y) > 65504.0f) continue;
    pmc_u32 e = 0;
    ASSERT_EQ(pmc_cache_encode(make_float4(x, y, 7.0f, 7.0f), PMC_ENC_HALF2, &e), 1) << x << " " << y;
    float4 d = pmc_cache_decode(e, PMC_ENC_HALF2);
    EXPECT_EQ(d.z, 0.0f);
    const float in[2] = {x, y}, out[2] = {d.x, d.y};
    for (int c = 0; c < 2; ++c) {
      double a = std::fabs(double(in[c])), err = std::fabs(double(out[c]) - double(in[c]));
      if (a >= min_normal)
        ASSERT_LE(err, std::ldexp(a, -11)) << in[c] << " -> " << out[c];
      else
        ASSERT_LE(err, sub_step / 2) << "subnormal " << in[c] << " -> " << out[c];
      ASSERT_TRUE(out[c] == 0.0f || std::signbit(out[c]) == std::signbit(in[c]));
    }
    pmc_u32 again = 0;
    ASSERT_EQ(pmc_cache_encode(d, PMC_ENC_HALF2, &again), 1);
    ASSERT_EQ(again, e) << "idempotent";
  }
  auto enc = [](float x, float y, pmc_u32* out) {
    return pmc_cache_encode(make_float4(x, y, 0.0f, 0.0f), PMC_ENC_HALF2, out);
  };
  pmc_u32 e = 0;
  EXPECT_EQ(enc(kNaN, 0, &e), 0);
  EXPECT_EQ(enc(0, kInf, &e), 0);
  EXPECT_EQ(enc(-kInf, 0, &e), 0);
  EXPECT_EQ(enc(65505.0f, 0, &e), 0);
  EXPECT_EQ(enc(0, -1e30f, &e), 0);
  ASSERT_EQ(enc(65504.0f, -65504.0f, &e), 1);
  EXPECT_EQ(pmc_cache_decode(e, PMC_ENC_HALF2).x, 65504.0f);
  EXPECT_EQ(pmc_cache_decode(e, PMC_ENC_HALF2).y, -65504.0f);
  ASSERT_EQ(enc(65408.0f, 1e-30f, &e), 1);
  EXPECT_EQ(pmc_cache_decode(e, PMC_ENC_HALF2).x, 65408.0f);
  EXPECT_EQ(pmc_cache_decode(e, PMC_ENC_HALF2).y, 0.0f) << "far below the smallest subnormal: zero";
  // Subnormals: the smallest one exactly, half of it (a tie) to even (zero),
  // a little more than half of it up to the smallest.
  const float tiny = std::ldexp(1.0f, -24);
  ASSERT_EQ(enc(tiny, tiny / 2, &e), 1);
  EXPECT_EQ(e & 0xffffu, 1u);
  EXPECT_EQ(e >> 16, 0u);
  ASSERT_EQ(enc(std::nextafter(tiny / 2, 1.0f), -3 * tiny, &e), 1);
  EXPECT_EQ(e & 0xffffu, 1u);
  EXPECT_EQ(pmc_cache_decode(e, PMC_ENC_HALF2).y, -3 * tiny);
  ASSERT_EQ(enc(-0.0f, kDenormMin, &e), 1);
  EXPECT_EQ(e, 0x8000u) << "-0 keeps its sign, a float denormal becomes +0";
}

}  // namespace
}  // namespace pmc
