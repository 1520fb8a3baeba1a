// cache_floor_interp_test.cpp — level floors from the key functions to the
// host interpreter (core/device/pmc_cache.h, core/device/pmc_interp.h).
//
// A grid (uvtiling 8, thickness 0.1: lines 1/80 uv wide) is the material's
// one cache point; two texels across a line need level 8 (texels of 1/256).
// The footprint is level 6 (texels of 1/64):
//  - with the floor, two points in one level-6 texel but different level-8
//    texels miss apart, and points in one level-8 texel share a value;
//  - without it (floors off), the level-6 texel is shared;
//  - with a refinement limit of 1 (< 8 - 6), the point is evaluated without
//    the cache: counted as bypassed, never looked up or inserted, the table
//    stays empty, and the value is the cacheless program's, bit for bit.
#include <gtest/gtest.h>

#include <vector>

#include "core/device/pmc_interp.h"
#include "core/texture.h"
#include "materials/cache_plan.h"
#include "materials/compiler.h"
#include "tests/support/graph_builder.h"

namespace pmc {
namespace {

using VT = ValueType;
using test::add;
using test::add_surface;
using test::link;
using test::new_graph;
using test::value;

Graph grid_material(const std::string& name) {
  Graph g = new_graph(name);
  int uv = add(g, "uv", "texcoord", VT::Vector2);
  int grid = add(g, "grid", "grid", VT::Color3,
                 {{"texcoord", link(uv)},
                  {"uvtiling", value(VT::Vector2, 8, 8)},
                  {"thickness", value(VT::Float, 0.1f)}});
  add_surface(g, {{"base_color", link(grid)}});
  return g;
}

TEST(CacheFloor, FlooredLevelRefinesOrBypasses) {
  pmc_u32 bypass = 7u;
  EXPECT_EQ(pmc_cache_floored_level(9, 8, 2, &bypass), 9);
  EXPECT_EQ(bypass, 0u) << "footprint finer than the floor";
  EXPECT_EQ(pmc_cache_floored_level(6, 8, 2, &bypass), 8);
  EXPECT_EQ(bypass, 0u);
  EXPECT_EQ(pmc_cache_floored_level(6, 8, 1, &bypass), 8);
  EXPECT_EQ(bypass, 1u) << "two levels of refinement, limit 1";
  EXPECT_EQ(pmc_cache_floored_level(6, PMC_LEVEL_NO_FLOOR, 0, &bypass), 6);
  EXPECT_EQ(bypass, 0u);
  EXPECT_EQ(pmc_cache_floored_level(PMC_LAMBDA_MIN, PMC_LAMBDA_MAX + 5, 100, &bypass), PMC_LAMBDA_MAX)
      << "clamped to the cache's levels";

  // A floored texel is the plain texel at the floor's level, and remembers the footprint's.
  const float2 g1 = make_float2(1.0f / 64, 0), g2 = make_float2(0, 1.0f / 64);
  const float2 uv = make_float2(0.3712f, 0.8121f), jitter = make_float2(0.25f, -0.3f);
  PmcCacheTexel f = pmc_cache_texel_floored(uv, g1, g2, 0.0f, jitter, 3u, 8, 2);
  PmcCacheTexel plain = pmc_cache_texel_of(uv, g1, g2, 2.0f, jitter, 3u);  // bias 2: level 8
  EXPECT_EQ(f.lambda, 8);
  EXPECT_EQ(f.footprint_lambda, 6);
  EXPECT_EQ(plain.lambda, 8);
  EXPECT_EQ(f.tx, plain.tx);
  EXPECT_EQ(f.ty, plain.ty);
  EXPECT_EQ(f.hash, plain.hash);
  PmcCacheTexel c =
      pmc_cache_cell_floored(make_float3(1, 2, 3), 1.0f / 64, 0.0f, make_float4(0, 0, 0, 0), 3u, 9, 3);
  EXPECT_EQ(c.lambda, 9);
  EXPECT_EQ(c.footprint_lambda, 6);
  EXPECT_EQ(c.bypass, 0u);
}

struct Fixture {
  TexturePool tex;
  MaterialProgram prog;
  std::vector<uint64_t> words = std::vector<uint64_t>(size_t(1) << 14, 0);
  PmcCacheContext cx{};
  int floor_uv = PMC_LEVEL_NO_FLOOR;
  Fixture() {
    CompileOptions on;
    on.cache = true;
    on.cache_min_nodes = 1;
    on.cache_feature_texels = 2.0;
    Graph off_g = grid_material("M_off"), on_g = grid_material("M_on");
    compile_material(off_g, tex, prog);
    const CompiledMaterial& cm = compile_material(on_g, tex, prog, on);
    floor_uv = material_level_floor(cm.cache_plan, CacheKey::Uv);
    cx.table.entries = words.data();
    cx.table.cells = words.size() / 8;
    cx.table.ways = 8;
    cx.g1 = make_float2(1.0f / 64, 0.0f);  // footprint level 6
    cx.g2 = make_float2(0.0f, 1.0f / 64);
    cx.material = 1;
    cx.center = 0;
  }
  void eval(int material, float2 uv, float out[PMC_P_COUNT], bool cached) {
    PmcShadingInputs in{};
    in.uv = uv;
    in.normal = make_float3(0, 0, 1);
    in.tangent = make_float3(1, 0, 0);
    in.bitangent = make_float3(0, 1, 0);
    in.footprint = 1.0f / 32;
    PmcTextureSet ts{};
    float stack[PMC_STACK_SIZE] = {0};
    pmc_surface_defaults(out, in.normal);
    cx.hits = 0;
    cx.texel.ready = 0u;
    cx.cell.ready = 0u;
    pmc_interp_run(prog.code.data(), prog.materials[size_t(material)].entry, &in, &ts, stack, out,
                   cached ? &cx : nullptr);
  }
  size_t occupied() const {
    size_t n = 0;
    for (uint64_t w : words) n += w != 0;
    return n;
  }
};

TEST(CacheFloor, TheFloorSplitsAFootprintTexel) {
  Fixture f;
  ASSERT_EQ(f.floor_uv, 8);
  f.cx.floors = 1u;
  f.cx.level_floor_uv = f.floor_uv;
  f.cx.max_refine = 2;
  float a[PMC_P_COUNT], b[PMC_P_COUNT];
  // One level-6 texel [0.25, 0.265625); level-8 texels of 1/256.
  f.eval(1, make_float2(0.2502f, 0.2502f), a, true);
  EXPECT_EQ(f.cx.hits, 0u);
  f.eval(1, make_float2(0.2600f, 0.2600f), b, true);  // another level-8 texel
  EXPECT_EQ(f.cx.hits, 0u) << "the floor keeps it apart";
  f.eval(1, make_float2(0.2510f, 0.2510f), b, true);  // a's level-8 texel
  EXPECT_EQ(f.cx.hits, 1u);
  EXPECT_EQ(f.cx.counts[PMC_CSTAT_BYPASSED], 0u);

  Fixture off;
  off.cx.floors = 0u;  // the paper's texel: the footprint's
  off.eval(1, make_float2(0.2502f, 0.2502f), a, true);
  off.eval(1, make_float2(0.2600f, 0.2600f), b, true);
  EXPECT_EQ(off.cx.hits, 1u) << "without the floor the level-6 texel is shared";
}

TEST(CacheFloor, BeyondTheRefinementLimitThePointIsEvaluatedUncached) {
  Fixture f;
  f.cx.floors = 1u;
  f.cx.level_floor_uv = f.floor_uv;
  f.cx.max_refine = 1;
  for (int i = 0; i < 50; ++i) {
    const float2 uv = make_float2(0.013f * float(i), 0.71f - 0.007f * float(i));
    float plain[PMC_P_COUNT], cached[PMC_P_COUNT];
    f.eval(0, uv, plain, false);
    f.eval(1, uv, cached, true);
    for (int k = 0; k < 3; ++k) ASSERT_EQ(cached[PMC_P_BASE_COLOR + k], plain[PMC_P_BASE_COLOR + k]) << i;
    ASSERT_EQ(f.cx.hits, 0u);
  }
  EXPECT_EQ(f.cx.counts[PMC_CSTAT_BYPASSED], 50u);
  EXPECT_EQ(f.cx.counts[PMC_CSTAT_LOOKUPS], 0u);
  EXPECT_EQ(f.cx.counts[PMC_CSTAT_INSERTS], 0u);
  EXPECT_EQ(f.occupied(), 0u) << "nothing was inserted";
}

}  // namespace
}  // namespace pmc
