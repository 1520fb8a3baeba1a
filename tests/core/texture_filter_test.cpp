// texture_filter_test.cpp — anisotropic texture filtering
// (pmc_texture_sample_ellipse, core/device/pmc_texture.h) and the footprint's
// ellipse from the ray cone's gradients (pmc_ray_cone_ellipse).
//
// * A long thin ellipse over stripes gives the stripes' average over the
//   ellipse, computed here by brute force from the finest texels (nearest,
//   the image's own pixels), within 0.06: stripes along the major axis keep
//   their value (the old isotropic lookup at the major axis' level averages
//   them to grey), stripes across it average out (so the taps do follow the
//   major axis, not the minor one). Both axes, and a diagonal ellipse over
//   diagonal stripes.
// * A round ellipse (or none) is the isotropic lookup bit for bit.
// * PMC_FOOTPRINT_ONE_LEVEL reads the footprint's nearest level alone.
// * The ellipse of two gradients: orthogonal ones give their own lengths,
//   sheared ones the eigen-axes of g1 g1^T + g2 g2^T (checked by sampling
//   the ellipse's boundary), degenerate ones zeros.
// * A pixel's sample i scales the ellipse's major axis by 1/sqrt(i + 1)
//   (pmc_shading_footprint), never below the minor width, which stays; one
//   the scale makes round is the isotropic lookup at that width, bit for bit;
//   at the first sample, or without an ellipse, the footprint is the
//   gradients' own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/device/pmc_interp.h"
#include "core/device/pmc_raycone.h"
#include "core/device/pmc_texture.h"
#include "core/texture.h"

namespace pmc {
namespace {

constexpr int kSize = 256;

// A linear (not sRGB) kSize x kSize grey texture whose texel (x, y) (y down
// from the top row) is white where stripe(x, y) holds.
struct StripeTexture {
  std::function<bool(int, int)> stripe;
  TexturePool pool;
  std::vector<uint32_t> words;
  std::vector<float> lut = srgb_decode_table();
  PmcTextureSet ts{};

  explicit StripeTexture(std::function<bool(int, int)> f) : stripe(std::move(f)) {
    std::vector<uint8_t> px(size_t(kSize) * kSize * 4);
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        uint8_t v = stripe(x, y) ? 255 : 0;
        uint8_t* p = &px[(size_t(y) * kSize + size_t(x)) * 4];
        p[0] = p[1] = p[2] = v;
        p[3] = 255;
      }
    pool.add("stripes", kSize, kSize, px, false);
    words.assign(pool.words()->begin(), pool.words()->end());
    ts.textures = pool.textures().data();
    ts.texels = words.data();
    ts.srgb_lut = lut.data();
    ts.count = 1;
  }

  // The image at uv (periodic), nearest texel of the finest level.
  double at(double u, double v) const {
    int x = int(std::floor(u * kSize)) % kSize, y = int(std::floor((1.0 - v) * kSize)) % kSize;
    return stripe(x < 0 ? x + kSize : x, y < 0 ? y + kSize : y) ? 1.0 : 0.0;
  }

  // The image's average over the ellipse {uv + axis a + perp b}, a^2 + b^2 <= 1
  // (perp: the minor half-axis), brute force on a 400 x 400 grid.
  double ellipse_average(float2 uv, float2 axis, float minor) const {
    const double len = std::hypot(axis.x, axis.y);
    const double px = -axis.y / len * 0.5 * minor, py = axis.x / len * 0.5 * minor;
    double sum = 0.0;
    int count = 0;
    const int n = 400;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        double a = (i + 0.5) / n * 2.0 - 1.0, b = (j + 0.5) / n * 2.0 - 1.0;
        if (a * a + b * b > 1.0) continue;
        sum += at(uv.x + axis.x * a + px * b, uv.y + axis.y * a + py * b);
        ++count;
      }
    return sum / count;
  }

