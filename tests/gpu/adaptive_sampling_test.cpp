// adaptive_sampling_test.cpp — --adaptive-threshold (gpu/adaptive_sampling.h) on PoCL.
//
// Independent answers:
//  * the stopping rule against its closed form on films built from known
//    samples (a constant pixel stops at once; samples alternating 0 and 2
//    have mean 1 and variance n / (n - 1), so a relative standard error of
//    sqrt(1 / (n - 1) / 1.01), against mean^2 + 0.01);
//  * a pixel that stopped after n samples equals, bit for bit, the same
//    pixel of a render with --spp n and no adaptive sampling (the sampler is
//    keyed by pixel and sample index), for every count that occurs, with the
//    cache off (the default room) and on in centre mode (the brick teapot);
//  * the adaptive image does not depend on the wave shape or the window:
//    crop tiles rendered alone equal the whole frame's pixels, and merge
//    (`pmc merge`) into its EXR bit for bit;
//  * sample ranges are refused with an error naming the setting.
#include "gpu/adaptive_sampling.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "core/device/pmc_film.h"
#include "core/error.h"
#include "core/film_sum.h"
#include "core/image_io.h"
#include "core/render_part.h"
#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

// A film pixel holding grey samples `values` (r = g = b), as the film kernel adds them.
PmcFilmPixel film_of(const std::vector<float>& values) {
  PmcFilmPixel px{};
  for (float v : values) {
    pmc_u32 w[PMC_FIXED_WORDS];
    EXPECT_TRUE(pmc_fixed_of_float(v, w));
    for (int c = 0; c < 3; ++c) pmc_fixed_add(&px.sum[4 * c], w);
    px.grey_sq_sum += v * v;
  }
  return px;
}

TEST(AdaptiveSampling, StoppingRuleMatchesTheRelativeStandardErrorOfTheMean) {
  // Constant samples: no variance, the mean is exact after two.
  EXPECT_TRUE(adaptive_pixel_converged(film_of({0.5f, 0.5f}), 2, 1e-6));
  EXPECT_FALSE(adaptive_pixel_converged(film_of({0.5f}), 1, 0.5));  // one sample says nothing
  // 0, 2, 0, 2, ... (n = 100): mean 1, variance 100/99, standard error^2 1/99,
  // against mean^2 + 0.01: relative error sqrt(1 / 99 / 1.01) = 0.1000050.
  std::vector<float> alternating;
  for (int i = 0; i < 100; ++i) alternating.push_back(i % 2 ? 2.0f : 0.0f);
  const PmcFilmPixel px = film_of(alternating);
  EXPECT_TRUE(adaptive_pixel_converged(px, 100, 0.10002));
  EXPECT_FALSE(adaptive_pixel_converged(px, 100, 0.09999));
  // A dark pixel is weighed against 0.01, not its own tiny mean: samples 0 and 0.002
  // (mean 0.001, standard error 0.001) have a relative error of 0.001 / sqrt(1e-6 + 0.01) = 0.0099995.
  const std::vector<float> dark = {0.0f, 0.002f};
  EXPECT_TRUE(adaptive_pixel_converged(film_of(dark), 2, 0.01001));
  EXPECT_FALSE(adaptive_pixel_converged(film_of(dark), 2, 0.00999));
  // Bad samples do not count: 3 drawn, 2 of them dropped, 1 good.
  PmcFilmPixel bad = film_of({0.5f});
  bad.bad_samples = 2;
  EXPECT_FALSE(adaptive_pixel_converged(bad, 3, 0.5));
}

