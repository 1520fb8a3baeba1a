// cache_fit_test.cpp — --cache-fit: coarser texels when the table is too
// small for the frame's keys (core/cache_sizing.h, real OpenCL on PoCL).
//
//  * The level offset is half a level per halving of the table below what the
//    frame's keys need, none where they fit; the automatic table always fits.
//  * A render with fit on in a small table is the render with fit off whose
//    mip bias is lower by that offset, bit for bit: in --cache-eval center a
//    texel's value depends on its key alone, so the table's size does not
//    change the image and the offset is the only difference. Its hit rate is
//    far above the same table's without fit (fewer, wider texels).
#include <gtest/gtest.h>


#include "core/cache_sizing.h"
#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

TEST(CacheFit, HalfALevelPerHalvingOfTheTable) {
  EXPECT_FLOAT_EQ(fit_levels(16.0 * 4096, 4096), 2.0f);
  EXPECT_FLOAT_EQ(fit_levels(4.0 * 4096, 4096), 1.0f);
  EXPECT_FLOAT_EQ(fit_levels(2.0 * 4096, 4096), 0.5f);
  EXPECT_FLOAT_EQ(fit_levels(4096, 4096), 0.0f);
  EXPECT_FLOAT_EQ(fit_levels(100, 4096), 0.0f);
  EXPECT_FLOAT_EQ(fit_levels(1e9, 0), 0.0f);  // no table: nothing to fit
  // The automatic size (no memory cap) holds the expected entries at every
  // image size and sample count, so fit never coarsens it.
  for (int spp : {1, 4, 16, 256})
    for (auto [w, h] : {std::pair{96, 54}, std::pair{640, 360}, std::pair{3840, 2160}}) {
      const CacheSize cs = choose_cache_size(w, h, spp, 1.6, ~uint64_t(0));
      EXPECT_EQ(fit_levels(expected_entries(w, h, spp, 1.6), cs.cells * cs.entries), 0.0f)
          << w << "x" << h << " " << spp << " spp";
    }
  // A table the memory limit halved twice is 1 level short.
  const CacheSize capped = choose_cache_size(1920, 1080, 64, 2.0, 16ull << 20);
  EXPECT_NE(capped.reason.find("capped by the memory limit"), std::string::npos);
  EXPECT_GT(fit_levels(expected_entries(1920, 1080, 64, 2.0), capped.cells * capped.entries), 0.5f);
}

TEST(CacheFit, SmallTableRendersAsTheCoarserBiasAndHitsMore) {
  RenderConfig config = test::default_scene_config(96, 54, 4);
  config.max_depth = 3;
  config.seed = 5;
  config.cache_cells = 512;  // 1/16 of the automatic 8192
  config.cache_fit = true;
  RenderSession session(config, test::cl());
  const CacheSettings& fit = session.settings().cache;
  ASSERT_TRUE(fit.on);
  EXPECT_GT(fit.fit_levels, 1.0f);
  EXPECT_NE(fit.reason.find("levels coarser"), std::string::npos) << fit.reason;

  const RenderOutput fitted = session.render();
  RenderSettings as_bias = session.settings();
  as_bias.cache.fit_levels = 0.0f;
  as_bias.cache.mip_bias = -fit.fit_levels;
  const RenderOutput biased = session.render(as_bias);
  RenderSettings plain = session.settings();
  plain.cache.fit_levels = 0.0f;
  const RenderOutput unfitted = session.render(plain);

  ASSERT_EQ(fitted.image.pixels.size(), biased.image.pixels.size());
  ASSERT_GT(test::image_mean(fitted.image), 0.0);
  EXPECT_EQ(test::differing_values(fitted.image, biased.image), 0u);
  EXPECT_GT(test::differing_values(fitted.image, unfitted.image), 0u) << "fit changed no texel";
  const CacheStats &f = fitted.stats.cache, &u = unfitted.stats.cache;
  const double fit_rate = double(f.hits) / double(f.lookups), plain_rate = double(u.hits) / double(u.lookups);
  EXPECT_GT(fit_rate, 1.5 * plain_rate)
      << "hit rate " << fit_rate << " with fit, " << plain_rate << " without";
}

}  // namespace
}  // namespace pmc
