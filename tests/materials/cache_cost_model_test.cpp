// cache_cost_model_test.cpp — the cache plan's cost model (materials/node_costs.h)
// on graphs built in code, against figures computed by hand:
//  (a) node weights: a 3D Worley noise is 8.1 unit nodes, a fractal its
//      per-octave weight times its octaves, key inputs nothing;
//  (b) the expected hit rate from the samples, the path depth and the key kind;
//  (c) a cheap uv sub-graph is not cached (its reason gives the figures), an
//      expensive one is, with the gain h C - L - (1 - h) M;
//  (d) a marginal point pays at 16 spp and not at 2 (few samples per key);
//  (e) the node count stays a floor: an expensive sub-graph of fewer nodes
//      than the node-count floor (min_nodes) is not cached;
//  (f) compile_material applies the model from CompileOptions;
//  (g) supersampled misses: K sub-samples make a miss evaluate the sub-graph
//      K times (M = miss + miss_per_cost C + (K - 1)(1 + miss_per_cost) C), so
//      a point that pays with K = 1 may not with K = 16; the automatic K is
//      the largest power of two up to lookups per key / 4, 1..16, per key kind.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/texture.h"
#include "materials/cache_plan.h"
#include "materials/compiler.h"
#include "materials/node_costs.h"
#include "tests/support/graph_builder.h"

