// stage_timer.h — where a render's time goes, per pipeline stage.
//
// Host stages (Embree tracing, transfers) are timed with a scoped wall-clock
// timer; device stages (kernels) with OpenCL's profiling events, whose times
// are summed once the wave is done. On a CPU device both run on the same
// cores, so the two kinds of time can overlap and their sum may exceed the
// render's wall time.
#pragma once

#include <chrono>
#include <utility>
#include <vector>

#include "gpu/cl_context.h"

namespace pmc {

// Adds the wall time of its scope to `seconds`.
class ScopedStage {
 public:
  explicit ScopedStage(double& seconds) : seconds_(seconds), t0_(std::chrono::steady_clock::now()) {}
  ~ScopedStage() {
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;

 private:
  double& seconds_;
  std::chrono::steady_clock::time_point t0_;
};

// Device time of enqueued commands, summed per stage when they have finished.
class DeviceStageLog {
 public:
  ~DeviceStageLog() { collect(); }
  // An event slot to pass to an enqueue call; its time goes to `seconds`.
  cl_event* add(double& seconds) {
    events_.push_back({nullptr, &seconds});
    return &events_.back().first;
  }
  // Call after clFinish (or any wait that covers the events).
  void collect() {
    for (auto& [ev, seconds] : events_) {
      if (!ev) continue;
      cl_ulong t0 = 0, t1 = 0;
      if (clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_START, sizeof(t0), &t0, nullptr) == CL_SUCCESS &&
          clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_END, sizeof(t1), &t1, nullptr) == CL_SUCCESS &&
          t1 >= t0)
        *seconds += double(t1 - t0) * 1e-9;
      clReleaseEvent(ev);
    }
    events_.clear();
  }

 private:
  std::vector<std::pair<cl_event, double*>> events_;
};

}  // namespace pmc
