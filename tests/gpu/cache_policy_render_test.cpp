// cache_policy_render_test.cpp — --cache-policy keep-first vs priority in a
// render of the default scene (data/default, real OpenCL on PoCL).
//
// One session (one program) renders 96x54 at 4 spp with the automatic table
// (8192 cells) and with tables of 1/4 and 1/8 of its cells, under both
// policies, with the same seed. Required:
//  * in the small tables priority replaces entries (replaced > 0; keep-first
//    none) and finds more camera-ray hits than keep-first; both look up
//    exactly as often (the same paths). Measured on PoCL (2 threads): 1/4:
//    12640 -> 13080 camera hits (+3.5%; total hits 35.8k -> 34.0k), 1/8:
//    9730 -> 10600 (+9%; total 22.9k -> 20.4k); run to run the counts move by
//    about 0.2% (the order in which threads insert). Not compared below 1/8:
//    from about 1/16 the camera hits of the first sample alone fill the table,
//    nothing is deeper, nothing is replaced, and the policies differ only by
//    that thread-order noise (at 1/64, 890-1260 camera hits run to run);
//  * the counters add up under both: hits + misses = lookups, every miss ends
//    in one of inserts / replaced / already present / dropped / not encodable,
//    occupied entries = inserts (a replacement overwrites, it adds nothing),
//    camera lookups <= lookups;
//  * the images are bit-identical across policies and sizes: in --cache-eval
//    center (the default) a texel's value does not depend on who inserted it,
//    so a replacement that stored a wrong value, or under a wrong key, or tore
//    a word, would change pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

void expect_consistent(const CacheStats& c) {
  EXPECT_GT(c.lookups, 0u);
  EXPECT_EQ(c.hits + c.misses, c.lookups);
  EXPECT_EQ(c.inserts + c.replaced + c.already_present + c.dropped_full + c.not_encodable, c.misses);
  EXPECT_EQ(c.occupied, c.inserts) << "only inserts into empty entries add entries";
  EXPECT_GT(c.camera_lookups, 0u);
  EXPECT_LT(c.camera_lookups, c.lookups);
  EXPECT_LE(c.camera_hits, c.camera_lookups);
  EXPECT_LE(c.camera_hits, c.hits);
}

TEST(CachePolicy, PriorityHitsMoreOftenOnCameraRaysInSmallTables) {
  RenderConfig config;
  config.scene = test::source_path("data/default/room.obj");
  config.mtlx = {test::source_path("data/default/materials.mtlx")};
  config.width = 96;
  config.height = 54;
  config.spp = 4;
  config.max_depth = 4;
  config.seed = 11;
  // The paper's texels (the default; said here because at 96x54 level
  // floors would send most points past the refinement limit, uncached, and
  // leave the table too empty to need a policy).
  config.cache_bandwidth = CacheBandwidth::Off;
  config.cache_audit = true;  // occupied counted from the table itself, checked against inserts
  RenderSession session(config, test::cl());
  ASSERT_TRUE(session.settings().cache.on);
  const uint64_t full = session.settings().cache.cells;

  RenderOutput reference;
  for (uint64_t divisor : {uint64_t(1), uint64_t(4), uint64_t(8)}) {
    SCOPED_TRACE("1/" + std::to_string(divisor) + " of " + std::to_string(full) + " cells");
    RenderOutput out[2];
    for (int priority = 0; priority < 2; ++priority) {
      RenderSettings s = session.settings();
      s.cache.cells = std::max<uint64_t>(1, full / divisor);
      s.cache.priority = priority == 1;
      // One sample per wave, as frames of 2^16 pixels and more render: the
      // policy's case is a later sample's camera point meeting a table that
      // earlier samples' deeper bounces filled. (When a small frame puts all
      // four samples in one wave, every camera point is looked up before any
      // deeper one, keep-first keeps them anyway, and priority only churns.)
      s.max_wave_paths = size_t(config.width) * size_t(config.height);
      // And one wave loop: with two, each half of the frame runs its samples
      // at its own pace, the halves' lookups interleave anyhow, and at 1/4 the
      // policies' camera hits came out in either order (1 run in 5).
      s.waves_in_flight = 1;
      out[priority] = session.render(s);
      SCOPED_TRACE(priority ? "priority" : "keep-first");
      expect_consistent(out[priority].stats.cache);
      if (reference.image.pixels.empty()) reference = out[priority];
      size_t differ = 0;
      for (size_t i = 0; i < reference.image.pixels.size(); ++i)
        differ += out[priority].image.pixels[i] != reference.image.pixels[i];
      EXPECT_EQ(differ, 0u) << "center mode: the policy and the table size must not change the image";
    }
    const CacheStats &keep = out[0].stats.cache, &prio = out[1].stats.cache;
    EXPECT_EQ(keep.replaced, 0u);
    RecordProperty("camera_hit_rate_keep_first_1_" + std::to_string(divisor),
                   std::to_string(camera_hit_rate(keep)));
    RecordProperty("camera_hit_rate_priority_1_" + std::to_string(divisor),
                   std::to_string(camera_hit_rate(prio)));
    std::printf("1/%llu: camera hit rate keep-first %.4f, priority %.4f; total %.4f vs %.4f; replaced %llu\n",
                (unsigned long long)divisor, camera_hit_rate(keep), camera_hit_rate(prio), hit_rate(keep),
                hit_rate(prio), (unsigned long long)prio.replaced);
    if (divisor > 1) {
      EXPECT_GT(prio.replaced, 0u) << "a small table fills up: camera inserts replace deeper entries";
      EXPECT_GT(prio.camera_hits, keep.camera_hits) << "priority must hit more often on camera rays";
      EXPECT_EQ(prio.lookups, keep.lookups) << "the same paths look up the same points";
      EXPECT_EQ(prio.camera_lookups, keep.camera_lookups);
    }
  }
}

}  // namespace
}  // namespace pmc
