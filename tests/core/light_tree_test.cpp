// light_tree_test.cpp — the light tree (core/light_tree.cpp) and the tree
// sampler's pick (core/device/pmc_lights.h compiled as C++), against
// answers that do not come from the code under test:
//   * the tree's shape: 2n - 1 nodes, every light in exactly one leaf, each
//     light's trail leads to its leaf, a node's box, energy and cones hold
//     its children's;
//   * at random shading points and normals, the pick probabilities of all
//     lights sum to one, and the probability the traversal returns with a
//     light is the one pmc_light_pick_pmf recomputes for MIS (exactly), and
//     the frequencies of many picks follow it (chi-square);
//   * a far stray object changes the power sampler's environment share but
//     not the tree sampler's;
//   * 50k emissive triangles: the build's time and memory (printed).
#include "core/light_tree.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "core/device/pmc_lights.h"
#include "core/lights.h"

namespace pmc {
namespace {

struct Rng {
  std::mt19937 gen;
  explicit Rng(uint32_t seed) : gen(seed) {}
  float next() { return float(gen() >> 8) * (1.0f / 16777216.0f); }
  float range(float lo, float hi) { return lo + (hi - lo) * next(); }
};

float3 random_unit(Rng& r) {
  float z = r.range(-1.0f, 1.0f), phi = r.range(0.0f, 6.2831853f),
        s = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return make_float3(s * std::cos(phi), s * std::sin(phi), z);
}

PmcLightSet light_set(const LightTable& t) {
  PmcLightSet ls;
  ls.lights = t.lights.data();
  ls.tree = t.tree_nodes.data();
  ls.env = t.env_floats();
  ls.h = t.header;
  return ls;
}

// A scene with `triangles` emissive triangles scattered in a 10 m box.
Scene emissive_triangles(int triangles, uint32_t seed) {
  Rng r(seed);
  Scene s;
  for (int i = 0; i < triangles; ++i) {
    float c[3] = {r.range(-5, 5), r.range(-5, 5), r.range(-5, 5)};
    for (int k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) s.positions.push_back(c[a] + r.range(-0.1f, 0.1f));
      s.bounds.extend(&s.positions[s.positions.size() - 3]);
    }
    PmcTriangle t{};
    for (int k = 0; k < 3; ++k) t.v[k] = 3 * i + k, t.n[k] = -1, t.t[k] = -1;
    t.material = i % 2;  // two emissive materials
    s.triangles.push_back(t);
  }
  return s;
}

// Dozens of lights of every finite kind, a sun disk, a directional light and
// a constant sky, plus `triangles` emissive triangles.
LightTable many_lights(int triangles, uint32_t seed) {
  Rng r(seed);
  SceneLights sl;
  for (int i = 0; i < 40; ++i) {
    LightSpec l;
    const int kind = i % 4;
    l.type = kind == 0 ? LightSpec::Type::Point : kind == 1 ? LightSpec::Type::Spot : LightSpec::Type::Quad;
    for (int k = 0; k < 3; ++k) {
      l.position[k] = r.range(-4, 4);
      l.corner[k] = r.range(-4, 4);
      l.rgb[k] = r.range(0.5f, 20.0f);
    }
    float3 d = random_unit(r);
    l.direction[0] = d.x, l.direction[1] = d.y, l.direction[2] = d.z;
    l.cone_angle_deg = r.range(10, 120);
    l.blend = r.range(0, 1);
    float3 u = random_unit(r), v = random_unit(r);
    for (int k = 0; k < 3; ++k) l.edge_u[k] = 0.3f * (&u.x)[k], l.edge_v[k] = 0.5f * (&v.x)[k];
    l.two_sided = kind == 3;
    sl.lights.push_back(l);
  }
  LightSpec sun;
  sun.type = LightSpec::Type::Directional;
  sun.direction[0] = 0.3f, sun.direction[1] = -0.9f, sun.direction[2] = 0.31f;
  sun.rgb[0] = sun.rgb[1] = sun.rgb[2] = 3.0f;
  sun.angle_deg = 2.0f;
  sl.lights.push_back(sun);
  LightSpec dir = sun;
  dir.angle_deg = 0.0f;
  dir.direction[0] = -0.6f, dir.direction[1] = -0.5f, dir.direction[2] = 0.62f;
  sl.lights.push_back(dir);
  const float sky[3] = {0.2f, 0.3f, 0.4f};
  sl.environment = constant_environment(sky);
  return build_light_table(emissive_triangles(triangles, seed + 1), {4.0f, 4.0f, 4.0f, 1.0f, 2.0f, 3.0f}, sl);
}

// Each finite light is one leaf, its trail leads there, and each node holds
// its children: box, energy, one- or two-sidedness, cones.
void expect_a_sound_tree(const LightTable& t) {
  std::vector<int> leaves_of(t.lights.size(), 0);
  for (const PmcLightTreeNode& n : t.tree_nodes)
    if (n.flags & PMC_TREE_LEAF) ++leaves_of[n.second];
  for (int k = 0; k < t.header.count; ++k)
    EXPECT_EQ(leaves_of[size_t(k)], k < t.header.distant_end ? 0 : 1) << k;
  for (int k = t.header.distant_end; k < t.header.count; ++k) {
    const uint64_t trail =
        uint64_t(t.lights[size_t(k)].tree_trail[0]) | (uint64_t(t.lights[size_t(k)].tree_trail[1]) << 32);
    size_t a = 0;
    for (int depth = 0; !(t.tree_nodes[a].flags & PMC_TREE_LEAF); ++depth) {
      ASSERT_LT(depth, kMaxLightTreeDepth);
      a = (trail >> depth) & 1u ? t.tree_nodes[a].second : a + 1;
    }
    EXPECT_EQ(t.tree_nodes[a].second, uint32_t(k));
  }
  // A node holds its children: box, energy, one- or two-sidedness, cones.
  for (size_t a = 0; a < t.tree_nodes.size(); ++a) {
    const PmcLightTreeNode& n = t.tree_nodes[a];
    if (n.flags & PMC_TREE_LEAF) continue;
    for (size_t c : {a + 1, size_t(n.second)}) {
      const PmcLightTreeNode& ch = t.tree_nodes[c];
      for (int k = 0; k < 3; ++k) {
        EXPECT_LE(n.lo[k], ch.lo[k]);
        EXPECT_GE(n.hi[k], ch.hi[k]);
      }
      if (ch.flags & PMC_TREE_TWO_SIDED) EXPECT_TRUE(n.flags & PMC_TREE_TWO_SIDED);
      EXPECT_LE(n.cos_theta_e, ch.cos_theta_e);
      // The child's cone lies inside the parent's: angle(axes) + theta_child <= theta_parent.
      const double pa[3] = {n.axis[0], n.axis[1], n.axis[2]}, ca[3] = {ch.axis[0], ch.axis[1], ch.axis[2]};
      const double cx[3] = {pa[1] * ca[2] - pa[2] * ca[1], pa[2] * ca[0] - pa[0] * ca[2],
                            pa[0] * ca[1] - pa[1] * ca[0]};
      const double axes =
          std::atan2(std::sqrt(cx[0] * cx[0] + cx[1] * cx[1] + cx[2] * cx[2]),
                     pa[0] * ca[0] + pa[1] * ca[1] + pa[2] * ca[2]);  // well conditioned near 0
      if (n.cos_theta_o > -1.0f)
        EXPECT_LE(axes + std::acos(double(ch.cos_theta_o)), std::acos(double(n.cos_theta_o)) + 5e-4)
            << a;  // (a float cosine next to 1 stands for up to 3.5e-4 radians)
    }
    EXPECT_NEAR(n.energy, t.tree_nodes[a + 1].energy + t.tree_nodes[n.second].energy, 1e-5 * n.energy);
  }
}

TEST(LightTree, EveryLightIsOneLeafAndItsTrailLeadsThere) {
  const LightTable t = many_lights(300, 7);
  const int finite = t.header.count - t.header.distant_end;
  ASSERT_EQ(finite, 40 + 300);
  ASSERT_EQ(t.header.tree_nodes, 2 * finite - 1);
  ASSERT_EQ(t.tree_nodes.size(), size_t(2 * finite - 1));
  expect_a_sound_tree(t);
}

TEST(LightTree, PickProbabilitiesSumToOneAndMatchTheRecomputedPmf) {
  const LightTable t = many_lights(200, 11);
  const PmcLightSet ls = light_set(t);
  Rng r(3);
  int checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const float3 p = make_float3(r.range(-6, 6), r.range(-6, 6), r.range(-6, 6)), n = random_unit(r);
    std::vector<double> pmf(t.lights.size());
    double sum = 0.0;
    for (int k = 0; k < t.header.count; ++k) sum += pmf[size_t(k)] = pmc_light_pick_pmf(&ls, p, n, k);
    ASSERT_GT(sum, 0.0);  // the constant sky lights every point
    EXPECT_NEAR(sum, 1.0, 2e-5) << "trial " << trial;
    // Every pick returns the probability recomputed for its light.
    const int picks = trial < 4 ? 400000 : 2000;
    std::vector<double> count(t.lights.size(), 0.0);
    for (int i = 0; i < picks; ++i) {
      float got;
      const float u = (float(i) + r.next()) / float(picks);  // stratified: the test is of the pmf, not of u
      const int k = pmc_light_pick(&ls, p, n, u, &got);
      ASSERT_GE(k, 0);
      ASSERT_EQ(got, float(pmf[size_t(k)])) << "light " << k << " trial " << trial;
      count[size_t(k)] += 1.0;
      ++checked;
    }
    if (trial >= 4) continue;
    // Frequencies against the pmf: chi-square over bins of expected count >= 20.
    double chi2 = 0.0, bin_expected = 0.0, bin_count = 0.0;
    int bins = 0;
    for (size_t k = 0; k < t.lights.size(); ++k) {
      bin_expected += pmf[k] * picks;
      bin_count += count[k];
      if (bin_expected >= 20.0 || k + 1 == t.lights.size()) {
        chi2 += (bin_count - bin_expected) * (bin_count - bin_expected) / std::max(bin_expected, 1e-9);
        ++bins;
        bin_expected = bin_count = 0.0;
      }
    }
    const double dof = bins - 1;
    EXPECT_LT(chi2, dof + 6.0 * std::sqrt(2.0 * dof)) << "trial " << trial << ", " << bins << " bins";
  }
  EXPECT_GT(checked, 1000000);
}

