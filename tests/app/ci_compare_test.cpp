// ci_compare_test.cpp — scripts/ci-compare, the cache quality gate a user's CI
// calls, end to end through the real script and this build's pmc binary.
//
// The gate must pass on a healthy render (the brick teapot at default cache
// settings: about 47 dB PSNR and relMSE 0.0008 vs cacheless at 160x120,
// 8 spp) and must be able to fail: with an impossible
// threshold (--min-psnr 200), and with a realistic threshold (42 dB, relMSE
// 0.0018) when the cache is deliberately broken by a far too coarse virtual
// mip level (--mip-bias -10 stores one value per cache point for the whole
// teapot: the bricks disappear; 37.4 dB, relMSE 0.0082). Usage errors exit
// with 2.
//
// The bias gates (pmc compare --bias: a second seed, the noise taken out):
// measured on PoCL, the teapot's cache bias reads 46.5 dB over the image and
// 37.4 dB in its worst tile (the two cacheless renders' noise floor: 35.9
// dB); with --mip-bias -10, 36.5 and 28.2 dB. Gates of 42 and 33 dB pass the
// first and fail the second on both counts.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/test_support.h"

namespace pmc {
namespace {

struct Result {
  int code = -1;
  std::string output;  // stdout and stderr together
};

// Runs scripts/ci-compare with this build's pmc binary and `args`.
Result ci_compare(const std::string& args) {
  const std::string cmd =
      test::source_path("scripts/ci-compare") + " --pmc " + std::string(PMC_BINARY) + " " + args + " 2>&1";
  Result r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// The brick teapot filling a 160x120 frame, white environment.
std::string teapot() {
  return test::shared_scene("materialx/geometry/teapot.obj") + " --mtlx " +
         test::shared_scene("materialx/standard_surface_brick_procedural.mtlx") +
         " --material M_BrickPattern --env 1,1,1 --camera-from 0.75,1.0,2.45 --camera-at -0.09,0.05,-0.01"
         " --width 160 --height 120 --spp 8";
}

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

TEST(CiCompare, PassesOnTheBrickTeapotWithALenientThreshold) {
  const std::string dir = test::temp_dir();
  Result r = ci_compare(teapot() + " --min-psnr 30 --max-relmse 0.05 --out-dir " + dir);
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "ci-compare: PASS")) << r.output;
  EXPECT_TRUE(has(r.output, "PSNR")) << r.output;
  EXPECT_TRUE(has(r.output, "hit rate")) << r.output;
  // The report points at the images, and they are there.
  EXPECT_TRUE(has(r.output, dir)) << r.output;
  for (const char* f : {"metrics.json", "cache_off.png", "cache_on.png", "difference.png", "hitmap.png"})
    EXPECT_TRUE(test::file_exists(dir + "/" + f)) << f;
  std::ifstream in(dir + "/metrics.json");
  nlohmann::json m = nlohmann::json::parse(in);
  EXPECT_EQ(m["width"].get<int>(), 160);
  EXPECT_EQ(m["spp"].get<int>(), 8);
  EXPECT_GT(m["hit_rate"].get<double>(), 0.2) << "the brick teapot must actually use the cache";
}

TEST(CiCompare, FailsWithAnImpossiblePsnrThreshold) {
  Result r = ci_compare(teapot() + " --min-psnr 200 --out-dir " + test::temp_dir());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "FAIL")) << r.output;
  EXPECT_TRUE(has(r.output, "PSNR")) << r.output;
  EXPECT_TRUE(has(r.output, "below --min-psnr 200")) << r.output;
  EXPECT_FALSE(has(r.output, "ci-compare: PASS")) << r.output;
}

TEST(CiCompare, FailsOnADeliberatelyWrongMipLevelWithARealisticThreshold) {
  // The same realistic gate passes at the default mip bias ...
  const std::string gate = " --min-psnr 42 --max-relmse 0.0018";
  Result good = ci_compare(teapot() + gate + " --out-dir " + test::temp_dir() + "/good");
  EXPECT_EQ(good.code, 0) << good.output;
  // ... and fails when the virtual texture is 2^10 times too coarse.
  Result bad = ci_compare(teapot() + gate + " --mip-bias -10 --out-dir " + test::temp_dir() + "/bad");
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_TRUE(has(bad.output, "PSNR")) << bad.output;
  EXPECT_TRUE(has(bad.output, "below --min-psnr 42")) << bad.output;
  EXPECT_TRUE(has(bad.output, "above --max-relmse")) << bad.output;
}

TEST(CiCompare, BiasGatesPassTheTeapotAndFailAWrongMipLevel) {
  const std::string gate = " --min-bias-psnr 42 --min-bias-tile-psnr 33", dir = test::temp_dir() + "/good";
  Result good = ci_compare(teapot() + gate + " --out-dir " + dir);
  EXPECT_EQ(good.code, 0) << good.output;
  EXPECT_TRUE(has(good.output, "bias (two seeds)")) << good.output;
  for (const char* f : {"cache_off_seed2.exr", "cache_on_seed2.exr"})
    EXPECT_TRUE(test::file_exists(dir + "/" + f)) << f;
  std::ifstream in(dir + "/metrics.json");
  const nlohmann::json m = nlohmann::json::parse(in);
  ASSERT_TRUE(m.contains("cache_bias")) << m.dump();
  EXPECT_EQ(m["cache_bias"]["seed2"].get<uint32_t>(), m["seed"].get<uint32_t>() + 0x632be5abu);
  EXPECT_LT(m["cache_bias"]["noise_psnr"].get<double>(), m["psnr"].get<double>())
      << "the same-seed PSNR sits above the noise floor: the renders share their noise";

  Result bad = ci_compare(teapot() + gate + " --mip-bias -10 --out-dir " + test::temp_dir() + "/bad");
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_TRUE(has(bad.output, "below --min-bias-psnr 42")) << bad.output;
  EXPECT_TRUE(has(bad.output, "below --min-bias-tile-psnr 33")) << bad.output;
}

TEST(CiCompare, UsageErrorsExitWith2) {
  const std::string scene = test::shared_scene("materialx/geometry/teapot.obj");
  const struct {
    std::string args;
    const char* mentions;
  } cases[] = {
      {scene, "--min-psnr"},                                                       // threshold missing
      {"--min-psnr 30", "SCENE"},                                                  // scene missing
      {scene + " --min-psnr abc", "--min-psnr"},                                   // not a number
      {scene + " --min-bias-psnr x", "--min-bias-psnr"},                           // not a number
      {scene + " --min-psnr 30 --max-relmse -1", "--max-relmse"},                  // negative
      {scene + " --min-psnr 30 --cache on", "--cache"},                            // compare renders both
      {scene + " --min-psnr 30 --width 0", "--width"},                             // pmc's own check
      {scene + " --min-psnr 30 --reference /nonexistent/ref.exr", "--reference"},  // checked before rendering
      {scene + " --min-psnr 30 --diff-scale -1", "--diff-scale"},
      {scene + " --min-psnr 30 --no-such-option 1", "no-such-option"},
  };
  for (const auto& c : cases) {
    Result r = ci_compare(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_TRUE(has(r.output, c.mentions)) << c.args << "\n" << r.output;
  }
  Result help = ci_compare("--help");
  EXPECT_EQ(help.code, 0);
  EXPECT_TRUE(has(help.output, "--min-psnr")) << help.output;
}

}  // namespace
}  // namespace pmc
