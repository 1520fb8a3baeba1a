// passes_test.cpp — the graph passes (materials/passes.h) on graphs built in code.
//
// The passes decide what the compiler emits: a fold that keeps a node costs
// an instruction per shading point, a wrong fold or merge changes the image.
// Each test builds a small Graph by hand and checks the live node count after
// fold_constants / remove_dead / deduplicate / optimize, the folded values
// against answers computed here analytically, the error messages of
// check_types and check_acyclic (they must name the node), and the
// shading-point dependency bits.
#include "materials/passes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "materials/node_graph.h"
#include "materials/node_table.h"
#include "tests/support/graph_builder.h"

namespace pmc {
namespace {

using VT = ValueType;

using test::add;
using test::add_surface;
using test::link;
using test::new_graph;
using test::text;
using test::value;

const Input& surface_input(const Graph& g, const std::string& name) {
  return *g.nodes[size_t(g.surface)].input(name);
}

// u = extract(texcoord, 0): a float that depends on the shading point.
int add_u(Graph& g, int* texcoord = nullptr) {
  int tc = add(g, "uv", "texcoord", VT::Vector2);
  if (texcoord) *texcoord = tc;
  return add(g, "u", "extract", VT::Float, {{"in", link(tc, VT::Vector2)}, {"index", value(VT::Integer, 0)}});
}

TEST(Passes, FoldsAConstantChainIntoItsConsumer) {
  Graph g;
  int c1 = add(g, "c1", "constant", VT::Float, {{"value", value(VT::Float, 1)}});
  int c2 = add(g, "c2", "constant", VT::Float, {{"value", value(VT::Float, 2)}});
  int sum = add(g, "sum", "add", VT::Float, {{"in1", link(c1)}, {"in2", link(c2)}});
  int u = add_u(g);
  int m = add(g, "m", "multiply", VT::Float, {{"in1", link(sum)}, {"in2", link(u)}});
  add_surface(g, {{"base", link(m)}});
  ASSERT_EQ(g.live_count(), 7u);
  EXPECT_EQ(fold_constants(g), 3u);  // c1, c2, then the add of their values
  EXPECT_EQ(g.live_count(), 4u);     // texcoord, extract, multiply, surface
  const Input* in1 = g.nodes[size_t(m)].input("in1");
  EXPECT_FALSE(in1->linked);
  EXPECT_EQ(in1->value.f[0], 3.0f);
  EXPECT_TRUE(g.nodes[size_t(sum)].dead);
  EXPECT_TRUE(surface_input(g, "base").linked);
}

TEST(Passes, FoldedValuesMatchAnalyticAnswers) {
  Graph g;
  int half = add(g, "half", "constant", VT::Float, {{"value", value(VT::Float, 0.5f)}});
  int s = add(g, "s", "sin", VT::Float, {{"in", link(half)}});
  int p = add(g, "p", "power", VT::Float, {{"in1", value(VT::Float, 2)}, {"in2", value(VT::Float, 3)}});
  int base = add(g, "base", "multiply", VT::Float, {{"in1", link(s)}, {"in2", link(p)}});
  int remap = add(g, "remap", "remap", VT::Color3,
                  {{"in", value(VT::Color3, 0.25f, 0.5f, 0.75f)},
                   {"outlow", value(VT::Color3, 1, 1, 1)},
                   {"outhigh", value(VT::Color3, 3, 3, 3)}});
  int mix = add(g, "mix", "mix", VT::Color3,
                {{"fg", value(VT::Color3, 1, 0, 0)},
                 {"bg", value(VT::Color3, 0, 0, 1)},
                 {"mix", value(VT::Color3, 0.25f, 0.25f, 0.25f)}});
  int smooth = add(g, "smooth", "smoothstep", VT::Float, {{"in", value(VT::Float, 0.25f)}});
  int hsv = add(g, "hsv", "hsvtorgb", VT::Color3, {{"in", value(VT::Color3, 1.0f / 3.0f, 1, 1)}});
  int clampn = add(g, "clamp", "clamp", VT::Float, {{"in", value(VT::Float, 1.7f)}});
  int swz =
      add(g, "swz", "swizzle", VT::Color3, {{"in", value(VT::Color3, 1, 2, 3)}, {"channels", text("bgr")}});
  int dotp = add(g, "dotp", "dotproduct", VT::Float,
                 {{"in1", value(VT::Vector3, 1, 2, 3)}, {"in2", value(VT::Vector3, 4, 5, 6)}});
  int modn =
      add(g, "mod", "modulo", VT::Float, {{"in1", value(VT::Float, -1)}, {"in2", value(VT::Float, 3)}});
  int conv = add(g, "conv", "convert", VT::Color3, {{"in", value(VT::Float, 0.5f)}});
  int ifg = add(g, "ifg", "ifgreater", VT::Color3,
                {{"value1", value(VT::Float, 2)},
                 {"value2", value(VT::Float, 1)},
                 {"in1", value(VT::Color3, 0.1f, 0.2f, 0.3f)},
                 {"in2", value(VT::Color3, 9, 9, 9)}});
  add_surface(g, {{"base", link(base)},
                  {"base_color", link(remap)},
                  {"specular_color", link(mix)},
                  {"specular_roughness", link(smooth)},
                  {"emission_color", link(hsv)},
                  {"metalness", link(clampn)},
                  {"coat_color", link(swz)},
                  {"specular_IOR", link(dotp)},
                  {"coat_roughness", link(modn)},
                  {"opacity", link(conv)},
                  {"normal", link(ifg, VT::Vector3)}});
  fold_constants(g);
  EXPECT_EQ(g.live_count(), 1u) << "everything is constant";
  auto expect = [&](const char* name, std::vector<double> want) {
    const Input& in = surface_input(g, name);
    ASSERT_FALSE(in.linked) << name;
    for (size_t i = 0; i < want.size(); ++i)
      EXPECT_NEAR(in.value.f[i], want[i], 1e-6 * (1 + std::fabs(want[i]))) << name << " lane " << i;
  };
  expect("base", {std::sin(0.5) * 8.0});
  expect("base_color", {1.5, 2.0, 2.5});      // 1 + 2 x
  expect("specular_color", {0.25, 0, 0.75});  // bg + (fg - bg) * 0.25
  expect("specular_roughness", {0.25 * 0.25 * (3 - 2 * 0.25)});
  expect("emission_color", {0, 1, 0});  // hue 1/3 = green
  expect("metalness", {1.0});
  expect("coat_color", {3, 2, 1});
  expect("specular_IOR", {32});
  expect("coat_roughness", {2});  // MaterialX modulo is floored: -1 mod 3 = 2
  expect("opacity", {0.5, 0.5, 0.5});
  expect("normal", {0.1, 0.2, 0.3});
}

TEST(Passes, MultiplyByOnePassesItsInputThrough) {
  Graph g;
  int u = add_u(g);
  int m = add(g, "m", "multiply", VT::Float, {{"in1", link(u)}, {"in2", value(VT::Float, 1)}});
  add_surface(g, {{"base", link(m)}});
  EXPECT_EQ(fold_constants(g), 1u);
  EXPECT_EQ(g.live_count(), 3u);  // texcoord, extract, surface
  EXPECT_TRUE(surface_input(g, "base").linked);
  EXPECT_EQ(surface_input(g, "base").node, u);
  // One on the left as well.
  Graph h;
  int u2 = add_u(h);
  int m2 = add(h, "m", "multiply", VT::Float, {{"in1", value(VT::Float, 1)}, {"in2", link(u2)}});
  add_surface(h, {{"base", link(m2)}});
  fold_constants(h);
  EXPECT_EQ(surface_input(h, "base").node, u2);
}

TEST(Passes, MultiplyByOneKeepsABroadcastThatChangesTheWidth) {
  // color3 = float u * (1,1,1) is a broadcast, not a pass-through: replacing
  // it by u would feed a float where a color3 is read.
  Graph g;
  int u = add_u(g);
  int m =
      add(g, "m", "multiply", VT::Color3, {{"in1", link(u, VT::Float)}, {"in2", value(VT::Color3, 1, 1, 1)}});
  add_surface(g, {{"base_color", link(m)}});
  EXPECT_EQ(fold_constants(g), 0u);
  EXPECT_EQ(surface_input(g, "base_color").node, m);
}

TEST(Passes, MultiplyByZeroBecomesAConstantAndItsInputsDie) {
  Graph g;
  int u = add_u(g);
  int m =
      add(g, "m", "multiply", VT::Color3, {{"in1", link(u, VT::Float)}, {"in2", value(VT::Color3, 0, 0, 0)}});
  add_surface(g, {{"base_color", link(m)}});
  ASSERT_EQ(g.live_count(), 4u);
  EXPECT_EQ(fold_constants(g), 1u);
  const Input& bc = surface_input(g, "base_color");
  ASSERT_FALSE(bc.linked);
  EXPECT_EQ(bc.value.type, VT::Color3);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(bc.value.f[size_t(i)], 0.0f);
  EXPECT_EQ(remove_dead(g), 2u);  // texcoord and extract reach nothing now
  EXPECT_EQ(g.live_count(), 1u);
}

TEST(Passes, AddZeroAndDivideByOnePassThrough) {
  Graph g;
  int u = add_u(g);
  int a = add(g, "a", "add", VT::Float, {{"in1", value(VT::Float, 0)}, {"in2", link(u)}});
  int d = add(g, "d", "divide", VT::Float, {{"in1", link(a)}, {"in2", value(VT::Float, 1)}});
  int p = add(g, "p", "power", VT::Float, {{"in1", link(d)}, {"in2", value(VT::Float, 1)}});
  int s = add(g, "s", "subtract", VT::Float, {{"in1", link(p)}, {"in2", value(VT::Float, 0)}});
  add_surface(g, {{"base", link(s)}});
  EXPECT_EQ(fold_constants(g), 4u);
  EXPECT_EQ(surface_input(g, "base").node, u);
  EXPECT_EQ(g.live_count(), 3u);
}

TEST(Passes, MixByZeroOrOneSelectsAnInput) {
  Graph g;
  int tc = -1;
  int u = add_u(g, &tc);
  int v =
      add(g, "v", "extract", VT::Float, {{"in", link(tc, VT::Vector2)}, {"index", value(VT::Integer, 1)}});
  int mix0 =
      add(g, "mix0", "mix", VT::Float, {{"fg", link(u)}, {"bg", link(v)}, {"mix", value(VT::Float, 0)}});
  int mix1 =
      add(g, "mix1", "mix", VT::Float, {{"fg", link(u)}, {"bg", link(v)}, {"mix", value(VT::Float, 1)}});
  int mixh =
      add(g, "mixh", "mix", VT::Float, {{"fg", link(u)}, {"bg", link(v)}, {"mix", value(VT::Float, 0.5f)}});
  add_surface(g, {{"base", link(mix0)}, {"metalness", link(mix1)}, {"specular", link(mixh)}});
  EXPECT_EQ(fold_constants(g), 2u);
  EXPECT_EQ(surface_input(g, "base").node, v);       // mix 0: background
  EXPECT_EQ(surface_input(g, "metalness").node, u);  // mix 1: foreground
  EXPECT_EQ(surface_input(g, "specular").node, mixh);
}

TEST(Passes, RemoveDeadDropsNodesThatReachNoOutput) {
  Graph g;
  int u = add_u(g);
  int orphan = add(g, "orphan", "sin", VT::Float, {{"in", link(u)}});
  int orphan2 = add(g, "orphan2", "cos", VT::Float, {{"in", link(orphan)}});
  add_surface(g, {{"base", link(u)}});
  EXPECT_EQ(g.live_count(), 5u);
  EXPECT_EQ(remove_dead(g), 2u);
  EXPECT_TRUE(g.nodes[size_t(orphan)].dead);
  EXPECT_TRUE(g.nodes[size_t(orphan2)].dead);
  EXPECT_FALSE(g.nodes[size_t(u)].dead);
  EXPECT_EQ(remove_dead(g), 0u);
}

// texcoord -> multiply by 4 -> image, built twice.
int image_chain(Graph& g, const std::string& suffix, const std::string& file = "bricks.png",
                float tiling = 4) {
  int tc = add(g, "uv" + suffix, "texcoord", VT::Vector2);
  int m = add(g, "tile" + suffix, "multiply", VT::Vector2,
              {{"in1", link(tc)}, {"in2", value(VT::Vector2, tiling, tiling)}});
  return add(g, "img" + suffix, "image", VT::Color3,
             {{"file", text(file, VT::Filename)}, {"texcoord", link(m)}});
}

TEST(Passes, DeduplicateMergesIdenticalImageSubgraphs) {
  Graph g;
  int a = image_chain(g, "_a");
  int b = image_chain(g, "_b");
  add_surface(g, {{"base_color", link(a)}, {"specular_color", link(b)}});
  ASSERT_EQ(g.live_count(), 7u);
  EXPECT_EQ(deduplicate(g), 3u);  // texcoord, multiply, image
  EXPECT_EQ(surface_input(g, "base_color").node, a);
  EXPECT_EQ(surface_input(g, "specular_color").node, a);
  EXPECT_EQ(g.live_count(), 4u);
}

TEST(Passes, DeduplicateKeepsSubgraphsThatDiffer) {
  Graph g;
  int a = image_chain(g, "_a", "bricks.png", 4);
  int b = image_chain(g, "_b", "bricks.png", 3);  // other tiling
  int c = image_chain(g, "_c", "wood.png", 4);    // other file
  add_surface(g, {{"base_color", link(a)}, {"specular_color", link(b)}, {"coat_color", link(c)}});
  // The three texcoords merge; then the "_a" and "_c" multiplies (same
  // tiling) merge; the images all differ.
  EXPECT_EQ(deduplicate(g), 3u);
  EXPECT_NE(surface_input(g, "base_color").node, surface_input(g, "specular_color").node);
  EXPECT_NE(surface_input(g, "base_color").node, surface_input(g, "coat_color").node);
}

TEST(Passes, DeduplicateComparesConstantsExactly) {
  // Two offsets that differ by 0.2 but print alike with 6 significant digits
  // ("100000"): merging them would shift one pattern.
  Graph g;
  int pos = add(g, "pos", "position", VT::Vector3);
  int x =
      add(g, "x", "extract", VT::Float, {{"in", link(pos, VT::Vector3)}, {"index", value(VT::Integer, 0)}});
  int a = add(g, "a", "add", VT::Float, {{"in1", link(x)}, {"in2", value(VT::Float, 100000.2f)}});
  int b = add(g, "b", "add", VT::Float, {{"in1", link(x)}, {"in2", value(VT::Float, 100000.4f)}});
  ASSERT_NE(100000.2f, 100000.4f);
  add_surface(g, {{"base", link(a)}, {"metalness", link(b)}});
  EXPECT_EQ(deduplicate(g), 0u);
  EXPECT_EQ(surface_input(g, "base").node, a);
  EXPECT_EQ(surface_input(g, "metalness").node, b);
}

TEST(Passes, OptimizeChainsThePassesAndReportsCounts) {
  Graph g;
  int a = image_chain(g, "_a");
  int b = image_chain(g, "_b");
  int one = add(g, "one", "constant", VT::Color3, {{"value", value(VT::Color3, 1, 1, 1)}});
  int m = add(g, "m", "multiply", VT::Color3, {{"in1", link(b)}, {"in2", link(one)}});
  int unused = add(g, "unused", "sin", VT::Float, {{"in", value(VT::Float, 1)}});
  (void)unused;
  add_surface(g, {{"base_color", link(a)}, {"specular_color", link(m)}});
  ASSERT_EQ(g.live_count(), 10u);
  std::vector<PassStat> stats = optimize(g);
  ASSERT_FALSE(stats.empty());
  for (size_t i = 1; i < stats.size(); ++i) EXPECT_EQ(stats[i].before, stats[i - 1].after) << stats[i].pass;
  EXPECT_EQ(stats.front().before, 10u);
  EXPECT_EQ(stats.back().after, g.live_count());
  // unused dies, one folds, m passes b through, then the two chains merge.
  EXPECT_EQ(g.live_count(), 4u);
  EXPECT_EQ(surface_input(g, "specular_color").node, a);
}

TEST(Passes, CheckTypesNamesTheNodeAndBothTypes) {
  Graph g;
  int tc = add(g, "uv", "texcoord", VT::Vector2);
  int m = add(g, "tint", "multiply", VT::Color3, {{"in1", link(tc, VT::Color3)}});
  add_surface(g, {{"base_color", link(m)}});
  try {
    check_types(g);
    FAIL() << "a vector2 into a color3 input must be refused";
  } catch (const Error& e) {
    std::string w = e.what();
    EXPECT_NE(w.find("test.mtlx"), std::string::npos) << w;
    EXPECT_NE(w.find("'tint'"), std::string::npos) << w;
    EXPECT_NE(w.find("'in1'"), std::string::npos) << w;
    EXPECT_NE(w.find("'uv'"), std::string::npos) << w;
    EXPECT_NE(w.find("vector2"), std::string::npos) << w;
    EXPECT_NE(w.find("color3"), std::string::npos) << w;
    EXPECT_NE(w.find("type mismatch"), std::string::npos) << w;
  }
  // A float broadcasts into any width, and equal widths are compatible.
  Graph ok;
  int u = add_u(ok);
  int pos = add(ok, "pos", "position", VT::Vector3);
  int m1 =
      add(ok, "m1", "multiply", VT::Color3, {{"in1", link(u, VT::Color3)}, {"in2", link(pos, VT::Color3)}});
  add_surface(ok, {{"base_color", link(m1)}});
  EXPECT_NO_THROW(check_types(ok));
}

TEST(Passes, CheckAcyclicNamesTheCycle) {
  Graph g;
  int a = add(g, "a", "add", VT::Float);
  int b = add(g, "b", "add", VT::Float, {{"in1", link(a)}});
  g.nodes[size_t(a)].input("in1")->linked = true;
  g.nodes[size_t(a)].input("in1")->node = b;
  add_surface(g, {{"base", link(a)}});
  try {
    check_acyclic(g);
    FAIL() << "a -> b -> a must be refused";
  } catch (const Error& e) {
    std::string w = e.what();
    EXPECT_NE(w.find("test.mtlx"), std::string::npos) << w;
    EXPECT_NE(w.find("cycle"), std::string::npos) << w;
    EXPECT_NE(w.find("'a' -> 'b' -> 'a'"), std::string::npos) << w;
  }
  Graph ok;
  int u = add_u(ok);
  add_surface(ok, {{"base", link(u)}, {"metalness", link(u)}});  // shared, not cyclic
  EXPECT_NO_THROW(check_acyclic(ok));
}

TEST(Passes, DependenciesFollowTheShadingInputs) {
  Graph g;
  int u = add_u(g);
  int uv_only = add(g, "uv_only", "sin", VT::Float, {{"in", link(u)}});
  int pos = add(g, "pos", "position", VT::Vector3);
  int noise = add(g, "noise", "noise3d", VT::Float, {{"position", link(pos)}});
  int both = add(g, "both", "add", VT::Float, {{"in1", link(uv_only)}, {"in2", link(noise)}});
  int nrm = add(g, "nrm", "normal", VT::Vector3);
  int cst = add(g, "cst", "cos", VT::Float, {{"in", value(VT::Float, 1)}});
  add_surface(g, {{"base", link(both)}, {"metalness", link(cst)}, {"normal", link(nrm)}});
  std::vector<uint32_t> deps = dependencies(g);
  EXPECT_EQ(deps[size_t(uv_only)], uint32_t(kDepUv));
  EXPECT_EQ(deps[size_t(noise)], uint32_t(kDepPosition));
  EXPECT_EQ(deps[size_t(both)], uint32_t(kDepUv | kDepPosition));
  EXPECT_EQ(deps[size_t(nrm)], uint32_t(kDepNormal));
  EXPECT_EQ(deps[size_t(cst)], 0u);
  EXPECT_EQ(dependency_names(kDepUv | kDepPosition), "uv+position");
  EXPECT_EQ(dependency_names(0), "constant");
  EXPECT_EQ(dependency_names(kDepNormal | kDepTangent | kDepBitangent), "normal+tangent+bitangent");
}

}  // namespace
}  // namespace pmc
