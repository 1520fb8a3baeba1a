// cache_plan_test.cpp — which nodes the progressive cache stores
// (materials/cache_plan.h) and how the compiler wraps them (compiler.h).
//
// On graphs built in code:
//  (a) a uv-only chain texcoord -> multiply -> noise2d -> mix -> base_color
//      has exactly one cache point, at its top (the mix feeding the surface);
//  (b) a position input mixed with uv anywhere below makes every node above
//      it uncacheable (each listed with a reason naming position); the
//      position-only part below is a position-keyed point when big enough,
//      and nothing with position keys off;
//  (c) two uv-only branches under a position-dependent mix give two cache
//      points, the two branch tops;
//  (d) a sub-graph smaller than min_nodes is not cached, with its reason;
//  (e) a color4 top (no 32-bit encoding) falls back to its uv-only inputs.
// Compiling with CompileOptions{cache=true} vs {cache=false}: the cache-off
// program has no CACHE_* opcode, the cache-on one one LOOKUP/STORE pair per
// point, and the host interpreter gives identical surface parameters for
// both at random uvs with a null cache (every lookup misses). With a host
// cache table the second evaluation hits every point, jumps over the blocks
// and returns the stored values (within the encodings' error).
#include "materials/cache_plan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/device/pmc_interp.h"
#include "core/texture.h"
#include "materials/compiler.h"
#include "materials/node_graph.h"
#include "materials/node_table.h"
#include "materials/passes.h"
#include "tests/support/graph_builder.h"
#include "tests/support/material_eval.h"

