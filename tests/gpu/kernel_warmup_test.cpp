// kernel_warmup_test.cpp — the kernel warm-up covers every work-group
// function the render then launches (gpu/wave_kernels.h), on PoCL.
//
// PoCL compiles a work-group function per kernel, work-group size and grid
// class (narrower than 65535 work-items, or wider) at its first launch, and
// keeps each in its kernel cache folder (POCL_CACHE_DIR) as a .so file. With
// an empty folder, the files present when rendering starts (the progress
// callback's 0 samples done, before the film and table are cleared) are
// those the warm-up compiled; a file that appears later was compiled inside
// render_seconds. The render below has
// grids of both classes: 76800 paths per wave, 1200 shade batches.
//
// PoCL reads POCL_CACHE_DIR when the process first opens OpenCL: ctest runs
// every test in its own process, so this one sets it before anything opens
// a device, and fails with a message if PoCL did not take it.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <set>
#include <string>

#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

namespace fs = std::filesystem;

std::set<std::string> compiled_kernels(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".so")
      out.insert(fs::relative(e.path(), dir).string());
  return out;
}

bool holds_files(const fs::path& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) return true;
  return false;
}

std::string list(const std::set<std::string>& files) {
  std::string s;
  for (const std::string& f : files) s += "\n  " + f;
  return s;
}

TEST(KernelWarmUp, RenderCompilesNothingAfterTheWarmUp) {
  const fs::path cache = fs::path(test::temp_dir()) / "pocl-kernel-cache";
  fs::remove_all(cache);
  fs::create_directories(cache);
  ASSERT_EQ(0, setenv("POCL_CACHE_DIR", cache.c_str(), 1));

  RenderConfig c = test::default_scene_config(320, 240, 2);
  c.cache = true;
  // At 2 spp no point would pay under the cost model, and the cache's kernels are what is tested.
  c.cache_model = CacheModel::Nodes;
  RenderSession session(c);
  ASSERT_TRUE(holds_files(cache))  // the program's build is cached there
      << "PoCL did not use POCL_CACHE_DIR=" << cache
      << ": OpenCL was opened before this test set it (run the test in its own process, as ctest does)";

  std::set<std::string> at_start;
  int calls_at_zero = 0;
  RenderOutput out = session.render([&](int done, int total, uint64_t rays) {
    if (done != 0) return;
    ++calls_at_zero;
    EXPECT_EQ(total, 2);
    EXPECT_EQ(rays, 0u);
    at_start = compiled_kernels(cache);
  });
  ASSERT_EQ(calls_at_zero, 1);
  ASSERT_GT(test::image_mean(out.image), 0.0);
  const std::set<std::string> at_end = compiled_kernels(cache);
  EXPECT_EQ(at_start, at_end) << "compiled while rendering; before:" << list(at_start)
                              << "\nafter:" << list(at_end);
}

}  // namespace
}  // namespace pmc
