// render_part_test.cpp — part EXRs (write, read back) and merge_parts' checks,
// on small synthetic parts (no rendering; the end-to-end merges through the
// pmc binary are in tests/app/merge_cli_test.cpp).
#include "core/render_part.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/device/pmc_film.h"
#include "core/error.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

// A part of a 6x4 frame of 8 spp: every sample of every channel is `value`.
RenderPart make_part(const std::string& path, int a, int b, std::array<int, 4> crop, float value = 1.0f) {
  RenderPart p;
  p.path = path;
  PartInfo& i = p.info;
  i.scene_hash = "scene1";
  i.settings_hash = "settings1";
  i.scene = "s.obj";
  i.frame_width = 6;
  i.frame_height = 4;
  i.spp = 8;
  i.sample_begin = a;
  i.sample_end = b;
  i.crop = crop;
  i.seed = 5;
  i.cache_counters.lookups = 10;
  i.cache_counters.hits = 4;
  p.film = FilmSums::zero(crop[2] - crop[0], crop[3] - crop[1]);
  uint32_t v[4];
  EXPECT_TRUE(pmc_fixed_of_float(value, v));
  for (size_t px = 0; px < p.film.pixels(); ++px) {
    p.film.samples[px] = uint32_t(b - a);
    for (int s = a; s < b; ++s)
      for (int c = 0; c < 3; ++c) pmc_fixed_add(&p.film.sum[px * FilmSums::kWords + size_t(4 * c)], v);
  }
  return p;
}

