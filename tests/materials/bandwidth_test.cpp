// bandwidth_test.cpp — feature sizes and level floors of hand-built graphs
// with known answers (materials/bandwidth.h, materials/cache_plan.h).
//
// Each pattern's smallest feature follows from its definition:
//  - grid, uvtiling 8, thickness 0.1: lines 0.1 / 8 = 0.0125 uv wide;
//  - the same behind place2d with scale 0.5: the coordinate runs twice as
//    fast, 0.00625;
//  - tiledhexagons, uvtiling 2, size 0.9, on uv * (3, 12): the gap between
//    tiles (1 - 0.9) / 2 = 0.05 in the pattern's coordinate, / 12;
//  - fractal2d, 5 octaves, lacunarity 2, diminish 0.5, on uv * 4: the finest
//    octave with at least 1/8 of the first one's amplitude is the fourth,
//    whose noise cells are 1 / 8 wide, features half that: 0.5 / 8 / 4;
//  - noise3d on position * 10: half a lattice cell, 0.05 scene units;
//  - cellnoise2d on floor(uv * 5): cells 1/5;
//  - a faint pattern (grid * 0.05) is below the amplitude threshold; an
//    image has no feature; a grid on a coordinate warped by an image has no
//    bound and says so.
// The floor for feature w with n texels across it is ceil(log2(n / w)).
#include "materials/bandwidth.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/device/pmc_cache.h"
#include "materials/cache_plan.h"
#include "tests/support/graph_builder.h"

