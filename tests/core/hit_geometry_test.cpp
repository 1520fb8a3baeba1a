// hit_geometry_test.cpp — a ray hit's geometry from its triangle
// (core/device/pmc_hit_geometry.h, the scalar form; the shade kernel's float8
// form must equal it bit for bit, which tests/gpu/shade_lanes_test.cpp checks
// through whole images).
//
// Against a double-precision reading of the same definitions, on random
// triangles and rays with and without vertex normals and uvs:
//  * the point is the barycentric combination of the corners, and the scale
//    of its ray offsets the corners' largest |coordinate|;
//  * the geometric normal is the unit winding normal turned against the ray,
//    twice the area its length, and the edges are the corners' differences;
//  * the shading normal is the interpolated vertex normal, on the geometric
//    normal's side, unless it faces away from the viewer (then the geometric
//    one); "front" says whether the ray met the side the normals point to;
//  * the uv is the corners' uvs combined (the barycentrics without uvs);
//  * the tangent is unit, orthogonal to the shading normal, and along dp/du
//    where the uvs give one;
//  * with the mesh's smooth tangents (PMC_TRI_TANGENTS: the corners'
//    octahedral words, as the shade kernel loads them), the tangent is their
//    barycentric combination orthogonalised to the shading normal, and equals
//    pmc_oct_decode's vectors so combined in single precision;
// and a triangle without area gives the reversed ray as its normal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/device/pmc_hit_geometry.h"
#include "core/device/pmc_octahedral.h"

