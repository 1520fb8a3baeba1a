// test_support.h — shared helpers for the test suite: paths, temp dirs,
// tiny scene writers, running the pmc binary, one shared OpenCL context.
#pragma once

#include <string>

#include "core/image_io.h"
#include "gpu/cl_context.h"

namespace pmc::test {

// ../shared/scenes/<rel> next to the repository.
std::string shared_scene(const std::string& rel);
std::string source_path(const std::string& rel);
// A fresh empty directory under the build's temp area, named after the test.
std::string temp_dir();
void write_file(const std::string& path, const std::string& text);
bool file_exists(const std::string& path);
// Runs build/pmc with `args`; returns the exit code, output in `output`.
int run_pmc(const std::string& args, std::string* output = nullptr);
// One OpenCL context (PoCL on CI) reused by all tests.
const ClContext& cl();
// Mean of all channels, and counts of non-finite values.
double image_mean(const Image& img);
size_t non_finite(const Image& img);

}  // namespace pmc::test
