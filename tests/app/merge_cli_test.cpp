// merge_cli_test.cpp — `pmc render --samples/--crop` and `pmc merge` through the pmc binary.
//
// The independent answer for a merge is the one-process render of the same
// frame: its EXR must equal the merged EXR's R, G, B bit for bit.
//  * Cacheless (the default room, --cache off): sample ranges merged in a
//    shuffled order. Exact because the film adds samples as 128-bit fixed-point
//    integers (core/device/pmc_film.h): any split sums to the same integer.
//  * Cached, --cache-eval center (the brick teapot, one cache point): also
//    exact, not just within 1e-5. A centre-mode texel's value is evaluated at
//    the texel centre and decoded the same way on a hit and on a miss, and the
//    bilinear texel pick comes from the path's own random numbers, so a
//    sample's radiance does not depend on what else is in the table; the parts
//    see lower hit rates (checked: their tables start empty) and the same image.
//  * Parts that straddle the camera-sample limit (--cache-camera-samples) too.
//  * Tiles (--crop), one of them split by samples too, assemble into the frame.
//  * Mismatched parts (another seed, another scene, overlaps, missing
//    samples) exit 2 naming the file, and write nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/image_io.h"
#include "core/render_part.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

std::string room() { return test::source_path("data/default/room.obj"); }
const char* kRoomArgs = " --width 40 --height 24 --spp 6 --max-depth 4 --cache off --quiet";

std::string teapot_args() {
  return test::shared_scene("materialx/geometry/teapot.obj") + " --mtlx " +
         test::shared_scene("materialx/standard_surface_brick_procedural.mtlx") +
         " --material M_BrickPattern --env 1,1,1 --camera-from -0.1,0.5,2.2 --camera-at -0.1,0.1,0 --fov 40 "
         "--width 40 --height 30 --spp 6 --max-depth 3 --cache-eval center --quiet";
}

