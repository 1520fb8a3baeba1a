// render_config_test.cpp — RenderConfig::validate() names the field that is wrong.
//
// Every check is made to fail once, on a config that is valid otherwise;
// the ConfigError must name that field (its settings(), the names app/ turns
// into flags) and nothing is loaded: the scene path does not exist, so an
// error that came from loading would name the file instead. The camera a
// session resolves follows the documented order: camera_from/at, else
// SCENE.camera beside the OBJ (fov overrides its fov), else framing.
#include "gpu/render_config.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "core/error.h"
#include "core/scene.h"
#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

RenderConfig valid() {
  RenderConfig c;
  c.scene = "/nonexistent/scene.obj";
  return c;
}

std::vector<std::string> settings_named_by(const std::function<void(RenderConfig&)>& change) {
  RenderConfig c = valid();
  change(c);
  try {
    c.validate();
  } catch (const ConfigError& e) {
    return e.settings();
  }
  return {};
}

TEST(RenderConfig, DefaultsAreValid) { EXPECT_NO_THROW(valid().validate()); }

TEST(RenderConfig, EachBadFieldIsNamed) {
  using S = std::vector<std::string>;
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.scene.clear(); }), S{"scene"});
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.width = 0; }), (S{"width", "height"}));
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.height = 1 << 20, c.width = 1 << 10; }),
            (S{"width", "height"}));
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.spp = 0; }), S{"spp"});
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.max_depth = 1025; }), S{"max_depth"});
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.seed = int64_t(1) << 32; }), S{"seed"});
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.env[1] = -1.0f; }), S{"env"});
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.chunk_rays = -1; }), S{"chunk_rays"});
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.threads = 0; }), S{"threads"});
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.fov = 180.0f; }), S{"fov"});
  EXPECT_EQ(settings_named_by([](RenderConfig& c) {
              c.camera_from = Vec3{1, 2, 3};
            }),
            (S{"camera_from", "camera_at"}));
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.cache_min_nodes = 0; }), S{"cache_min_nodes"});
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.material = "M"; }), (S{"material", "mtlx"}));
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.mip_bias = 33.0f; }), S{"mip_bias"});
  for (float bad : {-0.5f, 4.5f, std::nanf("")})
    EXPECT_EQ(settings_named_by([bad](RenderConfig& c) { c.cache_lobe_spread = bad; }),
              S{"cache_lobe_spread"})
        << bad;
  EXPECT_EQ(settings_named_by([](RenderConfig& c) {
              c.cache_eval = CacheEval::Hit;
              c.cache_filter = CacheFilter::Bilinear;
            }),
            (S{"cache_filter", "cache_eval"}));
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.cache_policy = static_cast<CachePolicy>(7); }),
            S{"cache_policy"});
  for (int bad : {-1, 3, 12, 32})
    EXPECT_EQ(settings_named_by([bad](RenderConfig& c) { c.cache_supersample = bad; }),
              S{"cache_supersample"})
        << bad;
  for (int good : {0, 1, 2, 4, 8, 16}) {
    RenderConfig c = valid();
    c.cache_supersample = good;
    EXPECT_NO_THROW(c.validate()) << good;
  }
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.cache_cells = 0; }), S{"cache_cells"});
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.cache_entries = 1025; }), S{"cache_entries"});
  EXPECT_EQ(settings_named_by([](RenderConfig& c) { c.cache_cells = int64_t(1) << 50; }),
            (S{"cache_cells", "cache_entries"}));
}

TEST(RenderConfig, ErrorsShowSettingsByNameOrRenamed) {
  RenderConfig c = valid();
  c.spp = -3;
  try {
    c.validate();
    FAIL() << "spp -3 accepted";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "spp: samples per pixel must be at least 1, got -3");
    EXPECT_EQ(e.phrased([](const std::string& s) { return "<" + s + ">"; }),
              "<spp>: samples per pixel must be at least 1, got -3");
  }
}

TEST(RenderConfig, CacheFilterFollowsTheEvalModeUnlessGiven) {
  RenderConfig c = valid();
  EXPECT_EQ(c.effective_cache_filter(), CacheFilter::Bilinear);
  c.cache_eval = CacheEval::Hit;
  EXPECT_EQ(c.effective_cache_filter(), CacheFilter::Nearest);
  c.cache_eval = CacheEval::Center;
  c.cache_filter = CacheFilter::Nearest;
  EXPECT_EQ(c.effective_cache_filter(), CacheFilter::Nearest);
  const RenderSettings s = base_render_settings(c);
  EXPECT_TRUE(s.cache.center);
  EXPECT_FALSE(s.cache.bilinear);
}

TEST(RenderConfig, CachePolicyIsKeepFirstUnlessPriorityIsAsked) {
  RenderConfig c = valid();
  EXPECT_EQ(c.cache_policy, CachePolicy::KeepFirst) << "the paper's rule is the default";
  EXPECT_FALSE(base_render_settings(c).cache.priority);
  c.cache_policy = CachePolicy::Priority;
  EXPECT_NO_THROW(c.validate());
  EXPECT_TRUE(base_render_settings(c).cache.priority);
}

TEST(RenderConfig, CameraComesFromFlagsThenTheCameraFileThenFraming) {
  const std::string dir = test::temp_dir();
  Scene scene;
  scene.bounds.lo[0] = scene.bounds.lo[1] = scene.bounds.lo[2] = -1.0f;
  scene.bounds.hi[0] = scene.bounds.hi[1] = scene.bounds.hi[2] = 1.0f;
  RenderConfig c = valid();
  c.scene = dir + "/s.obj";
  // No file: framing the bounds, looking at their centre.
  Camera framed = resolve_camera(c, scene);
  for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(framed.at[i], 0.0f);
  EXPECT_FLOAT_EQ(framed.fov_degrees, 45.0f);
  // A camera file beside the OBJ, its fov overridden by config.fov.
  test::write_file(dir + "/s.camera", "from 1 2 3\nat 4 5 6\nup 0 0 1\nfov 30\n");
  Camera filed = resolve_camera(c, scene);
  EXPECT_FLOAT_EQ(filed.from[1], 2.0f);
  EXPECT_FLOAT_EQ(filed.at[2], 6.0f);
  EXPECT_FLOAT_EQ(filed.up[2], 1.0f);
  EXPECT_FLOAT_EQ(filed.fov_degrees, 30.0f);
  c.fov = 50.0f;
  EXPECT_FLOAT_EQ(resolve_camera(c, scene).fov_degrees, 50.0f);
  // Explicit from/at win over the file; up defaults to +y.
  c.camera_from = Vec3{7, 8, 9};
  c.camera_at = Vec3{0, 0, 0};
  Camera given = resolve_camera(c, scene);
  EXPECT_FLOAT_EQ(given.from[0], 7.0f);
  EXPECT_FLOAT_EQ(given.up[1], 1.0f);
  EXPECT_FLOAT_EQ(given.up[2], 0.0f);
  EXPECT_FLOAT_EQ(given.fov_degrees, 50.0f);
}

}  // namespace
}  // namespace pmc
