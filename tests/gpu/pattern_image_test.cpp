// pattern_image_test.cpp — a rendered procedural pattern against its formula.
//
// The whole chain (MaterialX reader, passes, compiler, OpenCL interpreter,
// uv interpolation in the shade kernel, camera, film) is checked pixel by
// pixel: a unit plane (z = 0, uv = (x + 0.5, y + 0.5), written here so the
// uv mapping is exact) seen head-on from z = 10 with a 4.6 degree field of
// view shows the window [-0.4, 0.4]^2 of the plane, i.e. uv in [0.1, 0.9]^2.
// A pinhole camera looking straight at a plane maps pixels to the plane
// affinely, so a pixel's uv follows from the camera alone:
//   u = 0.5 + 0.4 * (2 (x + jx) / W - 1),  v = 0.5 + 0.4 * (1 - 2 (y + jy) / H)
// (jx, jy in [0, 1): the sample's jitter). The material emits its pattern with
// base = specular = 0 against a black environment, so every camera sample's
// radiance is exactly the pattern at its uv:
//   R = ramplr(0, 1) = u,  G = checker: mod(floor(8u) + floor(8v), 2),
//   B = ramptb(valuet 1, valueb 0) = v.
// A pixel averages its samples; each sample lies within half a pixel
// (0.4 / W in uv) of the pixel centre, so the ramps may differ from their
// value at the centre by at most that much (linear, slope 1). The checker is
// exact except where a pixel straddles a cell edge: pixels within one pixel
// of an edge are skipped. A second test compares the same image against the
// left-right mirrored pattern and requires that comparison to fail, showing
// the check can fail at all.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

constexpr int kSize = 64;
constexpr int kSpp = 8;
constexpr float kHalfView = 0.4f;  // the window shows uv 0.5 +- 0.4
constexpr float kCells = 8.0f;     // checker cells per unit of uv

const char* kPlaneObj =
    "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "vn 0 0 1\n"
    "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";

const char* kPatternMtlx = R"XML(<?xml version="1.0"?>
<materialx version="1.39">
  <texcoord name="uv" type="vector2"/>
  <multiply name="uv8" type="vector2">
    <input name="in1" type="vector2" nodename="uv"/>
    <input name="in2" type="float" value="8"/>
  </multiply>
  <floor name="cells" type="vector2">
    <input name="in" type="vector2" nodename="uv8"/>
  </floor>
  <extract name="cx" type="float">
    <input name="in" type="vector2" nodename="cells"/>
    <input name="index" type="integer" value="0"/>
  </extract>
  <extract name="cy" type="float">
    <input name="in" type="vector2" nodename="cells"/>
    <input name="index" type="integer" value="1"/>
  </extract>
  <add name="cell_sum" type="float">
    <input name="in1" type="float" nodename="cx"/>
    <input name="in2" type="float" nodename="cy"/>
  </add>
  <modulo name="checker" type="float">
    <input name="in1" type="float" nodename="cell_sum"/>
    <input name="in2" type="float" value="2"/>
  </modulo>
  <ramplr name="ramp_u" type="float">
    <input name="valuel" type="float" value="0"/>
    <input name="valuer" type="float" value="1"/>
  </ramplr>
  <ramptb name="ramp_v" type="float">
    <input name="valuet" type="float" value="1"/>
    <input name="valueb" type="float" value="0"/>
  </ramptb>
  <combine3 name="pattern" type="color3">
    <input name="in1" type="float" nodename="ramp_u"/>
    <input name="in2" type="float" nodename="checker"/>
    <input name="in3" type="float" nodename="ramp_v"/>
  </combine3>
  <standard_surface name="SR_pattern" type="surfaceshader">
    <input name="base" type="float" value="0"/>
    <input name="specular" type="float" value="0"/>
    <input name="emission" type="float" value="1"/>
    <input name="emission_color" type="color3" nodename="pattern"/>
  </standard_surface>
  <surfacematerial name="Pattern" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_pattern"/>
  </surfacematerial>
</materialx>
)XML";

// The pattern's uv at image position (px, py) in pixels (pixel centres at +0.5).
void uv_at(double px, double py, double* u, double* v) {
  *u = 0.5 + kHalfView * (2.0 * px / kSize - 1.0);
  *v = 0.5 + kHalfView * (1.0 - 2.0 * py / kSize);
}

