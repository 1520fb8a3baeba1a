// fuzz_mtlx.cpp — libFuzzer target for MaterialX reading and compilation
// (materials/mtlx_reader.cpp, passes.cpp, cache_plan.cpp, compiler.cpp) and
// the bytecode interpreter (core/device/pmc_interp.h) on what the compiler
// emits; the checks live in harness.h (check_mtlx). Bad input must end in
// pmc::Error; a crash, a sanitizer report or an uncaught exception is a
// finding.
#include <cstdio>
#include <cstdlib>

#include "tests/fuzz/harness.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string problem = pmc::fuzz::check_mtlx(data, size);
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_mtlx: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
