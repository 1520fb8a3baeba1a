// render_parts_test.cpp — sample ranges and windows of one frame (RenderSettings
// sample_begin/sample_end and crop; RenderConfig samples/crop) through a
// RenderSession on PoCL.
//
// The independent answer is the one-process render of the whole frame:
//  * parts' exact films (core/film_sum.h) added in any order resolve to its
//    image bit for bit — cacheless (the default room) and with the cache in
//    --cache-eval center (the brick teapot, one cache point: a centre-mode
//    texel holds its centre's value whoever inserted it, so a sample's
//    radiance does not depend on the table; the parts' tables start empty and
//    find fewer hits, which the test checks so the comparison is not vacuous),
//    also with supersampled misses (--cache-supersample 4: a texel holds the
//    mean of its 4 key-scrambled sub-samples, a function of the key alone);
//  * a window's pixels equal the whole frame's pixels at the same place, and
//    tiles, one split by samples as well, assemble into the frame;
//  * the part hashes (gpu/part_identity.h) change with the seed and the
//    scene but not with the sample range or window;
//  * RenderConfig::validate refuses ranges and windows outside the frame.
#include <gtest/gtest.h>

#include <array>

#include "core/error.h"
#include "core/film_sum.h"
#include "gpu/part_identity.h"
#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

RenderConfig room() {
  RenderConfig c;
  c.scene = test::source_path("data/default/room.obj");
  c.width = 40;
  c.height = 24;
  c.spp = 6;
  c.max_depth = 4;
  c.cache = false;
  return c;
}

RenderConfig teapot() { return test::brick_teapot_config(6); }

RenderSettings part(const RenderSettings& s, int a, int b, std::array<int, 4> crop = {0, 0, 0, 0}) {
  RenderSettings p = s;
  p.sample_begin = a;
  p.sample_end = b;
  for (int i = 0; i < 4; ++i) p.crop[i] = crop[size_t(i)];
  return p;
}

TEST(RenderParts, CachelessSampleRangesAddToTheOneProcessImageBitForBit) {
  RenderSession session(room(), test::cl());
  const RenderOutput full = session.render();
  const RenderSettings& s = session.settings();
  FilmSums sum = FilmSums::zero(s.width, s.height);
  for (auto [a, b] : {std::pair{4, 6}, std::pair{0, 1}, std::pair{1, 4}}) {
    const RenderOutput p = session.render(part(s, a, b));
    EXPECT_NE(p.image.pixels, full.image.pixels);  // a part alone is another image
    add_film(sum, p.film, 0, 0);
  }
  EXPECT_EQ(sum.sum, full.film.sum);
  EXPECT_TRUE(film_mean(sum).pixels == full.image.pixels);
}

TEST(RenderParts, CenterCachedSampleRangesAddToTheOneProcessImageExactly) {
  RenderSession session(teapot(), test::cl());
  const RenderSettings& s = session.settings();
  ASSERT_TRUE(s.cache.on);
  const RenderOutput full = session.render();
  ASSERT_GT(full.stats.cache.hits, 0u);
  const RenderOutput a = session.render(part(s, 0, 2)), b = session.render(part(s, 2, 6));
  EXPECT_LT(a.stats.cache.hits + b.stats.cache.hits, full.stats.cache.hits);  // each table warmed alone
  FilmSums sum = FilmSums::zero(s.width, s.height);
  add_film(sum, b.film, 0, 0);
  add_film(sum, a.film, 0, 0);
  EXPECT_TRUE(film_mean(sum).pixels == full.image.pixels);
}

