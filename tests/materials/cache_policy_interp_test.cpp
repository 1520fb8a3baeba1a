// cache_policy_interp_test.cpp — the replacement policy through the CPU
// interpreter (core/device/pmc_interp.h compiled for the host): the depth
// of the hit travels from the cache context to the insert and to the
// camera counters.
//
// A material with one uv-only cache point (texcoord -> multiply -> noise2d
// -> mix, a colour) evaluated in --cache-eval hit mode at distinct texels
// against a table of one cell of two entries. With --cache-policy priority:
// texels A (depth 2) and B (depth 1) fill the cell; C at depth 1 is dropped;
// C at depth 0 replaces A (the deeper of the two) and B stays; A is then a
// miss, C and B hits; D at depth 0 replaces B; E at depth 0 is dropped (only
// camera entries left). Counters: inserts, replaced, dropped, lookups, hits,
// camera lookups and camera hits exactly as the sequence implies. Every hit
// returns the value the plain program computes at that texel's inserting
// uv (within RGB9E5's error): a replaced entry holds its new key's value.
// With keep-first the same sequence replaces nothing.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/device/pmc_interp.h"
#include "core/texture.h"
#include "materials/compiler.h"
#include "materials/node_graph.h"
#include "tests/support/graph_builder.h"

namespace pmc {
namespace {

using VT = ValueType;
using test::add;
using test::add_surface;
using test::link;
using test::value;

Graph noise_material(const std::string& name) {
  Graph g = test::new_graph(name, "cache_policy_interp_test.mtlx");
  int tc = add(g, "uv", "texcoord", VT::Vector2);
  int mul = add(g, "mul", "multiply", VT::Vector2, {{"in1", link(tc)}, {"in2", value(VT::Vector2, 5, 5)}});
  int noise = add(g, "noise", "noise2d", VT::Color3,
                  {{"texcoord", link(mul)},
                   {"amplitude", value(VT::Color3, 0.5f, 0.5f, 0.5f)},
                   {"pivot", value(VT::Float, 0.5f)}});
  int mix = add(g, "mix", "mix", VT::Color3,
                {{"fg", link(noise)},
                 {"bg", value(VT::Color3, 0.2f, 0.3f, 0.4f)},
                 {"mix", value(VT::Color3, 0.7f, 0.7f, 0.7f)}});
  add_surface(g, {{"base_color", link(mix)}});
  return g;
}

void run_host(const MaterialProgram& p, const CompiledMaterial& m, float2 uv, float params[PMC_P_COUNT],
              PmcCacheContext* cache) {
  PmcShadingInputs in{};
  in.uv = uv;
  in.position = make_float3(0, 0, 0);
  in.normal = make_float3(0, 0, 1);
  in.tangent = make_float3(1, 0, 0);
  in.bitangent = make_float3(0, 1, 0);
  in.footprint = 0.01f;
  PmcTextureSet ts{};
  float stack[PMC_STACK_SIZE] = {0};
  pmc_surface_defaults(params, in.normal);
  pmc_interp_run(p.code.data(), m.entry, &in, &ts, stack, params, cache);
}

struct Step {
  char texel;      // A..E
  uint32_t depth;  // surface hits before this one
  bool hit;        // expected
};

TEST(CachePolicy, InterpreterPassesTheHitDepthToTheTable) {
  Graph off_graph = noise_material("M_off"), on_graph = noise_material("M_on");
  TexturePool tex;
  MaterialProgram prog;
  CompileOptions on_opts;
  on_opts.cache = true;
  on_opts.cache_min_nodes = 4;
  compile_material(off_graph, tex, prog);
  compile_material(on_graph, tex, prog, on_opts);
  const CompiledMaterial& off = prog.materials[0];
  const CompiledMaterial& on = prog.materials[1];
  ASSERT_EQ(on.cache_plan.points.size(), 1u);
  auto uv_of = [](char t) {
    return make_float2(0.1f + 0.13f * float(t - 'A'), 0.7f - 0.11f * float(t - 'A'));
  };

  for (uint32_t policy : {PMC_CACHE_PRIORITY, PMC_CACHE_KEEP_FIRST}) {
    const bool priority = policy == PMC_CACHE_PRIORITY;
    SCOPED_TRACE(priority ? "priority" : "keep-first");
    std::vector<uint64_t> words(2, 0);  // one cell of two entries
    PmcCacheContext cache{};
    cache.table.entries = words.data();
    cache.table.cells = 1;
    cache.table.ways = 2;
    cache.table.policy = policy;
    cache.g1 = make_float2(1e-4f, 0.0f);  // level 13: the texels are far apart
    cache.g2 = make_float2(0.0f, 1e-4f);
    cache.material = 1;
    cache.center = 0;
    // keep-first: C at depth 0 is dropped, so A stays and C, D, E miss.
    const std::vector<Step> steps =
        priority ? std::vector<Step>{{'A', 2, false}, {'B', 1, false}, {'C', 1, false}, {'C', 0, false},
                                     {'A', 1, false}, {'C', 3, true},  {'B', 0, true},  {'D', 0, false},
                                     {'B', 2, false}, {'E', 0, false}, {'C', 0, true},  {'D', 1, true}}
                 : std::vector<Step>{{'A', 2, false}, {'B', 1, false}, {'C', 1, false}, {'C', 0, false},
                                     {'A', 1, true},  {'C', 3, false}, {'B', 0, true},  {'D', 0, false},
                                     {'B', 2, true},  {'E', 0, false}, {'C', 0, false}, {'D', 1, false}};
    uint32_t camera_lookups = 0, camera_hits = 0, hits = 0;
    for (size_t i = 0; i < steps.size(); ++i) {
      const Step& s = steps[i];
      SCOPED_TRACE("step " + std::to_string(i) + ": texel " + s.texel + " at depth " +
                   std::to_string(s.depth));
      cache.depth = s.depth;
      cache.hits = 0;
      float ref[PMC_P_COUNT], got[PMC_P_COUNT];
      run_host(prog, off, uv_of(s.texel), ref, nullptr);
      run_host(prog, on, uv_of(s.texel), got, &cache);
      EXPECT_EQ(cache.hits, s.hit ? 1u : 0u);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[PMC_P_BASE_COLOR + c], ref[PMC_P_BASE_COLOR + c], 1.0 / 511.5) << "channel " << c;
      hits += s.hit;
      camera_lookups += s.depth == 0;
      camera_hits += s.depth == 0 && s.hit;
    }
    const uint32_t* n = cache.counts;
    EXPECT_EQ(n[PMC_CSTAT_LOOKUPS], steps.size());
    EXPECT_EQ(n[PMC_CSTAT_HITS], hits);
    EXPECT_EQ(n[PMC_CSTAT_MISSES], steps.size() - hits);
    EXPECT_EQ(n[PMC_CSTAT_CAMERA_LOOKUPS], camera_lookups);
    EXPECT_EQ(n[PMC_CSTAT_CAMERA_HITS], camera_hits);
    EXPECT_EQ(n[PMC_CSTAT_INSERTS], 2u) << "two empty entries";
    EXPECT_EQ(n[PMC_CSTAT_REPLACED], priority ? 2u : 0u) << "C replaced A, D replaced B";
    EXPECT_EQ(n[PMC_CSTAT_INSERTS] + n[PMC_CSTAT_REPLACED] + n[PMC_CSTAT_ALREADY_PRESENT] +
                  n[PMC_CSTAT_DROPPED_FULL] + n[PMC_CSTAT_NOT_ENCODABLE],
              n[PMC_CSTAT_MISSES])
        << "every miss ends in exactly one outcome";
    if (priority) {  // the cell ends with C and D, both camera entries (tag 0)
      EXPECT_EQ(words[0] >> 32 & 3u, 0u);
      EXPECT_EQ(words[1] >> 32 & 3u, 0u);
    }
  }
}

}  // namespace
}  // namespace pmc
