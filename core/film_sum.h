// film_sum.h — a render's film as exact per-pixel sums, and the images they make.
//
// The film kernel adds each sample's radiance as a 128-bit fixed-point number
// (core/device/pmc_film.h), so a film is exact: the films of sample ranges
// [0,4) and [4,16) add to the film of [0,16) bit for bit, whatever the order.
// WavefrontRenderer::render fills a FilmSums for the window it rendered;
// `pmc merge` reads them back from part EXRs (core/render_part.h), adds them
// with add_film() and resolves the sum with film_mean(), the same function a
// one-process render uses, so a merged image equals it bit for bit.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image_io.h"

namespace pmc {

struct FilmSums {
  int width = 0, height = 0;      // pixels (the window when cropped)
  std::vector<uint32_t> sum;      // 12 words per pixel: rgb, each 4 words of a Q63.64 number
  std::vector<uint32_t> samples;  // samples drawn per pixel
  std::vector<uint32_t> bad;      // of those, dropped as NaN/Inf/|v| >= 2^62
  std::vector<uint32_t> hits;     // cache points found by its samples

  static constexpr int kWords = 12;
  size_t pixels() const { return size_t(width) * size_t(height); }
  // An empty film of w x h pixels.
  static FilmSums zero(int w, int h);
};

// Adds `part` into `into` with its top-left pixel at (x0, y0) of `into`
// (the part must fit). Integer additions: exact and order-independent.
void add_film(FilmSums& into, const FilmSums& part, int x0, int y0);
// The mean of each pixel's good samples (0 where there are none), rgb.
Image film_mean(const FilmSums& film);
// Cache points found per sample, per pixel (1 channel).
Image film_hitmap(const FilmSums& film);
// One channel's sum as a long double (tests, stats).
long double film_channel_sum(const FilmSums& film, size_t pixel, int channel);

}  // namespace pmc
