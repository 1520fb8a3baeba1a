// image_metrics_test.cpp — whole-image and worst-tile errors (core/image_metrics.h).
//
// Two 40x36 images equal but for one 16x16 tile (and, separately, a partial
// tile at the bottom-right edge) offset by 0.1: the worst tile's clamped PSNR
// is exactly 20 dB there, the whole image's follows from the fraction of
// changed pixels, and identical images report 999 dB. The trimmed worst tile
// (each tile less its 2 largest pixel errors): a uniformly offset tile keeps
// its 20 dB, one or two outlier pixels vanish (999 dB), a third remains as
// one pixel's error over 254, and a 1-pixel corner tile is not trimmed.
//
// The bias estimate: renders of 0.5 with Gaussian noise (sigma 0.02 per
// render, independent per render) whose cached pair has one tile 0.01 too
// bright (40 dB of bias there) finds that tile at 40 +- 1.5 dB under noise
// twice the bias, while a same-seed comparison reads about 31 dB everywhere;
// the noise floor is 10 log10(1 / (2 sigma^2)) = 31 dB; without a bias no
// tile reads below 40 dB.
#include "core/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"

namespace pmc {
namespace {

Image flat(int w, int h, float v) {
  Image im;
  im.width = w;
  im.height = h;
  im.channels = 3;
  im.pixels.assign(size_t(w) * size_t(h) * 3, v);
  return im;
}

void offset_block(Image& im, int x0, int y0, int x1, int y1, float d) {
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      for (int c = 0; c < 3; ++c) im.pixels[(size_t(y) * size_t(im.width) + size_t(x)) * 3 + size_t(c)] += d;
}

TEST(ImageMetrics, WorstTileFindsTheOneChangedTile) {
  const Image ref = flat(40, 36, 0.5f);
  Image test = ref;
  offset_block(test, 16, 16, 32, 32, 0.1f);  // the tile at (16, 16)
  ImageError e = compare_images(test, ref);
  EXPECT_NEAR(e.worst_tile_psnr, 20.0, 1e-4);  // mse 0.01
  EXPECT_EQ(e.worst_tile_x, 16);
  EXPECT_EQ(e.worst_tile_y, 16);
  const double whole_mse = 0.01 * (16.0 * 16.0) / (40.0 * 36.0);
  EXPECT_NEAR(e.psnr, 10.0 * std::log10(1.0 / whole_mse), 1e-4);
  EXPECT_GT(e.psnr, e.worst_tile_psnr + 7.0) << "the local error hides in the whole image";
}

TEST(ImageMetrics, PartialEdgeTilesCountTheirOwnPixelsOnly) {
  const Image ref = flat(40, 36, 0.5f);
  Image test = ref;
  offset_block(test, 32, 32, 40, 36, 0.1f);  // the whole 8x4 edge tile at (32, 32)
  ImageError e = compare_images(test, ref);
  EXPECT_NEAR(e.worst_tile_psnr, 20.0, 1e-4) << "mean over the tile's 32 pixels, not 256";
  EXPECT_EQ(e.worst_tile_x, 32);
  EXPECT_EQ(e.worst_tile_y, 32);
  EXPECT_EQ(compare_images(ref, ref).worst_tile_psnr, 999.0);
}

void offset_pixel(Image& im, int x, int y, float d) { offset_block(im, x, y, x + 1, y + 1, d); }

TEST(ImageMetrics, TrimmedWorstTileIgnoresTwoOutlierPixelsPerTile) {
  const Image ref = flat(40, 36, 0.5f);
  Image block = ref;
  offset_block(block, 16, 16, 32, 32, 0.1f);
  ImageError e = compare_images(block, ref);
  EXPECT_NEAR(e.worst_trimmed_tile_psnr, 20.0, 1e-4) << "a whole tile's error is not an outlier";
  EXPECT_EQ(e.worst_trimmed_tile_x, 16);
  EXPECT_EQ(e.worst_trimmed_tile_y, 16);

  Image two = ref;
  offset_pixel(two, 20, 3, 0.5f);
  offset_pixel(two, 21, 9, -0.4f);
  e = compare_images(two, ref);
  EXPECT_NEAR(e.worst_tile_psnr, 10.0 * std::log10(256.0 / (0.25 + 0.16)), 1e-4);
  EXPECT_EQ(e.worst_trimmed_tile_psnr, 999.0) << "two diverged pixels are all the tile's error";

  Image three = two;
  offset_pixel(three, 17, 12, 0.3f);
  e = compare_images(three, ref);
  EXPECT_NEAR(e.worst_trimmed_tile_psnr, 10.0 * std::log10(254.0 / 0.09), 1e-4)
      << "the smallest of three stays";
  EXPECT_EQ(e.worst_trimmed_tile_x, 16);
  EXPECT_EQ(e.worst_trimmed_tile_y, 0);

  const Image small_ref = flat(17, 17, 0.5f);
  Image corner = small_ref;
  offset_pixel(corner, 16, 16, 0.1f);  // the 1x1 tile at (16, 16)
  e = compare_images(corner, small_ref);
  EXPECT_NEAR(e.worst_trimmed_tile_psnr, 20.0, 1e-4) << "too few pixels to trim";
  EXPECT_EQ(e.worst_trimmed_tile_x, 16);
}

Image noisy(const Image& im, std::mt19937& rng) {
  std::normal_distribution<float> noise(0.0f, 0.02f);
  Image out = im;
  for (float& v : out.pixels) v += noise(rng);
  return out;
}

TEST(ImageMetrics, BiasEstimateFindsABiasedTileUnderNoiseTwiceAsLarge) {
  std::mt19937 rng(7);
  const Image truth = flat(48, 32, 0.5f);
  Image biased = truth;
  offset_block(biased, 16, 16, 32, 32, 0.01f);
  const Image off1 = noisy(truth, rng), on1 = noisy(biased, rng), off2 = noisy(truth, rng),
              on2 = noisy(biased, rng);
  const BiasEstimate b = estimate_bias(off1, on1, off2, on2);
  EXPECT_EQ(b.worst_tile_x, 16);
  EXPECT_EQ(b.worst_tile_y, 16);
  EXPECT_NEAR(b.worst_tile_psnr, 40.0, 1.5);
  EXPECT_NEAR(b.noise_psnr, 10.0 * std::log10(1.0 / (2.0 * 0.02 * 0.02)), 0.5);
  EXPECT_GT(b.psnr, 45.0) << "a sixth of the image at 40 dB, the rest unbiased";
  EXPECT_LT(compare_images(on1, off1).worst_tile_psnr, 33.0) << "the same-seed figure is the noise";

  const BiasEstimate none =
      estimate_bias(noisy(truth, rng), noisy(truth, rng), noisy(truth, rng), noisy(truth, rng));
  EXPECT_GT(none.worst_tile_psnr, 40.0);
  EXPECT_THROW(estimate_bias(off1, on1, off2, flat(40, 32, 0.5f)), Error);
}

}  // namespace
}  // namespace pmc