namespace pmc {
namespace {

using VT = ValueType;
using test::add;
using test::add_surface;
using test::link;
using test::new_graph;
using test::value;

// The feature of `node` in graph g, with the default amplitude threshold.
double feature_of(const Graph& g, int node) { return node_bandwidths(g)[size_t(node)].feature(); }

TEST(Bandwidth, GridLinesAreThicknessOverTiling) {
  Graph g = new_graph("M");
  int uv = add(g, "uv", "texcoord", VT::Vector2);
  int grid = add(g, "grid", "grid", VT::Color3,
                 {{"texcoord", link(uv)},
                  {"uvtiling", value(VT::Vector2, 8, 8)},
                  {"thickness", value(VT::Float, 0.1f)}});
  add_surface(g, {{"base_color", link(grid)}});
  EXPECT_NEAR(feature_of(g, grid), 0.1 / 8, 1e-6);
}

TEST(Bandwidth, Place2dScaleDividesTheFeature) {
  Graph g = new_graph("M");
  int uv = add(g, "uv", "texcoord", VT::Vector2);
  int placed = add(g, "p", "place2d", VT::Vector2,
                   {{"texcoord", link(uv)}, {"scale", value(VT::Vector2, 0.5f, 0.5f)}});
  int grid = add(g, "grid", "grid", VT::Color3,
                 {{"texcoord", link(placed)},
                  {"uvtiling", value(VT::Vector2, 8, 8)},
                  {"thickness", value(VT::Float, 0.1f)}});
  add_surface(g, {{"base_color", link(grid)}});
  EXPECT_NEAR(feature_of(g, grid), 0.1 / 8 / 2, 1e-6);
}

TEST(Bandwidth, TiledShapeGapOverTilingAndCoordinateScale) {
  Graph g = new_graph("M");
  int uv = add(g, "uv", "texcoord", VT::Vector2);
  int scaled = add(g, "s", "multiply", VT::Vector2, {{"in1", link(uv)}, {"in2", value(VT::Vector2, 3, 12)}});
  int hex = add(
      g, "hex", "tiledhexagons", VT::Color3,
      {{"texcoord", link(scaled)}, {"uvtiling", value(VT::Vector2, 2, 2)}, {"size", value(VT::Float, 0.9f)}});
  add_surface(g, {{"base_color", link(hex)}});
  EXPECT_NEAR(feature_of(g, hex), 0.1 / 2 / 12, 1e-6);
}

TEST(Bandwidth, FractalStopsAtItsLastVisibleOctave) {
  Graph g = new_graph("M");
  int uv = add(g, "uv", "texcoord", VT::Vector2);
  int scaled = add(g, "s", "multiply", VT::Vector2, {{"in1", link(uv)}, {"in2", value(VT::Float, 4)}});
  int f = add(g, "f", "fractal2d", VT::Float,
              {{"texcoord", link(scaled)},
               {"octaves", value(VT::Integer, 5)},
               {"lacunarity", value(VT::Float, 2)},
               {"diminish", value(VT::Float, 0.5f)}});
  add_surface(g, {{"specular_roughness", link(f)}});
  EXPECT_NEAR(feature_of(g, f), 0.5 / 8 / 4, 1e-6);
  // Two octaves: the second one is visible, 0.5 / 2 / 4.
  g.nodes[size_t(f)].input("octaves")->value.f[0] = 2;
  EXPECT_NEAR(feature_of(g, f), 0.5 / 2 / 4, 1e-6);
}

TEST(Bandwidth, Noise3dOnScaledPositionIsInSceneUnits) {
  Graph g = new_graph("M");
  int p = add(g, "p", "position", VT::Vector3);
  int scaled = add(g, "s", "multiply", VT::Vector3, {{"in1", link(p)}, {"in2", value(VT::Float, 10)}});
  int n = add(g, "n", "noise3d", VT::Float, {{"position", link(scaled)}});
  add_surface(g, {{"specular_roughness", link(n)}});
  EXPECT_NEAR(feature_of(g, n), 0.05, 1e-6);
}

TEST(Bandwidth, CellnoiseOnFlooredCoordinate) {
  Graph g = new_graph("M");
  int uv = add(g, "uv", "texcoord", VT::Vector2);
  int scaled = add(g, "s", "multiply", VT::Vector2, {{"in1", link(uv)}, {"in2", value(VT::Float, 5)}});
  int fl = add(g, "fl", "floor", VT::Vector2, {{"in", link(scaled)}});
  int c = add(g, "c", "cellnoise2d", VT::Float, {{"texcoord", link(fl)}});
  add_surface(g, {{"specular_roughness", link(c)}});
  EXPECT_NEAR(feature_of(g, c), 0.2, 1e-6);
}

TEST(Bandwidth, FaintPatternsImagesAndUnboundedCoordinatesGetNoFeature) {
  Graph g = new_graph("M");
  int uv = add(g, "uv", "texcoord", VT::Vector2);
  int grid = add(g, "grid", "grid", VT::Float,
                 {{"texcoord", link(uv)},
                  {"uvtiling", value(VT::Vector2, 8, 8)},
                  {"thickness", value(VT::Float, 0.1f)}});
  int faint = add(g, "faint", "multiply", VT::Float, {{"in1", link(grid)}, {"in2", value(VT::Float, 0.05f)}});
  int strong =
      add(g, "strong", "multiply", VT::Float, {{"in1", link(grid)}, {"in2", value(VT::Float, 0.5f)}});
  int img = add(g, "img", "image", VT::Vector2, {{"texcoord", link(uv)}});
  int warped = add(g, "warped", "add", VT::Vector2, {{"in1", link(uv)}, {"in2", link(img)}});
  int wgrid = add(g, "wgrid", "grid", VT::Float,
                  {{"texcoord", link(warped)}, {"uvtiling", value(VT::Vector2, 8, 8)}});
  add_surface(g, {{"specular_roughness", link(faint)}, {"metalness", link(strong)}, {"coat", link(wgrid)}});
  std::vector<NodeBandwidth> bw = node_bandwidths(g);
  EXPECT_GE(bw[size_t(faint)].feature(), kNoFeature) << "amplitude 0.05 is below the threshold";
  EXPECT_NEAR(bw[size_t(faint)].feature(0.01), 0.0125, 1e-6) << "but it is there";
  EXPECT_NEAR(bw[size_t(strong)].feature(), 0.0125, 1e-6);
  EXPECT_GE(bw[size_t(img)].feature(), kNoFeature) << "images are filtered by their own mip map";
  EXPECT_GE(bw[size_t(wgrid)].feature(), kNoFeature);
  EXPECT_NE(bw[size_t(wgrid)].unbounded.find("wgrid"), std::string::npos) << bw[size_t(wgrid)].unbounded;
}

TEST(Bandwidth, LevelFloorIsCeilLog2OfTexelsOverFeature) {
  EXPECT_EQ(level_floor_for_feature(0.0125, 2, PMC_LEVEL_NO_FLOOR, PMC_LAMBDA_MAX), 8);  // log2(160) = 7.3
  EXPECT_EQ(level_floor_for_feature(0.0125, 1, PMC_LEVEL_NO_FLOOR, PMC_LAMBDA_MAX), 7);  // log2(80) = 6.3
  EXPECT_EQ(level_floor_for_feature(0.25, 2, PMC_LEVEL_NO_FLOOR, PMC_LAMBDA_MAX), 3)
      << "exactly 2^-3: no rounding up";
  EXPECT_EQ(level_floor_for_feature(1e-30, 2, PMC_LEVEL_NO_FLOOR, PMC_LAMBDA_MAX), PMC_LAMBDA_MAX);
  EXPECT_EQ(level_floor_for_feature(1e9, 2, PMC_LEVEL_NO_FLOOR, PMC_LAMBDA_MAX), PMC_LEVEL_NO_FLOOR);
  EXPECT_EQ(level_floor_for_feature(kNoFeature, 2, PMC_LEVEL_NO_FLOOR, PMC_LAMBDA_MAX), PMC_LEVEL_NO_FLOOR);
  EXPECT_EQ(level_floor_for_feature(std::nan(""), 2, PMC_LEVEL_NO_FLOOR, PMC_LAMBDA_MAX), PMC_LEVEL_NO_FLOOR);
  EXPECT_EQ(level_floor_for_feature(0.0125, 0, PMC_LEVEL_NO_FLOOR, PMC_LAMBDA_MAX), PMC_LEVEL_NO_FLOOR);
}

TEST(Bandwidth, PlanGivesEachPointItsFloorAndTheMaterialTheHighest) {
  Graph g = new_graph("M");
  int uv = add(g, "uv", "texcoord", VT::Vector2);
  int grid = add(g, "grid", "grid", VT::Color3,
                 {{"texcoord", link(uv)},
                  {"uvtiling", value(VT::Vector2, 8, 8)},
                  {"thickness", value(VT::Float, 0.1f)}});
  int scaled = add(g, "s", "multiply", VT::Vector2, {{"in1", link(uv)}, {"in2", value(VT::Float, 4)}});
  int noise = add(g, "n", "noise2d", VT::Float, {{"texcoord", link(scaled)}});
  add_surface(g, {{"base_color", link(grid)}, {"specular_roughness", link(noise)}});
  CachePlan plan = plan_cache(g, 1, true, 2.0);
  ASSERT_EQ(plan.points.size(), 2u);
  for (const CachePoint& p : plan.points) {
    if (p.node == grid) EXPECT_EQ(p.level_floor, 8);   // 2 / 0.0125 = 160
    if (p.node == noise) EXPECT_EQ(p.level_floor, 4);  // 2 / 0.125 = 16
  }
  EXPECT_EQ(material_level_floor(plan, CacheKey::Uv), 8);
  EXPECT_EQ(material_level_floor(plan, CacheKey::Position), PMC_LEVEL_NO_FLOOR);
  CachePlan off = plan_cache(g, 1, true, 0.0);
  for (const CachePoint& p : off.points) EXPECT_EQ(p.level_floor, PMC_LEVEL_NO_FLOOR);
  EXPECT_EQ(material_level_floor(off, CacheKey::Uv), PMC_LEVEL_NO_FLOOR);
}

}  // namespace
}  // namespace pmc