  float sample(float2 uv, float2 axis, float minor) const {
    float footprint = 2.0f * std::hypot(axis.x, axis.y);
    return pmc_texture_sample_ellipse(&ts, 0, uv, footprint, axis, minor, PMC_ADDR_PERIODIC,
                                      PMC_ADDR_PERIODIC, PMC_FILTER_LINEAR, make_float4(0, 0, 0, 0))
        .x;
  }
  float isotropic(float2 uv, float footprint) const {
    return pmc_texture_sample(&ts, 0, uv, footprint, PMC_ADDR_PERIODIC, PMC_ADDR_PERIODIC, PMC_FILTER_LINEAR,
                              make_float4(0, 0, 0, 0))
        .x;
  }
};

// Stripes 16 texels wide: along u (rows alternate) or along v (columns do).
bool rows(int, int y) { return (y / 16) % 2 == 0; }
bool columns(int x, int) { return (x / 16) % 2 == 0; }

TEST(TextureFilter, ThinEllipseAveragesTheStripesOverItself) {
  const StripeTexture across_v(rows), across_u(columns);
  const float major = 64.0f / kSize, minor = 8.0f / kSize;  // 64 x 8 texels: 8 taps at level 3
  // Centred in a white stripe: rows 32..47 (v = 1 - 40/256), columns 32..47.
  const float2 uv = make_float2(40.0f / kSize, 1.0f - 40.0f / kSize);
  struct Case {
    const StripeTexture* t;
    float2 axis;
    bool along;  // the stripes run along the major axis
  };
  const Case cases[] = {
      {&across_v, make_float2(0.5f * major, 0.0f), true},
      {&across_v, make_float2(0.0f, 0.5f * major), false},
      {&across_u, make_float2(0.0f, 0.5f * major), true},
      {&across_u, make_float2(0.0f, -0.5f * major), true},
      {&across_u, make_float2(0.5f * major, 0.0f), false},
  };
  for (const Case& c : cases) {
    const double expect = c.t->ellipse_average(uv, c.axis, minor);
    const float got = c.t->sample(uv, c.axis, minor);
    const float old = c.t->isotropic(uv, major);
    SCOPED_TRACE(testing::Message() << "axis " << c.axis.x << " " << c.axis.y << " expect " << expect
                                    << " anisotropic " << got << " isotropic " << old);
    EXPECT_NEAR(got, expect, 0.06);
    if (c.along) {
      EXPECT_NEAR(expect, 1.0, 1e-9);  // the ellipse lies inside the white stripe
      EXPECT_GT(std::fabs(old - expect), 0.3) << "the isotropic lookup greys the stripe";
      EXPECT_LT(std::fabs(got - expect), 0.2 * std::fabs(old - expect));
    }
  }
}

TEST(TextureFilter, DiagonalEllipseFollowsDiagonalStripes) {
  // Stripes along the diagonal x = y, 16 texels across (about 11.3 texels
  // perpendicular to the stripes: (x - y) / 16 alternates).
  const StripeTexture diag([](int x, int y) { return ((x - y + 4096) / 16) % 2 == 0; });
  const float major = 64.0f / kSize, minor = 6.0f / kSize;
  // x - y = 8 (inside a white band: x - y in [0, 16)); in uv, y = (1 - v) kSize.
  const float2 uv = make_float2(100.5f / kSize, 1.0f - 92.5f / kSize);
  const float h = 0.5f * major / std::sqrt(2.0f);
  // x and y grow together along the stripes: u up, v down.
  const float2 along = make_float2(h, -h), across = make_float2(h, h);
  const double e_along = diag.ellipse_average(uv, along, minor);
  const double e_across = diag.ellipse_average(uv, across, minor);
  EXPECT_GT(e_along, 0.9);
  // The taps' mip texels are axis-aligned squares, which straddle diagonal
  // stripes: 0.83 here, still far above the isotropic lookup's grey.
  const float got = diag.sample(uv, along, minor), old = diag.isotropic(uv, major);
  EXPECT_NEAR(got, e_along, 0.2);
  EXPECT_LT(std::fabs(got - e_along), 0.5 * std::fabs(old - e_along));
  EXPECT_NEAR(diag.sample(uv, across, minor), e_across, 0.1);
}

