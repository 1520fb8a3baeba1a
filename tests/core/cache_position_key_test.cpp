// cache_position_key_test.cpp — position-keyed cache descriptors
// (core/device/pmc_cache.h: pmc_cache_cell_of, pmc_cache_cell3_hash).
//
// A position cell is (level from the cone radius in scene units, floor(p *
// 2^level) per axis). Hard inputs: huge and negative coordinates, NaN/Inf
// positions, radii 0 / subnormal / huge / Inf / NaN must give a finite level
// in [PMC_LAMBDA_MIN, PMC_LAMBDA_MAX] and indices without overflow; points in
// one cell share a key, neighbouring cells (along each axis, at each level,
// of other nodes and materials) and the uv texel with the same indices do
// not; ~100k distinct cells hash without (cell, fingerprint) collisions; the
// jittered cell is picked with its trilinear weight along each axis; the
// kernel's offsets lie in the surface's tangent plane (pmc_cache_plane_jitter).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "core/device/pmc_cache.h"

namespace pmc {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();
const float4 kNoJitter = make_float4(0, 0, 0, 0);

PmcCacheKey position_key(uint32_t material, uint32_t node, float3 p, float radius) {
  PmcCacheTexel c = pmc_cache_cell_of(p, radius, 0.0f, kNoJitter, material);
  return pmc_cache_key_at(c.hash, c.base, material, node, 0u);
}

bool same(PmcCacheKey a, PmcCacheKey b) { return a.h1 == b.h1 && a.fingerprint == b.fingerprint; }

TEST(CachePositionKey, LevelComesFromTheConeRadiusInSceneUnits) {
  // floor(-log2(r)): radius 1/1000 -> level 9 (cells of 1/512), 1 -> 0, 3 -> -2.
  EXPECT_EQ(pmc_cache_cell_of(make_float3(0, 0, 0), 1.0f / 1000.0f, 0.0f, kNoJitter, 0).lambda, 9);
  EXPECT_EQ(pmc_cache_cell_of(make_float3(0, 0, 0), 1.0f, 0.0f, kNoJitter, 0).lambda, 0);
  EXPECT_EQ(pmc_cache_cell_of(make_float3(0, 0, 0), 3.0f, 0.0f, kNoJitter, 0).lambda, -2);
  EXPECT_EQ(pmc_cache_cell_of(make_float3(0, 0, 0), 1.0f, 2.0f, kNoJitter, 0).lambda, 2) << "bias adds";
  // A cell is at least the radius wide and narrower than the footprint's
  // diameter, as a uv texel is against min(|g1|, |g2|).
  for (float r : {1e-4f, 0.01f, 0.3f, 1.0f, 7.0f, 1000.0f}) {
    int l = pmc_cache_cell_of(make_float3(0, 0, 0), r, 0.0f, kNoJitter, 0).lambda;
    float width = std::ldexp(1.0f, -l);
    EXPECT_GE(width, r) << r;
    EXPECT_LT(width, 2.0f * r) << r;
  }
}

TEST(CachePositionKey, HardInputsGiveFiniteClampedLevelsAndNoOverflow) {
  const float radii[] = {0.0f, -1.0f, 1e-45f, 1e-38f, 1e-20f, 1e-3f, 1.0f, 1e20f, 3.4e38f, kInf, kNaN};
  const float coords[] = {0.0f,  -0.0f,  1e-30f,  -1e-30f,  0.5f, -0.5f, 1e7f, -1e7f,
                          1e19f, -1e19f, 3.4e38f, -3.4e38f, kInf, -kInf, kNaN};
  for (float r : radii)
    for (float x : coords) {
      PmcCacheTexel c =
          pmc_cache_cell_of(make_float3(x, -x, 0.25f), r, 0.0f, make_float4(0.49f, -0.5f, 0, 0), 3);
      EXPECT_GE(c.lambda, PMC_LAMBDA_MIN) << "r " << r << " x " << x;
      EXPECT_LE(c.lambda, PMC_LAMBDA_MAX) << "r " << r << " x " << x;
      const long lim = (long(1) << 62) + (long(1) << 32);
      EXPECT_LE(std::labs(c.tx), lim) << "r " << r << " x " << x;
      EXPECT_LE(std::labs(c.ty), lim) << "r " << r << " x " << x;
      EXPECT_EQ(c.ready, 1u);
      // The centre of the cell is finite, so center-mode evaluation reads a real position.
      EXPECT_TRUE(std::isfinite(pmc_cache_cell_center(c.tx, c.lambda))) << "r " << r << " x " << x;
    }
  // Degenerate radii use the finest level (distinct points never share a coarse cell by accident).
  for (float r : {0.0f, -1.0f, kInf, kNaN})
    EXPECT_EQ(pmc_cache_cell_of(make_float3(1, 2, 3), r, 0.0f, kNoJitter, 0).lambda, PMC_LAMBDA_MAX) << r;
  // Huge coordinates that differ stay in different cells, at any level.
  for (int l : {PMC_LAMBDA_MIN, 0, PMC_LAMBDA_MAX}) {
    const float r = std::ldexp(1.0f, -l);
    EXPECT_FALSE(same(position_key(0, 1, make_float3(1e19f, 0, 0), r),
                      position_key(0, 1, make_float3(std::nextafter(1e19f, 0.0f), 0, 0), r)))
        << "level " << l;
    EXPECT_FALSE(same(position_key(0, 1, make_float3(-3e38f, 0, 0), r),
                      position_key(0, 1, make_float3(3e38f, 0, 0), r)))
        << "level " << l;
  }
}

TEST(CachePositionKey, SameCellSharesAKeyAndNeighboursDoNot) {
  const float r = 1.0f / 1000.0f;  // level 9: cells of 1/512
  const float w = 1.0f / 512.0f;
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> cell(-5000, 5000);
  std::uniform_real_distribution<float> in(0.05f, 0.95f);
  for (int i = 0; i < 5000; ++i) {
    // Cell k spans [(k - 1/2) w, (k + 1/2) w): it is centred on k w.
    const float x0 = (float(cell(rng)) - 0.5f) * w, y0 = (float(cell(rng)) - 0.5f) * w,
                z0 = (float(cell(rng)) - 0.5f) * w;
    const float3 p = make_float3(x0 + in(rng)*w, y0 + in(rng)*w, z0 + in(rng)*w);
    const float3 q = make_float3(x0 + in(rng)*w, y0 + in(rng)*w, z0 + in(rng)*w);
    PmcCacheKey k = position_key(1, 7, p, r);
    ASSERT_TRUE(same(k, position_key(1, 7, q, r))) << "same cell";
    ASSERT_FALSE(same(k, position_key(1, 7, make_float3(p.x + w, p.y, p.z), r))) << "next cell in x";
    ASSERT_FALSE(same(k, position_key(1, 7, make_float3(p.x, p.y - w, p.z), r))) << "previous cell in y";
    ASSERT_FALSE(same(k, position_key(1, 7, make_float3(p.x, p.y, p.z + w), r))) << "next cell in z";
    ASSERT_FALSE(same(k, position_key(1, 7, make_float3(-p.x, p.y, p.z), r)) && std::fabs(p.x) >= w)
        << "mirrored cell";
    ASSERT_FALSE(same(k, position_key(1, 8, p, r))) << "other node";
    ASSERT_FALSE(same(k, position_key(2, 7, p, r))) << "other material";
    ASSERT_FALSE(same(k, position_key(1, 7, p, r * 0.5f))) << "finer level";
    // The uv texel with the cell's x and y indices is a different key.
    PmcCacheTexel c = pmc_cache_cell_of(p, r, 0.0f, kNoJitter, 1);
    PmcCacheKey uv = pmc_cache_key(1, 7, 0u, c.lambda, c.tx, c.ty);
    ASSERT_FALSE(same(k, uv)) << "uv texel with equal indices";
  }
}

// Cells are centred on multiples of their width, so a plane at a coordinate
// that is a multiple of the width (the floor at y = 0, a wall at x = 2)
// lies in the middle of one layer of cells: the rounding of barycentric
// interpolation (a wall at x = 2 is hit at 2 - 1 ulp or 2 + 1 ulp) does not
// split it across two layers, and a cell's centre, where --cache-eval
// center evaluates, lies on the plane. (With cells starting at multiples of
// the width, both failed: a wall at x = 2 had half its hits in each layer.)
TEST(CachePositionKey, GridAlignedPlanesKeepOneLayerOfCells) {
  for (int level = 0; level <= 12; ++level) {
    const float r = std::ldexp(1.0f, -level);  // cells of 2^-level
    for (float plane : {0.0f, 2.0f, -2.0f, 0.5f, 3.0f, -0.25f, 10.0f}) {
      if (std::ldexp(plane, level) != std::floor(std::ldexp(plane, level))) continue;  // not on the grid
      const PmcCacheTexel on = pmc_cache_cell_of(make_float3(plane, 0.3f, 0.7f), r, 0.0f, kNoJitter, 0);
      ASSERT_EQ(on.lambda, level);
      EXPECT_EQ(pmc_cache_cell_center(on.tx, on.lambda), plane) << "level " << level << " plane " << plane;
      float below = plane, above = plane;
      for (int ulp = 0; ulp < 4; ++ulp) {
        below = std::nextafter(below, -kInf);
        above = std::nextafter(above, kInf);
        EXPECT_EQ(pmc_cache_cell_of(make_float3(below, 0.3f, 0.7f), r, 0.0f, kNoJitter, 0).tx, on.tx)
            << "level " << level << " plane " << plane << " - " << ulp + 1 << " ulp";
        EXPECT_EQ(pmc_cache_cell_of(make_float3(above, 0.3f, 0.7f), r, 0.0f, kNoJitter, 0).tx, on.tx)
            << "level " << level << " plane " << plane << " + " << ulp + 1 << " ulp";
      }
    }
  }
}

TEST(CachePositionKey, NoCellAndFingerprintCollisionsAmongDistinctCells) {
  // Dense blocks of cells (including the same indices at every level and
  // every permutation of axes), and random cells: a (cell, fingerprint)
  // collision in 2^20 cells has probability ~1e-6 (see the uv test).
  const uint64_t cells = uint64_t(1) << 20;
  std::vector<std::pair<uint64_t, uint32_t>> cf;
  std::set<std::tuple<int, long, long, long>> seen;
  auto add = [&](int l, long x, long y, long z) {
    if (!seen.insert({l, x, y, z}).second) return;
    pmc_u64 h = pmc_cache_cell3_hash(l, x, y, z);
    PmcCacheKey k = pmc_cache_key_at(h, pmc_cache_group_base(h, 2u), 2u, 5u, 0u);
    cf.push_back({k.h1 % cells, k.fingerprint});
  };
  for (int l = 6; l < 10; ++l)
    for (long x = -12; x < 12; ++x)
      for (long y = -12; y < 12; ++y)
        for (long z = -12; z < 12; ++z) add(l, x, y, z);
  std::mt19937_64 rng(17);
  while (cf.size() < 150000)
    add(int(rng() % 57) - 16, long(rng() % 2000001) - 1000000, long(rng() % 2000001) - 1000000,
        long(rng() % 2000001) - 1000000);
  std::sort(cf.begin(), cf.end());
  size_t collisions = 0;
  for (size_t i = 1; i < cf.size(); ++i) collisions += cf[i] == cf[i - 1];
  EXPECT_EQ(collisions, 0u) << cf.size() << " cells";
}

// --cache-filter bilinear with position keys: offsets uniform in [-0.5, 0.5)
// on each axis pick the neighbour cell with its linear weight per axis, so
// the mean of the picked cells' centres is the position itself (trilinear).
TEST(CachePositionKey, JitteredCellsAverageToThePosition) {
  const float r = 0.1f;  // level 3: cells of 1/8
  const float3 p = make_float3(0.3f, -1.17f, 2.02f);
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> offset(-0.5f, 0.5f);
  double sx = 0, sy = 0, sz = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    PmcCacheTexel c = pmc_cache_cell_of(p, r, 0.0f, make_float4(offset(rng), offset(rng), offset(rng), 0), 0);
    sx += pmc_cache_cell_center(c.tx, c.lambda);
    sy += pmc_cache_cell_center(c.ty, c.lambda);
    sz += pmc_cache_cell_center(c.tz, c.lambda);
  }
  // Each centre is within one cell (1/8) of p: the mean's sd < 0.125 / sqrt(n) = 2.8e-4.
  EXPECT_NEAR(sx / n, p.x, 1.5e-3);
  EXPECT_NEAR(sy / n, p.y, 1.5e-3);
  EXPECT_NEAR(sz / n, p.z, 1.5e-3);
}

