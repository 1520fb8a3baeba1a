// background_test.cpp — Background<T> (core/background.h): a value comes back,
// an exception comes back unchanged (type and message), the thread limit
// holds (one allowed thread: the job runs on the caller's thread), and the
// destructor waits for a job nobody asked for.
#include "core/background.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include "core/error.h"

namespace pmc {
namespace {

TEST(Background, ReturnsTheValueAndHowLongItTook) {
  Background<std::unique_ptr<std::string>> job([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return std::make_unique<std::string>("done");
  });
  std::unique_ptr<std::string> v = job.get();
  ASSERT_TRUE(v);
  EXPECT_EQ(*v, "done");
  EXPECT_GE(job.seconds(), 0.015);
}

TEST(Background, RethrowsTheJobsExceptionWithItsTypeAndMessage) {
  Background<int> config_job([]() -> int { fail_config("--device: no OpenCL device matches 'x'"); });
  try {
    config_job.get();
    FAIL() << "no exception";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--device: no OpenCL device matches 'x'"), std::string::npos)
        << e.what();
  }
  Background<int> error_job([]() -> int { fail("scene.obj: cannot open OBJ file"); });
  try {
    error_job.get();
    FAIL() << "no exception";
  } catch (const ConfigError&) {
    FAIL() << "a pmc::Error must not come back as a ConfigError";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "scene.obj: cannot open OBJ file");
  }
}

TEST(Background, OneAllowedThreadRunsTheJobOnTheCallersThread) {
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  Background<std::thread::id> job([] { return std::this_thread::get_id(); });
  EXPECT_EQ(job.get(), std::this_thread::get_id());
}

TEST(Background, TheDestructorWaitsForTheJob) {
  std::atomic<bool> finished{false};
  {
    Background<int> job([&finished] {
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
      finished = true;
      return 1;
    });
  }
  EXPECT_TRUE(finished.load());
}

}  // namespace
}  // namespace pmc
