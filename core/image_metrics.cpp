// image_metrics.cpp — RMSE, relMSE, PSNR, max error, difference images.
//
// The errors come from one pass of our own (the worst tiles from a second): relMSE and the clamped PSNR
// (999 dB for identical images) are pmc's conventions, which
// OpenImageIO's ImageBufAlgo::compare does not compute; the difference image
// is the scaled absolute difference of the tone-mapped images.
#include "core/image_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/tone_map.h"

namespace pmc {
namespace {

// PSNR with peak 1 of a mean squared error; identical images (0): 999 dB.
double psnr_of(double mse) { return mse > 0 ? 10.0 * std::log10(1.0 / mse) : 999.0; }

}  // namespace

ImageError compare_images(const Image& t, const Image& r) {
  if (t.width != r.width || t.height != r.height || t.channels != r.channels ||
      t.pixels.size() != r.pixels.size())
    fail("image comparison: sizes differ (", t.width, "x", t.height, "x", t.channels, " vs ", r.width, "x",
         r.height, "x", r.channels, ")");
  ImageError e;
  double se = 0, rel = 0, se_clamped = 0;
  const size_t n = t.pixels.size();
  for (size_t i = 0; i < n; ++i) {
    double a = t.pixels[i], b = r.pixels[i];
    if (!std::isfinite(a) || !std::isfinite(b)) {
      e.max_abs = INFINITY;
      continue;
    }
    double d = a - b;
    se += d * d;
    rel += d * d / (b * b + 0.01);
    double dc = std::clamp(a, 0.0, 1.0) - std::clamp(b, 0.0, 1.0);
    se_clamped += dc * dc;
    e.max_abs = std::max(e.max_abs, std::fabs(d));
  }
  e.rmse = n ? std::sqrt(se / double(n)) : 0.0;
  e.relmse = n ? rel / double(n) : 0.0;
  double mse_c = n ? se_clamped / double(n) : 0.0;
  e.psnr = psnr_of(mse_c);
  // Per-tile clamped squared error; the worst tile has the largest mean.
  const int tiles_x = (t.width + kMetricTile - 1) / kMetricTile,
            tiles_y = (t.height + kMetricTile - 1) / kMetricTile;
  std::vector<double> tile_se(size_t(tiles_x) * size_t(tiles_y), 0.0);
  std::vector<size_t> tile_n(tile_se.size(), 0), tile_pixels(tile_se.size(), 0);
  // Each tile's kTrimPixels largest per-pixel errors (summed over channels), largest first.
  std::vector<std::array<double, kTrimPixels>> tile_top(tile_se.size());
  for (auto& top : tile_top) top.fill(0.0);
  const size_t c = size_t(t.channels);
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      const size_t tile = size_t(y / kMetricTile) * size_t(tiles_x) + size_t(x / kMetricTile);
      double pixel_se = 0.0;
      for (size_t k = 0; k < c; ++k) {
        const size_t i = (size_t(y) * size_t(t.width) + size_t(x)) * c + k;
        double a = t.pixels[i], b = r.pixels[i];
        double dc =
            std::isfinite(a) && std::isfinite(b) ? std::clamp(a, 0.0, 1.0) - std::clamp(b, 0.0, 1.0) : 1.0;
        pixel_se += dc * dc;
        tile_n[tile] += 1;
      }
      tile_se[tile] += pixel_se;
      tile_pixels[tile] += 1;
      std::array<double, kTrimPixels>& top = tile_top[tile];
      for (size_t j = 0; j < top.size(); ++j)
        if (pixel_se > top[j]) std::swap(pixel_se, top[j]);  // insert, pushing the smaller ones down
    }
  double worst = 0.0, worst_trimmed = 0.0;
  for (size_t i = 0; i < tile_se.size(); ++i) {
    const int tx = int(i % size_t(tiles_x)) * kMetricTile, ty = int(i / size_t(tiles_x)) * kMetricTile;
    const double mse = tile_n[i] ? tile_se[i] / double(tile_n[i]) : 0.0;
    if (mse > worst) {
      worst = mse;
      e.worst_tile_x = tx;
      e.worst_tile_y = ty;
    }
    double trimmed = mse;
    if (tile_pixels[i] >= 3 * size_t(kTrimPixels)) {
      double se_kept = tile_se[i];
      for (double v : tile_top[i]) se_kept -= v;
      const size_t n_kept = tile_n[i] - size_t(kTrimPixels) * c;
      trimmed = std::max(se_kept, 0.0) / double(n_kept);
    }
    if (trimmed > worst_trimmed) {
      worst_trimmed = trimmed;
      e.worst_trimmed_tile_x = tx;
      e.worst_trimmed_tile_y = ty;
    }
  }
  e.worst_tile_psnr = psnr_of(worst);
  e.worst_trimmed_tile_psnr = psnr_of(worst_trimmed);
  return e;
}