TEST(LightTree, LightsBehindTheSurfaceAreNeverPicked) {
  // A quad 1 m above a point, facing down; the normal points away from it.
  SceneLights sl;
  LightSpec q;
  q.type = LightSpec::Type::Quad;
  q.corner[0] = -0.5f, q.corner[1] = 1.0f, q.corner[2] = -0.5f;
  q.edge_u[0] = 1.0f, q.edge_u[1] = 0.0f, q.edge_u[2] = 0.0f;
  q.edge_v[0] = 0.0f, q.edge_v[1] = 0.0f, q.edge_v[2] = 1.0f;  // u x v = -y: faces down
  q.rgb[0] = q.rgb[1] = q.rgb[2] = 1.0f;
  LightSpec point;
  point.type = LightSpec::Type::Point;
  point.position[1] = -2.0f;
  point.rgb[0] = point.rgb[1] = point.rgb[2] = 1.0f;
  sl.lights = {q, point};
  Scene empty;
  const LightTable t = build_light_table(empty, {}, sl);
  const PmcLightSet ls = light_set(t);
  const float3 p = make_float3(0, 0, 0);
  EXPECT_EQ(pmc_light_pick_pmf(&ls, p, make_float3(0, 1, 0), 1), 0.0f) << "the point light is below";
  EXPECT_EQ(pmc_light_pick_pmf(&ls, p, make_float3(0, 1, 0), 0), 1.0f);
  EXPECT_EQ(pmc_light_pick_pmf(&ls, p, make_float3(0, -1, 0), 0), 0.0f) << "the quad is above";
  // Seen from above its back, the one-sided quad gives nothing.
  EXPECT_EQ(pmc_light_pick_pmf(&ls, make_float3(0, 3, 0), make_float3(0, -1, 0), 0), 0.0f);
}