TEST(RenderParts, SupersampledCenterCachedSampleRangesAddToTheOneProcessImageExactly) {
  RenderConfig c = teapot();
  c.cache_supersample = 4;
  c.cache_model = CacheModel::Nodes;  // at 6 spp a 4-sample miss would not pay: keep the point
  RenderSession session(c, test::cl());
  const RenderSettings& s = session.settings();
  ASSERT_TRUE(s.cache.on);
  ASSERT_EQ(session.cache_supersample().uv, 4);
  const RenderOutput full = session.render();
  ASSERT_GT(full.stats.cache.hits, 0u);
  const RenderOutput a = session.render(part(s, 0, 3)), b = session.render(part(s, 3, 6));
  EXPECT_LT(a.stats.cache.hits + b.stats.cache.hits, full.stats.cache.hits);  // each table warmed alone
  FilmSums sum = FilmSums::zero(s.width, s.height);
  add_film(sum, b.film, 0, 0);
  add_film(sum, a.film, 0, 0);
  EXPECT_TRUE(film_mean(sum).pixels == full.image.pixels);
}

TEST(RenderParts, WindowsKeepTheirFramePixelsAndTilesAssemble) {
  RenderSession session(room(), test::cl());
  const RenderSettings& s = session.settings();
  const RenderOutput full = session.render();
  const RenderOutput t1 = session.render(part(s, 0, 6, {25, 3, 40, 10}));
  ASSERT_EQ(t1.image.width, 15);
  ASSERT_EQ(t1.image.height, 7);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 15; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(t1.image.pixels[size_t((y * 15 + x) * 3 + c)],
                  full.image.pixels[size_t(((y + 3) * 40 + x + 25) * 3 + c)])
            << x << "," << y;
  FilmSums sum = FilmSums::zero(s.width, s.height);
  add_film(sum, session.render(part(s, 0, 6, {0, 0, 40, 12})).film, 0, 0);
  add_film(sum, session.render(part(s, 0, 2, {0, 12, 40, 24})).film, 0, 12);
  add_film(sum, session.render(part(s, 2, 6, {0, 12, 40, 24})).film, 0, 12);
  EXPECT_TRUE(film_mean(sum).pixels == full.image.pixels);
}

TEST(RenderParts, HashesNameTheFrameNotThePart) {
  RenderSession session(room(), test::cl());
  const RenderSettings& s = session.settings();
  EXPECT_EQ(settings_hash(s), settings_hash(part(s, 1, 3, {0, 0, 5, 5})));
  RenderSettings seeded = s;
  seeded.seed = 9;
  EXPECT_NE(settings_hash(seeded), settings_hash(s));
  RenderSettings deeper = s;
  deeper.max_depth = 5;
  EXPECT_NE(settings_hash(deeper), settings_hash(s));
  RenderSettings cached = s;
  cached.cache.on = true;
  RenderSettings widened = cached;  // coarser cells after bounces change the image
  widened.cache.lobe_spread = 0.03125f;
  EXPECT_NE(settings_hash(widened), settings_hash(cached));
  RenderConfig other = room();
  other.scene = test::shared_scene("cornell/cornell_box.obj");
  RenderSession cornell(other, test::cl());
  EXPECT_NE(scene_hash(cornell), scene_hash(session));
  RenderSession again(room(), test::cl());
  EXPECT_EQ(scene_hash(again), scene_hash(session));
}

TEST(RenderParts, ValidateRefusesRangesAndWindowsOutsideTheFrame) {
  auto problem = [](const RenderConfig& c) -> std::string {
    try {
      c.validate();
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  RenderConfig c = room();
  EXPECT_EQ(problem(c), "");
  for (std::array<int, 2> r : {std::array<int, 2>{3, 3}, {4, 2}, {-1, 2}, {0, 7}}) {
    c.samples = r;
    EXPECT_NE(problem(c).find("samples"), std::string::npos) << r[0] << ":" << r[1];
  }
  c.samples = std::array<int, 2>{0, 6};
  EXPECT_EQ(problem(c), "");
  for (std::array<int, 4> w :
       {std::array<int, 4>{0, 0, 41, 24}, {5, 0, 5, 10}, {0, -1, 10, 10}, {0, 0, 10, 25}}) {
    c.crop = w;
    EXPECT_NE(problem(c).find("crop"), std::string::npos)
        << w[0] << "," << w[1] << "," << w[2] << "," << w[3];
  }
  c.crop = std::array<int, 4>{0, 0, 40, 24};
  EXPECT_EQ(problem(c), "");
}

}  // namespace
}  // namespace pmc
