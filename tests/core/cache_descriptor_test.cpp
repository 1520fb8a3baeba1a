// cache_descriptor_test.cpp — the cache descriptor (core/device/pmc_cache.h,
// core/device/pmc_raycone.h): virtual mip level, texel indices, keys.
//
// A descriptor is (material, node, lambda, texel x, texel y); lambda comes
// from the ray-cone uv gradients. Hard inputs must give a finite lambda in
// [PMC_LAMBDA_MIN, PMC_LAMBDA_MAX] and texel indices without overflow or
// undefined behaviour: a ray along the normal, grazing rays, zero-area uv
// triangles, radius 0 / NaN / Inf, NaN and huge gradients and biases, uv
// negative, >= 1, around +-1e7, NaN and Inf. (Built by hand once with
// clang++ 14 -fsanitize=undefined,float-cast-overflow,float-divide-by-zero
// -fno-sanitize-recover, and with g++ 12 -fsanitize=undefined,
// float-cast-overflow, together with cache_encoding_test.cpp: no reports.)
// Keys: uvs in the same texel share a key;
// different texels, levels, nodes and materials do not, and over ~100k
// distinct descriptors in 2^20 cells no two share cell + fingerprint.
// pmc_ray_cone_gradients is checked against the analytic footprint of a
// camera ray hitting a square whose uv is its position.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <tuple>
#include <unordered_set>
#include <vector>

#include "core/device/pmc_cache.h"
#include "core/device/pmc_raycone.h"