TEST(TextureFilter, RoundEllipseIsTheIsotropicLookupBitForBit) {
  const StripeTexture t(rows);
  for (float f : {0.0f, 1e-4f, 3.0f / kSize, 0.05f, 0.4f, 3.0f})
    for (float u : {0.1f, 0.37f, 0.9f}) {
      const float2 uv = make_float2(u, 1.0f - u * 0.7f);
      const float iso = t.isotropic(uv, f);
      auto ellipse = [&](float2 axis, float minor) {
        return pmc_texture_sample_ellipse(&t.ts, 0, uv, f, axis, minor, PMC_ADDR_PERIODIC, PMC_ADDR_PERIODIC,
                                          PMC_FILTER_LINEAR, make_float4(0, 0, 0, 0))
            .x;
      };
      EXPECT_EQ(ellipse(make_float2(0, 0), 0.0f), iso) << "no ellipse";
      EXPECT_EQ(ellipse(make_float2(0.5f * f, 0), f), iso) << "a circle";
      EXPECT_EQ(ellipse(make_float2(0, 0.5f * f), 1.05f * f), iso) << "nearly round (ratio 1/1.05)";
      const float s = 0.5f * f / std::sqrt(2.0f);
      EXPECT_EQ(ellipse(make_float2(s, -s), f * 0.95f), iso) << "nearly round, diagonal";
    }
}

// PMC_FOOTPRINT_ONE_LEVEL: the nearest mip level alone, bilinear. At a
// footprint whose level is whole it is the trilinear lookup; between two
// levels it reads the nearer one, so it is one of the two levels' values
// and the trilinear lookup lies between them.
TEST(TextureFilter, OneLevelLookupReadsTheNearestLevel) {
  const StripeTexture t(rows);
  auto level = [&](int l, float2 uv) {
    const PmcTextureLevel L = pmc_texture_level_at(&t.ts.textures[0], l);
    return pmc_texture_level(&t.ts, L, 0, uv, PMC_ADDR_PERIODIC, PMC_ADDR_PERIODIC, PMC_FILTER_LINEAR,
                             make_float4(0, 0, 0, 0))
        .x;
  };
  auto one_level = [&](float2 uv, float f) {
    return pmc_texture_sample_ellipse(&t.ts, 0, uv, f, make_float2(0.01f, 0.0f), PMC_FOOTPRINT_ONE_LEVEL,
                                      PMC_ADDR_PERIODIC, PMC_ADDR_PERIODIC, PMC_FILTER_LINEAR,
                                      make_float4(0, 0, 0, 0))
        .x;
  };
  int levels_differ = 0;  // points where reading the wrong level would show
  for (float u : {0.1f, 0.37f, 0.9f, 0.53f, 0.71f}) {
    const float2 uv = make_float2(u, 1.0f - u * 0.7f);
    levels_differ += level(3, uv) != level(4, uv);
    // whole levels: 2^l texels of the finest level across the footprint
    for (int l : {0, 2, 4}) {
      const float f = std::ldexp(1.0f, l) / kSize;
      EXPECT_EQ(one_level(uv, f), t.isotropic(uv, f)) << "level " << l;
      EXPECT_EQ(one_level(uv, f), level(l, uv)) << "level " << l;
    }
    // a quarter and three quarters of the way from level 3 to level 4
    const float f3 = std::ldexp(1.0f, 3) / kSize;
    EXPECT_EQ(one_level(uv, f3 * std::pow(2.0f, 0.25f)), level(3, uv));
    EXPECT_EQ(one_level(uv, f3 * std::pow(2.0f, 0.75f)), level(4, uv));
    const float tri = t.isotropic(uv, f3 * std::pow(2.0f, 0.75f));
    EXPECT_GE(tri, std::fmin(level(3, uv), level(4, uv)) - 1e-6f);
    EXPECT_LE(tri, std::fmax(level(3, uv), level(4, uv)) + 1e-6f);
  }
  EXPECT_GE(levels_differ, 2);
  // no texture: the fallback
  EXPECT_EQ(pmc_texture_sample_ellipse(&t.ts, 7, make_float2(0.5f, 0.5f), 0.01f, make_float2(0, 0),
                                       PMC_FOOTPRINT_ONE_LEVEL, PMC_ADDR_PERIODIC, PMC_ADDR_PERIODIC,
                                       PMC_FILTER_LINEAR, make_float4(0.25f, 0, 0, 0))
                .x,
            0.25f);
}