TEST(AdaptiveSampling, SamplerChecksAtFixedCountsAndKeepsTheActiveListInWindowOrder) {
  AdaptiveSampler a(4, 0.1, 8);
  EXPECT_EQ(a.samples_to_next_check(0), 8);
  EXPECT_EQ(a.samples_to_next_check(5), 3);
  a.add_samples(8);
  std::vector<PmcFilmPixel> film = {film_of({1, 1, 1, 1, 1, 1, 1, 1}), film_of({0, 2, 0, 2, 0, 2, 0, 2}),
                                    film_of({1, 1, 1, 1, 1, 1, 1, 1}), film_of({0, 0, 0, 0, 0, 0, 0, 9})};
  EXPECT_EQ(a.check(film), 0u);  // converged once is not enough
  a.add_samples(8);
  film[0] = film_of({1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1});
  film[1] = film_of({0, 2, 0, 2, 0, 2, 0, 2, 0, 2, 0, 2, 0, 2, 0, 2});
  film[2] = film_of({1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 9});  // a bright sample showed up
  film[3] = film_of({0, 0, 0, 0, 0, 0, 0, 9, 0, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_EQ(a.check(film), 1u);  // only pixel 0 passed twice in a row
  EXPECT_EQ(a.active(), (std::vector<uint32_t>{1, 2, 3}));
  a.add_samples(4);
  EXPECT_EQ(a.samples(), (std::vector<uint32_t>{16, 20, 20, 20}));
  AdaptiveSampler off(3, 0.0, 8);
  EXPECT_FALSE(off.on());
  EXPECT_EQ(off.check(film), 0u);
}

RenderConfig room() {
  RenderConfig c;
  c.scene = test::source_path("data/default/room.obj");
  c.mtlx = {test::source_path("data/default/materials.mtlx")};
  c.width = 40;
  c.height = 24;
  c.spp = 24;
  c.max_depth = 4;
  c.cache = false;
  c.adaptive_threshold = 0.08;
  c.adaptive_min_spp = 6;
  return c;
}

RenderConfig teapot() {
  RenderConfig c = test::brick_teapot_config(16);
  c.cache_model = CacheModel::Nodes;  // at 16 spp the cost model may leave the point out
  c.adaptive_threshold = 0.05;
  c.adaptive_min_spp = 4;
  return c;
}

// Every pixel that drew n samples equals that pixel of the plain n-spp render, for each n.
void expect_stopped_pixels_equal_plain_renders(const RenderConfig& config) {
  RenderSession session(config, test::cl());
  const RenderOutput adaptive = session.render();
  const RenderSettings& s = session.settings();
  std::map<uint32_t, std::vector<size_t>> by_count;
  for (size_t i = 0; i < adaptive.film.pixels(); ++i) by_count[adaptive.film.samples[i]].push_back(i);
  // Not vacuous: some pixels stopped early, some drew every sample.
  ASSERT_GE(by_count.size(), 2u);
  ASSERT_EQ(by_count.rbegin()->first, uint32_t(s.spp));
  EXPECT_GT(adaptive.stats.adaptive_stopped_pixels, 0u);
  EXPECT_LT(adaptive.stats.adaptive_mean_spp, double(s.spp));
  for (const auto& [n, pixels] : by_count) {
    ASSERT_EQ(n % uint32_t(s.adaptive_min_spp), 0u) << "a pixel stopped between checks";
    RenderSettings plain = s;
    plain.adaptive_threshold = 0.0;
    plain.spp = int(n);
    const RenderOutput p = session.render(plain);
    for (size_t i : pixels)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(adaptive.image.pixels[3 * i + size_t(c)], p.image.pixels[3 * i + size_t(c)])
            << "pixel " << i << " (" << n << " samples)";
  }
}

TEST(AdaptiveSampling, AStoppedPixelEqualsThePixelRenderedWithItsSampleCount) {
  expect_stopped_pixels_equal_plain_renders(room());
}

TEST(AdaptiveSampling, WithTheCacheInCentreModeToo) { expect_stopped_pixels_equal_plain_renders(teapot()); }

TEST(AdaptiveSampling, TheImageDoesNotDependOnTheWaveShapeOrTheWindow) {
  RenderSession session(room(), test::cl());
  const RenderOutput full = session.render();
  RenderSettings small_waves = session.settings();
  small_waves.max_wave_paths = 97;  // blocks of 97 pixels, one sample per wave
  EXPECT_TRUE(session.render(small_waves).image.pixels == full.image.pixels);
  RenderSettings tile = session.settings();
  const int x0 = 13, y0 = 5, x1 = 31, y1 = 20;
  tile.crop[0] = x0, tile.crop[1] = y0, tile.crop[2] = x1, tile.crop[3] = y1;
  const RenderOutput t = session.render(tile);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const size_t a = size_t((y - y0) * (x1 - x0) + (x - x0)), b = size_t(y * 40 + x);
      ASSERT_EQ(t.film.samples[a], full.film.samples[b]) << x << "," << y;
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(t.image.pixels[3 * a + size_t(c)], full.image.pixels[3 * b + size_t(c)]);
    }
}

TEST(AdaptiveSampling, RefusesASampleRangeNamingTheSettings) {
  RenderConfig c = room();
  c.samples = std::array<int, 2>{0, 12};
  try {
    c.validate();
    FAIL() << "a sample range with adaptive sampling was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("adaptive_threshold"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("crop"), std::string::npos) << e.what();
  }
  c.samples = std::array<int, 2>{0, 24};  // the whole range is fine
  EXPECT_NO_THROW(c.validate());
}

TEST(AdaptiveSampling, CropTilesMergeToTheOneProcessRenderThroughThePmcBinary) {
  const std::string d = test::temp_dir();
  const std::string args = "render " + test::source_path("data/default/room.obj") +
                           " --width 40 --height 24 --spp 24 --max-depth 4 --cache off --quiet "
                           "--adaptive-threshold 0.08 --adaptive-min-spp 6";
  std::string log;
  ASSERT_EQ(test::run_pmc(args + " -o " + d + "/full.exr", &log), 0) << log;
  ASSERT_EQ(test::run_pmc(args + " --crop 0,0,40,9 -o " + d + "/a.exr", &log), 0) << log;
  ASSERT_EQ(test::run_pmc(args + " --crop 0,9,40,24 -o " + d + "/b.exr", &log), 0) << log;
  const RenderPart a = read_part_exr(d + "/a.exr");
  EXPECT_TRUE(a.info.adaptive);
  std::set<uint32_t> counts(a.film.samples.begin(), a.film.samples.end());
  EXPECT_GE(counts.size(), 2u);  // the part holds pixels of several sample counts
  ASSERT_EQ(test::run_pmc("merge " + d + "/b.exr " + d + "/a.exr -o " + d + "/m.exr", &log), 0) << log;
  const Image full = read_image(d + "/full.exr"), merged = read_image(d + "/m.exr");
  ASSERT_EQ(full.width * full.height, merged.width * merged.height);
  for (size_t i = 0; i < size_t(full.width * full.height); ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(full.pixels[i * size_t(full.channels) + size_t(c)],
                merged.pixels[i * size_t(merged.channels) + size_t(c)])
          << "pixel " << i;
  // A sample range of an adaptive frame is refused before rendering, naming the flags.
  EXPECT_EQ(test::run_pmc(args + " --samples 0:12 -o " + d + "/r.exr", &log), 2) << log;
  EXPECT_NE(log.find("--adaptive-threshold"), std::string::npos) << log;
  EXPECT_FALSE(test::file_exists(d + "/r.exr"));
}

}  // namespace
}  // namespace pmc
