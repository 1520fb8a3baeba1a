// film_sum.cpp — exact film sums: adding, and the mean they resolve to.
#include "core/film_sum.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace pmc {
namespace {

// Words [w, w + 4) as a signed 128-bit integer.
__int128 fixed_value(const uint32_t* w) {
  unsigned __int128 u = 0;
  for (int k = 3; k >= 0; --k) u = (u << 32) | w[k];
  return __int128(u);
}

// acc += v, four-word two's complement numbers.
void add_fixed(uint32_t* acc, const uint32_t* v) {
  uint64_t carry = 0;
  for (int k = 0; k < 4; ++k) {
    const uint64_t t = uint64_t(acc[k]) + uint64_t(v[k]) + carry;
    acc[k] = uint32_t(t);
    carry = t >> 32;
  }
}

}  // namespace

FilmSums FilmSums::zero(int w, int h, bool passes) {
  FilmSums f;
  f.width = w;
  f.height = h;
  const size_t n = f.pixels();
  f.sum.assign(n * kWords, 0u);
  f.samples.assign(n, 0u);
  f.bad.assign(n, 0u);
  f.hits.assign(n, 0u);
  if (passes) {
    f.pass_sum.assign(n * kPassWords, 0u);
    f.pass_hits.assign(n, 0u);
    f.pass_material_inv.assign(n, 0u);
  }
  return f;
}

void add_film(FilmSums& into, const FilmSums& part, int x0, int y0) {
  PMC_CHECK(x0 >= 0 && y0 >= 0 && x0 + part.width <= into.width && y0 + part.height <= into.height,
            "film part outside the frame");
  PMC_CHECK(into.has_passes() == part.has_passes(), "film parts with and without passes");
  for (int y = 0; y < part.height; ++y)
    for (int x = 0; x < part.width; ++x) {
      const size_t s = size_t(y) * size_t(part.width) + size_t(x);
      const size_t d = size_t(y + y0) * size_t(into.width) + size_t(x + x0);
      for (int c = 0; c < 3; ++c)
        add_fixed(&into.sum[d * FilmSums::kWords + size_t(4 * c)],
                  &part.sum[s * FilmSums::kWords + size_t(4 * c)]);
      if (part.has_passes()) {
        for (int c = 0; c < FilmSums::kPassWords / 4; ++c)
          add_fixed(&into.pass_sum[d * FilmSums::kPassWords + size_t(4 * c)],
                    &part.pass_sum[s * FilmSums::kPassWords + size_t(4 * c)]);
        into.pass_hits[d] += part.pass_hits[s];
        into.pass_material_inv[d] = std::max(into.pass_material_inv[d], part.pass_material_inv[s]);
      }
      into.samples[d] += part.samples[s];
      into.bad[d] += part.bad[s];
      into.hits[d] += part.hits[s];
    }
}

long double fixed_sum_value(const uint32_t* words) {
  return std::ldexp((long double)fixed_value(words), -64);
}

long double film_channel_sum(const FilmSums& film, size_t pixel, int channel) {
  return fixed_sum_value(&film.sum[pixel * FilmSums::kWords + size_t(4 * channel)]);
}

long double film_pass_sum(const FilmSums& film, size_t pixel, int channel) {
  const __int128 n = fixed_value(&film.pass_sum[pixel * FilmSums::kPassWords + size_t(4 * channel)]);
  return std::ldexp((long double)n, -64);
}

Image film_mean(const FilmSums& film) {
  Image out;
  out.width = film.width;
  out.height = film.height;
  out.channels = 3;
  out.pixels.resize(film.pixels() * 3);
  for (size_t i = 0; i < film.pixels(); ++i) {
    const uint32_t good = film.samples[i] - std::min(film.bad[i], film.samples[i]);
    for (int c = 0; c < 3; ++c)
      out.pixels[3 * i + size_t(c)] =
          good > 0 ? float(film_channel_sum(film, i, c) / (long double)good) : 0.0f;
  }
  return out;
}

Image film_hitmap(const FilmSums& film) {
  Image out;
  out.width = film.width;
  out.height = film.height;
  out.channels = 1;
  out.pixels.resize(film.pixels());
  for (size_t i = 0; i < film.pixels(); ++i)
    out.pixels[i] = film.samples[i] > 0 ? float(film.hits[i]) / float(film.samples[i]) : 0.0f;
  return out;
}

}  // namespace pmc
