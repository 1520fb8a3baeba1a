// progress.cpp — drawing the bar.
#include "app/progress.h"

#include <unistd.h>

#include <cstdio>

namespace pmc {

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), tty_(::isatty(2) != 0) {
  start_ = last_ = std::chrono::steady_clock::now();
}

void ProgressBar::update(int done, int total, uint64_t rays) {
  if (!enabled_ || total <= 0) return;
  auto now = std::chrono::steady_clock::now();
  if (done == 0) {  // rendering starts: rates and time left count from here, not from the warm-up
    start_ = last_ = now;
    return;
  }
  double elapsed = std::chrono::duration<double>(now - start_).count();
  double since_last = std::chrono::duration<double>(now - last_).count();
  if (!tty_ && since_last < 5.0 && done < total) return;
  if (tty_ && since_last < 0.1 && done < total) return;
  last_ = now;
  double frac = double(done) / total;
  double left = frac > 0 ? elapsed * (1.0 - frac) / frac : 0.0;
  double mrays = elapsed > 0 ? rays / elapsed * 1e-6 : 0.0;
  const int width = 30;
  int filled = int(frac * width + 0.5);
  std::string bar(size_t(filled), '#');
  bar.append(size_t(width - filled), '.');
  std::fprintf(stderr, "%s%s [%s] %d/%d spp  %.2f Mrays/s  %.1fs elapsed  %.1fs left%s", tty_ ? "\r" : "",
               label_.c_str(), bar.c_str(), done, total, mrays, elapsed, left, tty_ ? "\033[K" : "\n");
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (enabled_ && drawn_ && tty_) std::fprintf(stderr, "\n");
  drawn_ = false;
}

}  // namespace pmc
