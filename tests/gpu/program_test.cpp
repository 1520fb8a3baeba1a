// program_test.cpp — kernel sources: embedding, include expansion, build errors.
#include "gpu/program.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

TEST(Program, EmbedsAndExpandsIncludesWithLineDirectives) {
  std::string src = expand_kernel_source("pmc_kernels.cl");
  EXPECT_NE(src.find("#line 1 \"pmc_types.h\""), std::string::npos);
  EXPECT_NE(src.find("__kernel void pmc_shade"), std::string::npos);
  // pmc_vec.h is included by several headers but expanded once.
  size_t first = src.find("#line 1 \"pmc_vec.h\"");
  ASSERT_NE(first, std::string::npos);
  EXPECT_EQ(src.find("#line 1 \"pmc_vec.h\"", first + 1), std::string::npos);
}

TEST(Program, BuildFailureCarriesTheCompilerLog) {
  try {
    ClProgram::from_text(test::cl(), "broken.cl",
                         "__kernel void k(__global int* x) { x[0] = undefined_name; }\n");
    FAIL() << "a broken kernel must not build";
  } catch (const Error& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("broken.cl"), std::string::npos) << what;
    EXPECT_NE(what.find("undefined_name"), std::string::npos) << what;
  }
}

TEST(Program, MissingKernelSourceIsAnError) { EXPECT_THROW(expand_kernel_source("no_such_file.cl"), Error); }

}  // namespace
}  // namespace pmc
