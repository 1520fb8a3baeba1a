// shade_lanes_test.cpp — the shade kernel's batch size changes speed, never
// the image.
//
// A shade work-item evaluates one material for a batch of PMC_LANES hits
// (gpu/wave_kernels.h). Batches of 1 (the GPU build), 16 (the CPU fallback
// for very deep material stacks) and the CPU default (64) must render
// bit-identical images with identical ray counts, with the cache off and on
// (--cache-eval center: a stored value depends on its key alone; the batch
// also decides which lanes run a cache group's misses together). The default
// itself follows the materials' stack depth. With many lights (a light tree
// several levels deep, beside a sky and a sun), batches of 16 and 64 pick
// lights eight lanes at a time (pmc_light_pick_lanes) and batches of 1 one
// by one: the picks, their probabilities and so the images are identical.
// So are the diffuse directions, which batches of 16 and 64 draw eight lanes
// at a time (pmc_sample_cosine8): a twin that drifted fails both tests. A
// uniform material (constants only: PMC_MAT_UNIFORM) runs once per batch and
// shares its BSDF, while each hit keeps its own normal: the MTL stand-ins'
// glossy sphere and cylinder render alike in every batch size.
#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>
#include <optional>
#include <sstream>
#include <string>

#include "core/image_io.h"
#include "gpu/render_session.h"
#include "gpu/wave_kernels.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

// Kernels built with `options` appended (PMC_CL_BUILD_OPTIONS, which the
// build appends to its own: a later -D wins) while it lives; the variable's
// earlier value comes back after.
class ExtraBuildOptions {
 public:
  explicit ExtraBuildOptions(const char* options) {
    const char* before = std::getenv("PMC_CL_BUILD_OPTIONS");
    had_ = before != nullptr;
    if (had_) saved_ = before;
    setenv("PMC_CL_BUILD_OPTIONS", options, 1);
  }
  ~ExtraBuildOptions() {
    if (had_)
      setenv("PMC_CL_BUILD_OPTIONS", saved_.c_str(), 1);
    else
      unsetenv("PMC_CL_BUILD_OPTIONS");
  }
  ExtraBuildOptions(const ExtraBuildOptions&) = delete;
  ExtraBuildOptions& operator=(const ExtraBuildOptions&) = delete;

 private:
  bool had_ = false;
  std::string saved_;
};

RenderOutput render_default_scene(bool cache, int lanes, uint32_t min_stack = 0,
                                  const std::string& lights = "") {
  RenderConfig c = test::default_scene_config(48, 27, 2);
  if (!lights.empty()) c.lights = test::source_path(lights);
  c.cache = cache;
  c.cache_cells = 4096;
  c.shade_lanes = lanes;
  c.min_kernel_stack = min_stack;
  RenderSession session(c, test::cl());
  return session.render(session.settings());
}

TEST(ShadeLanes, BatchSizesRenderIdenticalImages) {
  for (bool cache : {false, true}) {
    SCOPED_TRACE(cache ? "cache on" : "cache off");
    const RenderOutput by_default = render_default_scene(cache, 0);
    EXPECT_EQ(by_default.stats.shade_lanes, test::cl().info().is_gpu ? 1 : 64);
    EXPECT_GT(test::image_mean(by_default.image), 0.0);
    for (int lanes : {1, 16}) {
      SCOPED_TRACE("lanes " + std::to_string(lanes));
      const RenderOutput other = render_default_scene(cache, lanes);
      EXPECT_EQ(other.stats.shade_lanes, lanes);
      ASSERT_EQ(other.image.pixels.size(), by_default.image.pixels.size());
      EXPECT_EQ(test::differing_values(other.image, by_default.image), 0u)
          << "of " << other.image.pixels.size() << " values";
      EXPECT_EQ(other.stats.rays, by_default.stats.rays);
      EXPECT_EQ(other.stats.shadow_rays, by_default.stats.shadow_rays);
    }
  }
}