std::string merge_error(const std::vector<RenderPart>& parts, bool allow_partial = false) {
  try {
    merge_parts(parts, allow_partial);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(RenderPart, WritesAndReadsBackItsWindowSumsAndAttributes) {
  const std::string dir = test::temp_dir();
  RenderPart p = make_part(dir + "/p.exr", 2, 6, {1, 2, 5, 4}, 0.75f);
  p.info.cache_counters.inserts = 1ull << 40;  // beyond 32 bits
  p.film.hits[3] = 9;
  write_part_exr(p.path, film_mean(p.film), p.info, &p.film);
  const RenderPart q = read_part_exr(p.path);
  EXPECT_EQ(q.info.crop, p.info.crop);
  EXPECT_EQ(q.info.frame_width, 6);
  EXPECT_EQ(q.info.frame_height, 4);
  EXPECT_EQ(q.info.sample_begin, 2);
  EXPECT_EQ(q.info.sample_end, 6);
  EXPECT_EQ(q.info.spp, 8);
  EXPECT_EQ(q.info.seed, 5u);
  EXPECT_EQ(q.info.scene_hash, "scene1");
  EXPECT_EQ(q.info.settings_hash, "settings1");
  EXPECT_EQ(q.info.cache_counters.inserts, 1ull << 40);
  EXPECT_EQ(q.info.cache_counters.lookups, 10u);
  EXPECT_EQ(q.film.sum, p.film.sum);
  EXPECT_EQ(q.film.samples, p.film.samples);
  EXPECT_EQ(q.film.hits, p.film.hits);
  // The mean channels read as an ordinary image of the window.
  const Image rgb = read_image(p.path);
  EXPECT_EQ(rgb.width, 4);
  EXPECT_EQ(rgb.height, 2);
  EXPECT_EQ(rgb.pixels[0], 0.75f);
}

TEST(RenderPart, AnImageWithoutSumsIsNotAPart) {
  const std::string dir = test::temp_dir();
  RenderPart p = make_part(dir + "/p.exr", 0, 8, {0, 0, 6, 4});
  write_part_exr(p.path, film_mean(p.film), p.info, nullptr);  // what a plain render writes
  try {
    read_part_exr(p.path);
    FAIL() << "read a part without sums";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(p.path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("pmc.sum0"), std::string::npos) << e.what();
  }
  Image plain;
  plain.width = 2;
  plain.height = 2;
  plain.pixels.assign(12, 0.5f);
  write_exr(dir + "/plain.exr", plain);
  try {
    read_part_exr(dir + "/plain.exr");
    FAIL() << "read a plain EXR as a part";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a pmc render part"), std::string::npos) << e.what();
  }
}

TEST(MergeParts, SampleRangesAndTilesAddUpToTheFrame) {
  const std::vector<RenderPart> parts = {
      make_part("a", 0, 3, {0, 0, 6, 4}, 1.0f), make_part("b", 3, 8, {0, 0, 3, 4}, 3.0f),
      make_part("c", 3, 5, {3, 0, 6, 4}, 3.0f), make_part("d", 5, 8, {3, 0, 6, 4}, 3.0f)};
  const MergedFrame m = merge_parts(parts, false);
  EXPECT_FALSE(m.info.partial);
  EXPECT_EQ(m.info.cache_counters.lookups, 40u);
  const Image img = film_mean(m.film);
  for (float v : img.pixels) EXPECT_EQ(v, (3 * 1.0f + 5 * 3.0f) / 8.0f);  // sample-weighted
}

TEST(MergeParts, RefusesPartsOfAnotherSceneOrSettingsNamingTheFile) {
  RenderPart a = make_part("a.exr", 0, 4, {0, 0, 6, 4}), b = make_part("b.exr", 4, 8, {0, 0, 6, 4});
  b.info.scene_hash = "scene2";
  std::string e = merge_error({a, b});
  EXPECT_NE(e.find("b.exr: a different scene from a.exr"), std::string::npos) << e;
  b.info.scene_hash = "scene1";
  b.info.settings_hash = "settings2";
  e = merge_error({a, b});
  EXPECT_NE(e.find("b.exr: different render settings"), std::string::npos) << e;
  b.info.settings_hash = "settings1";
  b.info.seed = 6;
  e = merge_error({a, b});
  EXPECT_NE(e.find("b.exr: a different frame"), std::string::npos) << e;
  b.info.seed = 5;
  EXPECT_EQ(merge_error({a, b}), "");
}

TEST(MergeParts, RefusesOverlapsAndMissingSamplesUnlessPartialIsAllowed) {
  const RenderPart a = make_part("a.exr", 0, 5, {0, 0, 6, 4}), b = make_part("b.exr", 4, 8, {0, 0, 6, 4});
  std::string e = merge_error({a, b});
  EXPECT_NE(e.find("b.exr: samples 4:8"), std::string::npos) << e;
  EXPECT_NE(e.find("overlap a.exr"), std::string::npos) << e;
  // Tiles that overlap by one column, same samples.
  e = merge_error({make_part("l.exr", 0, 8, {0, 0, 4, 4}), make_part("r.exr", 0, 8, {3, 0, 6, 4})});
  EXPECT_NE(e.find("r.exr"), std::string::npos) << e;
  EXPECT_NE(e.find("overlap l.exr"), std::string::npos) << e;

  const RenderPart c = make_part("c.exr", 0, 4, {0, 0, 6, 4}, 2.0f);
  const RenderPart d = make_part("d.exr", 6, 8, {0, 0, 6, 4}, 2.0f);
  e = merge_error({c, d});
  EXPECT_NE(e.find("samples missing"), std::string::npos) << e;
  EXPECT_NE(e.find("6 of 8"), std::string::npos) << e;
  EXPECT_NE(e.find("(pass allow_partial to merge"), std::string::npos) << e << " (app/ shows the flag)";
  const MergedFrame m = merge_parts({c, d}, true);
  EXPECT_TRUE(m.info.partial);
  EXPECT_EQ(m.missing_pixel_samples, 2u * 24u);
  EXPECT_EQ(film_mean(m.film).pixels[0], 2.0f);  // the mean of the samples there are
  // A missing tile.
  e = merge_error({make_part("l.exr", 0, 8, {0, 0, 3, 4})});
  EXPECT_NE(e.find("pixel (3,0) has 0 of 8"), std::string::npos) << e;
}

TEST(MergeParts, APartialMergeCannotBeMergedAgain) {
  const std::string dir = test::temp_dir();
  const MergedFrame m = merge_parts({make_part("c.exr", 0, 4, {0, 0, 6, 4})}, true);
  write_part_exr(dir + "/partial.exr", film_mean(m.film), m.info, &m.film);
  try {
    read_part_exr(dir + "/partial.exr");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("partial merge"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pmc
