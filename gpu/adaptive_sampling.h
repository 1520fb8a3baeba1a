// adaptive_sampling.h — which pixels keep drawing samples (the adaptive_threshold setting).
//
// Every pixel draws `check_every` samples, then, at every multiple of
// `check_every` samples, a pixel whose mean is good enough at this check
// and at the one before stops: its relative standard error,
// sqrt(var / n / (mean^2 + 0.01)) of its grey value ((r + g + b) / 3), is
// below the threshold (the 0.01 is the one bench's relMSE adds to the
// reference's square, so a dark pixel is not sampled without end). var
// comes from the film's exact sums and the sum of squared grey values the
// film kernel keeps beside them (PmcFilmPixel). One check is not enough: a
// pixel whose rare bright paths have not shown up yet looks converged
// (docs/BENCHMARKS.md, "Adaptive sampling"), and stopping it then biases it.
//
// The checks sit at fixed sample counts, not at wave boundaries, and read
// only the pixel's own film, which one work-item adds up in sample order, so
// which pixels stop, and when, is the same for any thread count, wave shape
// or crop window: a window rendered alone (a farm chunk split by crop)
// equals the same pixels of the whole frame. Sample i of a pixel is the same
// sample with or without adaptive sampling (the sampler is keyed by pixel
// and sample index), so a pixel stopped after n samples equals that pixel
// rendered with spp n. Sample ranges (the samples setting) are refused: a
// pixel's later samples depend on its earlier ones.
#pragma once

#include <cstdint>
#include <vector>

#include "core/abi/pmc_types.h"

namespace pmc {

// Whether a pixel that has drawn `samples` samples (film `px`) has its mean
// within `threshold` relative standard error (at least 2 good samples).
bool adaptive_pixel_converged(const PmcFilmPixel& px, uint32_t samples, double threshold);

class AdaptiveSampler {
 public:
  // `pixels` of the window, all active; `threshold` 0: never stops a pixel.
  AdaptiveSampler(size_t pixels, double threshold, int check_every);

  bool on() const { return threshold_ > 0.0; }
  // Samples until the next check from `done` samples (a wave stops there).
  int samples_to_next_check(int done) const;
  // The window indices of the pixels still drawing samples, in window order.
  const std::vector<uint32_t>& active() const { return active_; }
  // Samples each pixel of the window has drawn.
  const std::vector<uint32_t>& samples() const { return samples_; }
  // The active pixels each drew `n` more samples.
  void add_samples(int n);
  // At a check (`done` samples, a multiple of check_every): stops the
  // active pixels whose film (the window's, in window order) is converged
  // now and was at the previous check. Returns how many stopped.
  size_t check(const std::vector<PmcFilmPixel>& film);

 private:
  double threshold_;
  int check_every_;
  std::vector<uint32_t> active_;
  std::vector<uint32_t> samples_;
  std::vector<uint8_t> passed_;  // converged at the previous check
};

}  // namespace pmc