TEST(ShadeLanes, UniformMaterialsRenderAlikeInEveryBatchSize) {
  auto render = [](int lanes) {
    RenderConfig c = test::default_scene_config(48, 27, 2);
    c.mtlx.clear();  // room.mtl: constant walls, sphere and cylinder; textured floor and box
    c.shade_lanes = lanes;
    RenderSession session(c, test::cl());
    return session.render(session.settings());
  };
  const RenderOutput by_default = render(0);
  EXPECT_GT(test::image_mean(by_default.image), 0.0);
  for (int lanes : {1, 16}) {
    SCOPED_TRACE("lanes " + std::to_string(lanes));
    const RenderOutput other = render(lanes);
    ASSERT_EQ(other.image.pixels.size(), by_default.image.pixels.size());
    EXPECT_EQ(test::differing_values(other.image, by_default.image), 0u)
        << "of " << other.image.pixels.size() << " values";
    EXPECT_EQ(other.stats.rays, by_default.stats.rays);
  }
}

// The light picks of batches of 1 and 16 against the default batch's:
// render(lanes) renders a scene with that many lanes (0: the default); the
// images match bit for bit, and so do the shadow rays traced.
void expect_picks_alike_in_every_batch_size(const std::function<RenderOutput(int)>& render) {
  const RenderOutput by_default = render(0);
  EXPECT_GT(test::image_mean(by_default.image), 0.0);
  for (int lanes : {1, 16}) {
    SCOPED_TRACE("lanes " + std::to_string(lanes));
    const RenderOutput other = render(lanes);
    ASSERT_EQ(other.image.pixels.size(), by_default.image.pixels.size());
    EXPECT_EQ(test::differing_values(other.image, by_default.image), 0u)
        << "of " << other.image.pixels.size() << " values";
    EXPECT_EQ(other.stats.shadow_rays, by_default.stats.shadow_rays);
  }
}

TEST(ShadeLanes, ManyLightsArePickedAlikeInEveryBatchSize) {
  expect_picks_alike_in_every_batch_size(
      [](int lanes) { return render_default_scene(false, lanes, 0, "data/default/many.lights.json"); });
}

// Hundreds of small emissive triangles of many sizes and facings above a
// floor: a light tree about ten levels deep, in which a batch's lanes sit at
// different nodes (each level's two children gathered per lane and weighed in
// one loop, pmc_tree_importance2_lanes) and reach their leaves at different
// levels (the walk closes up its packed lanes). Batches of 1 walk the tree
// one hit at a time with the scalar pmc_light_pick; every batch size renders
// the same image.
TEST(ShadeLanes, DeepLightTreesArePickedAlikeInEveryBatchSize) {
  const std::string dir = test::temp_dir();
  std::ostringstream obj;
  obj << "mtllib scene.mtl\nusemtl floor\n"
      << "v -4 0 -4\nv 4 0 -4\nv 4 0 4\nv -4 0 4\nf 1 3 2\nf 1 4 3\nusemtl lamp\n";
  int v = 4;
  for (int i = 0; i < 24; ++i)
    for (int j = 0; j < 24; ++j) {
      // a lamp over cell (i, j), its size and tilt varying with the cell
      const double x = -3.6 + 0.3 * i, z = -3.6 + 0.3 * j, y = 0.6 + 0.1 * ((i * 7 + j * 3) % 13);
      const double r = 0.02 + 0.01 * ((i + 2 * j) % 5), tilt = 0.5 * (((i * 5 + j) % 7) - 3) * r;
      obj << "v " << x - r << " " << y + tilt << " " << z - r << "\nv " << x + r << " " << y << " " << z - r
          << "\nv " << x << " " << y - tilt << " " << z + r << "\n";
      obj << "f " << v + 1 << " " << v + 2 << " " << v + 3 << "\n";
      v += 3;
    }
  test::write_file(dir + "/scene.mtl",
                   "newmtl floor\nKd 0.5 0.5 0.5\nKs 0 0 0\nnewmtl lamp\nKd 0 0 0\nKs 0 0 0\nKe 4 3 2\n");
  test::write_file(dir + "/scene.obj", obj.str());
  auto render = [&](int lanes) {
    RenderConfig c;
    c.scene = dir + "/scene.obj";
    c.width = 48;
    c.height = 32;
    c.spp = 2;
    c.cache = false;
    c.camera_from = Vec3{0.0f, 3.0f, 5.0f};
    c.camera_at = Vec3{0.0f, 0.3f, 0.0f};
    c.shade_lanes = lanes;
    RenderSession session(c, test::cl());
    return session.render(session.settings());
  };
  expect_picks_alike_in_every_batch_size(render);
}

