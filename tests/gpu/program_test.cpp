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

// The device calibration's key hashes kernel_code_of its source: an edit of
// comments or layout must read the same, an edit of the code must not.
TEST(Program, KernelCodeLeavesOutCommentsLayoutAndLineMarkers) {
  const std::string code = kernel_code_of(
      "#line 1 \"a.cl\"\n"
      "/* a header\n   over two lines */\n"
      "int   f(int x) {   // the doubling\n"
      "\n"
      "\treturn 2 * x; /* inline */ }\n");
  EXPECT_EQ(code, "int f(int x) {\nreturn 2 * x; }\n");
  EXPECT_EQ(kernel_code_of("#line 7 \"b.cl\"\n// another comment\nint f(int x) {\n  return 2 * x;\n}\n"),
            "int f(int x) {\nreturn 2 * x;\n}\n");
  EXPECT_NE(kernel_code_of("int f(int x) { return 3 * x; }\n"),
            kernel_code_of("int f(int x) { return 2 * x; }\n"));
  // Comment markers and blanks inside literals are code.
  EXPECT_EQ(kernel_code_of("s = \"a // b /* c */  d\"; // gone\n"), "s = \"a // b /* c */  d\";\n");
  EXPECT_EQ(kernel_code_of("c = '/'; q = \"\\\"//\"; x = a /* y */ / b;\n"),
            "c = '/'; q = \"\\\"//\"; x = a / b;\n");
  // The embedded kernels keep every function; only comments go.
  const std::string kernels = kernel_code_of(expand_kernel_source("pmc_kernels.cl"));
  EXPECT_NE(kernels.find("__kernel void pmc_shade("), std::string::npos);
  EXPECT_EQ(kernels.find("/*"), std::string::npos);
  EXPECT_EQ(kernels.find("#line"), std::string::npos);
}

}  // namespace
}  // namespace pmc
