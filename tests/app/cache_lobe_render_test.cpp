// cache_lobe_render_test.cpp — position cells that widen after rough bounces
// (--cache-lobe-spread; core/device/pmc_raycone.h), end to end through the
// pmc binary (real OpenCL on PoCL).
//
// Scene: data/default/room.obj with data/default/solid_materials.mtlx (every
// pattern a solid texture on position keys; a closed room, so most hits come
// after diffuse bounces), 160x90, 8 spp, --max-depth 4, seed 5. Against the
// paper's cone (--cache-lobe-spread 0, the default):
//  * lookups after a bounce miss at most 65% as often with C = 1/32 (measured
//    on PoCL: 46%), and less often still with C = 1/4 (14%): coarser cells
//    are shared by more hits;
//  * every image's mean is within 1% of the cacheless render's (measured:
//    0.02% for 1/32, 0.4% for 1/4) and its PSNR above 30 dB; the paper's cone
//    above 40 dB (measured 41.9 dB). Widened cells measure 33.8-34.1 dB here:
//    their paths part from the cacheless render's more often (other lobe
//    and roulette choices after a bounce), which at 8 spp is noise against
//    the same-seed render, not bias (docs/BENCHMARKS.md).
// A widening that never reached the kernels fails the first check; keys
// built from a garbled level fail the second. Then: with one hit per path
// (--max-depth 1), and on the default scene with uv keys only, C = 1/4 gives
// the paper's image and cache counts exactly (a widening that leaked into
// camera rays or uv texels changes both); centre mode stays bit-identical
// with 1 and 2 threads; and level floors (--cache-bandwidth on) bypass as
// often as without the widening.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "core/image_io.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

struct Render {
  Image image;
  nlohmann::json cache;
};

// Points by node count (at 8 spp the cost model drops the position points
// whose cells this test is about). The room at 160x90, 8 spp, seed 5 with `materials` (a file of
// data/default) and `max_depth`, then `extra`.
Render render(const std::string& dir, const std::string& name, const std::string& extra,
              const std::string& materials = "solid_materials.mtlx", int max_depth = 4) {
  const std::string base = dir + "/" + name;
  std::string log;
  Render r;
  const int rc = test::run_pmc("render " + test::source_path("data/default/room.obj") + " --mtlx " +
                                   test::source_path("data/default/" + materials) +
                                   " --width 160 --height 90 --spp 8 --seed 5 --quiet --cache-model nodes"
                                   " --max-depth " +
                                   std::to_string(max_depth) + " " + extra + " -o " + base + ".exr --stats " +
                                   base + ".json",
                               &log);
  EXPECT_EQ(rc, 0) << log;
  if (rc != 0) return r;
  r.image = read_image(base + ".exr");
  std::ifstream in(base + ".json");
  r.cache = nlohmann::json::parse(in)["cache"];
  return r;
}

double mean(const Image& a) {
  double s = 0;
  for (float v : a.pixels) s += v;
  return a.pixels.empty() ? 0.0 : s / double(a.pixels.size());
}

double psnr(const Image& a, const Image& b) {
  double se = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) se += std::pow(double(a.pixels[i]) - b.pixels[i], 2);
  const double mse = se / double(a.pixels.size());
  return mse > 0 ? 10.0 * std::log10(1.0 / mse) : 1e9;
}

uint64_t after_bounce_misses(const nlohmann::json& c) {
  const uint64_t camera_misses = c["camera_lookups"].get<uint64_t>() - c["camera_hits"].get<uint64_t>();
  return c["misses"].get<uint64_t>() - camera_misses;
}

TEST(CacheLobeRender, RoughBouncesShareCoarserCellsAndKeepTheImage) {
  const std::string dir = test::temp_dir();
  const Render off = render(dir, "off", "--cache off");
  const Render paper = render(dir, "paper", "--cache-lobe-spread 0");
  const Render c32 = render(dir, "c32", "--cache-lobe-spread 0.03125");
  const Render wide = render(dir, "wide", "--cache-lobe-spread 0.25");
  for (const Render* r : {&off, &paper, &c32, &wide}) {
    ASSERT_FALSE(r->image.pixels.empty());
    ASSERT_EQ(r->image.pixels.size(), off.image.pixels.size());
  }
  EXPECT_EQ(c32.cache["lobe_spread"].get<double>(), 1.0 / 32.0);
  EXPECT_EQ(render(dir, "unset", "").cache["lobe_spread"].get<double>(), 0.0)
      << "the paper's cone by default";

  const uint64_t m_paper = after_bounce_misses(paper.cache), m_c32 = after_bounce_misses(c32.cache),
                 m_wide = after_bounce_misses(wide.cache);
  std::printf("misses after a bounce: paper's cone %llu, C = 1/32 %llu, C = 1/4 %llu\n",
              (unsigned long long)m_paper, (unsigned long long)m_c32, (unsigned long long)m_wide);
  EXPECT_GT(m_paper, 1000u) << "the scene must have lookups after bounces";
  EXPECT_LT(double(m_c32), 0.65 * double(m_paper));
  EXPECT_LT(m_wide, m_c32) << "a wider lobe shares coarser cells still";

  const double m_off = mean(off.image);
  for (const Render* r : {&paper, &c32, &wide}) {
    const double p = psnr(r->image, off.image), m = mean(r->image);
    std::printf("C = %.4f: PSNR vs cacheless %.2f dB, mean %.5f (cacheless %.5f)\n",
                r->cache["lobe_spread"].get<double>(), p, m, m_off);
    EXPECT_GT(p, 30.0);
    EXPECT_LT(p, 1e9) << "the cache must change something";
    EXPECT_NEAR(m, m_off, 0.01 * m_off);
  }
  // Measured 38.2 dB with the layered BSDF (40.5 before it: its rough
  // specular lobes, compensated for multiple scattering, part same-seed paths
  // more often); a cache that changed the image would fall far below.
  EXPECT_GT(psnr(paper.image, off.image), 36.0);
}