double checker(double u, double v) { return std::fmod(std::floor(kCells * u) + std::floor(kCells * v), 2.0); }

const Image& rendered() {
  static Image image = [] {
    const std::string dir = test::temp_dir();
    test::write_file(dir + "/plane.obj", kPlaneObj);
    test::write_file(dir + "/pattern.mtlx", kPatternMtlx);
    RenderConfig s;
    s.scene = dir + "/plane.obj";
    s.mtlx = {dir + "/pattern.mtlx"};
    s.material = "Pattern";
    s.cache = false;
    s.width = kSize;
    s.height = kSize;
    s.spp = kSpp;
    s.max_depth = 2;
    s.camera_from = Vec3{0, 0, 10};
    s.camera_at = Vec3{0, 0, 0};
    // tan(fov / 2) * distance = half the window: 0.04 * 10 = 0.4.
    s.fov = float(2.0 * std::atan(double(kHalfView) / 10.0) * 180.0 / M_PI);
    RenderOutput out = RenderSession(s, test::cl()).render();
    EXPECT_EQ(out.stats.nan_pixels, 0u);
    return out.image;
  }();
  return image;
}

struct Comparison {
  int compared = 0;  // pixel channels compared
  int mismatches = 0;
  int checker_skipped = 0;
  double max_ramp_error = 0;
  std::string first;  // the first mismatch, for the message
};

// Compares the image with the pattern; `mirror` evaluates the expectation at
// the left-right mirrored pixel instead (a deliberately wrong expectation).
Comparison compare(const Image& img, bool mirror) {
  Comparison c;
  const double pixel_uv = 2.0 * kHalfView / kSize;  // one pixel in uv
  // Ramps: every sample is within half a pixel of the centre, the ramp has
  // slope 1, so the average is within pixel_uv / 2 of the centre value; 1e-5
  // covers float rounding in the camera and the uv interpolation.
  const double ramp_tol = 0.5 * pixel_uv + 1e-5;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const int ex = mirror ? kSize - 1 - x : x;
      double u, v;
      uv_at(ex + 0.5, y + 0.5, &u, &v);
      const float* p = &img.pixels[3 * (size_t(y) * kSize + size_t(x))];
      auto check = [&](int channel, double want, double tol) {
        ++c.compared;
        if (channel != 1) c.max_ramp_error = std::max(c.max_ramp_error, std::fabs(p[channel] - want));
        if (std::fabs(p[channel] - want) <= tol) return;
        if (c.mismatches++ == 0)
          c.first = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                    std::to_string(channel) + ": " + std::to_string(p[channel]) + ", expected " +
                    std::to_string(want);
      };
      check(0, u, ramp_tol);
      check(2, v, ramp_tol);
      // The checker: skip pixels within one pixel of a cell edge (their
      // samples may fall in either cell), compare the rest exactly.
      if (checker(u - pixel_uv, v) != checker(u + pixel_uv, v) ||
          checker(u, v - pixel_uv) != checker(u, v + pixel_uv)) {
        ++c.checker_skipped;
        continue;
      }
      check(1, checker(u, v), 1e-6);
    }
  return c;
}

TEST(PatternImage, EmittedRampsAndCheckerMatchTheFormula) {
  const Image& img = rendered();
  ASSERT_EQ(img.width, kSize);
  ASSERT_EQ(img.height, kSize);
  ASSERT_EQ(test::non_finite(img), 0u);
  Comparison c = compare(img, false);
  EXPECT_EQ(c.mismatches, 0) << "first: " << c.first;
  // About 2 of every 10 pixels per axis lie next to an edge (cells are 10
  // pixels wide); most of the checker must still be compared.
  EXPECT_LT(c.checker_skipped, kSize * kSize / 2);
  EXPECT_GT(c.compared, 2 * kSize * kSize + kSize * kSize / 2);
  RecordProperty("max_ramp_error", std::to_string(c.max_ramp_error));
  RecordProperty("checker_pixels_skipped", c.checker_skipped);
}

TEST(PatternImage, MirroredExpectationIsRejected) {
  // Same image, expectation mirrored left-right: the u ramp and the checker
  // (8 cells, mirrored about the centre, swap colours) must both disagree.
  Comparison c = compare(rendered(), true);
  EXPECT_GT(c.mismatches, c.compared / 3) << "the comparison cannot tell a mirrored pattern apart";
}

}  // namespace
}  // namespace pmc