namespace pmc {
namespace {

using VT = ValueType;
using test::add;
using test::add_surface;
using test::link;
using test::value;

// Hand-picked device figures, so the answers below are easy to compute.
CacheCostModel model(int spp, int max_depth = 8) {
  CacheCostModel m;
  m.costs.unit_ns = 2.0;
  m.costs.lookup = 10.0;
  m.costs.miss = 10.0;
  m.costs.miss_per_cost = 0.0;
  m.costs.source = "test";
  m.frame = CacheFrame{100, 50, spp, max_depth};
  return m;
}

// texcoord -> multiply -> PATTERN (float) -> multiply -> specular_roughness.
// Returns the top multiply; `pattern` gets the pattern node.
int roughness_chain(Graph& g, const std::string& category, int octaves = 0, int* pattern = nullptr) {
  int tc = add(g, "uv", "texcoord", VT::Vector2);
  int scale =
      add(g, "scale", "multiply", VT::Vector2, {{"in1", link(tc)}, {"in2", value(VT::Vector2, 3, 3)}});
  test::Given given = {{"texcoord", link(scale)}};
  if (octaves) given.push_back({"octaves", value(VT::Integer, float(octaves))});
  int p = add(g, "pattern", category, VT::Float, given);
  if (pattern) *pattern = p;
  int top = add(g, "top", "multiply", VT::Float, {{"in1", link(p)}, {"in2", value(VT::Float, 0.5f)}});
  add_surface(g, {{"specular_roughness", link(top)}});
  return top;
}

std::string reason_for(const CachePlan& plan, int node) {
  for (const auto& [n, why] : plan.not_cached)
    if (n == node) return why;
  return "";
}

TEST(CacheCostModel, NodeWeightsFollowTheMeasuredFamilies) {
  Graph g = test::new_graph("M");
  int tc = add(g, "uv", "texcoord", VT::Vector2);
  int pos = add(g, "p", "position", VT::Vector3);
  int worley = add(g, "w", "worleynoise3d", VT::Float, {{"position", link(pos)}});
  int fractal =
      add(g, "f", "fractal3d", VT::Float, {{"position", link(pos)}, {"octaves", value(VT::Integer, 4)}});
  int sum = add(g, "s", "add", VT::Float, {{"in1", link(worley)}, {"in2", link(fractal)}});
  EXPECT_DOUBLE_EQ(node_cost(g.nodes[size_t(tc)]), 0.0);
  EXPECT_DOUBLE_EQ(node_cost(g.nodes[size_t(pos)]), 0.0);
  EXPECT_DOUBLE_EQ(node_cost(g.nodes[size_t(worley)]), 8.1);
  EXPECT_DOUBLE_EQ(node_cost(g.nodes[size_t(fractal)]), 4 * 2.2);
  EXPECT_DOUBLE_EQ(node_cost(g.nodes[size_t(sum)]), 1.0);
  // The position node is shared: counted once.
  EXPECT_DOUBLE_EQ(subgraph_cost(g, sum), 8.1 + 4 * 2.2 + 1.0);
}

TEST(CacheCostModel, HitRateFromSamplesDepthAndKeyKind) {
  // keys per pixel and point 1 + 3 (1 - 1/sqrt(spp)); lookups spp x 1.6 (paths
  // of several hits) or spp x 1 (camera hits only); position keys twice the keys.
  const CacheFrame f16{640, 360, 16, 8};
  EXPECT_NEAR(expected_hit_rate(f16, false), 1.0 - 3.25 / 25.6, 1e-12);
  EXPECT_NEAR(expected_hit_rate(f16, true), 1.0 - 6.5 / 25.6, 1e-12);
  const CacheFrame camera_only{640, 360, 16, 1};
  EXPECT_NEAR(expected_hit_rate(camera_only, false), 1.0 - 3.25 / 16.0, 1e-12);
  EXPECT_DOUBLE_EQ(expected_hit_rate(CacheFrame{64, 64, 1, 1}, false), 0.0);  // every key seen once
  // The frame's pixel count cancels: keys and lookups both scale with it.
  EXPECT_DOUBLE_EQ(expected_hit_rate(CacheFrame{160, 90, 16, 8}, false), expected_hit_rate(f16, false));
  // Camera hits look up in the first camera_samples samples only (16 by
  // default): at 64 spp, 16 camera lookups and 64 x 0.6 later ones; the keys
  // are those of 64 samples' paths (1 + 3 (1 - 1/8) = 3.625).
  const CacheFrame f64{640, 360, 64, 8};
  EXPECT_NEAR(lookups_per_pixel(f64), 16.0 + 64.0 * 0.6, 1e-12);
  EXPECT_NEAR(expected_hit_rate(f64, false), 1.0 - 3.625 / (16.0 + 64.0 * 0.6), 1e-12);
  const CacheFrame f64_every{640, 360, 64, 8, 64};  // every sample's camera hit (the paper)
  EXPECT_NEAR(expected_hit_rate(f64_every, false), 1.0 - 3.625 / 102.4, 1e-12);
  EXPECT_NEAR(lookups_per_pixel(CacheFrame{640, 360, 8, 8}), 8.0 * 1.6, 1e-12) << "at most K samples: all";
  // Camera hits only and none of them cached: nothing to look up, no hits.
  EXPECT_DOUBLE_EQ(expected_hit_rate(CacheFrame{640, 360, 64, 1, 0}, false), 0.0);
  EXPECT_DOUBLE_EQ(lookups_per_pixel(CacheFrame{640, 360, 64, 1, 0}), 0.0);
}

TEST(CacheCostModel, CheapSubgraphIsNotCachedAndExpensiveOneIs) {
  const CacheCostModel m = model(16);
  const double h = 1.0 - 3.25 / 25.6;
  {
    Graph g = test::new_graph("Cheap");
    int top = roughness_chain(g, "noise2d");  // multiply 1 + noise2d 1 + multiply 1 = 3 units
    CachePlan plan = plan_cache(g, 1, true, 0.0, &m);
    EXPECT_TRUE(plan.points.empty());
    const std::string why = reason_for(plan, top);
    EXPECT_NE(why.find("does not pay"), std::string::npos) << why;
    EXPECT_NE(why.find("C 3.0"), std::string::npos) << why;
    EXPECT_NE(why.find("h 87.3%"), std::string::npos) << why;
    // Without the model the node count alone caches it.
    EXPECT_EQ(plan_cache(g, 1).points.size(), 1u);
  }
  {
    Graph g = test::new_graph("Expensive");
    int top = roughness_chain(g, "fractal2d", 16);  // 1 + 16 octaves x 1.5 + 1 = 26 units
    CachePlan plan = plan_cache(g, 1, true, 0.0, &m);
    ASSERT_EQ(plan.points.size(), 1u);
    const CachePoint& p = plan.points[0];
    EXPECT_EQ(p.node, top);
    ASSERT_TRUE(p.modelled);
    EXPECT_NEAR(p.economics.cost, 26.0, 1e-9);
    EXPECT_NEAR(p.economics.hit_rate, h, 1e-12);
    EXPECT_NEAR(p.economics.gain, h * 26.0 - 10.0 - (1.0 - h) * 10.0, 1e-9);
    // Saved per frame: gain x 100 x 50 pixels x 16 spp x 1.6 lookups x 2 ns.
    EXPECT_NEAR(p.economics.frame_seconds, p.economics.gain * 100 * 50 * 16 * 1.6 * 2e-9, 1e-12);
  }
}

TEST(CacheCostModel, FewSamplesPerKeyTurnAMarginalPointOff) {
  // multiply 1 + fractal2d 12 octaves x 1.5 + multiply 1 = 20 units.
  Graph g = test::new_graph("Marginal");
  int top = roughness_chain(g, "fractal2d", 12);
  ASSERT_NEAR(subgraph_cost(g, top), 20.0, 1e-9);
  // 16 spp: h = 0.873, 17.46 > 10 + 1.27.
  const CacheCostModel many = model(16);
  ASSERT_EQ(plan_cache(g, 1, true, 0.0, &many).points.size(), 1u);
  // 2 spp: keys 1 + 3 (1 - 1/sqrt 2) = 1.879 of 3.2 lookups, h = 0.413: 8.26 < 10 + 5.87.
  const CacheCostModel few = model(2);
  const double h = 1.0 - (1.0 + 3.0 * (1.0 - 1.0 / std::sqrt(2.0))) / 3.2;
  EXPECT_LT(h * 20.0, 10.0 + (1.0 - h) * 10.0);
  CachePlan plan = plan_cache(g, 1, true, 0.0, &few);
  EXPECT_TRUE(plan.points.empty());
  EXPECT_NE(reason_for(plan, top).find("does not pay"), std::string::npos);
}

TEST(CacheCostModel, NodeCountStaysAFloor) {
  Graph g = test::new_graph("Costly but small");
  int top = roughness_chain(g, "fractal2d", 16);  // 4 nodes, 26 units: pays at 16 spp
  const CacheCostModel m = model(16);
  ASSERT_EQ(plan_cache(g, 4, true, 0.0, &m).points.size(), 1u);
  CachePlan plan = plan_cache(g, 5, true, 0.0, &m);
  EXPECT_TRUE(plan.points.empty());
  EXPECT_NE(reason_for(plan, top).find("threshold 5"), std::string::npos) << reason_for(plan, top);
}

TEST(CacheCostModel, CompilerAppliesTheModel) {
  auto compile = [](const CompileOptions& options) {
    Graph g = test::new_graph("Compiled");
    roughness_chain(g, "noise2d");
    TexturePool pool;
    MaterialProgram program;
    return compile_material(g, pool, program, options).cache_plan.points.size();
  };
  CompileOptions nodes;
  nodes.cache = true;
  nodes.cache_min_nodes = 1;
  CompileOptions cost = nodes;
  cost.cache_model = model(16);
  EXPECT_EQ(compile(nodes), 1u);
  EXPECT_EQ(compile(cost), 0u);
}

TEST(CacheCostModel, SubSamplesScaleTheMissAndCanTurnAPointOff) {
  Graph g = test::new_graph("Supersampled");
  int top = roughness_chain(g, "fractal2d", 16);  // 26 units
  CacheCostModel m = model(16);
  m.costs.miss_per_cost = 1.0;
  const double h = 1.0 - 3.25 / 25.6, c = 26.0;
  const PointEconomics one = point_economics(c, false, m.costs, m.frame);
  EXPECT_NEAR(one.miss, 10.0 + c, 1e-9);
  EXPECT_EQ(one.samples, 1);
  const PointEconomics four = point_economics(c, false, m.costs, m.frame, 4);
  EXPECT_NEAR(four.miss, 10.0 + c + 3 * 2.0 * c, 1e-9);
  EXPECT_NEAR(four.gain, h * c - 10.0 - (1.0 - h) * (10.0 + 7.0 * c), 1e-9);
  // K = 1: h C 22.7 > 10 + 0.127 x 36 = 14.6: pays. K = 16: 10 + 0.127 x (36 + 30 x 26) = 113.6: does
  // not.
  ASSERT_EQ(plan_cache(g, 1, true, 0.0, &m).points.size(), 1u);
  EXPECT_EQ(plan_cache(g, 1, true, 0.0, &m).points[0].supersample, 1);
  CachePlan plan = plan_cache(g, 1, true, 0.0, &m, CacheSupersample{16, 16});
  EXPECT_TRUE(plan.points.empty());
  EXPECT_NE(reason_for(plan, top).find("K 16 sub-samples"), std::string::npos) << reason_for(plan, top);
  // At 1024 spp it pays again, and the point carries its K.
  m.frame.spp = 1024;
  plan = plan_cache(g, 1, true, 0.0, &m, CacheSupersample{16, 16});
  ASSERT_EQ(plan.points.size(), 1u);
  EXPECT_EQ(plan.points[0].supersample, 16);
}

TEST(CacheCostModel, AutomaticSubSamplesKeepMissesASmallShare) {
  // Lookups per key: (camera lookups in min(spp, K) samples + spp x 0.6
  // later ones) / (1 + 3 (1 - 1/sqrt(spp))), position keys half that; K is
  // the camera-sample limit (16 by default).
  auto by_hand = [](int spp, bool position, int camera) {
    const double lookups = std::min(spp, camera) + spp * 0.6;
    const double per_key =
        lookups / ((1.0 + 3.0 * (1.0 - 1.0 / std::sqrt(double(spp)))) * (position ? 2 : 1));
    int k = 1;
    while (k < 16 && 2 * k <= per_key / 4.0) k *= 2;
    return k;
  };
  for (int camera : {0, 16, 1 << 30})
    for (int spp : {1, 4, 16, 64, 256, 1024, 65536})
      for (bool position : {false, true}) {
        const CacheFrame f{640, 360, spp, 8, camera};
        EXPECT_EQ(auto_supersample(f, position), by_hand(spp, position, camera))
            << spp << " spp, position " << position << ", camera samples " << camera;
      }
  EXPECT_EQ(auto_supersample(CacheFrame{640, 360, 16, 8}, false), 1);   // 7.9 lookups per key
  EXPECT_EQ(auto_supersample(CacheFrame{640, 360, 16, 8}, true), 1);    // 3.9
  EXPECT_EQ(auto_supersample(CacheFrame{640, 360, 256, 8}, false), 8);  // (16 + 153.6) / 3.81 = 44.5
  EXPECT_EQ(auto_supersample(CacheFrame{640, 360, 256, 8}, true), 4);   // 22.3
  const CacheFrame every{640, 360, 256, 8, 256};                        // camera hits in every sample
  EXPECT_EQ(auto_supersample(every, false), 16);                        // 107.5
  EXPECT_EQ(auto_supersample(every, true), 8);                          // 53.7
  EXPECT_EQ(auto_supersample(CacheFrame{640, 360, 65536, 8}, true), 16);
  const CacheSupersample fixed = resolve_supersample(CacheFrame{640, 360, 16, 8}, 4);
  EXPECT_EQ(fixed.uv, 4);
  EXPECT_EQ(fixed.position, 4);
  const CacheSupersample automatic = resolve_supersample(CacheFrame{640, 360, 256, 8}, 0);
  EXPECT_EQ(automatic.uv, 8);
  EXPECT_EQ(automatic.position, 4);
}

}  // namespace
}  // namespace pmc
