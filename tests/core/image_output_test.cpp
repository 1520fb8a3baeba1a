// image_output_test.cpp — tone mapping, difference and hit-map images, atomic writes.
//
// * tone_map() against the published curve computed here in double: the
//   Narkowicz ACES fit, then the sRGB encoding (IEC 61966-2-1), exposure
//   applied first; black for negative and non-finite values.
// * difference_image(): |tone_map(a) - tone_map(b)| x scale, at most 1.
// * The hit map's colours are matplotlib's viridis at the ends and the
//   middle (its published 8-bit values), its labels white, its bar to the right.
// * write_text_file() leaves either the whole new file or the old one, never a
//   temporary beside it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/atomic_write.h"
#include "core/error.h"
#include "core/heatmap.h"
#include "core/image_metrics.h"
#include "core/tone_map.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

double reference_tone_map(double x) {
  x = std::max(0.0, x);
  const double aces = std::clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
  return aces <= 0.0031308 ? 12.92 * aces : 1.055 * std::pow(aces, 1.0 / 2.4) - 0.055;
}

TEST(ToneMap, FollowsTheAcesFitAndTheSrgbEncoding) {
  for (double x : {0.0, 1e-4, 0.01, 0.18, 0.5, 1.0, 4.0, 100.0})
    EXPECT_NEAR(tone_map(float(x)), reference_tone_map(x), 2e-6) << x;
  EXPECT_NEAR(tone_map(0.25f, ToneMap{1.0f}), reference_tone_map(0.5), 2e-6)
      << "exposure (stops) scales first";
  EXPECT_EQ(tone_map(-1.0f), 0.0f);
  EXPECT_EQ(tone_map(NAN), 0.0f);
  EXPECT_EQ(tone_map(INFINITY), 0.0f);
  EXPECT_NEAR(tone_map(1e9f), 1.0f, 1e-6f) << "the curve saturates at white";
}

Image image_of(std::vector<float> px) {
  Image img;
  img.width = int(px.size());
  img.height = 1;
  img.channels = 1;
  img.pixels = std::move(px);
  return img;
}

TEST(DifferenceImage, IsTheScaledDifferenceOfDisplayValuesClampedToOne) {
  const Image a = image_of({0.1f, 0.5f, 2.0f, 0.3f}), b = image_of({0.1f, 0.4f, 0.0f, 0.31f});
  const Image d = difference_image(a, b, 5.0f);
  ASSERT_EQ(d.pixels.size(), 4u);
  EXPECT_EQ(d.pixels[0], 0.0f);
  EXPECT_NEAR(d.pixels[1], 5.0 * (reference_tone_map(0.5) - reference_tone_map(0.4)), 1e-5);
  EXPECT_EQ(d.pixels[2], 1.0f) << "clamped";
  EXPECT_NEAR(d.pixels[3], 5.0 * std::fabs(reference_tone_map(0.3) - reference_tone_map(0.31)), 1e-5);
}

TEST(HitMap, ColoursAreViridisAndTheBarIsLabelled) {
  Image values;
  values.width = 30;
  values.height = 40;
  values.channels = 1;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 30; ++x) values.pixels.push_back(x < 10 ? 0.0f : x < 20 ? 10.0f : 20.0f);
  const Image map = heatmap_with_colorbar(values, 20.0f);
  ASSERT_EQ(map.channels, 3);
  ASSERT_GT(map.width, 30) << "the colour bar is to the right";
  EXPECT_EQ(map.height, 40);
  auto px = [&](int x, int y, int c) {
    return 255.0f * map.pixels[3 * (size_t(y) * size_t(map.width) + x) + c];
  };
  // matplotlib's viridis: 0 -> (68, 1, 84), 0.5 -> (33, 145, 140), 1 -> (253, 231, 37).
  const float expected[3][3] = {{68, 1, 84}, {33, 145, 140}, {253, 231, 37}};
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(px(5 + 10 * k, 20, c), expected[k][c], 1.5f) << k << " " << c;
  size_t white = 0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 30; x < map.width; ++x) white += px(x, y, 0) == 255.0f && px(x, y, 1) == 255.0f ? 1 : 0;
  EXPECT_GT(white, 10u) << "the 20 / 10 / 0 labels";
}

TEST(AtomicWrite, WritesTheWholeFileOrLeavesTheOldOne) {
  const std::string dir = test::temp_dir(), path = dir + "/out.json";
  write_text_file(path, "{\"a\": 1}\n");
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "{\"a\": 1}\n");
  // A writer that fails half way: the old file stays, no temporary is left.
  EXPECT_THROW(write_atomically(path,
                                [&](const std::string& tmp) {
                                  std::ofstream(tmp) << "{\"a\":";
                                  fail("disk full");
                                }),
               Error);
  std::ifstream again(path);
  std::string kept((std::istreambuf_iterator<char>(again)), std::istreambuf_iterator<char>());
  EXPECT_EQ(kept, "{\"a\": 1}\n");
  size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 1u) << "no temporary left beside the output";
  // A folder that does not exist: an error naming the file.
  try {
    write_text_file(dir + "/missing/out.csv", "x\n");
    FAIL() << "writing into a missing folder succeeded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("out.csv"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pmc