// A sun and a sky (lights at infinity) beside the emissive ceiling (the light
// tree): in a batch the lanes weigh the lights at infinity together
// (pmc_pick_distant_lanes), where one hit at a time pmc_pick_distant does it,
// and escaped rays find their sky map's texels in one loop over the batch
// (pmc_infinity_seen_lanes). Every batch size renders the same image, with a
// constant sky and with an HDR map.
TEST(ShadeLanes, SunAndSkyArePickedAlikeInEveryBatchSize) {
  for (bool map : {false, true}) {
    SCOPED_TRACE(map ? "sky map" : "constant sky");
    auto render = [map](int lanes) {
      RenderConfig c = test::default_scene_config(48, 27, 2);
      c.lights = test::source_path("data/default/sun.lights.json");
      if (map)
        c.env_map = test::shared_scene("envmaps/table_mountain.hdr");
      else
        c.env = {0.3f, 0.4f, 0.6f};
      c.shade_lanes = lanes;
      RenderSession session(c, test::cl());
      return session.render(session.settings());
    };
    const RenderOutput by_default = render(0);
    EXPECT_GT(test::image_mean(by_default.image), 0.0);
    const RenderOutput one = render(1);
    ASSERT_EQ(one.image.pixels.size(), by_default.image.pixels.size());
    EXPECT_EQ(test::differing_values(one.image, by_default.image), 0u)
        << "of " << one.image.pixels.size() << " values";
    EXPECT_EQ(one.stats.shadow_rays, by_default.stats.shadow_rays);
  }
}

// The largest stack that still gets the full batch (256 floats x 64 lanes:
// 64 KiB of stack per work-item, besides the batch's hit records) runs on
// the device and renders what the default stack does.
TEST(ShadeLanes, DeepestStackAtTheFullBatchRendersTheSameImage) {
  const RenderOutput by_default = render_default_scene(false, 0);
  const RenderOutput deep = render_default_scene(false, 0, 256);
  EXPECT_EQ(deep.stats.shade_lanes, by_default.stats.shade_lanes);
  ASSERT_EQ(deep.image.pixels.size(), by_default.image.pixels.size());
  EXPECT_EQ(test::differing_values(deep.image, by_default.image), 0u);
  EXPECT_EQ(deep.stats.rays, by_default.stats.rays);
}

MaterialSet with_peak_stack(uint32_t floats) {
  MaterialSet set;
  set.program.materials.resize(2);
  set.program.materials[0].peak_stack = 3;
  set.program.materials[1].peak_stack = floats;
  return set;
}

TEST(ShadeLanes, CpuDefaultShrinksForDeepStacks) {
  const ClContext& cl = test::cl();
  if (cl.info().is_gpu) {
    EXPECT_EQ(default_shade_lanes(cl, with_peak_stack(34)), 1);
    return;
  }
  // Stacks round up to powers of two; 64 lanes while 4 bytes x stack x lanes <= 64 KiB.
  EXPECT_EQ(default_shade_lanes(cl, MaterialSet{}), 64);
  EXPECT_EQ(default_shade_lanes(cl, with_peak_stack(34)), 64);
  EXPECT_EQ(default_shade_lanes(cl, with_peak_stack(256)), 64);
  EXPECT_EQ(default_shade_lanes(cl, with_peak_stack(257)), 32);
  EXPECT_EQ(default_shade_lanes(cl, with_peak_stack(1024)), 16);
  EXPECT_EQ(default_shade_lanes(cl, with_peak_stack(100000)), 16);
  EXPECT_NE(wave_program_options(with_peak_stack(257), 32, false).find("-DPMC_STACK_SIZE=512 -DPMC_LANES=32"),
            std::string::npos);
}

// On CPU devices the shade kernel starts each batch's memory loads with
// prefetch instructions (PMC_CPU_PREFETCH); elsewhere with volatile loads.
// Either way only the timing may change: the same options without the
// prefetch (PMC_CPU_PREFETCH=0 through PMC_CL_BUILD_OPTIONS, which the
// build appends) render the identical image.
TEST(ShadeLanes, PrefetchOrVolatileTouchRendersTheSameImage) {
  const bool gpu = test::cl().info().is_gpu;
  EXPECT_EQ(wave_program_options(MaterialSet{}, 64, false).find("-DPMC_CPU_PREFETCH=1") != std::string::npos,
            true);
  EXPECT_EQ(wave_program_options(MaterialSet{}, 1, true).find("PMC_CPU_PREFETCH"), std::string::npos);
  if (gpu) return;  // the GPU build has no prefetch to turn off
  for (bool cache : {false, true}) {
    SCOPED_TRACE(cache ? "cache on" : "cache off");
    const RenderOutput prefetching = render_default_scene(cache, 0);
    const RenderOutput touching = [&] {
      const ExtraBuildOptions no_prefetch("-DPMC_CPU_PREFETCH=0");
      return render_default_scene(cache, 0);
    }();
    ASSERT_EQ(touching.image.pixels.size(), prefetching.image.pixels.size());
    EXPECT_GT(test::image_mean(prefetching.image), 0.0);
    EXPECT_EQ(test::differing_values(touching.image, prefetching.image), 0u);
    EXPECT_EQ(touching.stats.rays, prefetching.stats.rays);
  }
}