// The counters that a change of keys or levels would move. On one thread
// every counter is deterministic (measured: identical over repeated runs);
// with two, two threads missing one texel at once both count a miss, and the
// misses vary by up to 1.3% between runs (seen in CI), so these renders run
// on one thread and one wave loop (--waves-in-flight 1) and must agree exactly.
void expect_same_cache_events(const nlohmann::json& a, const nlohmann::json& b, const char* what) {
  for (const char* k :
       {"lookups", "camera_lookups", "position_lookups", "bypassed", "hits", "misses", "inserts"})
    EXPECT_EQ(a[k], b[k]) << what << ": " << k;
}

TEST(CacheLobeRender, CameraRaysAndUvTexelsKeepThePapersCone) {
  const std::string dir = test::temp_dir();
  // One surface hit per path: no bounce, nothing to widen. The cache's event
  // counts depend on the order of the lookups: one thread, one wave loop.
  const std::string serial = "--threads 1 --waves-in-flight 1";
  const Render a = render(dir, "direct0", serial + " --cache-lobe-spread 0", "solid_materials.mtlx", 1);
  const Render b = render(dir, "direct1", serial + " --cache-lobe-spread 0.25", "solid_materials.mtlx", 1);
  ASSERT_FALSE(a.image.pixels.empty());
  ASSERT_FALSE(b.image.pixels.empty());
  EXPECT_GT(a.cache["lookups"].get<uint64_t>(), 0u);
  EXPECT_TRUE(a.image.pixels == b.image.pixels) << "camera hits must keep their cells";
  expect_same_cache_events(a.cache, b.cache, "camera hits");
  // The default scene on uv keys only: its texels never widen.
  const Render u0 = render(dir, "uv0", serial + " --cache-keys uv --cache-lobe-spread 0", "materials.mtlx");
  const Render u1 =
      render(dir, "uv1", serial + " --cache-keys uv --cache-lobe-spread 0.25", "materials.mtlx");
  ASSERT_FALSE(u0.image.pixels.empty());
  ASSERT_FALSE(u1.image.pixels.empty());
  EXPECT_GT(u0.cache["lookups"].get<uint64_t>(), 0u);
  EXPECT_EQ(u0.cache["position_lookups"].get<uint64_t>(), 0u);
  EXPECT_TRUE(u0.image.pixels == u1.image.pixels) << "uv texels must keep the texture's cone";
  expect_same_cache_events(u0.cache, u1.cache, "uv texels");
}

TEST(CacheLobeRender, CentreModeStaysBitIdenticalAcrossThreadCounts) {
  const std::string dir = test::temp_dir();
  const Render one = render(dir, "t1", "--cache-lobe-spread 0.25 --threads 1");
  const Render two = render(dir, "t2", "--cache-lobe-spread 0.25 --threads 2");
  ASSERT_FALSE(one.image.pixels.empty());
  ASSERT_FALSE(two.image.pixels.empty());
  EXPECT_TRUE(one.image.pixels == two.image.pixels);
}

// --cache-bandwidth on: the floors count from the texture cone's level, so a
// widened cone coarsens cells down to a floor at most and bypasses where the
// paper's cone does (paths after a bounce differ a little, so the counts do).
// Measured on PoCL: 64283 bypassed lookups with C = 0, 64291 with C = 1/4,
// and 145064 with floors counted from the widened level.
TEST(CacheLobeRender, LevelFloorsBypassAsWithoutTheWidening) {
  const std::string dir = test::temp_dir();
  const Render a = render(dir, "floors0", "--cache-bandwidth on --cache-lobe-spread 0");
  const Render b = render(dir, "floors1", "--cache-bandwidth on --cache-lobe-spread 0.25");
  ASSERT_FALSE(a.image.pixels.empty());
  ASSERT_FALSE(b.image.pixels.empty());
  const double by0 = a.cache["bypassed"].get<double>(), by1 = b.cache["bypassed"].get<double>();
  std::printf("bypassed: C = 0 %.0f, C = 1/4 %.0f\n", by0, by1);
  EXPECT_GT(by0, 0.0) << "the floors must bypass somewhere for this check to mean anything";
  EXPECT_LT(by1, 1.2 * by0);
}

}  // namespace
}  // namespace pmc
