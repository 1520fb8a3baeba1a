// test_support.h — shared helpers for the test suite: paths, temp dirs,
// writing files, running the pmc binary, one shared OpenCL context.
//
// Third-party scenes: tests that need them (Sponza, the MaterialX examples,
// the Cornell box, ...) find them through shared_scene(), in one place: the
// folder named by the PMC_SCENES environment variable, else ../shared/scenes
// next to the repository. They are not part of the repository; when the
// folder is missing, shared_scene() fails the test with a message that says
// how to provide it.
//
// Where a test binary runs away from its build (scripts/gpu-bundle's
// tarball on a GPU machine), PMC_TEST_SOURCE_DIR, PMC_TEST_BINARY_DIR and
// PMC_TEST_PMC replace the source folder, build folder and pmc binary that
// were compiled in.
#pragma once

#include <string>

#include "core/image_io.h"
#include "gpu/cl_context.h"
#include "gpu/render_config.h"

namespace pmc::test {

// The third-party scenes' folder: $PMC_SCENES, else ../shared/scenes next to the repository.
std::string scenes_dir();
// scenes_dir()/<rel>; fails the current test (saying how to get the scenes)
// when the scenes' folder or `rel` in it does not exist.
std::string shared_scene(const std::string& rel);
// <source folder>/<rel>: $PMC_TEST_SOURCE_DIR, else the checkout built from.
std::string source_path(const std::string& rel);
// The build's folder for test files (build/test_tmp): per checkout, so the
// test runs of several checkouts on one machine never share a folder.
std::string temp_root();
// A fresh empty directory under temp_root(), named after the test.
std::string temp_dir();
// Writes `text` to `path`, creating its folders; a failed write fails the test.
void write_file(const std::string& path, const std::string& text);
// The whole file as bytes (empty when it cannot be read).
std::string read_file(const std::string& path);
bool file_exists(const std::string& path);
// Runs pmc ($PMC_TEST_PMC, else the build's) with `args`; returns the exit code, output in `output`.
int run_pmc(const std::string& args, std::string* output = nullptr);
// One OpenCL context (PoCL on CI) reused by all tests.
const ClContext& cl();
// Mean of all channels, and counts of non-finite values.
double image_mean(const Image& img);
size_t non_finite(const Image& img);
// Values (pixel channels) that differ between two images of the same size.
size_t differing_values(const Image& a, const Image& b);
// The bundled default scene (data/default) at this size, path length 4,
// cache points by node count (cache_model nodes).
RenderConfig default_scene_config(int width, int height, int spp);
// The shared brick teapot (M_BrickPattern, one uv cache point) seen close up
// under a white environment, 40x30, path length 3, cache_eval center.
RenderConfig brick_teapot_config(int spp);

}  // namespace pmc::test
