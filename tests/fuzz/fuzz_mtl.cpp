// fuzz_mtl.cpp — libFuzzer target for MTL files: tinyobjloader's MTL parser
// (through core/obj_loader.cpp), the MTL -> network conversion
// (materials/mtl_graph.cpp), material binding and compilation
// (materials/material_set.cpp, compiler.cpp) with the cache off and on, and
// the host interpreter, cut-out tester and light table on the result. The
// input is the scene.mtl of a fixed OBJ; the checks live in harness.h
// (check_mtl). Bad input must end in pmc::Error; a crash, a sanitizer
// report, an uncaught exception, a refused valid OBJ or a material set that
// does not match its MTL is a finding.
#include <cstdio>
#include <cstdlib>

#include "tests/fuzz/harness.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string problem = pmc::fuzz::check_mtl(data, size);
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_mtl: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