BiasEstimate estimate_bias(const Image& off1, const Image& on1, const Image& off2, const Image& on2) {
  for (const Image* im : {&on1, &off2, &on2})
    if (im->width != off1.width || im->height != off1.height || im->channels != off1.channels ||
        im->pixels.size() != off1.pixels.size())
      fail("bias estimate: sizes differ (", im->width, "x", im->height, "x", im->channels, " vs ", off1.width,
           "x", off1.height, "x", off1.channels, ")");
  auto clamped = [](float v) { return std::isfinite(v) ? std::clamp(double(v), 0.0, 1.0) : 0.0; };
  const int tiles_x = (off1.width + kMetricTile - 1) / kMetricTile,
            tiles_y = (off1.height + kMetricTile - 1) / kMetricTile;
  std::vector<double> tile_sum(size_t(tiles_x) * size_t(tiles_y), 0.0);
  std::vector<size_t> tile_n(tile_sum.size(), 0);
  double sum = 0.0, noise = 0.0;
  const size_t c = size_t(off1.channels);
  for (int y = 0; y < off1.height; ++y)
    for (int x = 0; x < off1.width; ++x) {
      const size_t tile = size_t(y / kMetricTile) * size_t(tiles_x) + size_t(x / kMetricTile);
      for (size_t k = 0; k < c; ++k) {
        const size_t i = (size_t(y) * size_t(off1.width) + size_t(x)) * c + k;
        const double a = clamped(off1.pixels[i]), b = clamped(off2.pixels[i]);
        const double product = (clamped(on1.pixels[i]) - a) * (clamped(on2.pixels[i]) - b);
        tile_sum[tile] += product;
        tile_n[tile] += 1;
        sum += product;
        noise += (a - b) * (a - b);
      }
    }
  const size_t n = off1.pixels.size();
  BiasEstimate e;
  e.psnr = psnr_of(n ? sum / double(n) : 0.0);
  e.noise_psnr = psnr_of(n ? noise / double(n) : 0.0);
  double worst = 0.0;
  for (size_t i = 0; i < tile_sum.size(); ++i) {
    const double mean = tile_n[i] ? tile_sum[i] / double(tile_n[i]) : 0.0;
    if (mean > worst) {
      worst = mean;
      e.worst_tile_x = int(i % size_t(tiles_x)) * kMetricTile;
      e.worst_tile_y = int(i / size_t(tiles_x)) * kMetricTile;
    }
  }
  e.worst_tile_psnr = psnr_of(worst);
  return e;
}

Image difference_image(const Image& a, const Image& b, float scale) {
  if (a.pixels.size() != b.pixels.size()) fail("difference image: sizes differ");
  Image diff = tone_map_image(a);
  const Image tb = tone_map_image(b);
  for (size_t i = 0; i < diff.pixels.size(); ++i)
    diff.pixels[i] = std::min(std::fabs(diff.pixels[i] - tb.pixels[i]) * scale, 1.0f);
  return diff;
}

}  // namespace pmc