TEST(TextureFilter, EllipseOfTheRayConeGradients) {
  float2 axis;
  float minor;
  // Orthogonal gradients: their own lengths, along the longer.
  pmc_ray_cone_ellipse(make_float2(0.0f, 0.2f), make_float2(0.05f, 0.0f), &axis, &minor);
  EXPECT_NEAR(axis.x, 0.0f, 1e-7f);
  EXPECT_NEAR(std::fabs(axis.y), 0.2f, 1e-6f);
  EXPECT_NEAR(minor, 0.1f, 1e-6f);
  // Sheared: the ellipse g1 cos t + g2 sin t's farthest and nearest points.
  const float2 g1 = make_float2(0.3f, 0.1f), g2 = make_float2(0.2f, -0.05f);
  pmc_ray_cone_ellipse(g1, g2, &axis, &minor);
  double rmax = 0, rmin = 1e9;
  double dir_x = 0, dir_y = 0;
  for (int i = 0; i < 100000; ++i) {
    double t = i * 2.0 * M_PI / 100000;
    double x = g1.x * std::cos(t) + g2.x * std::sin(t), y = g1.y * std::cos(t) + g2.y * std::sin(t);
    double r = std::hypot(x, y);
    if (r > rmax) rmax = r, dir_x = x, dir_y = y;
    rmin = std::min(rmin, r);
  }
  EXPECT_NEAR(std::hypot(axis.x, axis.y), rmax, 1e-5);
  EXPECT_NEAR(minor, 2.0 * rmin, 1e-5);
  EXPECT_NEAR(std::fabs(axis.x * dir_y - axis.y * dir_x), 0.0, 1e-5)
      << "the axis points at the farthest point";
  // Round, degenerate, not finite.
  pmc_ray_cone_ellipse(make_float2(0.1f, 0.0f), make_float2(0.0f, 0.1f), &axis, &minor);
  EXPECT_NEAR(2.0f * std::hypot(axis.x, axis.y), minor, 1e-7f);
  pmc_ray_cone_ellipse(make_float2(0, 0), make_float2(0, 0), &axis, &minor);
  EXPECT_EQ(axis.x, 0.0f);
  EXPECT_EQ(axis.y, 0.0f);
  EXPECT_EQ(minor, 0.0f);
  pmc_ray_cone_ellipse(make_float2(1e30f, 0), make_float2(0, 1), &axis, &minor);
  EXPECT_EQ(axis.x, 0.0f);
  EXPECT_EQ(minor, 0.0f);
  // A needle (parallel gradients): minor 0, the axis along them.
  pmc_ray_cone_ellipse(make_float2(0.1f, 0.1f), make_float2(0.05f, 0.05f), &axis, &minor);
  EXPECT_NEAR(minor, 0.0f, 1e-6f);
  EXPECT_NEAR(std::fabs(axis.x), std::sqrt(0.0125f), 1e-6f);
}

