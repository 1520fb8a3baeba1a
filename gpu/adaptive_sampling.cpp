// adaptive_sampling.cpp — per-pixel error estimates and the active pixel list.
#include "gpu/adaptive_sampling.h"

#include <algorithm>
#include <cmath>

#include "core/film_sum.h"

namespace pmc {

namespace {
constexpr double kRelativeFloor = 0.01;  // added to mean^2, as bench's relMSE adds it to ref^2
}

bool adaptive_pixel_converged(const PmcFilmPixel& px, uint32_t samples, double threshold) {
  const uint32_t good = samples - std::min(px.bad_samples, samples);
  if (good < 2) return false;
  const double n = double(good);
  double grey_sum = 0.0;
  for (int c = 0; c < 3; ++c) grey_sum += double(fixed_sum_value(&px.sum[4 * c]));
  const double mean = grey_sum / 3.0 / n;
  // Sample variance of the grey value; the float sum of squares can round below mean^2.
  const double var = std::max(0.0, (double(px.grey_sq_sum) - n * mean * mean) / (n - 1.0));
  const double rel_sq = var / n / (mean * mean + kRelativeFloor);
  return rel_sq < threshold * threshold;
}

AdaptiveSampler::AdaptiveSampler(size_t pixels, double threshold, int check_every)
    : threshold_(threshold),
      check_every_(std::max(1, check_every)),
      active_(pixels),
      samples_(pixels, 0u),
      passed_(pixels, 0u) {
  for (size_t i = 0; i < pixels; ++i) active_[i] = uint32_t(i);
}

int AdaptiveSampler::samples_to_next_check(int done) const {
  if (!on()) return 1 << 30;
  return check_every_ - done % check_every_;
}

void AdaptiveSampler::add_samples(int n) {
  for (uint32_t k : active_) samples_[k] += uint32_t(n);
}

size_t AdaptiveSampler::check(const std::vector<PmcFilmPixel>& film) {
  if (!on()) return 0;
  const size_t before = active_.size();
  active_.erase(std::remove_if(active_.begin(), active_.end(),
                               [&](uint32_t k) {
                                 const bool now = adaptive_pixel_converged(film[k], samples_[k], threshold_);
                                 const bool stop = now && passed_[k];
                                 passed_[k] = now ? 1u : 0u;
                                 return stop;
                               }),
                active_.end());
  return before - active_.size();
}

}  // namespace pmc
