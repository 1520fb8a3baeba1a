// progress.h — a progress bar on stderr for long renders.
//
// Shows samples done, rays per second and the estimated time left, redrawn in
// place on a terminal and at most every few seconds (one line each) when
// stderr is a file or pipe, so CI logs stay readable. An update with 0 done
// (the renderer's, once its kernels are warmed up) restarts the clock, so the
// rate and the time left count rendering only.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace pmc {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool enabled = true);
  void update(int done, int total, uint64_t rays);
  void finish();

 private:
  std::string label_;
  bool enabled_, tty_;
  std::chrono::steady_clock::time_point start_, last_;
  bool drawn_ = false;
};

}  // namespace pmc