TEST(TextureFilter, PixelSamplesShortenTheEllipseAlongItsMajorAxis) {
  EXPECT_EQ(pmc_footprint_major_scale(0), 1.0f);
  EXPECT_EQ(pmc_footprint_major_scale(3), 0.5f);
  EXPECT_EQ(pmc_footprint_major_scale(15), 0.25f);
  EXPECT_EQ(pmc_footprint_major_scale(1023), 1.0f / 32.0f);
  // Gradients of an 8:1 ellipse along v: major 0.4 (half-axis 0.2), minor 0.05.
  const float2 g1 = make_float2(0.0f, 0.2f), g2 = make_float2(0.025f, 0.0f);
  float2 axis;
  float minor;
  pmc_ray_cone_ellipse(g1, g2, &axis, &minor);
  auto footprint = [&](pmc_u32 sample, int ellipse) {
    PmcShadingInputs in{};
    pmc_shading_footprint(&in, g1, g2, ellipse, pmc_footprint_major_scale(sample));
    return in;
  };
  PmcShadingInputs one = footprint(0, 1);  // a pixel's first sample: the whole ellipse
  EXPECT_EQ(one.footprint, 0.4f);
  EXPECT_EQ(one.footprint_axis.x, axis.x);
  EXPECT_EQ(one.footprint_axis.y, axis.y);
  EXPECT_EQ(one.footprint_minor, minor);
  PmcShadingInputs four = footprint(3, 1);  // the fourth: half as long, as thin, pointing the same way
  EXPECT_NEAR(std::hypot(four.footprint_axis.x, four.footprint_axis.y), 0.1f, 1e-6f);
  EXPECT_NEAR(four.footprint_axis.x * axis.y - four.footprint_axis.y * axis.x, 0.0f, 1e-7f);
  EXPECT_GT(four.footprint_axis.y * axis.y, 0.0f);
  EXPECT_EQ(four.footprint_minor, minor);
  for (pmc_u32 sample : {63u, 1023u}) {  // 0.4 / 8 = the minor width, and below: round, at the minor width
    PmcShadingInputs round = footprint(sample, 1);
    EXPECT_EQ(round.footprint_axis.x, 0.0f) << sample;
    EXPECT_EQ(round.footprint_axis.y, 0.0f) << sample;
    EXPECT_EQ(round.footprint_minor, 0.0f) << sample;
    EXPECT_NEAR(round.footprint, minor, 1e-6f) << sample;
    const StripeTexture t(rows);
    const float2 uv = make_float2(0.3f, 0.55f);
    EXPECT_EQ(pmc_texture_sample_ellipse(&t.ts, 0, uv, round.footprint, round.footprint_axis,
                                         round.footprint_minor, PMC_ADDR_PERIODIC, PMC_ADDR_PERIODIC,
                                         PMC_FILTER_LINEAR, make_float4(0, 0, 0, 0))
                  .x,
              t.isotropic(uv, round.footprint))
        << "one isotropic lookup";
  }
  // No ellipse (a hit after a rough bounce): the samples change nothing.
  PmcShadingInputs none = footprint(1023, 0);
  EXPECT_EQ(none.footprint, 0.4f);
  EXPECT_EQ(none.footprint_minor, PMC_FOOTPRINT_ONE_LEVEL);
}

}  // namespace
}  // namespace pmc

// A level's place in the pool is the sum of the sizes before it, each level
// half the one before and at least one texel: the closed form for sides that
// 2^level divides and the walk over the levels otherwise give that sum, for
// square, oblong, odd and power-of-two textures alike.
TEST(TextureFilter, LevelPlacesAreTheSumsOfTheLevelsBefore) {
  for (int w : {1, 2, 3, 8, 100, 256, 640, 1000, 1024, 2048, 4096})
    for (int h : {1, 2, 5, 8, 64, 100, 480, 512, 1024}) {
      int levels = 1;
      while ((std::max(w, h) >> (levels - 1)) > 1) ++levels;
      PmcTexture tex{};
      tex.offset = 77;
      tex.width = w;
      tex.height = h;
      tex.levels = levels;
      uint32_t base = tex.offset;
      int lw = w, lh = h;
      for (int l = 0; l < levels; ++l) {
        const PmcTextureLevel L = pmc_texture_level_at(&tex, l);
        EXPECT_EQ(L.base, base) << w << "x" << h << " level " << l;
        EXPECT_EQ(L.w, lw) << w << "x" << h << " level " << l;
        EXPECT_EQ(L.h, lh) << w << "x" << h << " level " << l;
        base += uint32_t(lw) * uint32_t(lh);
        lw = std::max(1, lw / 2);
        lh = std::max(1, lh / 2);
      }
    }
}
