// fuzz_obj.cpp — libFuzzer target for the OBJ loader (core/obj_parser.cpp and
// core/obj_loader.cpp; tinyobjloader reads the MTL); the checks live in harness.h (check_obj).
// Bad input must end in pmc::Error; anything else — a crash, a sanitizer
// report, an uncaught exception, a Scene whose triangles index outside its
// arrays or keep non-finite data — is a finding.
#include <cstdio>
#include <cstdlib>

#include "tests/fuzz/harness.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string problem = pmc::fuzz::check_obj(data, size);
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_obj: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