namespace pmc {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

void expect_level_in_range(int lambda, const char* what) {
  EXPECT_GE(lambda, PMC_LAMBDA_MIN) << what;
  EXPECT_LE(lambda, PMC_LAMBDA_MAX) << what;
}

struct Tri {
  float3 p0, p1, p2;
  float2 t0, t1, t2;
};
// Lower-left half of the unit square in z = 0, uv = (x, y) * uv_scale.
Tri unit_tri(float uv_scale = 1.0f) {
  return {make_float3(0, 0, 0), make_float3(1, 0, 0),     make_float3(0, 1, 0),
          make_float2(0, 0),    make_float2(uv_scale, 0), make_float2(0, uv_scale)};
}
// The other half, wound the other way round from a different corner.
Tri other_tri() {
  return {make_float3(1, 1, 0), make_float3(0, 1, 0), make_float3(1, 0, 0),
          make_float2(1, 1),    make_float2(0, 1),    make_float2(1, 0)};
}

void gradients(const Tri& t, float3 dir, float3 n, float radius, float2* g1, float2* g2) {
  pmc_ray_cone_gradients(dir, n, radius, t.p0, t.p1, t.p2, t.t0, t.t1, t.t2, g1, g2);
}

bool finite2(float2 g) { return std::isfinite(g.x) && std::isfinite(g.y); }

TEST(CacheDescriptor, RayConeGradientsMatchTheAnalyticFootprint) {
  // Camera at distance d straight above the square, cone spread angle a
  // (width 0 at the pinhole): width at the hit w = d * a, radius w / 2. The
  // uv is the position, so both uv gradients have length = radius and are
  // orthogonal.
  const float3 n = make_float3(0, 0, 1), down = make_float3(0, 0, -1);
  for (float d : {0.5f, 3.0f, 40.0f})
    for (float a : {1e-4f, 2e-3f, 0.05f}) {
      const float radius = 0.5f * d * a;
      for (const Tri& t : {unit_tri(), other_tri()}) {
        float2 g1, g2;
        gradients(t, down, n, radius, &g1, &g2);
        EXPECT_NEAR(length(g1), radius, 1e-5f * radius) << "d " << d << " a " << a;
        EXPECT_NEAR(length(g2), radius, 1e-5f * radius);
        EXPECT_NEAR(dot(g1, g2), 0.0f, 1e-5f * radius * radius);
        int lambda = pmc_cache_lambda(g1, g2, 0.0f);
        EXPECT_EQ(lambda, int(std::floor(-std::log2(radius)))) << "lambda = floor(-log2(min |g|))";
        EXPECT_EQ(pmc_cache_lambda(g1, g2, 2.0f), lambda + 2) << "the bias adds levels";
      }
      // uv = 3 * position: texels are 3x smaller in uv, gradients 3x longer.
      float2 g1, g2;
      gradients(unit_tri(3.0f), down, n, radius, &g1, &g2);
      EXPECT_NEAR(length(g1), 3 * radius, 3e-5f * radius);
      EXPECT_NEAR(length(g2), 3 * radius, 3e-5f * radius);
    }
  // Oblique incidence at angle theta in the xz plane: the footprint stretches
  // by 1/cos(theta) along x (the plane of incidence) and not along y.
  for (float theta : {0.3f, 1.0f, 1.4f}) {
    const float r = 0.01f;
    float3 dir = make_float3(std::sin(theta), 0.0f, -std::cos(theta));
    float2 g1, g2;
    gradients(unit_tri(), dir, n, r, &g1, &g2);
    float lo = std::fmin(length(g1), length(g2)), hi = std::fmax(length(g1), length(g2));
    EXPECT_NEAR(lo, r, 1e-5f * r) << "theta " << theta;
    EXPECT_NEAR(hi, r / std::cos(theta), 1e-4f * r / std::cos(theta)) << "theta " << theta;
    EXPECT_EQ(pmc_cache_lambda(g1, g2, 0.0f), int(std::floor(-std::log2(r))))
        << "lambda uses the shorter axis";
  }
}

TEST(CacheDescriptor, HardFootprintsGiveAFiniteClampedLevel) {
  const float3 n = make_float3(0, 0, 1);
  float2 g1, g2;
  // Ray exactly along the normal (dir = -n) and nearly so: a circle of the cone radius.
  for (float3 dir :
       {make_float3(0, 0, -1), normalize(make_float3(1e-9f, 0, -1)), normalize(make_float3(0, 1e-7f, -1))}) {
    gradients(unit_tri(), dir, n, 0.01f, &g1, &g2);
    ASSERT_TRUE(finite2(g1) && finite2(g2));
    EXPECT_NEAR(length(g1), 0.01f, 1e-6f);
    EXPECT_NEAR(length(g2), 0.01f, 1e-6f);
    EXPECT_EQ(pmc_cache_lambda(g1, g2, 0.0f), 6);  // floor(-log2(0.01)) = floor(6.64)
  }
  // Tilted normals, along the normal.
  std::mt19937 rng(5);
  std::normal_distribution<float> gauss;
  for (int i = 0; i < 1000; ++i) {
    float3 nn = normalize(make_float3(gauss(rng), gauss(rng), gauss(rng)));
    Tri t = unit_tri();
    float3 tt, bb;
    pmc_basis(nn, &tt, &bb);
    t.p1 = tt;
    t.p2 = bb;
    gradients(t, -nn, nn, 0.02f, &g1, &g2);
    ASSERT_TRUE(finite2(g1) && finite2(g2));
    EXPECT_NEAR(length(g1), 0.02f, 1e-5f);
    EXPECT_NEAR(length(g2), 0.02f, 1e-5f);
  }
  // Grazing: dir nearly in the plane. The long axis is clamped (1e4 x), the
  // short one keeps the radius; the level stays finite and in range.
  for (float eps : {1e-2f, 1e-4f, 1e-6f, 0.0f}) {
    float3 dir = normalize(make_float3(1, 0, -eps));
    gradients(unit_tri(), dir, n, 0.01f, &g1, &g2);
    ASSERT_TRUE(finite2(g1) && finite2(g2)) << eps;
    float hi = std::fmax(length(g1), length(g2));
    EXPECT_LE(hi, 0.01f * 1e4f * 1.001f) << "clamped elongation";
    int lambda = pmc_cache_lambda(g1, g2, 0.0f);
    expect_level_in_range(lambda, "grazing");
    EXPECT_EQ(lambda, 6) << "the short axis (radius 0.01) sets the level at eps " << eps;
  }
  // Zero-area uv triangle (all uvs equal): no gradient, the finest level.
  Tri flat = unit_tri();
  flat.t0 = flat.t1 = flat.t2 = make_float2(0.25f, 0.75f);
  gradients(flat, make_float3(0, 0, -1), n, 0.01f, &g1, &g2);
  EXPECT_EQ(length(g1), 0.0f);
  EXPECT_EQ(pmc_cache_lambda(g1, g2, 0.0f), PMC_LAMBDA_MAX);
  // Zero-area position triangle.
  Tri line = unit_tri();
  line.p2 = make_float3(2, 0, 0);
  gradients(line, make_float3(0, 0, -1), n, 0.01f, &g1, &g2);
  EXPECT_TRUE(finite2(g1) && finite2(g2));
  expect_level_in_range(pmc_cache_lambda(g1, g2, 0.0f), "zero-area triangle");
  // Radius 0, negative, NaN, Inf: no cone, g = 0, finest level.
  for (float r : {0.0f, -1.0f, kNaN, kInf, -kInf}) {
    gradients(unit_tri(), make_float3(0, 0, -1), n, r, &g1, &g2);
    EXPECT_EQ(length(g1), 0.0f) << r;
    EXPECT_EQ(length(g2), 0.0f) << r;
    EXPECT_EQ(pmc_cache_lambda(g1, g2, 0.0f), PMC_LAMBDA_MAX) << r;
  }
  // Gradients and biases straight into pmc_cache_lambda.
  const float vals[] = {0.0f, -0.0f, 1e-45f, 1e-30f, 1e-12f, 1e-3f, 1.0f,
                        1e6f, 1e30f, 3e38f,  kInf,   -kInf,  kNaN};
  for (float a : vals)
    for (float b : vals)
      for (float bias : {0.0f, -32.0f, 32.0f, 1e30f, -1e30f, kNaN, kInf, -kInf}) {
        int lambda = pmc_cache_lambda(make_float2(a, b), make_float2(b, 0.0f), bias);
        ASSERT_GE(lambda, PMC_LAMBDA_MIN) << a << " " << b << " bias " << bias;
        ASSERT_LE(lambda, PMC_LAMBDA_MAX) << a << " " << b << " bias " << bias;
      }
  EXPECT_EQ(pmc_cache_lambda(make_float2(1e18f, 0), make_float2(1e18f, 0), 0.0f), PMC_LAMBDA_MIN);
  // |g| overflowing float (1e30^2) is treated like a missing footprint: the
  // finest level, the safe choice (no texel sharing, so no accuracy loss).
  EXPECT_EQ(pmc_cache_lambda(make_float2(1e30f, 0), make_float2(1e30f, 0), 0.0f), PMC_LAMBDA_MAX);
  EXPECT_EQ(pmc_cache_lambda(make_float2(1e-30f, 0), make_float2(1e-30f, 0), 0.0f), PMC_LAMBDA_MAX);
  EXPECT_EQ(pmc_cache_lambda(make_float2(0.25f, 0), make_float2(0, 0.5f), 0.0f), 2) << "min of the two";
  EXPECT_EQ(pmc_cache_lambda(make_float2(0.25f, 0), make_float2(0, 0), 0.0f), 2)
      << "one zero axis: the other";
  EXPECT_EQ(pmc_cache_lambda(make_float2(kNaN, 0), make_float2(0, 0.5f), 0.0f), 1)
      << "one NaN axis: the other";
}

// The integral-bias path reads the level off m's exponent bits: it must equal
// floor(-log2(m) + bias) computed in long double, at powers of two and the
// floats next to them, for every bias; a fractional bias agrees too (library
// log2 there: away from level boundaries).
TEST(CacheDescriptor, LevelFromExponentBitsIsExactFloorOfMinusLog2) {
  auto expected = [](float m, float bias) {
    long double x = std::floor(-std::log2((long double)m) + (long double)bias);
    return int(std::min<long double>(PMC_LAMBDA_MAX, std::max<long double>(PMC_LAMBDA_MIN, x)));
  };
  for (int e = -60; e <= 60; ++e) {
    const float p = std::ldexp(1.0f, e);
    for (float m : {p, std::nextafter(p, 0.0f), std::nextafter(p, 1e30f), p * 1.5f})
      for (float bias : {0.0f, 1.0f, -1.0f, 2.0f, -16.0f, 24.0f, 64.0f, -64.0f}) {
        ASSERT_EQ(pmc_cache_lambda(make_float2(m, 0), make_float2(0, m), bias), expected(m, bias))
            << "m = " << m << " bias " << bias;
      }
  }
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> expo(-30.0f, 30.0f);
  for (int i = 0; i < 20000; ++i) {
    const float m = std::exp2(expo(rng));
    ASSERT_EQ(pmc_cache_lambda(make_float2(m, 0), make_float2(0, 2.0f * m), 0.0f), expected(m, 0.0f)) << m;
    const float frac = 0.5f;
    const long double x = -std::log2((long double)m) + frac;
    if (std::fabs(x - std::round(x)) > 1e-4L)  // not at a boundary: float log2 rounds the same way
      ASSERT_EQ(pmc_cache_lambda(make_float2(m, 0), make_float2(0, m), frac), expected(m, frac)) << m;
  }
}

// floor(u * 2^lambda) computed exactly in long double.
long double exact_texel(float u, int lambda) { return std::floor((long double)u * std::ldexp(1.0L, lambda)); }

TEST(CacheDescriptor, TexelIndicesOnHardUvs) {
  const long kLim = 4611686018427387904L;  // 2^62
  std::vector<float> uvs = {0.0f,    -0.0f,  0.3f,    -0.3f,        1.0f, 1.5f,  -1.0f,  0.999999f, 1e-40f,
                            -1e-40f, 1e7f,   -1e7f,   1.0000001e7f, 2e7f, -2e7f, 4.2e6f, 123456.7f, -98765.4f,
                            1e30f,   -1e30f, 3.4e38f, -3.4e38f,     kInf, -kInf, kNaN};
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uni(-3.0f, 3.0f);
  for (int i = 0; i < 2000; ++i) uvs.push_back(uni(rng));
  for (int i = 0; i < 2000; ++i) uvs.push_back(std::ldexp(uni(rng), int(rng() % 60) - 20));
  for (float u : uvs)
    for (int lambda = PMC_LAMBDA_MIN; lambda <= PMC_LAMBDA_MAX; ++lambda) {
      long t = pmc_cache_texel(u, lambda);
      if (std::isnan(u)) {
        EXPECT_EQ(t, 0) << "NaN uv maps to texel 0";
        continue;
      }
      long double x = exact_texel(u, lambda);
      if (std::fabs(x) < (long double)kLim) {
        // In range: exact, unless u * 2^lambda underflowed below the float range.
        if (std::fabs((long double)u * std::ldexp(1.0L, lambda)) >= std::ldexp(1.0L, -126) || u == 0.0f)
          ASSERT_EQ((long double)t, x) << "u " << u << " lambda " << lambda;
      } else {
        ASSERT_GE(std::llabs(t), kLim) << "beyond 2^62 the index saturates: u " << u << " lambda " << lambda;
        ASSERT_EQ(t > 0, u > 0) << "and keeps its sign";
      }
      // The texel centre is within the texel (where float can say so).
      if (std::fabs(x) < 1e6L) {
        float c = pmc_cache_texel_center(t, lambda);
        EXPECT_EQ(pmc_cache_texel(c, lambda), t) << "u " << u << " lambda " << lambda;
      }
    }
  // Negative uvs floor downwards, uv >= 1 continues past 2^lambda (no wrapping).
  EXPECT_EQ(pmc_cache_texel(-0.3f, 3), -3);
  EXPECT_EQ(pmc_cache_texel(-1e-6f, 10), -1);
  EXPECT_EQ(pmc_cache_texel(1.0f, 3), 8);
  EXPECT_EQ(pmc_cache_texel(1.99f, 0), 1);
  EXPECT_EQ(pmc_cache_texel(1e7f, 0), 10000000);
  EXPECT_EQ(pmc_cache_texel(-1e7f, 10), -10240000000L);
  EXPECT_EQ(pmc_cache_texel(0.75f, -1), 0) << "a level below 0 has texels wider than the [0,1) square";
  EXPECT_EQ(pmc_cache_texel(-0.75f, -1), -1);
}

TEST(CacheDescriptor, DistinctFloatUvsBeyondTheIndexRangeStayDistinct) {
  // At the finest level (degenerate footprints use it) uvs beyond ~4.2e6 are
  // outside +-2^62 texels; two different uvs there are different texels and
  // must not share a key (as long as u * 2^lambda is a finite float: beyond
  // ~3e26 at level 40 it is +-Inf, one texel per sign).
  const int l = PMC_LAMBDA_MAX;
  std::set<long> seen;
  for (float u : {1e7f, 1.0000001e7f, 2e7f, 1e20f, 1e26f, kInf})
    EXPECT_TRUE(seen.insert(pmc_cache_texel(u, l)).second) << u;
  for (float u : {-1e7f, -1.0000001e7f, -2e7f, -1e20f, -1e26f, -kInf})
    EXPECT_TRUE(seen.insert(pmc_cache_texel(u, l)).second) << u;
  EXPECT_EQ(pmc_cache_texel(3.4e38f, l), pmc_cache_texel(kInf, l));
  // --cache-eval center evaluates such a texel at its own uv, not near 2^62 * 2^-lambda.
  for (float u : {1e7f, -1e7f, 2e7f, -3e9f, 1e20f}) {
    long t = pmc_cache_texel(u, l);
    EXPECT_EQ(pmc_cache_texel_center(t, l), u) << u;
    EXPECT_EQ(pmc_cache_texel(pmc_cache_texel_center(t, l), l), t) << u;
  }
  // The texel of the infinite uvs is centred on the largest float: still finite.
  for (int lambda : {PMC_LAMBDA_MIN, 0, PMC_LAMBDA_MAX}) {
    EXPECT_EQ(pmc_cache_texel_center(pmc_cache_texel(kInf, lambda), lambda),
              std::numeric_limits<float>::max());
    EXPECT_EQ(pmc_cache_texel_center(pmc_cache_texel(-kInf, lambda), lambda),
              -std::numeric_limits<float>::max());
  }
  // Ordered like the uvs (a monotonic map), so it cannot meet an in-range index.
  EXPECT_LT(pmc_cache_texel(1e7f, l), pmc_cache_texel(2e7f, l));
  EXPECT_GT(pmc_cache_texel(-1e7f, l), pmc_cache_texel(-2e7f, l));
  EXPECT_GT(pmc_cache_texel(1e7f, l), pmc_cache_texel(4.1e6f, l));
}

TEST(CacheDescriptor, SameTexelSharesAKeyAndNeighboursDoNot) {
  auto key = [](uint32_t m, uint32_t node, float u, float v, float2 g) {
    int lambda = pmc_cache_lambda(g, g, 0.0f);
    return pmc_cache_key(m, node, node & 3u, lambda, pmc_cache_texel(u, lambda), pmc_cache_texel(v, lambda));
  };
  auto same = [](PmcCacheKey a, PmcCacheKey b) { return a.h1 == b.h1 && a.fingerprint == b.fingerprint; };
  const float2 g = make_float2(1.0f / 1000.0f, 0.0f);  // level 9: texels of 1/512
  const float t = 1.0f / 512.0f;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> cell(-5000, 5000);
  std::uniform_real_distribution<float> in(0.05f, 0.95f);
  for (int i = 0; i < 5000; ++i) {
    float u0 = float(cell(rng)) * t, v0 = float(cell(rng)) * t;
    float u = u0 + in(rng)*t, v = v0 + in(rng)*t, u2 = u0 + in(rng)*t, v2 = v0 + in(rng)*t;
    PmcCacheKey k = key(1, 7, u, v, g);
    ASSERT_TRUE(same(k, key(1, 7, u2, v2, g))) << "same texel " << u << "," << v << " vs " << u2 << "," << v2;
    ASSERT_FALSE(same(k, key(1, 7, u + t, v, g))) << "next texel in u";
    ASSERT_FALSE(same(k, key(1, 7, u, v - t, g))) << "previous texel in v";
    ASSERT_FALSE(same(k, key(1, 8, u, v, g))) << "other node";
    ASSERT_FALSE(same(k, key(2, 7, u, v, g))) << "other material";
    ASSERT_FALSE(same(k, key(1, 7, u, v, g * 0.5f))) << "finer level";
    if (pmc_cache_texel(u, 9) != pmc_cache_texel(v, 9))
      ASSERT_FALSE(same(k, key(1, 7, v, u, g))) << "transposed texel";
  }
}

struct Desc {
  uint32_t m, node;
  int lambda;
  long tx, ty;
  bool operator<(const Desc& o) const {
    return std::tie(m, node, lambda, tx, ty) < std::tie(o.m, o.node, o.lambda, o.tx, o.ty);
  }
};

// Number of pairs of descriptors sharing (cell, fingerprint) and sharing the fingerprint alone.
std::pair<size_t, size_t> collisions(const std::vector<Desc>& ds, uint64_t cells) {
  std::vector<std::pair<uint64_t, uint32_t>> cf;
  std::vector<uint32_t> fps;
  for (const Desc& d : ds) {
    PmcCacheKey k = pmc_cache_key(d.m, d.node, d.node & 7u, d.lambda, d.tx, d.ty);
    cf.push_back({k.h1 % cells, k.fingerprint});
    fps.push_back(k.fingerprint);
  }
  std::sort(cf.begin(), cf.end());
  std::sort(fps.begin(), fps.end());
  size_t a = 0, b = 0;
  for (size_t i = 1; i < cf.size(); ++i) a += cf[i] == cf[i - 1];
  for (size_t i = 1; i < fps.size(); ++i) b += fps[i] == fps[i - 1];
  return {a, b};
}

TEST(CacheDescriptor, NoCellAndFingerprintCollisionsAmongDistinctDescriptors) {
  // 100k descriptors, 2^20 cells: a (cell, fingerprint) collision has
  // probability ~ n^2 / 2 / 2^52 = 1e-6, so any is a hashing bug. Fingerprint
  // alone is 32 bits: ~ n^2 / 2 / 2^32 = 1.2 expected pairs (Poisson; > 12
  // has probability < 1e-9).
  const uint64_t cells = uint64_t(1) << 20;
  // Structured: a dense block of neighbouring texels, levels, nodes, materials.
  std::vector<Desc> grid;
  for (uint32_t m = 0; m < 4; ++m)
    for (uint32_t node = 0; node < 5; ++node)
      for (int lambda = 8; lambda < 13; ++lambda)
        for (long tx = -16; tx < 16; ++tx)
          for (long ty = 0; ty < 32; ++ty) grid.push_back({m, node, lambda, tx, ty});
  auto [gc, gf] = collisions(grid, cells);
  EXPECT_EQ(gc, 0u) << grid.size() << " structured descriptors";
  EXPECT_LE(gf, 12u);
  // Random, de-duplicated.
  std::mt19937_64 rng(99);
  std::set<Desc> seen;
  std::vector<Desc> rnd;
  while (rnd.size() < 100000) {
    Desc d{uint32_t(rng() % 64), uint32_t(rng() % 16384), int(rng() % 57) - 16,
           long(rng() % 2000001) - 1000000, long(rng() % 2000001) - 1000000};
    if (seen.insert(d).second) rnd.push_back(d);
  }
  auto [rc, rf] = collisions(rnd, cells);
  EXPECT_EQ(rc, 0u);
  EXPECT_LE(rf, 12u);
  std::printf("descriptor collisions: structured %zu (cell+fp) %zu (fp); random %zu (cell+fp) %zu (fp)\n", gc,
              gf, rc, rf);
  // Cells fill evenly: 100k keys in 1024 cells, ~97.7 each (sd ~9.9).
  std::vector<int> load(1024, 0);
  for (const Desc& d : grid) ++load[pmc_cache_key(d.m, d.node, d.node, d.lambda, d.tx, d.ty).h1 % 1024];
  int lo = *std::min_element(load.begin(), load.end()), hi = *std::max_element(load.begin(), load.end());
  EXPECT_GT(lo, 40);
  EXPECT_LT(hi, 160);
}

}  // namespace
}  // namespace pmc