TEST(LightTree, PointsJustBehindAOneSidedQuadDoNotPickIt) {
  // The Cornell box's set-up: a 1.3 x 1.05 quad light 0.8 cm under the
  // ceiling, facing down, and a point light in the room. Ceiling points
  // beside the quad (inside its bounding sphere, so theta_b says nothing)
  // are behind it: every pick of the quad there carries nothing.
  SceneLights sl;
  LightSpec q;
  q.type = LightSpec::Type::Quad;
  q.corner[0] = 2.13f, q.corner[1] = 5.48f, q.corner[2] = 2.27f;
  q.edge_u[0] = 1.3f;
  q.edge_v[2] = 1.05f;  // u x v = -y: faces down
  q.rgb[0] = q.rgb[1] = q.rgb[2] = 20.0f;
  LightSpec point;
  point.type = LightSpec::Type::Point;
  point.position[0] = 2.13f, point.position[1] = 3.0f, point.position[2] = 2.27f;
  point.rgb[0] = point.rgb[1] = point.rgb[2] = 4.0f;
  sl.lights = {q, point};
  Scene empty;
  const LightTable t = build_light_table(empty, {}, sl);
  const PmcLightSet ls = light_set(t);
  const float3 down = make_float3(0, -1, 0);
  for (float x : {0.0f, 1.0f, 2.0f, 2.7f, 3.6f, 4.5f, 5.56f}) {
    const float3 ceiling = make_float3(x, 5.488f, x < 1.0f ? 0.0f : 1.9f);
    EXPECT_EQ(pmc_light_pick_pmf(&ls, ceiling, down, 0), 0.0f) << "x " << x;
    EXPECT_EQ(pmc_light_pick_pmf(&ls, ceiling, down, 1), 1.0f) << "x " << x;
  }
  // A hair below the quad's plane, it lights the point again.
  EXPECT_GT(pmc_light_pick_pmf(&ls, make_float3(2.0f, 5.47f, 1.9f), make_float3(1, 0, 0), 0), 0.0f);
}

