// render_test.cpp — the whole renderer against analytic answers (real OpenCL on PoCL).
//
// * Closed-sphere furnace: inside a closed surface of albedo a and emission Le
//   every pixel's radiance is Le / (1 - a) (L = Le + a L). Exercises NEE, MIS
//   weights on emitter hits, Russian roulette and deep paths.
// * Convex object in a uniform environment: every reflected ray escapes, so a
//   Lambert surface of albedo a shows exactly a * Lenv, the background Lenv.
// * The Cornell box from ../shared/scenes renders without NaN/Inf and within
//   a justified brightness range.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

// A UV sphere of radius r around the origin, flat-shaded (no normals), one material.
std::string sphere_obj(float r, int rings, int segments, const std::string& mtllib,
                       const std::string& material) {
  std::ostringstream os;
  if (!mtllib.empty()) os << "mtllib " << mtllib << "\nusemtl " << material << "\n";
  os << "v 0 " << r << " 0\n";
  for (int i = 1; i < rings; ++i) {
    double th = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      double ph = 2 * M_PI * j / segments;
      os << "v " << r * std::sin(th) * std::cos(ph) << " " << r * std::cos(th) << " "
         << r * std::sin(th) * std::sin(ph) << "\n";
    }
  }
  os << "v 0 " << -r << " 0\n";
  auto ring = [&](int i, int j) { return 2 + (i - 1) * segments + (j % segments); };
  int bottom = 2 + (rings - 1) * segments;
  for (int j = 0; j < segments; ++j) os << "f 1 " << ring(1, j + 1) << " " << ring(1, j) << "\n";
  for (int i = 1; i < rings - 1; ++i)
    for (int j = 0; j < segments; ++j)
      os << "f " << ring(i, j) << " " << ring(i, j + 1) << " " << ring(i + 1, j + 1) << " " << ring(i + 1, j)
         << "\n";
  for (int j = 0; j < segments; ++j)
    os << "f " << bottom << " " << ring(rings - 1, j) << " " << ring(rings - 1, j + 1) << "\n";
  return os.str();
}

// `obj` with its MTL materials, no cache, seen from `from` towards `at`.
RenderConfig config_for(const std::string& obj, Vec3 from, Vec3 at, float fov) {
  RenderConfig c;
  c.scene = obj;
  c.cache = false;
  c.camera_from = from;
  c.camera_at = at;
  c.fov = fov;
  return c;
}

RenderOutput render_scene(const RenderConfig& config) { return RenderSession(config, test::cl()).render(); }

TEST(Render, ClosedSphereFurnaceMatchesAnalyticRadiance) {
  const std::string dir = test::temp_dir();
  const float albedo = 0.5f, le = 1.0f;
  test::write_file(dir + "/furnace.mtl", "newmtl shell\nKd 0.5 0.5 0.5\nKs 0 0 0\nKe 1 1 1\n");
  test::write_file(dir + "/furnace.obj", sphere_obj(1.0f, 24, 48, "furnace.mtl", "shell"));
  RenderConfig s = config_for(dir + "/furnace.obj", {0.0f, 0.0f, 0.0f}, {1.0f, 0.1f, 0.2f}, 90.0f);
  s.width = 48;
  s.height = 32;
  s.spp = 64;
  s.max_depth = 200;  // a^200 is far below the tolerance: the truncation bias is nil
  RenderOutput out = render_scene(s);
  const double expected = le / (1.0 - albedo);  // 2.0
  EXPECT_EQ(out.stats.nan_pixels, 0u);
  EXPECT_EQ(out.stats.bad_samples, 0u);
  EXPECT_NEAR(test::image_mean(out.image), expected, 0.01 * expected);
  EXPECT_GT(out.stats.shadow_rays, 0u) << "light sampling must be active";
}

TEST(Render, ConvexLambertObjectInUniformEnvironmentShowsAlbedo) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/ball.mtl", "newmtl ball\nKd 0.8 0.6 0.4\n");
  test::write_file(dir + "/ball.obj", sphere_obj(1.0f, 16, 32, "ball.mtl", "ball"));
  // The sphere fills the centre, background at the corners.
  RenderConfig s = config_for(dir + "/ball.obj", {0.0f, 0.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, 40.0f);
  s.width = 32;
  s.height = 32;
  s.spp = 4;
  s.max_depth = 8;
  s.env = {2.0f, 2.0f, 2.0f};
  RenderOutput out = render_scene(s);
  // Centre pixel: on the sphere; corner pixel: background.
  const float* centre = &out.image.pixels[3 * (16 * 32 + 16)];
  EXPECT_NEAR(centre[0], 1.6f, 1e-3f);
  EXPECT_NEAR(centre[1], 1.2f, 1e-3f);
  EXPECT_NEAR(centre[2], 0.8f, 1e-3f);
  const float* corner = &out.image.pixels[0];
  EXPECT_FLOAT_EQ(corner[0], 2.0f);
  EXPECT_FLOAT_EQ(corner[2], 2.0f);
}

TEST(Render, CornellBoxHasNoNanAndPlausibleBrightness) {
  // The camera of cornell_box.ecs.
  RenderConfig s =
      config_for(test::shared_scene("cornell/cornell_box.obj"), {278, 273, -800}, {278, 273, 0}, 37.0f);
  s.width = 80;
  s.height = 80;
  s.spp = 16;
  s.max_depth = 6;
  s.env = {1.0f, 1.0f, 1.0f};
  RenderOutput out = render_scene(s);
  EXPECT_EQ(test::non_finite(out.image), 0u);
  EXPECT_EQ(out.stats.nan_pixels, 0u);
  // The box is lit only by the unit environment through its open front (the
  // scene's light quad is commented out). With albedos <= 1 no pixel can
  // exceed the environment in expectation, so the mean is below 1; the
  // opening faces the camera and the walls' albedo is 0.4–0.8, so a large part
  // of the interior receives direct environment light: the mean stays well
  // above 0.1 (measured ~0.44 at these settings).
  double mean = test::image_mean(out.image);
  EXPECT_LT(mean, 1.0);
  EXPECT_GT(mean, 0.1);
}

}  // namespace
}  // namespace pmc
