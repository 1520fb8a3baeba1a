// fuzz_regression_test.cpp — replays fuzzing inputs in the normal test suite.
//
// Every file in tests/fuzz/regressions/{obj,mtlx,mtl,image} (inputs that once
// crashed or misled a fuzz target, kept after the fix) and every seed in
// tests/fuzz/corpus/{obj,mtlx,mtl,image} goes through the same checks as
// the libFuzzer targets (tests/fuzz/harness.h): the input is either loaded
// (and compiled, and interpreted) into something the renderer can trust, or
// refused with pmc::Error — never a crash. Under scripts/sanitize these run
// with AddressSanitizer and UBSan like the fuzz targets do.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/fuzz/harness.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

std::vector<std::string> files_in(const std::string& rel) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(test::source_path(rel), ec))
    if (e.is_regular_file() && e.path().filename().string()[0] != '.' && e.path().extension() != ".md")
      out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

void replay(const std::string& kind, std::string (*check)(const uint8_t*, size_t)) {
  size_t n = 0;
  for (const char* where : {"tests/fuzz/regressions/", "tests/fuzz/corpus/"})
    for (const std::string& f : files_in(where + kind)) {
      SCOPED_TRACE(f);
      std::string data = test::read_file(f);
      EXPECT_EQ(check(reinterpret_cast<const uint8_t*>(data.data()), data.size()), "");
      ++n;
    }
  EXPECT_GE(n, 5u) << "the seed corpus for " << kind << " is missing";
  ::testing::Test::RecordProperty(kind + "_inputs", int(n));
}

TEST(FuzzRegression, ObjInputsLoadOrFailCleanly) { replay("obj", &fuzz::check_obj); }

TEST(FuzzRegression, MaterialXInputsCompileOrFailCleanly) { replay("mtlx", &fuzz::check_mtlx); }

TEST(FuzzRegression, MtlInputsCompileOrFailCleanly) { replay("mtl", &fuzz::check_mtl); }

TEST(FuzzRegression, ImageInputsReadOrFailCleanly) { replay("image", &fuzz::check_image); }

}  // namespace
}  // namespace pmc