TEST(LightTree, EveryLightThatCanLightAPointMayBePicked) {
  // At random points and normals, every quad or emissive triangle with a
  // point e that faces p (its normal . (p - e) > 0) above p's plane has a
  // pick probability above 0: the one-sided bounds never cut a light that
  // gives something.
  const LightTable t = many_lights(300, 11);
  const PmcLightSet ls = light_set(t);
  Rng r(5);
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const float3 p = make_float3(r.range(-5, 5), r.range(-5, 5), r.range(-5, 5));
    const float3 n = random_unit(r);
    for (int k = 0; k < ls.h.count; ++k) {
      const PmcLight& l = ls.lights[k];
      if (l.type != PMC_LIGHT_QUAD && l.type != PMC_LIGHT_TRIANGLE) continue;
      const float u = r.next(), v = r.next();
      const float a = l.type == PMC_LIGHT_TRIANGLE && u + v > 1.0f ? 1.0f - u : u;
      const float b = l.type == PMC_LIGHT_TRIANGLE && u + v > 1.0f ? 1.0f - v : v;
      const float3 e = pmc_load3(l.pos) + pmc_load3(l.axis) * a + pmc_load3(l.edge_v) * b;
      const float3 ln = pmc_load3(l.normal);
      const bool faces = (l.flags & PMC_LIGHT_TWO_SIDED) || dot(ln, p - e) > 0.0f;
      if (!faces || !(dot(n, e - p) > 0.0f)) continue;
      ++checked;
      EXPECT_GT(pmc_light_pick_pmf(&ls, p, n, k), 0.0f) << "light " << k << " trial " << trial;
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(LightTree, EnvironmentShareIgnoresAFarStrayObject) {
  SceneLights sl;
  LightSpec q;
  q.type = LightSpec::Type::Quad;
  q.corner[0] = -0.5f, q.corner[1] = 2.0f, q.corner[2] = -0.5f;
  q.edge_u[0] = 1.0f, q.edge_v[2] = 1.0f, q.edge_u[2] = 0.0f, q.edge_v[0] = 0.0f;
  q.two_sided = true;
  q.rgb[0] = q.rgb[1] = q.rgb[2] = 5.0f;
  sl.lights = {q};
  const float sky[3] = {0.5f, 0.5f, 0.5f};
  sl.environment = constant_environment(sky);
  Scene room;  // a 4 m room
  float lo[3] = {-2, 0, -2}, hi[3] = {2, 3, 2};
  room.bounds.extend(lo);
  room.bounds.extend(hi);
  Scene stray = room;  // ... and one object 18 m above it
  float far[3] = {0, 21, 0};
  stray.bounds.extend(far);
  const float3 p = make_float3(0.3f, 0.0f, -0.2f), n = make_float3(0, 1, 0);
  float env_share[2][2];  // [sampler][scene]
  for (int s = 0; s < 2; ++s) {
    const LightSampler sampler = s == 0 ? LightSampler::Tree : LightSampler::Power;
    for (int c = 0; c < 2; ++c) {
      const LightTable t = build_light_table(c == 0 ? room : stray, {}, sl, sampler);
      ASSERT_EQ(t.lights[0].type, PMC_LIGHT_ENV);
      const PmcLightSet ls = light_set(t);
      env_share[s][c] = pmc_light_pick_pmf(&ls, p, n, 0);
    }
  }
  EXPECT_EQ(env_share[0][0], env_share[0][1]) << "tree sampler";
  EXPECT_LT(1.0f - env_share[1][1], 0.2f * (1.0f - env_share[1][0]))
      << "the power sampler gives the environment most of what the quad had";
  std::printf("environment share, room / with a stray object: tree %.3f / %.3f, power %.3f / %.3f\n",
              env_share[0][0], env_share[0][1], env_share[1][0], env_share[1][1]);
}

TEST(LightTree, FiftyThousandEmissiveTrianglesBuildQuickly) {
  const Scene scene = emissive_triangles(50000, 5);
  const std::vector<float> emission = {4.0f, 4.0f, 4.0f, 1.0f, 2.0f, 3.0f};
  const auto start = std::chrono::steady_clock::now();
  const LightTable t = build_light_table(scene, emission, SceneLights{});
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(t.header.count, 50000);
  ASSERT_EQ(t.tree_nodes.size(), 99999u);
  EXPECT_LE(t.tree_depth, kMaxLightTreeDepth - 1);
  std::printf(
      "light tree over 50000 emissive triangles: build %.3f s (whole table %.3f s), depth %d, "
      "%.1f MB of nodes + %.1f MB of lights\n",
      t.tree_build_seconds, total, t.tree_depth, double(t.tree_nodes.size() * sizeof(PmcLightTreeNode)) / 1e6,
      double(t.lights.size() * sizeof(PmcLight)) / 1e6);
  RecordProperty("build_seconds", std::to_string(t.tree_build_seconds));
  const PmcLightSet ls = light_set(t);
  Rng r(9);
  for (int trial = 0; trial < 3; ++trial) {
    const float3 p = make_float3(r.range(-5, 5), r.range(-5, 5), r.range(-5, 5)), n = random_unit(r);
    double sum = 0.0;
    for (int k = 0; k < t.header.count; ++k) sum += pmc_light_pick_pmf(&ls, p, n, k);
    EXPECT_NEAR(sum, 1.0, 1e-4) << trial;
  }
  // What a pick and a recomputation cost on the host (printed, not checked: the machine is shared).
  const int picks = 100000;
  std::vector<float3> points(64), normals(64);
  for (int i = 0; i < 64; ++i)
    points[size_t(i)] = make_float3(r.range(-5, 5), r.range(-5, 5), r.range(-5, 5)),
    normals[size_t(i)] = random_unit(r);
  double checksum = 0.0;
  const auto pick_start = std::chrono::steady_clock::now();
  for (int i = 0; i < picks; ++i) {
    float pmf;
    const int k = pmc_light_pick(&ls, points[size_t(i & 63)], normals[size_t(i & 63)], r.next(), &pmf);
    checksum += k >= 0 ? pmf : 0.0f;
  }
  const double pick_ns =
      1e9 * std::chrono::duration<double>(std::chrono::steady_clock::now() - pick_start).count() / picks;
  EXPECT_GT(checksum, 0.0);
  std::printf("a pick from 50000 triangles: %.0f ns on this host (depth %d)\n", pick_ns, t.tree_depth);
}

}  // namespace
}  // namespace pmc

