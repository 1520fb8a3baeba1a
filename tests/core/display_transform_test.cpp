// display_transform_test.cpp — the PNG view transform (core/tone_map.h):
// exposure in stops, the two view curves and the sRGB encoding, against the
// published formulas written out here, and the PNG written through them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/image_io.h"
#include "core/tone_map.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

double srgb(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }
double aces_fit(double x) {  // Narkowicz 2015
  return std::min(1.0, std::max(0.0, x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)));
}

TEST(DisplayTransform, StandardIsClippedSrgb) {
  ToneMap d;
  d.view = ViewTransform::Standard;
  EXPECT_NEAR(tone_map(0.5f, d), 0.7353569, 1e-6);  // sRGB of linear 0.5
  EXPECT_NEAR(tone_map(0.18f, d), srgb(0.18), 1e-6);
  EXPECT_EQ(tone_map(1.0f, d), 1.0f);
  EXPECT_EQ(tone_map(7.0f, d), 1.0f);
  EXPECT_EQ(tone_map(-1.0f, d), 0.0f);
  EXPECT_EQ(tone_map(NAN, d), 0.0f);
  EXPECT_EQ(tone_map(INFINITY, d), 0.0f);
}

TEST(DisplayTransform, ExposureIsInStops) {
  for (ViewTransform v : {ViewTransform::Standard, ViewTransform::Filmic}) {
    ToneMap plus;
    plus.view = v;
    plus.exposure_ev = 1.0f;
    ToneMap zero = plus;
    zero.exposure_ev = 0.0f;
    ToneMap minus2 = plus;
    minus2.exposure_ev = -2.0f;
    for (float x : {0.01f, 0.1f, 0.3f, 2.0f}) {
      EXPECT_FLOAT_EQ(tone_map(x, plus), tone_map(2.0f * x, zero));
      EXPECT_FLOAT_EQ(tone_map(x, minus2), tone_map(0.25f * x, zero));
    }
  }
}

TEST(DisplayTransform, FilmicIsTheAcesFitThenSrgb) {
  ToneMap d;  // the default
  EXPECT_EQ(d.view, ViewTransform::Filmic);
  for (double x : {0.0, 0.05, 0.18, 0.5, 1.0, 4.0, 100.0})
    EXPECT_NEAR(tone_map(float(x), d), srgb(aces_fit(x)), 2e-6) << x;
  // Highlights roll off instead of clipping: 4 and 16 stay distinguishable.
  EXPECT_LT(tone_map(4.0f, d), tone_map(16.0f, d));
  EXPECT_NEAR(aces_fit(1.0), 2.54 / 3.16, 1e-12);
}

TEST(DisplayTransform, PngHoldsTheEncodedValues) {
  const std::string dir = test::temp_dir();
  Image img;
  img.width = 4;
  img.height = 1;
  img.channels = 3;
  img.pixels = {0.0f, 0.02f, 0.1f, 0.18f, 0.3f, 0.5f, 0.8f, 1.0f, 2.0f, 5.0f, 40.0f, -3.0f};
  ToneMap d;
  d.exposure_ev = 0.5f;
  d.view = ViewTransform::Standard;
  write_png_display(dir + "/a.png", tone_map_image(img, d));
  Image back = read_image(dir + "/a.png");
  ASSERT_EQ(back.pixels.size(), img.pixels.size());
  for (size_t i = 0; i < img.pixels.size(); ++i) {
    double expected = std::round(255.0 * srgb(std::min(1.0, std::max(0.0, img.pixels[i] * std::sqrt(2.0)))));
    EXPECT_NEAR(back.pixels[i] * 255.0, expected, 1e-3) << i;
  }
  EXPECT_THROW(parse_view_transform("aces", "--view"), Error);
  EXPECT_EQ(parse_view_transform("standard", "--view"), ViewTransform::Standard);
}

}  // namespace
}  // namespace pmc