TEST(CachePositionKey, PlaneJitterLiesInTheTangentPlaneWithTheOffsetsLength) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), j(-0.5f, 0.5f);
  std::vector<float3> normals = {make_float3(0, 0, 1),       make_float3(0, 0, -1),
                                 make_float3(1, 0, 0),       make_float3(0, -1, 0),
                                 make_float3(0, 0, -1e-30f), make_float3(3e20f, -2e20f, 1e20f)};
  for (int i = 0; i < 1000; ++i) normals.push_back(make_float3(u(rng), u(rng), u(rng)));
  // Unit normals (the kernel's) take the short path, which skips the rescaling:
  // the same offsets as the long path takes for the same direction at twice the length.
  for (int i = 0; i < 1000; ++i) {
    const float3 v = make_float3(u(rng), u(rng), u(rng));
    const float l = std::sqrt(dot(v, v));
    if (!(l > 1e-3f)) continue;
    const float3 n = v * (1.0f / l);
    normals.push_back(n);
    const float ju = j(rng), jv = j(rng);
    const float4 unit = pmc_cache_plane_jitter(n, ju, jv), twice = pmc_cache_plane_jitter(n * 2.0f, ju, jv);
    EXPECT_NEAR(unit.x, twice.x, 1e-5f);
    EXPECT_NEAR(unit.y, twice.y, 1e-5f);
    EXPECT_NEAR(unit.z, twice.z, 1e-5f);
  }
  for (float3 n : normals) {
    const float ju = j(rng), jv = j(rng);
    const float4 o = pmc_cache_plane_jitter(n, ju, jv);
    const float3 d = make_float3(o.x, o.y, o.z);
    ASSERT_TRUE(std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z));
    const double len = std::sqrt(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z);
    const float3 nn = make_float3(float(n.x / len), float(n.y / len), float(n.z / len));
    EXPECT_NEAR(dot(d, nn), 0.0f, 1e-5f) << "normal " << n.x << "," << n.y << "," << n.z;
    EXPECT_NEAR(dot(d, d), ju * ju + jv * jv, 1e-5f) << "the basis is orthonormal";
  }
  // An axis-aligned wall: cells change only along the wall's own axes.
  const float4 wall = pmc_cache_plane_jitter(make_float3(0, 0, 2), 0.3f, -0.4f);
  EXPECT_EQ(wall.z, 0.0f);
  EXPECT_NEAR(std::fabs(wall.x) + std::fabs(wall.y), 0.7f, 1e-6f);
  // Degenerate and non-finite normals: no offset, never NaN.
  for (float3 n : {make_float3(0, 0, 0), make_float3(kNaN, 0, 1), make_float3(kInf, 0, 0)}) {
    const float4 o = pmc_cache_plane_jitter(n, 0.25f, 0.25f);
    EXPECT_EQ(o.x, 0.0f);
    EXPECT_EQ(o.y, 0.0f);
    EXPECT_EQ(o.z, 0.0f);
  }
}

}  // namespace
}  // namespace pmc
