// background.h — one piece of host setup work run beside the caller's.
//
// Background<T> job([] { return ...; }) hands the function to TBB (a
// tbb::task_group), so it runs on a TBB worker while the caller goes on, and
// the thread limit (the threads setting, tbb::global_control) holds: with one thread
// there is no worker, and the function runs on the caller's thread when it
// asks for the result. get() waits and returns the value, or rethrows the
// function's exception unchanged (same type, same message), so an error on
// the background reads exactly as it would have without it. The destructor
// waits too: no job outlives what it reads. In a ThreadSanitizer build the
// function runs inside get(), serially (see core/parallel.h for why).
// seconds() is how long the function itself ran (wall clock, on its thread).
#pragma once

#include <chrono>
#include <exception>
#include <functional>
#include <optional>
#include <utility>

#include "core/sanitizers.h"

#ifndef PMC_UNDER_TSAN
#include <tbb/task_group.h>
#endif

namespace pmc {

template <typename T>
class Background {
 public:
  template <typename Fn>
  explicit Background(Fn fn) : fn_(std::move(fn)) {
#ifndef PMC_UNDER_TSAN
    group_.run([this] { run(); });
#endif
  }
  ~Background() { finish(); }
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;

  // Waits for the function; its value (moved out: call once), or its exception.
  T get() {
    finish();
    if (error_) std::rethrow_exception(error_);
    return std::move(*value_);
  }
  double seconds() const { return seconds_; }

 private:
  void run() {
    const auto start = std::chrono::steady_clock::now();
    try {
      value_.emplace(fn_());
    } catch (...) {
      error_ = std::current_exception();
    }
    seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  void finish() {
#ifdef PMC_UNDER_TSAN
    if (!ran_) run();
    ran_ = true;
#else
    group_.wait();  // run() catches everything, so this does not throw
#endif
  }

  std::function<T()> fn_;
  std::optional<T> value_;
  std::exception_ptr error_;
  double seconds_ = 0.0;
#ifdef PMC_UNDER_TSAN
  bool ran_ = false;
#else
  tbb::task_group group_;
#endif
};

}  // namespace pmc
