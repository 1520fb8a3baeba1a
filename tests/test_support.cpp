// test_support.cpp — see test_support.h.
#include "tests/test_support.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>

namespace pmc::test {

std::string source_path(const std::string& rel) { return std::string(PMC_SOURCE_DIR) + "/" + rel; }

std::string shared_scene(const std::string& rel) {
  return std::string(PMC_SOURCE_DIR) + "/../shared/scenes/" + rel;
}

std::string temp_dir() {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "_" + info->name() : "anon";
  for (char& c : name)
    if (c == '/') c = '_';
  std::filesystem::path dir = std::filesystem::temp_directory_path() / "pmc_tests" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

bool file_exists(const std::string& path) { return std::filesystem::exists(path); }

int run_pmc(const std::string& args, std::string* output) {
  std::string cmd = std::string(PMC_BINARY) + " " + args + " 2>&1";
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

}  // namespace pmc::test