// Channels R, G, B of an EXR (a part's extra channels follow them).
std::vector<float> rgb(const std::string& path) {
  const Image img = read_image(path);
  EXPECT_GE(img.channels, 3);
  std::vector<float> out;
  for (size_t i = 0; i < size_t(img.width) * size_t(img.height); ++i)
    for (int c = 0; c < 3; ++c) out.push_back(img.pixels[i * size_t(img.channels) + size_t(c)]);
  return out;
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

void render(const std::string& scene_args, const std::string& out, const std::string& extra) {
  std::string log;
  ASSERT_EQ(test::run_pmc("render " + scene_args + " -o " + out + " " + extra, &log), 0) << log;
}

TEST(MergeCli, CachelessSampleRangesMergeToTheOneProcessRenderBitForBit) {
  const std::string d = test::temp_dir(), args = room() + kRoomArgs;
  render(args, d + "/full.exr", "");
  render(args, d + "/a.exr", "--samples 0:1");
  render(args, d + "/b.exr", "--samples 1:4");
  render(args, d + "/c.exr", "--samples 4:6");
  std::string log;
  ASSERT_EQ(test::run_pmc("merge " + d + "/c.exr " + d + "/a.exr " + d + "/b.exr -o " + d +
                              "/m.exr --stats " + d + "/m.json",
                          &log),
            0)
      << log;
  const std::vector<float> full = rgb(d + "/full.exr"), merged = rgb(d + "/m.exr");
  ASSERT_EQ(full.size(), size_t(40 * 24 * 3));
  EXPECT_TRUE(full == merged) << "merged image differs from the one-process render";
  EXPECT_FALSE(rgb(d + "/b.exr") == full);  // a part alone is a different (noisier) image
  EXPECT_TRUE(test::file_exists(d + "/m.png"));
  const nlohmann::json st = read_json(d + "/m.json");
  EXPECT_EQ(st["parts"].size(), 3u);
  EXPECT_EQ(st["spp"], 6);
  EXPECT_FALSE(st["partial"].get<bool>());
}

TEST(MergeCli, CenterCachedPartsMergeToTheOneProcessRenderExactly) {
  const std::string d = test::temp_dir(), args = teapot_args();
  render(args, d + "/full.exr", "--stats " + d + "/full.json");
  render(args, d + "/a.exr", "--samples 0:2 --stats " + d + "/a.json");
  render(args, d + "/b.exr", "--samples 2:6 --stats " + d + "/b.json");
  std::string log;
  ASSERT_EQ(test::run_pmc("merge " + d + "/a.exr " + d + "/b.exr -o " + d + "/m.exr --stats " + d + "/m.json",
                          &log),
            0)
      << log;
  const nlohmann::json full = read_json(d + "/full.json"), a = read_json(d + "/a.json"),
                       b = read_json(d + "/b.json"), m = read_json(d + "/m.json");
  ASSERT_TRUE(full["cache"]["enabled"].get<bool>());
  ASSERT_GT(full["cache"]["hits"].get<uint64_t>(), 0u);
  // Each part warmed its own table: fewer hits in all than the one process.
  EXPECT_LT(a["cache"]["hits"].get<uint64_t>() + b["cache"]["hits"].get<uint64_t>(),
            full["cache"]["hits"].get<uint64_t>());
  EXPECT_EQ(m["cache"]["lookups"].get<uint64_t>(),
            a["cache"]["lookups"].get<uint64_t>() + b["cache"]["lookups"].get<uint64_t>());
  EXPECT_TRUE(rgb(d + "/full.exr") == rgb(d + "/m.exr"))
      << "centre-mode merge differs from the one-process render";
}

// Camera hits use the cache in a pixel's first K samples only
// (--cache-camera-samples): a part that straddles sample K (here 1:4 with
// K = 3) caches its samples 1..2 at camera hits and not 3, as the one
// process does, so the merge is still exact; K = 6 (every sample) is
// another image (the check can fail).
TEST(MergeCli, PartsAcrossTheCameraSampleLimitMergeExactly) {
  const std::string d = test::temp_dir(), args = teapot_args() + " --cache-camera-samples 3";
  render(args, d + "/full.exr", "");
  render(args, d + "/a.exr", "--samples 0:1");
  render(args, d + "/b.exr", "--samples 1:4");
  render(args, d + "/c.exr", "--samples 4:6");
  render(teapot_args(), d + "/all.exr", "--cache-camera-samples 6");
  std::string log;
  ASSERT_EQ(test::run_pmc("merge " + d + "/b.exr " + d + "/c.exr " + d + "/a.exr -o " + d + "/m.exr", &log),
            0)
      << log;
  EXPECT_TRUE(rgb(d + "/full.exr") == rgb(d + "/m.exr")) << "merge across the camera-sample limit differs";
  EXPECT_FALSE(rgb(d + "/full.exr") == rgb(d + "/all.exr"));
  // Parts of another limit do not merge with these (the settings hash covers it).
  render(teapot_args(), d + "/other.exr", "--samples 1:4 --cache-camera-samples 2");
  EXPECT_EQ(
      test::run_pmc("merge " + d + "/a.exr " + d + "/other.exr " + d + "/c.exr -o " + d + "/x.exr", &log), 2)
      << log;
  EXPECT_FALSE(test::file_exists(d + "/x.exr"));
}

TEST(MergeCli, CropTilesAssembleIntoTheFrame) {
  const std::string d = test::temp_dir(), args = room() + kRoomArgs;
  render(args, d + "/full.exr", "");
  render(args, d + "/t0.exr", "--crop 0,0,25,10");
  render(args, d + "/t1.exr", "--crop 25,0,40,10");
  render(args, d + "/t2a.exr", "--crop 0,10,40,24 --samples 0:2");
  render(args, d + "/t2b.exr", "--crop 0,10,40,24 --samples 2:6");
  const Image tile = read_image(d + "/t1.exr");
  EXPECT_EQ(tile.width, 15);
  EXPECT_EQ(tile.height, 10);
  const RenderPart part = read_part_exr(d + "/t1.exr");
  EXPECT_EQ(part.info.crop, (std::array<int, 4>{25, 0, 40, 10}));
  EXPECT_EQ(part.info.frame_width, 40);
  // The tile's pixels are the full render's pixels at the same place.
  const std::vector<float> full = rgb(d + "/full.exr"), t1 = rgb(d + "/t1.exr");
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 15; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(t1[size_t((y * 15 + x) * 3 + c)], full[size_t((y * 40 + x + 25) * 3 + c)]) << x << "," << y;
  std::string log;
  ASSERT_EQ(test::run_pmc("merge " + d + "/t2b.exr " + d + "/t0.exr " + d + "/t2a.exr " + d + "/t1.exr -o " +
                              d + "/m.exr",
                          &log),
            0)
      << log;
  EXPECT_TRUE(full == rgb(d + "/m.exr"));
}

TEST(MergeCli, RefusesMismatchedPartsNamingTheFileAndWritesNothing) {
  const std::string d = test::temp_dir(), args = room() + kRoomArgs;
  render(args, d + "/a.exr", "--samples 0:3");
  render(args, d + "/b.exr", "--samples 3:6");
  render(args, d + "/seed.exr", "--samples 3:6 --seed 9");
  render(args, d + "/over.exr", "--samples 2:6");
  render(args, d + "/short.exr", "--samples 4:6");
  render(test::shared_scene("cornell/cornell_box.obj") + kRoomArgs, d + "/other.exr", "--samples 3:6");
  render(args, d + "/plain.exr", "");  // a plain render: no sums
  struct Case {
    std::string parts, expect;
  } cases[] = {
      {"a.exr seed.exr", "seed.exr: different render settings from"},
      {"a.exr other.exr", "other.exr: a different scene from"},
      {"a.exr over.exr", "over.exr: samples 2:6"},
      {"a.exr short.exr", "samples missing: pixel (0,0) has 5 of 6"},
      {"a.exr short.exr", "(pass --allow-partial to merge what there is)"},  // core names the setting
      {"a.exr plain.exr",
       "plain.exr: no channel pmc.sum0 (a part needs the film's sums: render it with "
       "'pmc render --samples A:B')"},
      {"a.exr nothing.exr", "nothing.exr"},
  };
  for (const Case& c : cases) {
    std::string parts, log;
    for (size_t i = 0, j; i < c.parts.size(); i = j + 1) {
      j = c.parts.find(' ', i);
      if (j == std::string::npos) j = c.parts.size();
      parts += " " + d + "/" + c.parts.substr(i, j - i);
    }
    EXPECT_EQ(test::run_pmc("merge" + parts + " -o " + d + "/out.exr --stats " + d + "/out.json", &log), 2)
        << c.parts << ": " << log;
    EXPECT_NE(log.find(c.expect), std::string::npos) << c.parts << ": " << log;
    EXPECT_FALSE(test::file_exists(d + "/out.exr")) << c.parts;
    EXPECT_FALSE(test::file_exists(d + "/out.png")) << c.parts;
    EXPECT_FALSE(test::file_exists(d + "/out.json")) << c.parts;
  }
  // --allow-partial merges what there is.
  std::string log;
  EXPECT_EQ(
      test::run_pmc("merge " + d + "/a.exr " + d + "/short.exr -o " + d + "/out.exr --allow-partial", &log),
      0)
      << log;
  EXPECT_NE(log.find("pixel samples missing"), std::string::npos) << log;
}

TEST(MergeCli, BadSampleRangesAndWindowsExitWithCode2) {
  const std::string d = test::temp_dir(), args = room() + kRoomArgs;
  const std::pair<std::string, std::string> cases[] = {
      {"--samples 4:2", "--samples"},  {"--samples 0:7", "--samples"}, {"--samples x", "--samples"},
      {"--samples -1:2", "--samples"}, {"--crop 0,0,41,24", "--crop"}, {"--crop 5,5,5,9", "--crop"},
      {"--crop 1,2,3", "--crop"},
  };
  for (const auto& [extra, flag] : cases) {
    std::string log;
    EXPECT_EQ(test::run_pmc("render " + args + " -o " + d + "/x.exr " + extra, &log), 2)
        << extra << ": " << log;
    EXPECT_NE(log.find(flag), std::string::npos) << extra << ": " << log;
    EXPECT_FALSE(test::file_exists(d + "/x.exr")) << extra;
  }
}

TEST(MergeCli, EveryRenderRecordsItsPartInTheExrHeader) {
  const std::string d = test::temp_dir(), args = teapot_args();
  render(args, d + "/p.exr", "--samples 1:5 --seed 7");
  const RenderPart p = read_part_exr(d + "/p.exr");
  EXPECT_EQ(p.info.sample_begin, 1);
  EXPECT_EQ(p.info.sample_end, 5);
  EXPECT_EQ(p.info.spp, 6);
  EXPECT_EQ(p.info.seed, 7u);
  EXPECT_EQ(p.info.scene_hash.size(), 16u);
  EXPECT_GT(p.info.cache_counters.lookups, 0u);
  EXPECT_EQ(p.info.cache_counters.lookups, p.info.cache_counters.hits + p.info.cache_counters.misses);
  for (uint32_t s : p.film.samples) ASSERT_EQ(s, 4u);
}

}  // namespace
}  // namespace pmc
