// film_sum.h — a render's film as exact per-pixel sums, and the images they make.
//
// The film kernel adds each sample's radiance as a 128-bit fixed-point number
// (core/device/pmc_film.h), so a film is exact: the films of sample ranges
// [0,4) and [4,16) add to the film of [0,16) bit for bit, whatever the order.
// WavefrontRenderer::render fills a FilmSums for the window it rendered;
// `pmc merge` reads them back from part EXRs (core/render_part.h), adds them
// with add_film() and resolves the sum with film_mean(), the same function a
// one-process render uses, so a merged image equals it bit for bit.
// With render passes the film also holds the pass film's exact sums
// (core/device/pmc_passes.h), which add and merge the same way;
// core/render_passes.h resolves them into pass images.
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
  // Render passes (empty without): kPassWords words per pixel (PMC_PASS_CHANNELS
  // channels of 4 words), the samples whose camera ray hit, and the complement
  // of the smallest material id they hit (0: none).
  std::vector<uint32_t> pass_sum;
  std::vector<uint32_t> pass_hits;
  std::vector<uint32_t> pass_material_inv;

  static constexpr int kWords = 12;
  static constexpr int kPassWords = 40;
  size_t pixels() const { return size_t(width) * size_t(height); }
  bool has_passes() const { return !pass_sum.empty(); }
  // An empty film of w x h pixels (with empty pass sums when `passes`).
  static FilmSums zero(int w, int h, bool passes = false);
};

// Adds `part` into `into` with its top-left pixel at (x0, y0) of `into`
// (the part must fit; both with passes or both without). Integer additions
// (and a max for the material): exact and order-independent.
void add_film(FilmSums& into, const FilmSums& part, int x0, int y0);
// The mean of each pixel's good samples (0 where there are none), rgb.
Image film_mean(const FilmSums& film);
// Cache points found per sample, per pixel (1 channel).
Image film_hitmap(const FilmSums& film);
// Four words of a film sum (a Q63.64 number, least significant word first) as a long double.
long double fixed_sum_value(const uint32_t* words);
// One channel's sum as a long double (tests, stats).
long double film_channel_sum(const FilmSums& film, size_t pixel, int channel);
// One pass channel's sum (PMC_PASS_* + component) as a long double.
long double film_pass_sum(const FilmSums& film, size_t pixel, int channel);

}  // namespace pmc
