// cache_position_plan_test.cpp — position-keyed cache points, from the plan
// to the host interpreter (materials/cache_plan.h, core/device/pmc_interp.h).
//
// A marble-like graph (position -> scale -> fractal3d -> ... -> mix ->
// base_color) next to a uv chain (-> roughness):
//  - the plan makes the mix a position-keyed point and the uv chain's top a
//    uv-keyed one; with position keys off only the uv point remains;
//  - the compiled groups mark the position lookup (disassembly says so), one
//    group per key kind, the uv point's first;
//  - with a host cache table, a second point in the same position cell hits
//    and gets the first point's value; a point one cell over misses;
//  - in --cache-eval center the value delivered equals the cacheless program
//    evaluated at the cell's centre (the independent answer), so it depends
//    on the cell alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
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

struct Marble {
  Graph g;
  int colour = -1, rough = -1;
};

Marble marble(const std::string& name) {
  Marble m{new_graph(name)};
  Graph& g = m.g;
  int pos = add(g, "pos", "position", VT::Vector3);
  int scaled =
      add(g, "scaled", "multiply", VT::Vector3, {{"in1", link(pos)}, {"in2", value(VT::Float, 3.0f)}});
  int fractal = add(g, "fractal", "fractal3d", VT::Float,
                    {{"position", link(scaled)}, {"octaves", value(VT::Integer, 3)}});
  int s = add(g, "s", "sin", VT::Float, {{"in", link(fractal)}});
  int a = add(g, "a", "absval", VT::Float, {{"in", link(s)}});
  m.colour = add(g, "veins", "mix", VT::Color3,
                 {{"fg", value(VT::Color3, 0.9f, 0.85f, 0.8f)},
                  {"bg", value(VT::Color3, 0.1f, 0.1f, 0.15f)},
                  {"mix", link(a, VT::Float)}});
  int tc = add(g, "uv", "texcoord", VT::Vector2);
  int mul = add(g, "rmul", "multiply", VT::Vector2, {{"in1", link(tc)}, {"in2", value(VT::Vector2, 2, 9)}});
  int rn = add(g, "rnoise", "noise2d", VT::Float, {{"texcoord", link(mul)}});
  int rs = add(g, "rsin", "sin", VT::Float, {{"in", link(rn)}});
  m.rough = add(g, "rabs", "absval", VT::Float, {{"in", link(rs)}});
  add_surface(g, {{"base_color", link(m.colour)}, {"specular_roughness", link(m.rough)}});
  return m;
}

void run(const MaterialProgram& p, const CompiledMaterial& m, float3 pos, float params[PMC_P_COUNT],
         PmcCacheContext* cache = nullptr) {
  PmcShadingInputs in{};
  in.uv = make_float2(0.3f, 0.6f);
  in.position = pos;
  in.normal = make_float3(0, 0, 1);
  in.tangent = make_float3(1, 0, 0);
  in.bitangent = make_float3(0, 1, 0);
  in.footprint = 0.01f;
  PmcTextureSet ts{};
  float stack[PMC_STACK_SIZE] = {0};
  pmc_surface_defaults(params, in.normal);
  pmc_interp_run(p.code.data(), m.entry, &in, &ts, stack, params, cache);
}

TEST(CachePositionPlan, PositionOnlySubgraphIsAPositionKeyedPoint) {
  Marble m = marble("M_marble");
  CachePlan plan = plan_cache(m.g, 4);
  ASSERT_EQ(plan.points.size(), 2u);
  for (const CachePoint& p : plan.points) {
    if (p.node == m.colour) {
      EXPECT_EQ(p.key, CacheKey::Position);
      EXPECT_GE(p.subgraph_nodes, 6);
    } else {
      EXPECT_EQ(p.node, m.rough);
      EXPECT_EQ(p.key, CacheKey::Uv);
    }
  }
  CachePlan uv_only = plan_cache(m.g, 4, false);
  ASSERT_EQ(uv_only.points.size(), 1u);
  EXPECT_EQ(uv_only.points[0].node, m.rough);
  bool said = false;
  for (const auto& [n, why] : uv_only.not_cached)
    said = said || (n == m.colour && why.find("position keys are off") != std::string::npos);
  EXPECT_TRUE(said) << "the plan says why the marble is not cached";

  TexturePool tex;
  MaterialProgram prog;
  CompileOptions on;
  on.cache = true;
  on.cache_min_nodes = 4;
  const CompiledMaterial& cm = compile_material(m.g, tex, prog, on);
  std::string dis = disassemble(prog, cm);
  EXPECT_NE(dis.find("key position"), std::string::npos) << dis;
  EXPECT_NE(dis.find("key uv"), std::string::npos) << dis;
}