namespace pmc {
namespace {

// --cache-filter bilinear: texel = floor(u * 2^lambda + offset), offset
// uniform in [-0.5, 0.5). Between the two texels whose centres bracket u the
// farther one must be picked with its bilinear weight, i.e. the mean of the
// picked texels' centre values equals linear interpolation between them.
TEST(CacheDescriptor, JitteredTexelsPickNeighboursWithTheirBilinearWeights) {
  const int lambda = 5;
  const float w = std::ldexp(1.0f, -lambda);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> offset(-0.5f, 0.5f);
  for (float u : {0.0f, 0.3f * w, 0.5f * w, 0.9f * w, 7.25f * w, -2.6f * w, 0.51f}) {
    // Centres bracketing u: texel i0 at (i0 + 0.5) w <= u < (i0 + 1.5) w.
    const double x = double(u) / w - 0.5;
    const long i0 = long(std::floor(x));
    const double f = x - double(i0);
    const int n = 200000;
    int far = 0;
    for (int k = 0; k < n; ++k) {
      long t = pmc_cache_texel_jittered(u, lambda, offset(rng));
      ASSERT_TRUE(t == i0 || t == i0 + 1)
          << "u " << u << " picked texel " << t << ", not " << i0 << " or " << i0 + 1;
      far += t == i0 + 1 ? 1 : 0;
    }
    // Binomial standard deviation <= 0.5 / sqrt(n) ~ 0.0011: allow 5 of them.
    EXPECT_NEAR(double(far) / n, f, 0.0056) << "u " << u;
  }
  EXPECT_EQ(pmc_cache_texel_jittered(0.3f * w, lambda, 0.0f), pmc_cache_texel(0.3f * w, lambda))
      << "offset 0 is the nearest texel";
  EXPECT_EQ(pmc_cache_texel_jittered(kNaN, lambda, 0.25f), 0L);
  EXPECT_EQ(pmc_cache_texel_jittered(kInf, lambda, -0.5f), pmc_cache_texel(kInf, lambda));
  EXPECT_EQ(pmc_cache_texel_jittered(1e7f, 30, 0.49f), pmc_cache_texel(1e7f, 30))
      << "beyond the index range the offset changes nothing";
}

// A center-mode miss filters textures with the footprint of the unbiased
// level, so a mip bias refines the texel grid without sharpening textures.
TEST(CacheDescriptor, TexelFootprintIgnoresTheMipBiasAndStaysFinite) {
  for (int lambda : {PMC_LAMBDA_MIN, -3, 0, 4, 17, PMC_LAMBDA_MAX}) {
    EXPECT_FLOAT_EQ(pmc_cache_texel_footprint(lambda, 0.0f), 2.0f * std::ldexp(1.0f, -lambda));
    EXPECT_FLOAT_EQ(pmc_cache_texel_footprint(lambda + 2, 2.0f), pmc_cache_texel_footprint(lambda, 0.0f));
    for (float bias : {kNaN, kInf, -kInf, 1e30f, -1e30f}) {
      float f = pmc_cache_texel_footprint(lambda, bias);
      EXPECT_TRUE(std::isfinite(f) && f >= 0.0f) << "lambda " << lambda << " bias " << bias << ": " << f;
    }
  }
}

}  // namespace
}  // namespace pmc