// On CPU devices a lookup compares its cell's 8 entries in one vector
// operation (PMC_CELL_VECTOR); the word-by-word scan it replaced must find
// the same entries: the same image and lookups, and as many hits give or
// take the races between work-items that insert and look up one key at once
// (which a loaded machine makes more frequent: 5%).
TEST(ShadeLanes, VectorCellCompareFindsWhatTheScanFinds) {
  if (test::cl().info().is_gpu) return;  // GPUs read 8 words at a time, lane by lane
  const RenderOutput vector = render_default_scene(true, 0);
  const RenderOutput scan = [] {
    const ExtraBuildOptions no_vector("-DPMC_CELL_VECTOR=0");
    return render_default_scene(true, 0);
  }();
  ASSERT_EQ(scan.image.pixels.size(), vector.image.pixels.size());
  EXPECT_EQ(test::differing_values(scan.image, vector.image), 0u);
  EXPECT_GT(scan.stats.cache.hits, scan.stats.cache.lookups / 4);
  EXPECT_NEAR(double(vector.stats.cache.hits), double(scan.stats.cache.hits),
              0.05 * double(scan.stats.cache.hits));
  EXPECT_EQ(vector.stats.cache.lookups, scan.stats.cache.lookups);
}

// An environment map of PMC_ENV_PREFETCH_MIN_TEXELS texels or more (here
// 1024 x 512, a bright spot in a varied sky) has its light samples' CDF
// reads and its escaped rays' texels started for a batch's lanes at once
// (pmc_env_sample_prefetch_lanes, pmc_infinity_seen_lanes): only the timing
// may change, so the build without prefetches, and batches of one lane
// (which take neither path), render the same image.
TEST(ShadeLanes, LargeSkyMapsRenderTheSameImageWithTheirReadsStartedAhead) {
  if (test::cl().info().is_gpu) return;  // the GPU build has no prefetch to turn off
  Image sky;
  sky.width = 1024;
  sky.height = 512;
  sky.pixels.resize(size_t(sky.width) * sky.height * 3);
  for (int y = 0; y < sky.height; ++y)
    for (int x = 0; x < sky.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const bool spot = (x - 300) * (x - 300) + (y - 120) * (y - 120) < 25;
        sky.pixels[(size_t(y) * sky.width + x) * 3 + c] =
            spot ? 400.0f : 0.2f + 0.1f * float(c) + 0.5f * float((x * 7 + y * 13) % 17) / 17.0f;
      }
  const std::string map = test::temp_dir() + "/large_sky.exr";
  write_exr(map, sky);
  auto render = [&](int lanes, bool prefetch) {
    RenderConfig c = test::default_scene_config(48, 27, 4);
    c.env_map = map;
    c.shade_lanes = lanes;
    std::optional<ExtraBuildOptions> no_prefetch;
    if (!prefetch) no_prefetch.emplace("-DPMC_CPU_PREFETCH=0");
    RenderSession session(c, test::cl());
    return session.render(session.settings());
  };
  const RenderOutput ahead = render(0, true);
  EXPECT_EQ(ahead.stats.shade_lanes, 64);
  EXPECT_GT(test::image_mean(ahead.image), 0.0);
  for (const RenderOutput& other : {render(0, false), render(1, true)}) {
    ASSERT_EQ(other.image.pixels.size(), ahead.image.pixels.size());
    EXPECT_EQ(test::differing_values(other.image, ahead.image), 0u) << "of " << other.image.pixels.size();
    EXPECT_EQ(other.stats.shadow_rays, ahead.stats.shadow_rays);
  }
}

}  // namespace
}  // namespace pmc
