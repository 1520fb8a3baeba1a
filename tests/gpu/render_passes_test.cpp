// render_passes_test.cpp — render passes (core/render_passes.h, core/device/pmc_passes.h)
// through a RenderSession on PoCL (denoising: tests/gpu/denoise_test.cpp).
//
// Independent answers:
//  * a plane of one constant standard_surface (base 1, no specular) seen
//    from straight above: its albedo pass is the base colour, its normal the
//    plane's (0, 1, 0), its position lies on the plane within the pixel's
//    footprint around the centre ray's analytic hit, its depth is the
//    distance from the eye to that position (Jensen's gap aside), and at the centre pixel the
//    analytic h sqrt(1 + tan^2(fov/2) (sx^2 + sy^2));
//  * the default room: every normal a surface gave is unit length, the albedo
//    within [0, 1], and sample ranges add to the one-process passes bit for bit.
#include "core/render_passes.h"

#include <gtest/gtest.h>

#include <cmath>

#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

constexpr float kHeight = 2.0f, kFov = 60.0f;
constexpr int kSize = 32;

RenderConfig plane_scene(const std::string& dir) {
  test::write_file(dir + "/plane.obj", "v -50 0 -50\nv 50 0 -50\nv 50 0 50\nv -50 0 50\nf 1 2 3\nf 1 3 4\n");
  test::write_file(dir + "/flat.mtlx", R"(<?xml version="1.0"?>
<materialx version="1.39">
  <standard_surface name="SR_flat" type="surfaceshader">
    <input name="base" type="float" value="1"/>
    <input name="base_color" type="color3" value="0.6, 0.3, 0.2"/>
    <input name="specular" type="float" value="0"/>
  </standard_surface>
  <surfacematerial name="flat" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_flat"/>
  </surfacematerial>
</materialx>
)");
  RenderConfig c;
  c.scene = dir + "/plane.obj";
  c.mtlx = {dir + "/flat.mtlx"};
  c.material = "flat";
  c.env = {1.0f, 1.0f, 1.0f};
  c.lights = "none";
  c.camera_from = Vec3{0.0f, kHeight, 0.0f};
  c.camera_at = Vec3{0.0f, 0.0f, 0.0f};
  c.camera_up = Vec3{0.0f, 0.0f, -1.0f};
  c.fov = kFov;
  c.width = kSize;
  c.height = kSize;
  c.spp = 8;
  c.max_depth = 3;
  c.passes = kPassAll;
  return c;
}

TEST(RenderPasses, ConstantPlaneAlbedoNormalPositionAndDepthAreAnalytic) {
  const std::string dir = test::temp_dir();
  RenderSession session(plane_scene(dir), test::cl());
  const RenderOutput out = session.render();
  const PassImages& p = out.passes;
  ASSERT_EQ(p.albedo.width, kSize);
  const float base[3] = {0.6f, 0.3f, 0.2f};
  const double t = std::tan(0.5 * kFov * M_PI / 180.0);
  const double pixel = 2.0 * kHeight * t / kSize;  // a pixel's width on the plane
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const size_t i = size_t(y) * kSize + size_t(x);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(p.albedo.pixels[3 * i + size_t(c)], base[c], 1e-5) << x << "," << y;
      EXPECT_NEAR(p.normal.pixels[3 * i + 0], 0.0f, 1e-6);
      EXPECT_NEAR(p.normal.pixels[3 * i + 1], 1.0f, 1e-6);
      EXPECT_NEAR(p.normal.pixels[3 * i + 2], 0.0f, 1e-6);
      // Position: on the plane, inside the pixel's square around its centre ray's hit
      // (x right, -z up on the screen).
      const float* pos = &p.position.pixels[3 * i];
      const double sx = (x + 0.5) / kSize * 2.0 - 1.0, sy = 1.0 - (y + 0.5) / kSize * 2.0;
      EXPECT_NEAR(pos[1], 0.0, 1e-5);
      EXPECT_NEAR(pos[0], kHeight * t * sx, 0.5 * pixel) << x << "," << y;
      EXPECT_NEAR(pos[2], -kHeight * t * sy, 0.5 * pixel) << x << "," << y;
      // Depth: the mean of the samples' distances from the eye, which is at least the
      // distance of their mean position (Jensen) and exceeds it by about the spread of
      // the hits over the pixel squared over the distance (~1e-4 of it).
      const double dist = std::sqrt(double(pos[0]) * pos[0] + kHeight * kHeight + double(pos[2]) * pos[2]);
      EXPECT_GE(p.depth.pixels[i], dist * (1.0 - 1e-6)) << x << "," << y;
      EXPECT_LE(p.depth.pixels[i], dist * (1.0 + 5e-4)) << x << "," << y;
      if (x == kSize / 2 && y == kSize / 2)  // the centre ray: h sqrt(1 + t^2 (sx^2 + sy^2))
        EXPECT_NEAR(p.depth.pixels[i], kHeight * std::sqrt(1.0 + t * t * (sx * sx + sy * sy)), 5e-4);
      EXPECT_EQ(p.material.pixels[i], p.material.pixels[0]);  // the scene's one material
    }
  EXPECT_GE(p.material.pixels[0], 0.0f);
  // The beauty is not touched by the passes: the same render without them.
  RenderSettings plain = session.settings();
  plain.passes = 0;
  const RenderOutput without = session.render(plain);
  EXPECT_TRUE(without.image.pixels == out.image.pixels);
  EXPECT_FALSE(without.film.has_passes());
}

TEST(RenderPasses, RoomNormalsAreUnitLengthAndSampleRangesAddToTheOneProcessPasses) {
  RenderConfig c = test::default_scene_config(40, 24, 6);
  c.passes = kPassAll;
  RenderSession session(c, test::cl());
  const RenderOutput full = session.render();
  const PassImages& p = full.passes;
  size_t surfaces = 0;
  for (size_t i = 0; i < size_t(40 * 24); ++i) {
    const float* n = &p.normal.pixels[3 * i];
    const double len = std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]);
    if (len == 0.0) continue;  // no sample found a non-specular surface
    ++surfaces;
    EXPECT_NEAR(len, 1.0, 1e-6) << "pixel " << i;
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(p.albedo.pixels[3 * i + size_t(k)], 0.0f);
      EXPECT_LE(p.albedo.pixels[3 * i + size_t(k)], 1.0f);
    }
  }
  EXPECT_GT(surfaces, size_t(40 * 24 * 9 / 10));  // the room is closed in front of the camera

  FilmSums sum = FilmSums::zero(40, 24, true);
  for (auto [a, b] : {std::pair{3, 6}, std::pair{0, 2}, std::pair{2, 3}}) {
    RenderSettings s = session.settings();
    s.sample_begin = a;
    s.sample_end = b;
    add_film(sum, session.render(s).film, 0, 0);
  }
  EXPECT_EQ(sum.pass_sum, full.film.pass_sum);
  EXPECT_EQ(sum.pass_hits, full.film.pass_hits);
  EXPECT_EQ(sum.pass_material_inv, full.film.pass_material_inv);
  const PassImages merged = film_passes(sum);
  for (auto [x, y] : {std::pair{&merged.albedo, &p.albedo}, std::pair{&merged.normal, &p.normal},
                      std::pair{&merged.depth, &p.depth}, std::pair{&merged.position, &p.position},
                      std::pair{&merged.material, &p.material}})
    EXPECT_TRUE(x->pixels == y->pixels);
  // (The hits pass is not compared: a part's cache table starts empty, so it finds fewer
  // hits; its beauty and other passes do not depend on the table.)
}

}  // namespace
}  // namespace pmc