namespace pmc {
namespace {

// Large subtrees build on TBB's workers into slots fixed in advance: the
// nodes and trails must be those one thread builds, byte for byte.
TEST(LightTree, ParallelBuildIsTheOneThreadsTree) {
  const LightTable parallel =
      build_light_table(emissive_triangles(20000, 11), {4.0f, 4.0f, 4.0f}, SceneLights{});
  LightTable serial;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    serial = build_light_table(emissive_triangles(20000, 11), {4.0f, 4.0f, 4.0f}, SceneLights{});
  }
  ASSERT_EQ(parallel.tree_nodes.size(), serial.tree_nodes.size());
  ASSERT_EQ(parallel.tree_nodes.size(), 2u * 20000u - 1u);
  EXPECT_EQ(parallel.tree_depth, serial.tree_depth);
  EXPECT_EQ(0, std::memcmp(parallel.tree_nodes.data(), serial.tree_nodes.data(),
                           serial.tree_nodes.size() * sizeof(PmcLightTreeNode)));
  expect_a_sound_tree(parallel);  // the one thread's tree could share a slotting error
  ASSERT_EQ(parallel.lights.size(), serial.lights.size());
  for (size_t k = 0; k < serial.lights.size(); ++k) {
    EXPECT_EQ(parallel.lights[k].tree_trail[0], serial.lights[k].tree_trail[0]) << k;
    EXPECT_EQ(parallel.lights[k].tree_trail[1], serial.lights[k].tree_trail[1]) << k;
  }
}

}  // namespace
}  // namespace pmc