struct HostTable {
  std::vector<uint64_t> words = std::vector<uint64_t>(size_t(1) << 14, 0);
  PmcCacheContext cx{};
  explicit HostTable(uint32_t center) {
    cx.table.entries = words.data();
    cx.table.cells = words.size() / 8;
    cx.table.ways = 8;
    cx.g1 = make_float2(1e-4f, 0.0f);
    cx.g2 = make_float2(0.0f, 1e-4f);
    cx.radius = 0.01f;  // level 6: cells of 1/64
    cx.material = 1;
    cx.center = center;
  }
  // A fresh evaluation context (the cells the last one computed are not reused).
  PmcCacheContext* fresh() {
    cx.hits = 0;
    cx.texel.ready = 0u;
    cx.cell.ready = 0u;
    return &cx;
  }
};

// The marble compiled twice into one program: cacheless, then with its
// cache points (threshold 4: both points of this graph).
struct OffAndOn {
  TexturePool tex;
  MaterialProgram prog;
  OffAndOn() {
    Marble off_m = marble("M_off"), on_m = marble("M_on");
    CompileOptions on;
    on.cache = true;
    on.cache_min_nodes = 4;
    compile_material(off_m.g, tex, prog);
    compile_material(on_m.g, tex, prog, on);
  }
  const CompiledMaterial& off() const { return prog.materials[0]; }
  const CompiledMaterial& on() const { return prog.materials[1]; }
};

// The two key kinds compile to two groups, the uv point's first: each
// group's lookups, then its own sub-graph (no node of the other kind's), then
// its stores, and its last lookup skips exactly to the end of its stores. So a
// point whose cell is new while its texel is not reruns the position
// sub-graph alone.
TEST(CachePositionPlan, EachKeyKindIsAGroupOfItsOwn) {
  const OffAndOn m;
  const MaterialProgram& prog = m.prog;
  const CompiledMaterial& cm = m.on();
  ASSERT_EQ(cm.cache_plan.points.size(), 2u);
  EXPECT_EQ(cm.cache_plan.points[0].key, CacheKey::Uv) << "the plan lists its points in rank order";
  EXPECT_EQ(cm.cache_plan.points[1].key, CacheKey::Position);
  struct Group {
    bool position = false;
    size_t skip_to = 0, stores_end = 0;
    std::vector<uint32_t> body;  // opcodes between the lookups and the stores
  };
  std::vector<Group> groups;
  bool in_stores = false;
  for (size_t pc = cm.entry; pc < prog.code.size();) {
    const uint32_t h = prog.code[pc], op = pmc_op_code(h);
    const size_t next = pc + 2 + pmc_op_nargs(h);
    if (op == PMC_OP_END) break;
    if (op == PMC_OP_CACHE_LOOKUP) {
      if (groups.empty() || in_stores || !groups.back().body.empty()) groups.emplace_back();
      in_stores = false;
      const uint32_t word = prog.code[pc + 2];
      groups.back().position = (word & PMC_CACHE_KEY_POSITION) != 0u;
      const uint32_t skip = word & ~(PMC_CACHE_KEY_POSITION | PMC_CACHE_SAMPLES_MASK);
      if (skip != 0u) groups.back().skip_to = next + skip;
    } else if (op == PMC_OP_CACHE_STORE) {
      ASSERT_FALSE(groups.empty());
      in_stores = true;
      groups.back().stores_end = next;
    } else if (!groups.empty() && !in_stores) {
      groups.back().body.push_back(op);
    }
    pc = next;
  }
  ASSERT_EQ(groups.size(), 2u) << disassemble(prog, cm);
  EXPECT_FALSE(groups[0].position);
  EXPECT_TRUE(groups[1].position);
  for (const Group& g : groups) {
    EXPECT_EQ(g.skip_to, g.stores_end) << "a group's hit skips its own sub-graph and stores";
    const uint32_t other = g.position ? PMC_OP_TEXCOORD : PMC_OP_POSITION;
    const uint32_t own = g.position ? PMC_OP_POSITION : PMC_OP_TEXCOORD;
    EXPECT_EQ(std::count(g.body.begin(), g.body.end(), other), 0) << disassemble(prog, cm);
    EXPECT_EQ(std::count(g.body.begin(), g.body.end(), own), 1) << disassemble(prog, cm);
  }
}

