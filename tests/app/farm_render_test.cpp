// farm_render_test.cpp — scripts/farm-render (Dask distributed) end to end:
// a LocalCluster of 2 worker processes on 127.0.0.1, the default room at
// 40x24, cacheless, against the one-process render of the same frame (the
// merged R, G, B must equal it bit for bit, tests/app/merge_cli_test.cpp says
// why that holds).
//  * 4 sample-range chunks, and 4 tiles.
//  * --denoise: the merged frame with its passes, denoised by pmc denoise.
//  * A worker killed (SIGKILL) while it runs a chunk: the nanny starts a new
//    worker, the scheduler reschedules the chunk, the job completes and the
//    image is the same; the chunk log shows that chunk started twice.
// Every run is bounded: farm-render's --timeout and an outer `timeout`.
// Loopback-only binding is checked by scripts/farm/tests (FarmScripts.Unittest).
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <nlohmann/json.hpp>
#include <thread>

#include "core/image_io.h"
#include "tests/support/exr_channels.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

const char* kArgs = " --width 40 --height 24 --spp 8 --max-depth 4 --cache off";

std::string room() { return test::source_path("data/default/room.obj"); }

int run(const std::string& cmd, std::string* output) {
  FILE* pipe = popen((cmd + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) output->append(buf, n);
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string farm(const std::string& out, const std::string& extra) {
  return "PMC=" + std::string(PMC_BINARY) + " timeout -k 10 300 " + test::source_path("scripts/farm-render") +
         " " + room() + " -o " + out + " --workers 2 --timeout 240 --chunk-timeout 120 --quiet" + kArgs +
         " " + extra;
}

std::vector<float> rgb(const std::string& path) {
  const Image img = read_image(path);
  std::vector<float> out;
  for (size_t i = 0; i < size_t(img.width) * size_t(img.height); ++i)
    for (int c = 0; c < 3; ++c) out.push_back(img.pixels[i * size_t(img.channels) + size_t(c)]);
  return out;
}

std::vector<float> one_process(const std::string& dir) {
  std::string log;
  EXPECT_EQ(test::run_pmc("render " + room() + kArgs + " --quiet -o " + dir + "/one.exr", &log), 0) << log;
  return rgb(dir + "/one.exr");
}

TEST(FarmRender, FourSampleChunksOnTwoLocalWorkersMergeToTheOneProcessImage) {
  const std::string d = test::temp_dir();
  std::string log;
  ASSERT_EQ(run(farm(d + "/farm.exr", "--chunks 4 --summary " + d + "/summary.json"), &log), 0) << log;
  EXPECT_TRUE(one_process(d) == rgb(d + "/farm.exr"));
  std::ifstream in(d + "/summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["chunks"], 4);
  EXPECT_EQ(s["workers"], 2);
  EXPECT_EQ(s["per_chunk"].size(), 4u);
  EXPECT_EQ(s["per_chunk"][3]["samples"], nlohmann::json({6, 8}));
  EXPECT_NE(log.find("speedup over one process"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(d + "/farm.parts"));  // parts removed after the merge
}

TEST(FarmRender, FourTilesAssembleIntoTheOneProcessImage) {
  const std::string d = test::temp_dir();
  std::string log;
  ASSERT_EQ(run(farm(d + "/farm.exr", "--chunks 4 --split tiles"), &log), 0) << log;
  EXPECT_TRUE(one_process(d) == rgb(d + "/farm.exr"));
}

TEST(FarmRender, AWorkerKilledDuringTheJobIsReplacedAndTheImageIsTheSame) {
  const std::string d = test::temp_dir(), chunk_log = d + "/chunks";
  std::filesystem::create_directories(chunk_log);
  std::string log;
  auto job = std::async(std::launch::async, [&] {
    return run(farm(d + "/farm.exr", "--chunks 4 --chunk-log " + chunk_log), &log);
  });
  // Wait for the first chunk to start, then kill the worker process running it.
  int victim = 0, chunk = -1;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(200);
  while (victim == 0 && std::chrono::steady_clock::now() < deadline &&
         job.wait_for(std::chrono::milliseconds(0)) != std::future_status::ready) {
    for (int k = 0; k < 4 && victim == 0; ++k) {
      std::ifstream f(chunk_log + "/chunk-" + std::to_string(k) + ".started");
      if (f >> victim) chunk = k;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_GT(victim, 0) << "no chunk started: " << log;
  ASSERT_EQ(kill(victim, SIGKILL), 0);
  ASSERT_EQ(job.get(), 0) << log;
  std::ifstream f(chunk_log + "/chunk-" + std::to_string(chunk) + ".started");
  int first = 0, second = 0;
  f >> first >> second;
  EXPECT_EQ(first, victim);
  EXPECT_GT(second, 0) << "the killed worker's chunk was not run again";
  EXPECT_NE(second, victim);
  EXPECT_TRUE(one_process(d) == rgb(d + "/farm.exr"));
}

TEST(FarmRender, DenoiseRendersThePassesAndDenoisesTheMergedFrame) {
  // Two sample chunks with --denoise: OUT.noisy.exr is the merged frame,
  // equal to the one-process render with the denoiser's passes bit for bit,
  // and OUT.exr is that frame denoised by pmc render --denoise.
  const std::string d = test::temp_dir();
  std::string log;
  ASSERT_EQ(run(farm(d + "/farm.exr", "--chunks 2 --denoise --aov depth"), &log), 0) << log;
  for (const char* f : {"/farm.exr", "/farm.png", "/farm.noisy.exr", "/farm.noisy.png"})
    EXPECT_TRUE(std::filesystem::exists(d + f)) << f;
  EXPECT_NE(log.find("denoised in"), std::string::npos) << log;
  ASSERT_EQ(test::run_pmc("render " + room() + kArgs + " --aov albedo,normal,depth --denoise --quiet -o " +
                              d + "/one.exr",
                          &log),
            0)
      << log;
  EXPECT_TRUE(rgb(d + "/one.noisy.exr") == rgb(d + "/farm.noisy.exr"));
  const auto layers = test::exr_channels(d + "/farm.noisy.exr");
  for (const char* c : {"albedo.R", "N.X", "Z"}) EXPECT_TRUE(layers.count(c)) << "no channel " << c;
  const std::vector<float> farm_clean = rgb(d + "/farm.exr"), one_clean = rgb(d + "/one.exr");
  ASSERT_EQ(farm_clean.size(), one_clean.size());
  double diff = 0, mag = 0;
  for (size_t i = 0; i < farm_clean.size(); ++i)
    diff += std::abs(farm_clean[i] - one_clean[i]), mag += one_clean[i];
  EXPECT_LT(diff, 1e-3 * mag);  // OIDN may differ in the last bits between runs
  EXPECT_FALSE(farm_clean == rgb(d + "/farm.noisy.exr"));
}

}  // namespace
}  // namespace pmc
