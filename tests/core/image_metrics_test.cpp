// image_metrics_test.cpp — whole-image and worst-tile errors (core/image_metrics.h).
//
// Two 40x36 images equal but for one 16x16 tile (and, separately, a partial
// tile at the bottom-right edge) offset by 0.1: the worst tile's clamped PSNR
// is exactly 20 dB there, the whole image's follows from the fraction of
// changed pixels, and identical images report 999 dB.
#include "core/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace pmc
