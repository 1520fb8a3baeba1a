// cache_load_test.cpp — the progressive material cache under load.
//
// The brick teapot (../shared/scenes/materialx: procedural brick material,
// several cache points, nested) rendered with thousands of samples per pixel
// on a tiny image, three times with the same seed:
//   * cacheless (the reference),
//   * with a deliberately tiny table (1 cell x 1 entry: every insert but the
//     first finds its cell full),
//   * with a huge table (nothing is ever dropped).
// Required: no crash, no NaN/Inf, and consistent counters:
//   hits + misses == lookups (each counted where it happens);
//   inserts + already_present + dropped_full + not_encodable == misses
//     (each missed point's STORE ends in exactly one of them);
//   occupied == inserts (an entry is written only by a successful insert and
//     never removed);
//   tiny table: exactly one insert, dropped_full > 0;
//   huge table: dropped_full == 0, hits > 0.
// Image quality vs the cacheless render (PSNR, linear values clamped to
// [0, 1], peak 1 — core/image_metrics.h) must stay >= 40 dB for both tables:
// an average error below 1% of the display range, invisible, and far below
// what a working cache reaches (the measured values are recorded as the
// test's properties), while a wrong level, a wrong encoding or a value stored under
// the wrong key (blocks of wrong colour) falls far below it. And with
// --cache-eval center (pmc's default) a miss is evaluated at the texel centre
// and quantised like a stored value, so a hit and a miss give the same value:
// the image must not depend on the table at all — the tiny and the huge
// table give bit-identical images.
#include <gtest/gtest.h>

#include <chrono>

#include "core/image_metrics.h"
#include "tests/hard_cases/hard_support.h"

namespace pmc {
namespace {

struct LoadRun {
  RenderOutput out;
  double seconds = 0;
};

TEST(CacheLoad, TinyAndHugeTablesOverThousandsOfSamples) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string obj = test::shared_scene("materialx/geometry/teapot.obj");
  const std::string mtlx = test::shared_scene("materialx/standard_surface_brick_procedural.mtlx");
  RenderConfig config;
  config.scene = obj;
  config.mtlx = {mtlx};
  config.material = "M_BrickPattern";
  config.width = 16;
  config.height = 16;
  config.spp = 2000;
  config.max_depth = 3;
  config.seed = 5;
  config.env = {1.0f, 1.0f, 1.0f};
  config.fov = 30.0f;  // framing the teapot: it fills the frame
  config.cache_eval = CacheEval::Center;
  config.cache_filter = CacheFilter::Nearest;
  config.cache_min_nodes = 4;  // the brick's 21- and 7-node points: more keys under load
  config.cache_audit = true;   // occupied counted from the table itself, checked against inserts

  auto run = [&](bool cache, int64_t cells, int64_t entries) {
    RenderConfig c = config;
    c.cache = cache;
    c.cache_cells = cells;
    c.cache_entries = entries;
    RenderSession session(c, test::cl());
    if (cache) EXPECT_GE(session.cache_points(), 2u) << "the brick material should have several cache points";
    LoadRun r;
    auto start = std::chrono::steady_clock::now();
    r.out = session.render();
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
  };

  LoadRun ref = run(false, 1, 1);
  LoadRun tiny = run(true, 1, 1);
  LoadRun huge = run(true, uint64_t(1) << 21, 16);  // 2^25 entries, 256 MiB

  hard::expect_clean(ref.out, "cacheless");
  hard::expect_clean(tiny.out, "tiny table");
  hard::expect_clean(huge.out, "huge table");

  auto check_counters = [](const CacheStats& c, const char* what) {
    SCOPED_TRACE(what);
    EXPECT_GT(c.lookups, 0u);
    EXPECT_EQ(c.hits + c.misses, c.lookups);
    EXPECT_EQ(c.inserts + c.already_present + c.dropped_full + c.not_encodable, c.misses);
    EXPECT_GT(c.misses, 0u);
    EXPECT_EQ(c.occupied, c.inserts) << "an entry is written only by a successful insert";
    EXPECT_LE(c.occupied, c.cells * c.ways);
  };
  check_counters(tiny.out.stats.cache, "tiny");
  check_counters(huge.out.stats.cache, "huge");
  const CacheStats& t = tiny.out.stats.cache;
  const CacheStats& h = huge.out.stats.cache;
  EXPECT_EQ(t.cells, 1u);
  EXPECT_EQ(t.ways, 1u);
  EXPECT_EQ(t.inserts, 1u) << "one entry: only the first insert can win";
  EXPECT_GT(t.dropped_full, 0u);
  EXPECT_GT(t.dropped_full, t.lookups / 2) << "nearly every miss finds the one cell full";
  EXPECT_EQ(h.dropped_full, 0u);
  EXPECT_GT(h.hits, h.lookups / 2) << "thousands of samples over 256 pixels revisit the same texels";
  EXPECT_GT(h.inserts, 100u);

  const ImageError et = compare_images(tiny.out.image, ref.out.image);
  const ImageError eh = compare_images(huge.out.image, ref.out.image);
  EXPECT_GE(et.psnr, 40.0) << "tiny table vs cacheless";
  EXPECT_GE(eh.psnr, 40.0) << "huge table vs cacheless";
  size_t differing = 0;
  for (size_t i = 0; i < tiny.out.image.pixels.size(); ++i)
    differing += tiny.out.image.pixels[i] != huge.out.image.pixels[i] ? 1 : 0;
  EXPECT_EQ(differing, 0u) << "center mode: the table size must not change the image";
  RecordProperty("psnr_tiny", hard::num(et.psnr));
  RecordProperty("psnr_huge", hard::num(eh.psnr));
  RecordProperty("hit_rate_huge", hard::num(double(h.hits) / double(h.lookups)));
  RecordProperty("dropped_tiny", std::to_string(t.dropped_full));
  RecordProperty("seconds_ref_tiny_huge",
                 hard::num(ref.seconds) + " " + hard::num(tiny.seconds) + " " + hard::num(huge.seconds));
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  RecordProperty("seconds_total", hard::num(total));
}

}  // namespace
}  // namespace pmc