namespace pmc {
namespace {

struct V {
  double x, y, z;
};
V operator+(V a, V b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V operator-(V a, V b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V operator*(V a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(V a, V b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V cross(V a, V b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double len(V a) { return std::sqrt(dot(a, a)); }
V unit(V a) { return a * (1.0 / len(a)); }

struct Case {
  V p[3], n[3], dir;
  double t[3][2];
  double b1, b2;
  bool normals, uvs;
};

V random_unit(std::mt19937& g) {
  std::normal_distribution<double> nd;
  return unit({nd(g), nd(g), nd(g)});
}

// A random triangle, ray and barycentrics; every other one with vertex normals.
Case random_case(std::mt19937& g, int i) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), w(0.0, 1.0);
  Case c;
  for (int j = 0; j < 3; ++j) {
    c.p[j] = {3 * u(g), 3 * u(g), 3 * u(g)};
    c.n[j] = random_unit(g);
    c.t[j][0] = 2 * u(g), c.t[j][1] = 2 * u(g);
  }
  c.dir = random_unit(g);
  c.b1 = w(g), c.b2 = w(g) * (1 - c.b1);
  c.normals = i % 2 == 0;
  return c;
}

void load(const Case& c, PmcHitLanes& L) {
  const int k = 0;
  pmc_hit_lane_clear(&L, k);
  L.dx[k] = float(c.dir.x), L.dy[k] = float(c.dir.y), L.dz[k] = float(c.dir.z);
  L.b1[k] = float(c.b1), L.b2[k] = float(c.b2);
  float* p[3][3] = {{L.p0x, L.p0y, L.p0z}, {L.p1x, L.p1y, L.p1z}, {L.p2x, L.p2y, L.p2z}};
  float* n[3][3] = {{L.n0x, L.n0y, L.n0z}, {L.n1x, L.n1y, L.n1z}, {L.n2x, L.n2y, L.n2z}};
  float* t[3][2] = {{L.t0u, L.t0v}, {L.t1u, L.t1v}, {L.t2u, L.t2v}};
  const double identity[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  for (int i = 0; i < 3; ++i) {
    p[i][0][k] = float(c.p[i].x), p[i][1][k] = float(c.p[i].y), p[i][2][k] = float(c.p[i].z);
    if (c.normals) n[i][0][k] = float(c.n[i].x), n[i][1][k] = float(c.n[i].y), n[i][2][k] = float(c.n[i].z);
    for (int j = 0; j < 2; ++j) t[i][j][k] = float(c.uvs ? c.t[i][j] : identity[i][j]);
  }
  L.normals[k] = c.normals ? -1 : 0;
  L.uvs[k] = c.uvs ? -1 : 0;
}

TEST(HitGeometry, MatchesTheDefinitionsInDoublePrecision) {
  std::mt19937 g(7);
  int smooth_seen = 0, tangents_seen = 0;
  for (int i = 0; i < 4000; ++i) {
    Case c = random_case(g, i);
    c.uvs = i % 3 != 0;
    PmcHitLanes L;
    load(c, L);
    pmc_hit_geometry_at(&L, 0);
    SCOPED_TRACE(i);

    const double b0 = 1 - c.b1 - c.b2;
    const V pos = c.p[0] * b0 + c.p[1] * c.b1 + c.p[2] * c.b2;
    EXPECT_NEAR(L.px[0], pos.x, 1e-5);
    EXPECT_NEAR(L.py[0], pos.y, 1e-5);
    EXPECT_NEAR(L.pz[0], pos.z, 1e-5);
    float scale = 0.0f;  // the largest |coordinate| of the corners
    for (int j = 0; j < 3; ++j)
      scale = std::max(
          {scale, std::fabs(float(c.p[j].x)), std::fabs(float(c.p[j].y)), std::fabs(float(c.p[j].z))});
    EXPECT_EQ(L.scale[0], scale);
    const V e1 = c.p[1] - c.p[0], e2 = c.p[2] - c.p[0];
    EXPECT_NEAR(L.e1x[0], e1.x, 1e-6);
    EXPECT_NEAR(L.e2z[0], e2.z, 1e-6);
    const V winding = cross(e1, e2);
    EXPECT_NEAR(L.area2[0], len(winding), 1e-4 * len(winding));
    V ng = unit(winding);
    const bool winding_front = dot(ng, c.dir) <= 0;
    if (dot(ng, c.dir) > 0) ng = ng * -1.0;
    const V got_ng = {L.nx[0], L.ny[0], L.nz[0]};
    EXPECT_GT(dot(got_ng, ng), 1 - 1e-6);

    V ns = ng;
    bool front = winding_front;
    if (c.normals) {
      const V n = unit(c.n[0] * b0 + c.n[1] * c.b1 + c.n[2] * c.b2);
      front = dot(n, c.dir) <= 0;
      ns = dot(n, ng) < 0 ? n * -1.0 : n;
    }
    if (dot(ns, c.dir * -1.0) <= 0) ns = ng;
    smooth_seen += c.normals && dot(ns, ng) < 0.999;
    const V got_ns = {L.sx[0], L.sy[0], L.sz[0]};
    EXPECT_GT(dot(got_ns, ns), 1 - 1e-5);
    // a ray that grazes the surface may round either way
    if (std::fabs(dot(c.normals ? ns : ng, c.dir)) > 1e-4) EXPECT_EQ(L.front[0] != 0, front);

    const double tu = c.uvs ? c.t[0][0] * b0 + c.t[1][0] * c.b1 + c.t[2][0] * c.b2 : c.b1;
    const double tv = c.uvs ? c.t[0][1] * b0 + c.t[1][1] * c.b1 + c.t[2][1] * c.b2 : c.b2;
    EXPECT_NEAR(L.u[0], tu, 1e-5);
    EXPECT_NEAR(L.v[0], tv, 1e-5);

    const V tangent = {L.tx[0], L.ty[0], L.tz[0]};
    EXPECT_NEAR(len(tangent), 1.0, 1e-5);
    EXPECT_NEAR(dot(tangent, got_ns), 0.0, 1e-5);
    // dp/du: dp = e1 du1 + e2 du2 with du = (d1, d2) solved for a unit step in u
    const double d1u = c.uvs ? c.t[1][0] - c.t[0][0] : 1, d1v = c.uvs ? c.t[1][1] - c.t[0][1] : 0;
    const double d2u = c.uvs ? c.t[2][0] - c.t[0][0] : 0, d2v = c.uvs ? c.t[2][1] - c.t[0][1] : 1;
    const double det = d1u * d2v - d1v * d2u;
    V dpdu = (e1 * d2v - e2 * d1v) * (1.0 / det);
    dpdu = dpdu - got_ns * dot(got_ns, dpdu);
    if (std::fabs(det) > 1e-3 && len(dpdu) > 1e-3) {
      EXPECT_GT(dot(tangent, unit(dpdu)), 1 - 1e-4);
      ++tangents_seen;
    }
  }
  EXPECT_GT(smooth_seen, 100);
  EXPECT_GT(tangents_seen, 3000);
}

// The corners' tangents as the shade kernel loads them (pmc_hit_load).
void load_tangents(const pmc_u32 words[3], PmcHitLanes& L) {
  float* o[3][2] = {{L.o0x, L.o0y}, {L.o1x, L.o1y}, {L.o2x, L.o2y}};
  for (int i = 0; i < 3; ++i) o[i][0][0] = pmc_snorm16(words[i]), o[i][1][0] = pmc_snorm16(words[i] >> 16);
  L.tangents[0] = -1;
}

TEST(HitGeometry, SmoothTangentsAreTheCornersCombinedAndOrthogonalised) {
  std::mt19937 g(11);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    Case c = random_case(g, i);
    c.uvs = true;
    pmc_u32 words[3];
    V corner[3];
    const V base = random_unit(g);  // corners near one direction, as a smooth mesh's are
    for (int j = 0; j < 3; ++j) {
      const V t = unit(base + random_unit(g) * 0.3);
      words[j] = pmc_oct_encode(make_float3(float(t.x), float(t.y), float(t.z)));
      const float3 d = pmc_oct_decode(words[j]);
      corner[j] = {d.x, d.y, d.z};
    }
    PmcHitLanes L;
    load(c, L);
    load_tangents(words, L);
    pmc_hit_geometry_at(&L, 0);
    SCOPED_TRACE(i);
    const V ns = {L.sx[0], L.sy[0], L.sz[0]};
    const double b0 = 1 - c.b1 - c.b2;
    V t = corner[0] * b0 + corner[1] * c.b1 + corner[2] * c.b2;
    t = t - ns * dot(ns, t);
    if (len(t) < 1e-3) continue;  // too short to say which way it points
    const V got = {L.tx[0], L.ty[0], L.tz[0]};
    EXPECT_NEAR(len(got), 1.0, 1e-5);
    EXPECT_NEAR(dot(got, ns), 0.0, 1e-5);
    EXPECT_GT(dot(got, unit(t)), 1 - 1e-5);
    ++checked;
  }
  EXPECT_GT(checked, 1900);
}

TEST(HitGeometry, NoSmoothTangentsWithoutTheFlag) {
  Case c{};
  c.p[0] = {0, 0, 0}, c.p[1] = {1, 0, 0}, c.p[2] = {0, 1, 0};
  c.t[1][0] = 1, c.t[2][1] = 1;  // dp/du = x
  c.uvs = true;
  c.dir = unit({0.1, 0.2, -1});
  c.b1 = 0.2, c.b2 = 0.3;
  const pmc_u32 y = pmc_oct_encode(make_float3(0, 1, 0));
  const pmc_u32 words[3] = {y, y, y};
  PmcHitLanes L;
  load(c, L);
  load_tangents(words, L);
  L.tangents[0] = 0;  // the words are there, the flag is not
  pmc_hit_geometry_at(&L, 0);
  EXPECT_NEAR(L.tx[0], 1.0f, 1e-6);
  load_tangents(words, L);  // with the flag: the corners' y
  pmc_hit_geometry_at(&L, 0);
  EXPECT_NEAR(L.ty[0], 1.0f, 1e-4);
}

TEST(HitGeometry, ATriangleWithoutAreaFacesTheRay) {
  Case c{};
  c.p[0] = {1, 2, 3}, c.p[1] = {2, 4, 6}, c.p[2] = {3, 6, 9};  // on one line
  c.dir = unit({0.3, -0.4, 0.5});
  c.b1 = 0.25, c.b2 = 0.25;
  PmcHitLanes L;
  load(c, L);
  pmc_hit_geometry_at(&L, 0);
  EXPECT_EQ(L.area2[0], 0.0f);
  EXPECT_FLOAT_EQ(L.nx[0], float(-c.dir.x));
  EXPECT_FLOAT_EQ(L.ny[0], float(-c.dir.y));
  EXPECT_FLOAT_EQ(L.nz[0], float(-c.dir.z));
  const V tangent = {L.tx[0], L.ty[0], L.tz[0]};
  EXPECT_NEAR(len(tangent), 1.0, 1e-6);  // any tangent, but a unit one
  EXPECT_NEAR(dot(tangent, {L.sx[0], L.sy[0], L.sz[0]}), 0.0, 1e-6);
}

}  // namespace
}  // namespace pmc