TEST(CachePositionPlan, SameCellHitsAndTheNextCellMisses) {
  const OffAndOn m;
  const MaterialProgram& prog = m.prog;
  const CompiledMaterial& off = m.off();
  const CompiledMaterial& cm = m.on();
  HostTable t(0);  // --cache-eval hit: the inserting point's own value is stored
  const float w = 1.0f / 64.0f;
  std::mt19937 rng(31);
  std::uniform_int_distribution<int> cell(-200, 200);
  std::uniform_real_distribution<float> in(0.05f, 0.95f);
  for (int i = 0; i < 100; ++i) {
    // Cells are centred on multiples of w: cell k spans [(k - 1/2) w, (k + 1/2) w).
    const float3 c0 = make_float3((float(cell(rng)) - 0.5f) * w, (float(cell(rng)) - 0.5f) * w,
                                  (float(cell(rng)) - 0.5f) * w);
    const float3 p = make_float3(c0.x + in(rng)*w, c0.y + in(rng)*w, c0.z + in(rng)*w);
    const float3 q = make_float3(c0.x + in(rng)*w, c0.y + in(rng)*w, c0.z + in(rng)*w);
    const float3 next = make_float3(p.x, p.y, p.z + w);
    float ref_p[PMC_P_COUNT], first[PMC_P_COUNT], second[PMC_P_COUNT], third[PMC_P_COUNT];
    run(prog, off, p, ref_p);
    run(prog, cm, p, first, t.fresh());
    const uint32_t first_hits = t.cx.hits;
    run(prog, cm, q, second, t.fresh());
    ASSERT_GE(t.cx.hits, 1u) << "the position point hits in the same cell";
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(first[PMC_P_BASE_COLOR + k], ref_p[PMC_P_BASE_COLOR + k])
          << "a miss computes the plain value";
      // The hit delivers p's value (RGB9E5: within 1/511.5 of colours <= 1), not q's.
      ASSERT_NEAR(second[PMC_P_BASE_COLOR + k], ref_p[PMC_P_BASE_COLOR + k], 1.0 / 511.5) << k;
    }
    run(prog, cm, next, third, t.fresh());
    // The uv point hits (same uv every time) after the first evaluation; the
    // position point one cell over is new.
    ASSERT_EQ(t.cx.hits, 1u) << "next cell: only the uv point hits (first evaluation had " << first_hits
                             << ")";
  }
  EXPECT_EQ(t.cx.counts[PMC_CSTAT_NOT_ENCODABLE], 0u);
}

TEST(CachePositionPlan, CenterModeDeliversTheValueAtTheCellCentre) {
  const OffAndOn m;
  const MaterialProgram& prog = m.prog;
  const CompiledMaterial& off = m.off();
  const CompiledMaterial& cm = m.on();
  HostTable t(1);
  const float w = 1.0f / 64.0f;
  std::mt19937 rng(37);
  std::uniform_real_distribution<float> uni(-5.0f, 5.0f);
  int differs = 0;
  for (int i = 0; i < 200; ++i) {
    const float3 p = make_float3(uni(rng), uni(rng), uni(rng));
    const float3 centre = make_float3(std::floor(p.x / w + 0.5f) * w, std::floor(p.y / w + 0.5f) * w,
                                      std::floor(p.z / w + 0.5f) * w);
    float at_centre[PMC_P_COUNT], at_p[PMC_P_COUNT], cached[PMC_P_COUNT];
    run(prog, off, centre, at_centre);
    run(prog, off, p, at_p);
    run(prog, cm, p, cached, t.fresh());
    for (int k = 0; k < 3; ++k)
      ASSERT_NEAR(cached[PMC_P_BASE_COLOR + k], at_centre[PMC_P_BASE_COLOR + k], 1.0 / 511.5)
          << "component " << k << " at " << p.x << " " << p.y << " " << p.z;
    differs += std::fabs(at_p[PMC_P_BASE_COLOR] - at_centre[PMC_P_BASE_COLOR]) > 2.0f / 511.5f;
  }
  EXPECT_GT(differs, 10) << "the test can tell the centre from the point";
}

}  // namespace
}  // namespace pmc
