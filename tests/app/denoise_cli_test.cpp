// denoise_cli_test.cpp — `pmc render --denoise`, `pmc denoise` and `pmc compare --denoise`
// through the pmc binary.
//
// Independent answers: the file names the issue fixes (OUT.exr/.png denoised,
// OUT.noisy.exr/.png as rendered, with albedo.R/G/B and N.X/Y/Z layers), the
// render's own denoised image for `pmc denoise` of its noisy frame, a
// reference render for compare's column, and for bad input: exit code 2, a
// message naming the file or what to install, and no output file left
// behind. OIDN comes from scripts/setup (.venv), so this file is not part of
// pmc_device_tests.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>

#include "core/image_backend.h"
#include "core/image_io.h"
#include "tests/support/exr_channels.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

std::string room_args() {
  return test::source_path("data/default/room.obj") + " --mtlx " +
         test::source_path("data/default/materials.mtlx") +
         " --width 40 --height 24 --spp 6 --max-depth 4 --quiet";
}

using test::exr_channels;

void render(const std::string& args) {
  std::string log;
  ASSERT_EQ(test::run_pmc("render " + args, &log), 0) << log;
}

TEST(DenoiseCli, DenoiseWritesTheDenoisedAndTheNoisyImagesSideBySide) {
  const std::string d = test::temp_dir();
  render(room_args() + " --denoise -o " + d + "/out.exr");
  for (const char* f : {"/out.exr", "/out.png", "/out.noisy.exr", "/out.noisy.png"})
    EXPECT_TRUE(test::file_exists(d + f)) << f;
  const auto clean = exr_channels(d + "/out.exr"), noisy = exr_channels(d + "/out.noisy.exr");
  for (const char* c : {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z"})
    EXPECT_TRUE(clean.count(c)) << "no channel " << c;
  EXPECT_FALSE(clean.at("R") == noisy.at("R"));
  EXPECT_TRUE(clean.at("N.X") == noisy.at("N.X"));

  // pmc denoise on the noisy frame gives the render's denoised image.
  std::string log;
  ASSERT_EQ(test::run_pmc("denoise " + d + "/out.noisy.exr -o " + d + "/again.exr", &log), 0) << log;
  for (const char* f : {"/again.exr", "/again.png", "/again.noisy.exr", "/again.noisy.png"})
    EXPECT_TRUE(test::file_exists(d + f)) << f;
  const auto again = exr_channels(d + "/again.exr");
  double diff = 0, mag = 0;
  for (size_t i = 0; i < again.at("R").size(); ++i) {
    diff += std::abs(again.at("R")[i] - clean.at("R")[i]);
    mag += std::abs(clean.at("R")[i]);
  }
  EXPECT_LT(diff, 1e-3 * mag);  // OIDN may differ in the last bits between runs
  EXPECT_TRUE(exr_channels(d + "/again.noisy.exr").at("R") == noisy.at("R"));
}

TEST(DenoiseCli, CompareGainsADenoisedColumnCloserToTheReference) {
  const std::string d = test::temp_dir();
  std::string log;
  ASSERT_EQ(test::run_pmc("compare " + test::source_path("data/default/room.obj") + " --mtlx " +
                              test::source_path("data/default/materials.mtlx") +
                              " --width 64 --height 36 --spp 8 --max-depth 4 --reference-spp 256 --denoise "
                              "--quiet --out-dir " +
                              d + "/cmp",
                          &log),
            0)
      << log;
  EXPECT_TRUE(test::file_exists(d + "/cmp/cache_on_denoised.png"));
  EXPECT_TRUE(test::file_exists(d + "/cmp/cache_on_denoised.exr"));
  const nlohmann::json m = nlohmann::json::parse(test::read_file(d + "/cmp/metrics.json"));
  EXPECT_LT(m["denoised_vs_reference"]["relmse"].get<double>(),
            m["cached_vs_reference"]["relmse"].get<double>());
  EXPECT_NE(test::read_file(d + "/cmp/report.md").find("cache_on_denoised.png"), std::string::npos);
}

TEST(DenoiseCli, BadDenoiseInputsAndAMissingOidnFailNamingTheCauseAndWriteNothing) {
  const std::string d = test::temp_dir();
  std::string log;
  auto nothing_written = [&](const std::string& stem) {
    for (const char* ext : {".exr", ".png", ".noisy.exr", ".noisy.png"})
      EXPECT_FALSE(test::file_exists(d + "/" + stem + ext)) << stem << ext;
  };
  // No passes in the input.
  render(room_args() + " -o " + d + "/plain.exr");
  EXPECT_EQ(test::run_pmc("denoise " + d + "/plain.exr -o " + d + "/x.exr", &log), 2) << log;
  EXPECT_NE(log.find(d + "/plain.exr"), std::string::npos) << log;
  EXPECT_NE(log.find("albedo.R"), std::string::npos) << log;
  nothing_written("x");
  // A window of a frame, not a whole frame.
  render(room_args() + " --aov albedo,normal --crop 0,0,20,12 -o " + d + "/tile.exr");
  EXPECT_EQ(test::run_pmc("denoise " + d + "/tile.exr -o " + d + "/y.exr", &log), 2) << log;
  EXPECT_NE(log.find("not a whole frame"), std::string::npos) << log;
  nothing_written("y");
  // Not an image.
  test::write_file(d + "/junk.exr", "not an exr");
  EXPECT_EQ(test::run_pmc("denoise " + d + "/junk.exr -o " + d + "/z.exr", &log), 2) << log;
  nothing_written("z");
  // A bad pass list, and --denoise on a part.
  EXPECT_EQ(test::run_pmc("render " + room_args() + " --aov albedo,shadows -o " + d + "/w.exr", &log), 2);
  EXPECT_NE(log.find("shadows"), std::string::npos) << log;
  EXPECT_EQ(test::run_pmc("render " + room_args() + " --denoise --samples 0:3 -o " + d + "/w.exr", &log), 2);
  EXPECT_NE(log.find("pmc denoise"), std::string::npos) << log;
  nothing_written("w");
  // OIDN missing: checked before the render, naming what to install.
  setenv("PMC_OIDN_LIBRARY", (d + "/no/libOpenImageDenoise.so.2").c_str(), 1);
  const int render_code = test::run_pmc("render " + room_args() + " --denoise -o " + d + "/v.exr", &log);
  const std::string render_log = log;
  const int denoise_code = test::run_pmc("denoise " + d + "/plain.exr -o " + d + "/u.exr", &log);
  unsetenv("PMC_OIDN_LIBRARY");
  EXPECT_EQ(render_code, 2) << render_log;
  EXPECT_NE(render_log.find("pyoidn"), std::string::npos) << render_log;
  EXPECT_NE(render_log.find("scripts/setup"), std::string::npos) << render_log;
  EXPECT_NE(render_log.find("--denoise: "), std::string::npos)
      << render_log;  // the flag, as the user wrote it
  EXPECT_EQ(denoise_code, 2) << log;
  EXPECT_NE(log.find("pyoidn"), std::string::npos) << log;
  nothing_written("v");
  nothing_written("u");
}

}  // namespace
}  // namespace pmc
