// test_support.cpp — see test_support.h.
#include "tests/support/test_support.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>

namespace pmc::test {
namespace {

std::string env_or(const char* name, const char* compiled_in) {
  const char* env = std::getenv(name);
  return env && *env ? env : compiled_in;
}

std::string source_dir() { return env_or("PMC_TEST_SOURCE_DIR", PMC_SOURCE_DIR); }

// The cache plan's device costs come from the cost model's table, not from a
// calibration of this machine's device (gpu/device_calibration.h), so every
// test (and every pmc it runs) plans the same on any machine. A test of the
// calibration names its folder itself; PMC_CACHE_COSTS set by the caller wins.
[[maybe_unused]] const bool kTableCosts = [] { return setenv("PMC_CACHE_COSTS", "table", 0) == 0; }();

}  // namespace

std::string source_path(const std::string& rel) { return source_dir() + "/" + rel; }

std::string scenes_dir() {
  const char* env = std::getenv("PMC_SCENES");
  if (env && *env) return env;
  return (std::filesystem::path(source_dir()).parent_path() / "shared" / "scenes").string();
}

std::string shared_scene(const std::string& rel) {
  const std::string dir = scenes_dir(), path = dir + "/" + rel;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    ADD_FAILURE()
        << "the third-party test scenes are not at '" << dir
        << "': they are not part of the repository (Crytek Sponza, the MaterialX examples, "
           "Embree's Cornell box, assimp's spider; sources and licences in their README.md). "
           "Put them in ../shared/scenes next to the repository, or set PMC_SCENES to their folder.";
  else if (!std::filesystem::exists(path, ec))
    ADD_FAILURE() << "'" << rel << "' is missing from the test scenes at '" << dir
                  << "' (PMC_SCENES): an incomplete copy? See their README.md.";
  return path;
}

std::string temp_root() { return env_or("PMC_TEST_BINARY_DIR", PMC_BINARY_DIR) + "/test_tmp"; }

std::string temp_dir() {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "_" + info->name() : "anon";
  for (char& c : name)
    if (c == '/') c = '_';
  std::filesystem::path dir = std::filesystem::path(temp_root()) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

void write_file(const std::string& path, const std::string& text) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) ADD_FAILURE() << "cannot write test file " << path;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

bool file_exists(const std::string& path) { return std::filesystem::exists(path); }

int run_pmc(const std::string& args, std::string* output) {
  std::string cmd = env_or("PMC_TEST_PMC", PMC_BINARY) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return -1;
  std::string text;
  std::array<char, 4096> buf{};
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) text.append(buf.data(), n);
  int status = pclose(pipe);
  if (output) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

const ClContext& cl() {
  static ClContext context;
  return context;
}

double image_mean(const Image& img) {
  double sum = 0;
  for (float v : img.pixels) sum += v;
  return img.pixels.empty() ? 0.0 : sum / double(img.pixels.size());
}

size_t non_finite(const Image& img) {
  size_t n = 0;
  for (float v : img.pixels) n += std::isfinite(v) ? 0 : 1;
  return n;
}

size_t differing_values(const Image& a, const Image& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.pixels.size() && i < b.pixels.size(); ++i) n += a.pixels[i] != b.pixels[i] ? 1 : 0;
  return n;
}

RenderConfig brick_teapot_config(int spp) {
  RenderConfig c;
  c.scene = shared_scene("materialx/geometry/teapot.obj");
  c.mtlx = {shared_scene("materialx/standard_surface_brick_procedural.mtlx")};
  c.material = "M_BrickPattern";
  c.env = {1.0f, 1.0f, 1.0f};
  c.camera_from = Vec3{-0.1f, 0.5f, 2.2f};
  c.camera_at = Vec3{-0.1f, 0.1f, 0.0f};
  c.fov = 40.0f;
  c.width = 40;
  c.height = 30;
  c.spp = spp;
  c.max_depth = 3;
  c.cache_eval = CacheEval::Center;
  return c;
}

RenderConfig default_scene_config(int width, int height, int spp) {
  RenderConfig c;
  c.scene = source_path("data/default/room.obj");
  c.mtlx = {source_path("data/default/materials.mtlx")};
  c.width = width;
  c.height = height;
  c.spp = spp;
  c.max_depth = 4;
  // The node count plans: at these small frames and sample counts the cost
  // model would drop most points (or all), and the tests using this config
  // are about the renderer and the cache's mechanics, not the plan.
  c.cache_model = CacheModel::Nodes;
  return c;
}

}  // namespace pmc::test