namespace pmc {
namespace {

using VT = ValueType;

using test::add;
using test::add_surface;
using test::link;
using test::text;
using test::value;

Graph new_graph(const std::string& material) { return test::new_graph(material, "cache_plan_test.mtlx"); }

// texcoord -> multiply(scale) -> noise2d (color3) -> mix with a constant colour.
// Returns the mix (4 nodes, all uv-only).
int uv_branch(Graph& g, const std::string& p, float scale, int* texcoord = nullptr) {
  int tc = texcoord && *texcoord >= 0 ? *texcoord : add(g, p + "uv", "texcoord", VT::Vector2);
  if (texcoord) *texcoord = tc;
  int mul = add(g, p + "mul", "multiply", VT::Vector2,
                {{"in1", link(tc)}, {"in2", value(VT::Vector2, scale, scale)}});
  int noise = add(g, p + "noise", "noise2d", VT::Color3,
                  {{"texcoord", link(mul)},
                   {"amplitude", value(VT::Color3, 0.5f, 0.5f, 0.5f)},
                   {"pivot", value(VT::Float, 0.5f)}});
  return add(g, p + "mix", "mix", VT::Color3,
             {{"fg", link(noise)},
              {"bg", value(VT::Color3, 0.2f, 0.3f, 0.4f)},
              {"mix", value(VT::Color3, 0.7f, 0.7f, 0.7f)}});
}

std::string reason_for(const CachePlan& plan, int node) {
  for (const auto& [n, why] : plan.not_cached)
    if (n == node) return why;
  return "";
}

bool is_point(const CachePlan& plan, int node) {
  for (const CachePoint& p : plan.points)
    if (p.node == node) return true;
  return false;
}

TEST(CachePlan, UvOnlyChainHasOneCachePointAtTheTop) {
  Graph g = new_graph("M_uv");
  int top = uv_branch(g, "", 4.0f);
  add_surface(g, {{"base_color", link(top)}});
  CachePlan plan = plan_cache(g, 4);
  ASSERT_EQ(plan.points.size(), 1u);
  EXPECT_EQ(plan.points[0].node, top) << "the highest uv-only node, the one feeding the surface";
  EXPECT_EQ(plan.points[0].subgraph_nodes, 4);
  EXPECT_EQ(plan.points[0].encoding, uint32_t(PMC_ENC_RGB9E5)) << "a colour3 is stored as RGB9E5";
  for (const auto& [n, why] : plan.not_cached) EXPECT_NE(n, top) << why;
}

// The layered BSDF's inputs (transmission colour, sheen, anisotropy) are
// planned like any other: a uv-only sub-graph feeding each is a cache point.
TEST(CachePlan, UvOnlyInputsOfTheNewLobesAreCached) {
  for (const char* input : {"transmission_color", "sheen_color", "coat_color"}) {
    Graph g = new_graph("M_lobes");
    int top = uv_branch(g, "", 4.0f);
    add_surface(g, {{input, link(top)}, {"transmission", value(VT::Float, 0.5f)}});
    CachePlan plan = plan_cache(g, 4);
    ASSERT_EQ(plan.points.size(), 1u) << input;
    EXPECT_EQ(plan.points[0].node, top) << input;
  }
  Graph g = new_graph("M_aniso");
  int top = uv_branch(g, "", 4.0f);
  int lum = add(g, "lum", "extract", VT::Float, {{"in", link(top)}, {"index", value(VT::Integer, 0.0f)}});
  add_surface(g, {{"specular_anisotropy", link(lum)}, {"sheen", link(lum)}});
  CachePlan plan = plan_cache(g, 4);
  ASSERT_EQ(plan.points.size(), 1u);
  EXPECT_EQ(plan.points[0].node, lum) << "the float feeding anisotropy and sheen";
}

TEST(CachePlan, PositionBelowMakesEverythingAboveUncacheable) {
  // texcoord -> multiply -> add(position.xy) -> noise2d -> mix -> base_color
  Graph g = new_graph("M_pos");
  int tc = add(g, "uv", "texcoord", VT::Vector2);
  int mul = add(g, "mul", "multiply", VT::Vector2, {{"in1", link(tc)}, {"in2", value(VT::Vector2, 4, 4)}});
  int pos = add(g, "pos", "position", VT::Vector3);
  int pxy = add(g, "pxy", "convert", VT::Vector2, {{"in", link(pos, VT::Vector3)}});
  int sum = add(g, "sum", "add", VT::Vector2, {{"in1", link(mul)}, {"in2", link(pxy)}});
  int noise = add(g, "noise", "noise2d", VT::Color3, {{"texcoord", link(sum)}});
  int mix = add(g, "mix", "mix", VT::Color3,
                {{"fg", link(noise)},
                 {"bg", value(VT::Color3, 0.2f, 0.3f, 0.4f)},
                 {"mix", value(VT::Color3, 0.7f, 0.7f, 0.7f)}});
  add_surface(g, {{"base_color", link(mix)}});
  CachePlan plan = plan_cache(g, 4);
  for (const CachePoint& p : plan.points)
    ADD_FAILURE() << "unexpected cache point " << g.nodes[size_t(p.node)].name;
  for (int n : {sum, noise, mix}) {
    std::string why = reason_for(plan, n);
    EXPECT_NE(why.find("position"), std::string::npos) << g.nodes[size_t(n)].name << ": '" << why << "'";
  }
  // The uv part below the add (texcoord, multiply) is two nodes: too small.
  EXPECT_FALSE(is_point(plan, mul));
  EXPECT_NE(reason_for(plan, mul).find("cheaper"), std::string::npos) << reason_for(plan, mul);
  // Even with min_nodes 1 nothing above the position is cached; the
  // position-only convert below is, keyed on position (not the bare position).
  CachePlan all = plan_cache(g, 1);
  for (int n : {sum, noise, mix, pos}) EXPECT_FALSE(is_point(all, n)) << g.nodes[size_t(n)].name;
  EXPECT_TRUE(is_point(all, mul)) << "min_nodes 1: the uv-only top below the position is cached";
  ASSERT_TRUE(is_point(all, pxy)) << "min_nodes 1: the position-only top is cached";
  for (const CachePoint& p : all.points)
    EXPECT_EQ(p.key, p.node == pxy ? CacheKey::Position : CacheKey::Uv) << g.nodes[size_t(p.node)].name;
  CachePlan uv_only = plan_cache(g, 1, false);
  for (int n : {sum, noise, mix, pos, pxy}) EXPECT_FALSE(is_point(uv_only, n)) << g.nodes[size_t(n)].name;
  EXPECT_TRUE(is_point(uv_only, mul));
}

TEST(CachePlan, TwoUvBranchesUnderAPositionDependentMixGiveTwoPoints) {
  Graph g = new_graph("M_two");
  int tc = -1;
  int b1 = uv_branch(g, "a_", 3.0f, &tc);
  int b2 = uv_branch(g, "b_", 7.0f, &tc);  // shares the texcoord node
  int pos = add(g, "pos", "position", VT::Vector3);
  int px =
      add(g, "px", "extract", VT::Float, {{"in", link(pos, VT::Vector3)}, {"index", value(VT::Integer, 0)}});
  int f = add(g, "f", "sin", VT::Float, {{"in", link(px)}});
  int top =
      add(g, "top", "mix", VT::Color3, {{"fg", link(b1)}, {"bg", link(b2)}, {"mix", link(f, VT::Float)}});
  add_surface(g, {{"base_color", link(top)}});
  CachePlan plan = plan_cache(g, 4);
  ASSERT_EQ(plan.points.size(), 2u);
  EXPECT_TRUE(is_point(plan, b1));
  EXPECT_TRUE(is_point(plan, b2));
  EXPECT_FALSE(is_point(plan, top));
  EXPECT_NE(reason_for(plan, top).find("not on uv alone or position alone"), std::string::npos)
      << reason_for(plan, top);
  EXPECT_NE(reason_for(plan, f).find("position"), std::string::npos) << reason_for(plan, f);
}

TEST(CachePlan, SmallSubgraphIsNotCachedAndSaysWhy) {
  // texcoord -> multiply -> noise2d: three nodes.
  Graph g = new_graph("M_small");
  int tc = add(g, "uv", "texcoord", VT::Vector2);
  int mul = add(g, "mul", "multiply", VT::Vector2, {{"in1", link(tc)}, {"in2", value(VT::Vector2, 4, 4)}});
  int noise = add(g, "noise", "noise2d", VT::Color3, {{"texcoord", link(mul)}});
  add_surface(g, {{"base_color", link(noise)}});
  CachePlan plan = plan_cache(g, 4);
  EXPECT_TRUE(plan.points.empty());
  std::string why = reason_for(plan, noise);
  EXPECT_NE(why.find("3 nodes"), std::string::npos) << why;
  EXPECT_NE(why.find("cheaper than a lookup"), std::string::npos) << why;
  EXPECT_NE(why.find("threshold 4"), std::string::npos) << why;
  EXPECT_TRUE(reason_for(plan, mul).empty()) << "inputs of a too-small top are not tried (they are smaller)";
  CachePlan at3 = plan_cache(g, 3);
  ASSERT_EQ(at3.points.size(), 1u);
  EXPECT_EQ(at3.points[0].node, noise);
}

TEST(CachePlan, Color4TopFallsBackToItsInputs) {
  // uv branch (colour3, 4 nodes) -> convert to colour4 (uv-only, no 32-bit
  // encoding) -> multiply by a position-dependent colour4 -> back to colour3.
  Graph g = new_graph("M_c4");
  int branch = uv_branch(g, "", 5.0f);
  int c4 = add(g, "c4", "convert", VT::Color4, {{"in", link(branch, VT::Color3)}});
  int pos = add(g, "pos", "position", VT::Vector3);
  int p4 = add(g, "p4", "convert", VT::Color4, {{"in", link(pos, VT::Vector3)}});
  int m = add(g, "m", "multiply", VT::Color4, {{"in1", link(c4)}, {"in2", link(p4)}});
  int c3 = add(g, "c3", "convert", VT::Color3, {{"in", link(m, VT::Color4)}});
  add_surface(g, {{"base_color", link(c3)}});
  CachePlan plan = plan_cache(g, 4);
  ASSERT_EQ(plan.points.size(), 1u);
  EXPECT_EQ(plan.points[0].node, branch) << "the colour3 input of the colour4 top";
  EXPECT_FALSE(is_point(plan, c4));
  std::string why = reason_for(plan, c4);
  EXPECT_NE(why.find("color4"), std::string::npos) << why;
  EXPECT_NE(why.find("no 32-bit encoding"), std::string::npos) << why;
}

// ---- compiled programs ---------------------------------------------------------

struct OpCounts {
  int lookup = 0, store = 0, other_cache = 0, instructions = 0;
};

// Walks one material's instructions (not its constants) up to END.
OpCounts count_ops(const MaterialProgram& p, const CompiledMaterial& m) {
  OpCounts c;
  uint32_t pc = m.entry;
  while (pc < m.entry + m.code_words) {
    uint32_t h = p.code[pc];
    uint32_t op = pmc_op_code(h);
    if (op == PMC_OP_END) break;
    ++c.instructions;
    if (op == PMC_OP_CACHE_LOOKUP) ++c.lookup;
    if (op == PMC_OP_CACHE_STORE) ++c.store;
    pc += 2u + pmc_op_nargs(h);
  }
  return c;
}

void run_host(const MaterialProgram& p, const CompiledMaterial& m, float u, float v,
              float params[PMC_P_COUNT], float3 pos, PmcCacheContext* cache = nullptr) {
  test::run_program_at(p, m, u, v, params, pos, cache, 0.01f);
}

// The graphs of (a) and (c), plus a float point feeding roughness.
Graph cached_material(const std::string& name) {
  Graph g = new_graph(name);
  int tc = -1;
  int b1 = uv_branch(g, "a_", 3.0f, &tc);
  int b2 = uv_branch(g, "b_", 7.0f, &tc);
  int pos = add(g, "pos", "position", VT::Vector3);
  int px =
      add(g, "px", "extract", VT::Float, {{"in", link(pos, VT::Vector3)}, {"index", value(VT::Integer, 0)}});
  int f = add(g, "f", "sin", VT::Float, {{"in", link(px)}});
  int top =
      add(g, "top", "mix", VT::Color3, {{"fg", link(b1)}, {"bg", link(b2)}, {"mix", link(f, VT::Float)}});
  int mul = add(g, "rmul", "multiply", VT::Vector2, {{"in1", link(tc)}, {"in2", value(VT::Vector2, 2, 9)}});
  int rn = add(g, "rnoise", "noise2d", VT::Float, {{"texcoord", link(mul)}});
  int rs = add(g, "rsin", "sin", VT::Float, {{"in", link(rn)}});
  int rabs = add(g, "rabs", "absval", VT::Float, {{"in", link(rs)}});
  add_surface(g, {{"base_color", link(top)}, {"specular_roughness", link(rabs)}});
  return g;
}

TEST(CachePlan, CacheOnAndOffProgramsComputeTheSameParameters) {
  Graph off_graph = cached_material("M_off"), on_graph = cached_material("M_on");
  TexturePool tex;
  MaterialProgram prog;
  CompileOptions off_opts, on_opts;
  off_opts.cache = false;
  on_opts.cache = true;
  on_opts.cache_min_nodes = 4;  // this graph's points have 4-5 nodes
  compile_material(off_graph, tex, prog, off_opts);
  compile_material(on_graph, tex, prog, on_opts);
  const CompiledMaterial& off = prog.materials[0];
  const CompiledMaterial& on = prog.materials[1];
  OpCounts co = count_ops(prog, off), cn = count_ops(prog, on);
  EXPECT_EQ(co.lookup + co.store, 0) << "cache off: no cache instructions\n" << disassemble(prog, off);
  EXPECT_TRUE(off.cache_plan.points.empty());
  ASSERT_EQ(on.cache_plan.points.size(), 3u) << disassemble(prog, on);
  EXPECT_EQ(cn.lookup, 3) << disassemble(prog, on);
  EXPECT_EQ(cn.store, 3) << disassemble(prog, on);

  std::mt19937 rng(17);
  std::uniform_real_distribution<float> uni(-3.0f, 4.0f);
  for (int i = 0; i < 500; ++i) {
    float u = uni(rng), v = uni(rng);
    float3 pos = make_float3(uni(rng), uni(rng), uni(rng));
    float a[PMC_P_COUNT], b[PMC_P_COUNT];
    run_host(prog, off, u, v, a, pos);
    run_host(prog, on, u, v, b, pos);
    for (int k = 0; k < PMC_P_COUNT; ++k)
      ASSERT_EQ(a[k], b[k]) << "param " << k << " at uv " << u << " " << v << "\n" << disassemble(prog, on);
  }
}

TEST(CachePlan, HostCacheHitsSkipTheBlocksAndReturnTheStoredValues) {
  Graph off_graph = cached_material("M_off"), on_graph = cached_material("M_on");
  TexturePool tex;
  MaterialProgram prog;
  CompileOptions on_opts;
  on_opts.cache = true;
  on_opts.cache_min_nodes = 4;  // this graph's points have 4-5 nodes
  compile_material(off_graph, tex, prog);
  compile_material(on_graph, tex, prog, on_opts);
  const CompiledMaterial& off = prog.materials[0];
  const CompiledMaterial& on = prog.materials[1];
  std::vector<uint64_t> words(size_t(1) << 14, 0);
  PmcCacheContext cache{};
  cache.table.entries = words.data();
  cache.table.cells = words.size() / 8;
  cache.table.ways = 8;
  cache.g1 = make_float2(1e-4f, 0.0f);  // level 13: tiny texels
  cache.g2 = make_float2(0.0f, 1e-4f);
  cache.material = 1;
  cache.center = 0;  // --cache-eval hit: the first evaluation stores its own values
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  for (int i = 0; i < 200; ++i) {
    float u = uni(rng), v = uni(rng);
    float3 pos = make_float3(uni(rng), uni(rng), uni(rng));
    float ref[PMC_P_COUNT], first[PMC_P_COUNT], second[PMC_P_COUNT];
    run_host(prog, off, u, v, ref, pos);
    cache.hits = 0;
    run_host(prog, on, u, v, first, pos, &cache);
    ASSERT_EQ(cache.hits, 0u) << "fresh texels miss";
    cache.hits = 0;
    run_host(prog, on, u, v, second, pos, &cache);
    ASSERT_EQ(cache.hits, 3u) << "the second evaluation finds all three points; inserts "
                              << cache.counts[PMC_CSTAT_INSERTS] << ", not encodable "
                              << cache.counts[PMC_CSTAT_NOT_ENCODABLE] << "\n"
                              << disassemble(prog, on);
    for (int k = 0; k < PMC_P_COUNT; ++k) {
      ASSERT_EQ(first[k], ref[k]) << "a miss computes the plain value, param " << k;
      // RGB9E5 colours: each branch (values <= 1) within 1/511.5; the top
      // mixes them with a factor t = sin(x) in [-1, 1]: |t| e1 + |1 - t| e2
      // <= 3/511.5. The float point is exact.
      ASSERT_NEAR(second[k], ref[k], 4.0 / 511.5) << "param " << k;
    }
    ASSERT_EQ(second[PMC_P_SPECULAR_ROUGHNESS], ref[PMC_P_SPECULAR_ROUGHNESS]) << "floats are stored exactly";
  }
  EXPECT_EQ(cache.counts[PMC_CSTAT_LOOKUPS], 200u * 6u);
  EXPECT_EQ(cache.counts[PMC_CSTAT_HITS], 200u * 3u);
  EXPECT_EQ(cache.counts[PMC_CSTAT_INSERTS], 200u * 3u);
  EXPECT_EQ(cache.counts[PMC_CSTAT_DROPPED_FULL], 0u);
}

// Two float cache points over one shared 9-node uv chain: base colour (via
// a position-driven mix) and roughness.
Graph shared_chain_material(const std::string& name) {
  Graph g = new_graph(name);
  int tc = add(g, "uv", "texcoord", VT::Vector2);
  int mul = add(g, "mul", "multiply", VT::Vector2, {{"in1", link(tc)}, {"in2", value(VT::Vector2, 4, 6)}});
  int chain = add(g, "n", "noise2d", VT::Float, {{"texcoord", link(mul)}});
  for (int k = 0; k < 6; ++k)
    chain = add(g, "c" + std::to_string(k), k % 2 ? "sin" : "absval", VT::Float, {{"in", link(chain)}});
  int a = add(g, "a", "multiply", VT::Float, {{"in1", link(chain)}, {"in2", value(VT::Float, 0.5f)}});
  int b = add(g, "b", "add", VT::Float, {{"in1", link(chain)}, {"in2", value(VT::Float, 0.25f)}});
  int pos = add(g, "pos", "position", VT::Vector3);
  int px =
      add(g, "px", "extract", VT::Float, {{"in", link(pos, VT::Vector3)}, {"index", value(VT::Integer, 0)}});
  int top = add(g, "top", "multiply", VT::Float, {{"in1", link(a)}, {"in2", link(px)}});
  int col = add(g, "col", "convert", VT::Color3, {{"in", link(top, VT::Float)}});
  add_surface(g, {{"base_color", link(col)}, {"specular_roughness", link(b)}});
  return g;
}

TEST(CachePlan, OverlappingCachePointsEvaluateTheirSharedNodesOnce) {
  Graph off_graph = shared_chain_material("M_off"), on_graph = shared_chain_material("M_on");
  TexturePool tex;
  MaterialProgram prog;
  CompileOptions on_opts;
  on_opts.cache = true;
  on_opts.cache_min_nodes = 4;
  compile_material(off_graph, tex, prog);
  compile_material(on_graph, tex, prog, on_opts);
  const CompiledMaterial& off = prog.materials[0];
  const CompiledMaterial& on = prog.materials[1];
  ASSERT_EQ(on.cache_plan.points.size(), 2u) << disassemble(prog, on);
  for (const CachePoint& p : on.cache_plan.points) EXPECT_EQ(p.subgraph_nodes, 10) << "chain + its own node";
  OpCounts c_off = count_ops(prog, off), c_on = count_ops(prog, on);
  EXPECT_EQ(c_on.lookup, 2);
  EXPECT_EQ(c_on.store, 2);
  // One block per point would emit the 9 shared nodes twice (2 x 10 block
  // nodes); the group emits the 11-node union once. Outside the group only
  // the texcoord-free nodes remain, so the cached program is the plain one
  // plus its 4 cache instructions.
  EXPECT_EQ(c_on.instructions, c_off.instructions + 4) << disassemble(prog, on);
}

TEST(CachePlan, APartialHitKeepsTheFoundValueAndRecomputesTheMissedOne) {
  Graph on_graph = shared_chain_material("M_on"), off_graph = shared_chain_material("M_off");
  TexturePool tex;
  MaterialProgram prog;
  CompileOptions on_opts;
  on_opts.cache = true;
  on_opts.cache_min_nodes = 4;
  compile_material(off_graph, tex, prog);
  compile_material(on_graph, tex, prog, on_opts);
  const CompiledMaterial& off = prog.materials[0];
  const CompiledMaterial& on = prog.materials[1];
  // Both orders: the hit first (the miss comes last) and the miss first
  // (the last lookup hits, and must not skip the group).
  for (int hit_index = 0; hit_index < 2; ++hit_index) {
    SCOPED_TRACE("cache point " + std::to_string(hit_index) + " hits");
    std::vector<uint64_t> words(size_t(1) << 12, 0);
    PmcCacheContext cache{};
    cache.table.entries = words.data();
    cache.table.cells = words.size() / 8;
    cache.table.ways = 8;
    cache.g1 = make_float2(1e-3f, 0.0f);
    cache.g2 = make_float2(0.0f, 1e-3f);
    cache.material = 1;
    cache.center = 0;
    const float u = 0.37f, v = 0.61f;
    const float3 pos = make_float3(0.8f, 0.1f, 0.2f);
    float ref[PMC_P_COUNT], first[PMC_P_COUNT], partial[PMC_P_COUNT];
    run_host(prog, off, u, v, ref, pos);
    run_host(prog, on, u, v, first, pos, &cache);
    ASSERT_EQ(cache.counts[PMC_CSTAT_INSERTS], 2u);
    // Plant a different value under one point's key and remove the other's:
    // the next evaluation must take the planted value for the first point and
    // compute the second one (floats are stored as raw bits).
    int lambda = pmc_cache_lambda(cache.g1, cache.g2, 0.0f);
    long tx = pmc_cache_texel(u, lambda), ty = pmc_cache_texel(v, lambda);
    const CachePoint& kept = on.cache_plan.points[hit_index];
    const CachePoint& dropped = on.cache_plan.points[1 - hit_index];
    // A point's rank is its place in the group (the plan's order).
    PmcCacheKey kk = pmc_cache_key(1u, uint32_t(kept.node), uint32_t(hit_index), lambda, tx, ty);
    PmcCacheKey kd = pmc_cache_key(1u, uint32_t(dropped.node), uint32_t(1 - hit_index), lambda, tx, ty);
    int cleared = 0;
    for (uint64_t& w : words) {
      if (w != 0 && uint32_t(w >> 32) == kd.fingerprint) w = 0, ++cleared;
      if (w != 0 && uint32_t(w >> 32) == kk.fingerprint)
        w = (uint64_t(kk.fingerprint) << 32) | pmc_float_bits(0.125f);
    }
    ASSERT_EQ(cleared, 1);
    // The cleared entry may have been in front of the kept one in a shared
    // cell; lookups stop at the first empty entry, so keep cells packed.
    ASSERT_NE(pmc_cache_cell(&cache.table, kk.h1), pmc_cache_cell(&cache.table, kd.h1));
    cache.hits = 0;
    run_host(prog, on, u, v, partial, pos, &cache);
    EXPECT_EQ(cache.hits, 1u);
    const std::string kept_name = on_graph.nodes[size_t(kept.node)].name;
    if (kept_name == "a") {
      EXPECT_FLOAT_EQ(partial[PMC_P_BASE_COLOR], 0.125f * 0.8f) << "the planted value, times the position";
      EXPECT_EQ(partial[PMC_P_SPECULAR_ROUGHNESS], ref[PMC_P_SPECULAR_ROUGHNESS]) << "recomputed";
    } else {
      ASSERT_EQ(kept_name, "b");
      EXPECT_EQ(partial[PMC_P_SPECULAR_ROUGHNESS], 0.125f) << "the planted value";
      EXPECT_EQ(partial[PMC_P_BASE_COLOR], ref[PMC_P_BASE_COLOR]) << "recomputed";
    }
    EXPECT_EQ(cache.counts[PMC_CSTAT_INSERTS], 3u) << "the missed point was inserted again";
  }
}

TEST(CachePlan, CompiledNoiseNodesReadTheirLookupPoint) {
  // noise2d/fractal2d (texcoord) and noise3d/fractal3d (position) list the
  // point last in MaterialX, while the opcodes read it first: emitted in
  // definition order, the noise ran at the constant amplitude as its point
  // (a cached block then stores a constant: "correct" and useless, and
  // often negative, so not even encodable). Checked against the noise
  // functions called directly, with the cache on (null context) and off.
  for (bool cache : {false, true}) {
    Graph g = new_graph(cache ? "M_noise_on" : "M_noise_off");
    int tc = add(g, "uv", "texcoord", VT::Vector2);
    int mul = add(g, "mul", "multiply", VT::Vector2, {{"in1", link(tc)}, {"in2", value(VT::Vector2, 3, 5)}});
    int pos = add(g, "pos", "position", VT::Vector3);
    int n2 = add(
        g, "n2", "noise2d", VT::Float,
        {{"texcoord", link(mul)}, {"amplitude", value(VT::Float, 2)}, {"pivot", value(VT::Float, 0.25f)}});
    int f2 = add(
        g, "f2", "fractal2d", VT::Float,
        {{"texcoord", link(mul)}, {"amplitude", value(VT::Float, 0.7f)}, {"octaves", value(VT::Integer, 2)}});
    int n3 = add(
        g, "n3", "noise3d", VT::Float,
        {{"position", link(pos)}, {"amplitude", value(VT::Float, 1.5f)}, {"pivot", value(VT::Float, 0.1f)}});
    int f3 = add(g, "f3", "fractal3d", VT::Float,
                 {{"position", link(pos)}, {"amplitude", value(VT::Float, 0.9f)}});
    add_surface(
        g,
        {{"base", link(n2)}, {"specular_roughness", link(f2)}, {"metalness", link(n3)}, {"coat", link(f3)}});
    TexturePool tex;
    MaterialProgram prog;
    CompileOptions opts;
    opts.cache = cache;
    opts.cache_min_nodes = 3;
    const CompiledMaterial& m = compile_material(g, tex, prog, opts);
    std::mt19937 rng(29);
    std::uniform_real_distribution<float> uni(-2.0f, 2.0f);
    for (int i = 0; i < 100; ++i) {
      float u = uni(rng), v = uni(rng);
      float3 p = make_float3(uni(rng), uni(rng), uni(rng));
      float params[PMC_P_COUNT];
      run_host(prog, m, u, v, params, p);
      float2 st = make_float2(u * 3, v * 5);
      float want[4] = {
          pmc_op_noise2d(st, 1u).x * 2.0f + 0.25f, pmc_op_fractal2d(st, 2, 2.0f, 0.5f, 1u).x * 0.7f,
          pmc_op_noise3d(p, 1u).x * 1.5f + 0.1f, pmc_op_fractal3d(p, 3, 2.0f, 0.5f, 1u).x * 0.9f};
      int at[4] = {PMC_P_BASE, PMC_P_SPECULAR_ROUGHNESS, PMC_P_METALNESS, PMC_P_COAT};
      const char* name[4] = {"noise2d", "fractal2d", "noise3d", "fractal3d"};
      for (int k = 0; k < 4; ++k)
        ASSERT_NEAR(params[at[k]], want[k], 1e-5f) << name[k] << " (cache " << cache << ")\n"
                                                   << disassemble(prog, m);
    }
  }
}

}  // namespace
}  // namespace pmc
