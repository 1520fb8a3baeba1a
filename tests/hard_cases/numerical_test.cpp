// numerical_test.cpp — numerically hostile scenes must render without NaN/Inf.
//
// Every render here checks the image (no NaN/Inf), RenderStats::nan_pixels
// and bad_samples (no path sample dropped as non-finite) — with the
// progressive material cache off AND on wherever a material network is
// involved (an MTL texture chain, a MaterialX noise network, a MaterialX
// tiledimage network). Cases:
//  * grazing angles: camera rays nearly parallel to a huge plane; paths that
//    bounce at cos -> 0 between two close mirrors; and the footprint / cache
//    level functions (pmc_ray_cone_gradients, pmc_cache_lambda,
//    pmc_cache_texel) called directly at and past grazing;
//  * degenerate and zero-area triangles (collinear, repeated vertices,
//    slivers) and zero-area / collinear uv triangles;
//  * uvs of magnitude 1e7 and negative uvs;
//  * NaN and Inf in vertex data: a triangle with a non-finite position is
//    skipped, counted in Scene::skipped_triangles and reported in ONE
//    warning with the count (checked through the binary); non-finite normals
//    and uvs are repaired to 0;
//  * NaN/Inf texels in a float EXR texture (they load as black);
//  * emitters of radiance 1e6 (an MTL Ke and a procedural MaterialX emitter
//    whose values the cache cannot encode);
//  * one scene scaled from 1e-4 to 1e5 (same image mean within a bound
//    derived below);
//  * the camera inside a closed mesh (no light may leak in);
//  * the maximum path depth reached by every path (closed box, albedo 1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/device/pmc_cache.h"
#include "core/device/pmc_geometry.h"
#include "core/device/pmc_raycone.h"
#include "core/obj_loader.h"
#include "tests/hard_cases/hard_support.h"

namespace pmc {
namespace {

using hard::ObjText;
using hard::RenderCase;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The MTL library most scenes here use. `tex` is an MTL texture chain; the
// M_* entries only give usemtl names that the MaterialX document binds.
std::string scene_mtl(const std::string& texture = "checker.png") {
  return "newmtl tex\nKd 1 1 1\nmap_Kd " + texture +
         "\n"
         "newmtl grey\nKd 0.5 0.5 0.5\nKs 0 0 0\n"
         "newmtl white\nKd 1 1 1\nKs 0 0 0\n"
         "newmtl lamp\nKd 0 0 0\nKe 1000000 1000000 1000000\n"
         "newmtl mirror\nKd 0.95 0.95 0.95\nPm 1\nPr 0\n"  // a smooth metal (docs/MTL.md)
         "newmtl M_noise\nKd 0.5 0.5 0.5\nnewmtl M_tiled\nKd 0.5 0.5 0.5\nnewmtl M_bright\nKd 0.5 0.5 0.5\n";
}

// Writes checker.png, materials.mtlx (tiledimage of `image`) and scene.mtl into `dir`.
void write_materials(const std::string& dir, const std::string& image = "checker.png") {
  hard::write_checker_png(dir + "/checker.png");
  test::write_file(dir + "/materials.mtlx", hard::materials_mtlx(image));
  test::write_file(dir + "/scene.mtl", scene_mtl(image));
}

// The three material networks each "materials involved" case renders with:
// the OBJ's own MTL texture chain (usemtl tex), MaterialX noise, MaterialX tiledimage.
std::vector<RenderCase> material_variants(const std::string& obj, const std::string& dir) {
  const std::string mtlx = dir + "/materials.mtlx";
  return {RenderCase{obj, {}, ""}, RenderCase{obj, {mtlx}, "M_noise"}, RenderCase{obj, {mtlx}, "M_tiled"}};
}

std::string label(const RenderCase& c, bool cache) {
  return (c.material.empty() ? std::string("MTL map_Kd") : c.material) +
         (cache ? ", cache on" : ", cache off");
}

// Renders every variant with the cache off and on; all must be clean. The
// cache must actually be exercised: lookups (or, past the level floors'
// refinement limit, bypassed points) happen when it is on.
void render_all_clean(const std::vector<RenderCase>& cases, const RenderConfig& s,
                      bool expect_lookups = true) {
  for (const RenderCase& c : cases)
    for (bool cache : {false, true}) {
      SCOPED_TRACE(label(c, cache));
      hard::Rendered r;
      ASSERT_NO_THROW(r = hard::render(c, s, cache));
      hard::expect_clean(r.out, label(c, cache));
      if (cache && expect_lookups) {
        EXPECT_GT(r.cache_points, 0u) << "the network has no cache point: the cache path is not tested";
        EXPECT_GT(r.out.stats.cache.lookups + r.out.stats.cache.bypassed, 0u);
        EXPECT_LE(r.out.stats.cache.hits, r.out.stats.cache.lookups);
      }
    }
}

// ---------------------------------------------------------------- grazing

TEST(Numerical, CameraRaysNearlyParallelToAHugePlane) {
  const std::string dir = test::temp_dir();
  write_materials(dir);
  // A 2000 x 2000 plane at y = 0 whose uvs follow the position (so they reach
  // +-1000); the camera 1 mm above it looks along the horizon: the lower half
  // of the image hits the plane at angles down to ~1e-5 rad.
  ObjText o;
  o.line("mtllib scene.mtl\nusemtl tex");
  const double p[4][3] = {{-1000, 0, 1000}, {1000, 0, 1000}, {1000, 0, -1000}, {-1000, 0, -1000}};
  o.quad(p, -1000, -1000, 1000, 1000);
  test::write_file(dir + "/plane.obj", o.str());
  RenderConfig s = hard::small_config(48, 32, 4, 4);
  hard::set_camera(s, 0, 1e-3, 0, 1, 1e-3, 0.05, 60.0f);
  s.env[0] = s.env[1] = s.env[2] = 1.0f;
  render_all_clean(material_variants(dir + "/plane.obj", dir), s);
}

TEST(Numerical, PathsBouncingAtGrazingAnglesBetweenTwoMirrors) {
  const std::string dir = test::temp_dir();
  write_materials(dir);
  // Two near-perfect mirrors 1 cm apart and 2 km long; the camera between
  // them looks along them, so its rays reflect at cos ~ 1e-3 .. 1e-6 many
  // times (up to the depth limit) and sampled directions come out at cos -> 0.
  ObjText o;
  o.line("mtllib scene.mtl\nusemtl mirror");
  const double lo[4][3] = {{-1000, 0, 1}, {1000, 0, 1}, {1000, 0, -1}, {-1000, 0, -1}};
  const double hi[4][3] = {{-1000, 0.01, -1}, {1000, 0.01, -1}, {1000, 0.01, 1}, {-1000, 0.01, 1}};
  o.quad(lo, 0, 0, 1e3, 1);
  o.quad(hi, 0, 0, 1e3, 1);
  o.line("usemtl tex");  // a textured end wall the grazing paths can reach
  const double end[4][3] = {{1000, -1, -1}, {1000, -1, 1}, {1000, 1, 1}, {1000, 1, -1}};
  o.quad(end);
  test::write_file(dir + "/slab.obj", o.str());
  RenderConfig s = hard::small_config(32, 24, 4, 12);
  hard::set_camera(s, -999, 0.005, 0, 0, 0.005, 0, 30.0f);
  s.env[0] = s.env[1] = s.env[2] = 1.0f;
  // The mirrors have no network; the end wall's texture chain is cached.
  render_all_clean({RenderCase{dir + "/slab.obj", {}, ""}}, s, false);
  // The same with a MaterialX network on every surface (glossy standard_surface).
  const std::string mtlx = dir + "/materials.mtlx";
  render_all_clean({RenderCase{dir + "/slab.obj", {mtlx}, "M_noise"}}, s);
}

// Footprint gradients and the cache level at and past grazing, for rays
// descending onto the plane y = 0 at angle eps (radians), exactly in-plane,
// along the normal, and with a NaN direction.
TEST(Numerical, RayConeGradientsAndCacheLevelStayFiniteAtGrazing) {
  const float3 ng = make_float3(0, 1, 0);
  const float3 p0 = make_float3(0, 0, 0), p1 = make_float3(1, 0, 0), p2 = make_float3(0, 0, 1);
  const float2 t0 = make_float2(0, 0), t1 = make_float2(1, 0), t2 = make_float2(0, 1);
  std::vector<float3> dirs;
  for (float eps : {0.5f, 1e-2f, 1e-4f, 1e-6f, 1e-8f, 1e-20f, 1e-40f, 0.0f, -0.0f, -1e-7f}) {
    float3 d = make_float3(std::cos(eps), -std::sin(eps), 0.0f);
    dirs.push_back(d);
    dirs.push_back(make_float3(d.x * 0.6f, d.y, d.x * 0.8f));  // diagonal in the plane
  }
  dirs.push_back(make_float3(0, -1, 0));  // along the normal
  dirs.push_back(make_float3(kNaN, kNaN, kNaN));
  for (float radius : {1e-30f, 1e-6f, 1e-2f, 1.0f, 1e6f, 1e30f}) {
    for (const float3& dir : dirs) {
      SCOPED_TRACE("dir (" + std::to_string(dir.x) + ", " + std::to_string(dir.y) + ", " +
                   std::to_string(dir.z) + ") radius " + std::to_string(radius));
      float2 g1, g2;
      pmc_ray_cone_gradients(dir, ng, radius, p0, p1, p2, t0, t1, t2, &g1, &g2);
      for (float c : {g1.x, g1.y, g2.x, g2.y}) ASSERT_TRUE(std::isfinite(c)) << c;
      // The projection is clamped at 1e-4: a footprint is at most radius / 1e-4
      // long (this triangle maps positions to uvs 1:1), plus rounding.
      const float bound = radius / 1e-4f * 1.001f;
      EXPECT_LE(std::hypot(g1.x, g1.y), bound);
      EXPECT_LE(std::hypot(g2.x, g2.y), bound);
      for (float bias : {0.0f, -32.0f, 32.0f, kNaN, kInf, -kInf}) {
        int lambda = pmc_cache_lambda(g1, g2, bias);
        EXPECT_GE(lambda, PMC_LAMBDA_MIN);
        EXPECT_LE(lambda, PMC_LAMBDA_MAX);
      }
      // A grazing footprint is long along one axis only: the level follows
      // the short axis (the finer level), so it never gets coarser than the
      // isotropic level of the same cone.
      if (std::isfinite(dir.x) && radius >= 1e-6f && radius <= 1.0f)
        EXPECT_GE(pmc_cache_lambda(g1, g2, 0.0f), int(std::floor(-std::log2(radius))) - 1);
    }
  }
  // Non-finite, zero, denormal and huge gradients go straight to the level function.
  const float vals[] = {0.0f, 1e-45f, 1e-30f, 1.0f, 1e30f, 3e38f, kInf, kNaN};
  for (float a : vals)
    for (float b : vals) {
      int lambda = pmc_cache_lambda(make_float2(a, 0), make_float2(0, b), 0.0f);
      EXPECT_GE(lambda, PMC_LAMBDA_MIN) << a << " " << b;
      EXPECT_LE(lambda, PMC_LAMBDA_MAX) << a << " " << b;
    }
  // Degenerate footprints take the finest level (documented in pmc_cache.h).
  EXPECT_EQ(pmc_cache_lambda(make_float2(0, 0), make_float2(0, 0), 0.0f), PMC_LAMBDA_MAX);
  EXPECT_EQ(pmc_cache_lambda(make_float2(kNaN, 0), make_float2(0, kNaN), 0.0f), PMC_LAMBDA_MAX);
  // Texel indices of huge, negative and non-finite uvs at the extreme levels
  // are defined and bounded (pmc_cache.h: at most 2^62 + 2^31 in magnitude).
  const long lim = 4611686018427387904L + 2147483648L;
  for (float u : {0.0f, -0.5f, 1e7f, -1e7f, 3e38f, -3e38f, kInf, -kInf, kNaN})
    for (int lambda : {PMC_LAMBDA_MIN, 0, PMC_LAMBDA_MAX}) {
      long t = pmc_cache_texel(u, lambda);
      EXPECT_GE(t, -lim) << u << " at " << lambda;
      EXPECT_LE(t, lim) << u << " at " << lambda;
      EXPECT_TRUE(std::isfinite(pmc_cache_texel_center(t, lambda)));
    }
  EXPECT_EQ(pmc_cache_texel(kNaN, 10), 0L);
  EXPECT_EQ(pmc_cache_texel(1e7f, 0), 10000000L);
  EXPECT_EQ(pmc_cache_texel(-1e7f - 2.0f, 0), -10000002L);
}

// ---------------------------------------------------------------- degenerate geometry

TEST(Numerical, DegenerateAndZeroAreaTriangles) {
  const std::string dir = test::temp_dir();
  write_materials(dir);
  ObjText o;
  o.line("mtllib scene.mtl\nusemtl tex");
  const double floor_q[4][3] = {{-2, -1, 2}, {2, -1, 2}, {2, -1, -2}, {-2, -1, -2}};
  o.quad(floor_q);
  int uv0 = o.vt(0.1, 0.2), uv1 = o.vt(0.9, 0.3), uv2 = o.vt(0.4, 0.8);
  auto tri = [&](double ax, double ay, double az, double bx, double by, double bz, double cx, double cy,
                 double cz) {
    int a = o.v(ax, ay, az), b = o.v(bx, by, bz), c = o.v(cx, cy, cz);
    o.ft(a, uv0, b, uv1, c, uv2);
  };
  tri(-1, 0, 0, 0, 0, 0, 1, 0, 0);             // collinear
  tri(-1, -1, 0, 0, 0, 0, 1, 1, 0);            // collinear, diagonal (the camera looks across it)
  tri(0.5, 0.5, 0, 0.5, 0.5, 0, 0.5, 0.5, 0);  // all corners the same point
  {
    int a = o.v(-0.5, 0.2, 0.1), b = o.v(0.5, 0.3, 0.1);
    o.ft(a, uv0, a, uv1, b, uv2);  // a repeated vertex index
    o.ft(a, uv0, b, uv1, b, uv2);
  }
  tri(-1, 0.7, 0, 1, 0.7, 0, 0, 0.7 + 1e-7, 0);         // a sliver: 1e-7 high
  tri(-1, -0.7, 0, 1, -0.7, 0, 3, -0.7, 1e-30);         // area underflows in float
  tri(-1, 0.4, 0.2, 1, 0.4, 0.2, 0, 0.4 + 1e-12, 0.2);  // sliver the camera sees edge-on
  // And a degenerate emitter: it must not enter the light table with zero area.
  o.line("usemtl lamp");
  tri(-0.2, 1.5, 0, 0, 1.5, 0, 0.2, 1.5, 0);
  test::write_file(dir + "/degenerate.obj", o.str());
  Scene scene = load_obj(dir + "/degenerate.obj");
  EXPECT_EQ(scene.skipped_triangles, 0u) << "finite degenerate triangles are kept (Embree ignores them)";
  EXPECT_EQ(scene.triangles.size(), 2u + 8u + 1u);
  RenderConfig s = hard::small_config(40, 40, 8, 5);
  hard::set_camera(s, 0.01, 0.3, 3, 0, 0, 0, 60.0f);
  s.env[0] = s.env[1] = s.env[2] = 1.0f;
  render_all_clean(material_variants(dir + "/degenerate.obj", dir), s);
  // Grazing at the degenerate triangles' plane, too.
  hard::set_camera(s, -3, 0.0, 1e-6, 0, 0, 0, 60.0f);
  render_all_clean(material_variants(dir + "/degenerate.obj", dir), s);
}

TEST(Numerical, ZeroAreaAndCollinearUvTriangles) {
  const std::string dir = test::temp_dir();
  write_materials(dir);
  ObjText o;
  o.line("mtllib scene.mtl\nusemtl tex");
  // Quad 1: every corner has the same uv. Quad 2: collinear uvs.
  const double q1[4][3] = {{-2, -1, 0}, {0, -1, 0}, {0, 1, 0}, {-2, 1, 0}};
  o.quad(q1, 0.5, 0.5, 0.5, 0.5);
  int a = o.v(0, -1, 0), b = o.v(2, -1, 0), c = o.v(2, 1, 0), d = o.v(0, 1, 0);
  int ta = o.vt(0, 0), tb = o.vt(1, 1), tc = o.vt(2, 2), td = o.vt(3, 3);
  o.ft(a, ta, b, tb, c, tc);
  o.ft(a, ta, c, tc, d, td);
  test::write_file(dir + "/zero_uv.obj", o.str());
  RenderConfig s = hard::small_config(40, 24, 8, 4);
  hard::set_camera(s, 0, 0, 4, 0, 0, 0, 50.0f);
  s.env[0] = s.env[1] = s.env[2] = 1.0f;
  render_all_clean(material_variants(dir + "/zero_uv.obj", dir), s);
  // The footprint of a zero-area uv triangle is zero: finest cache level.
  float2 g1, g2;
  pmc_ray_cone_gradients(make_float3(0, 0, -1), make_float3(0, 0, 1), 0.01f, make_float3(-2, -1, 0),
                         make_float3(0, -1, 0), make_float3(0, 1, 0), make_float2(0.5f, 0.5f),
                         make_float2(0.5f, 0.5f), make_float2(0.5f, 0.5f), &g1, &g2);
  EXPECT_EQ(pmc_cache_lambda(g1, g2, 0.0f), PMC_LAMBDA_MAX);
}

TEST(Numerical, HugeAndNegativeUvs) {
  const std::string dir = test::temp_dir();
  write_materials(dir);
  ObjText o;
  o.line("mtllib scene.mtl\nusemtl tex");
  // Left: uvs around 1e7 (float spacing 1 there); middle: around -1e7;
  // right: small negative uvs; far right: a quad spanning -1e7 .. 1e7.
  const double q1[4][3] = {{-4, -1, 0}, {-2, -1, 0}, {-2, 1, 0}, {-4, 1, 0}};
  const double q2[4][3] = {{-2, -1, 0}, {0, -1, 0}, {0, 1, 0}, {-2, 1, 0}};
  const double q3[4][3] = {{0, -1, 0}, {2, -1, 0}, {2, 1, 0}, {0, 1, 0}};
  const double q4[4][3] = {{2, -1, 0}, {4, -1, 0}, {4, 1, 0}, {2, 1, 0}};
  o.quad(q1, 1e7, 1e7, 1e7 + 16, 1e7 + 16);
  o.quad(q2, -1e7 - 16, -1e7, -1e7, -1e7 + 16);
  o.quad(q3, -3.5, -2.25, -0.5, 0.75);
  o.quad(q4, -1e7, -1e7, 1e7, 1e7);
  test::write_file(dir + "/huge_uv.obj", o.str());
  RenderConfig s = hard::small_config(64, 20, 8, 4);
  hard::set_camera(s, 0, 0, 6, 0, 0, 0, 40.0f);
  s.env[0] = s.env[1] = s.env[2] = 1.0f;
  // Level floors raise the level (and bypass) at every hit or at camera hits
  // only; without them, lookups.
  for (CacheBandwidth floors : {CacheBandwidth::On, CacheBandwidth::Camera, CacheBandwidth::Off})
    for (float bias : {0.0f, 8.0f}) {  // bias 8: finer levels, texel indices near 2^27
      SCOPED_TRACE("mip bias " + std::to_string(bias) + ", level floors " + std::to_string(int(floors)));
      s.mip_bias = bias;
      s.cache_bandwidth = floors;
      render_all_clean(material_variants(dir + "/huge_uv.obj", dir), s);
    }
  // (No floors from here on: every point is looked up.)
  s.cache_eval = CacheEval::Center;  // re-evaluates at texel centres of huge texel indices
  s.cache_filter = CacheFilter::Nearest;
  render_all_clean(material_variants(dir + "/huge_uv.obj", dir), s);
}

// ---------------------------------------------------------------- non-finite input data

// An OBJ whose vertex data hold NaN and Inf: 3 triangles with a non-finite
// position, 2 with NaN/Inf normals, 1 with NaN/Inf uvs, 2 clean ones.
std::string non_finite_obj() {
  return "mtllib scene.mtl\nusemtl tex\n"
         "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"  // 1-4: clean
         "v nan 0 0\nv 0 inf 0\nv 0 0 -inf\n"        // 5-7: non-finite positions
         "v 0 0 1e39\n"                              // 8: overflows float: +inf
         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"          // 1-4
         "vt nan 0.5\nvt 0.5 inf\nvt 1e39 -1e39\n"   // 5-7
         "vn 0 0 1\nvn nan nan nan\nvn inf 0 0\nvn 0 0 1e39\n"
         "f 1/1/1 2/2/1 3/3/1\n"   // clean
         "f 1/1/1 3/3/1 4/4/1\n"   // clean
         "f 1/1 2/2 5/3\n"         // NaN position: skipped
         "f 6 1 2\n"               // Inf position: skipped
         "f 3 4 7\n"               // -Inf position: skipped
         "f 4 3 8\n"               // 1e39 -> Inf position: skipped
         "f 1/1/2 2/2/3 3/3/4\n"   // non-finite normals: repaired
         "f 1/5/1 2/6/1 3/7/1\n";  // non-finite uvs: repaired
}

TEST(Numerical, NonFiniteVertexDataIsSkippedOrRepaired) {
  const std::string dir = test::temp_dir();
  write_materials(dir);
  test::write_file(dir + "/nonfinite.obj", non_finite_obj());
  Scene scene = load_obj(dir + "/nonfinite.obj");
  EXPECT_EQ(scene.skipped_triangles, 4u);
  EXPECT_EQ(scene.triangles.size(), 4u);
  for (float x : scene.normals) EXPECT_TRUE(std::isfinite(x));
  for (float x : scene.uvs) EXPECT_TRUE(std::isfinite(x));
  for (const PmcTriangle& t : scene.triangles)
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(scene.positions[3 * size_t(t.v[k]) + c]));
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(std::isfinite(scene.bounds.lo[i]));
    EXPECT_TRUE(std::isfinite(scene.bounds.hi[i]));
  }
  RenderConfig s = hard::small_config(32, 32, 8, 4);
  hard::set_camera(s, 0.2, 0.1, 3, 0, 0, 0, 50.0f);
  s.env[0] = s.env[1] = s.env[2] = 1.0f;
  render_all_clean(material_variants(dir + "/nonfinite.obj", dir), s);
}

TEST(Numerical, NonFinitePositionsWarnOnceWithTheCount) {
  const std::string dir = test::temp_dir();
  write_materials(dir);
  test::write_file(dir + "/nonfinite.obj", non_finite_obj());
  std::string log;
  ASSERT_EQ(test::run_pmc("render " + dir + "/nonfinite.obj -o " + dir +
                              "/out.exr --width 16 --height 16 --spp 1 --quiet",
                          &log),
            0)
      << log;
  size_t first = log.find("skipped");
  ASSERT_NE(first, std::string::npos) << log;
  EXPECT_EQ(log.find("skipped", first + 1), std::string::npos) << "one warning, not one per face:\n" << log;
  EXPECT_NE(log.find("skipped 4 faces"), std::string::npos) << log;
  EXPECT_NE(log.find("nonfinite.obj"), std::string::npos) << log;
  // Normals and uvs are repaired, with one warning and the count: 3 + 1 + 1
  // normal components (nan nan nan, inf, 1e39), 1 + 1 + 2 uv components.
  EXPECT_NE(log.find("replaced 9 non-finite normal/uv components"), std::string::npos) << log;
  EXPECT_NE(log.find("warning"), std::string::npos) << log;
  Image img = read_image(dir + "/out.exr");
  EXPECT_EQ(test::non_finite(img), 0u);
}

TEST(Numerical, NanAndInfTexelsInAFloatExrTexture) {
  const std::string dir = test::temp_dir();
  // 4 x 4 RGB float texels: NaN, +Inf, -Inf, huge, negative and ordinary values.
  const float special[] = {kNaN, kInf, -kInf, 3e38f, -5.0f, 0.25f, 1e-40f, 2.0f};
  std::vector<float> px;
  for (int i = 0; i < 16; ++i)
    for (int c = 0; c < 3; ++c) px.push_back(special[(i + c * 3) % 8]);
  hard::write_image(dir + "/bad.exr", 4, 4, 3, px, OIIO::TypeDesc::FLOAT);
  hard::write_checker_png(dir + "/checker.png");
  test::write_file(dir + "/materials.mtlx", hard::materials_mtlx("bad.exr"));
  test::write_file(dir + "/scene.mtl", scene_mtl("bad.exr"));
  ObjText o;
  o.line("mtllib scene.mtl\nusemtl tex");
  const double q[4][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  o.quad(q, -0.3, -0.3, 2.7, 2.7);
  test::write_file(dir + "/exr.obj", o.str());

  // The loader's choice: a non-finite texel becomes black (all channels of
  // colour; alpha is 1 for RGB). Texel 0 starts with NaN.
  Scene scene = load_obj(dir + "/exr.obj");
  ASSERT_EQ(scene.textures.size(), 1u);
  const TexelBytes t = scene.textures.texels();
  ASSERT_GE(t.size(), 16u * 4u);
  // Texel i, channel c holds special[(i + 3c) % 8]: red of texel 0 is NaN,
  // of texel 1 +Inf, of texel 2 -Inf.
  EXPECT_EQ(t[4 * 0 + 0], 0u) << "NaN texel channel";
  EXPECT_EQ(t[4 * 1 + 0], 0u) << "+Inf texel channel";
  EXPECT_EQ(t[4 * 2 + 0], 0u) << "-Inf texel channel";
  EXPECT_EQ(t[4 * 0 + 1], 255u) << "3e38 is finite: it saturates";
  RenderConfig s = hard::small_config(32, 32, 8, 4);
  hard::set_camera(s, 0, 0, 3, 0, 0, 0, 50.0f);
  s.env[0] = s.env[1] = s.env[2] = 1.0f;
  const std::string obj = dir + "/exr.obj";
  render_all_clean({RenderCase{obj, {}, ""}, RenderCase{obj, {dir + "/materials.mtlx"}, "M_tiled"}}, s);
  // The choice is announced once, with the count: every texel of this
  // texture has a NaN or Inf channel.
  std::string log;
  ASSERT_EQ(
      test::run_pmc("render " + obj + " -o " + dir + "/out.exr --width 16 --height 16 --spp 1 --quiet", &log),
      0)
      << log;
  const size_t at = log.find("16 of 16 texels hold NaN or Inf");
  EXPECT_NE(at, std::string::npos) << log;
  EXPECT_NE(log.find("bad.exr"), std::string::npos) << log;
  EXPECT_EQ(log.find("texels hold NaN", at + 40), std::string::npos) << "one warning per texture:\n" << log;
}

// ---------------------------------------------------------------- extreme radiance

TEST(Numerical, EmittersOfRadianceOneMillion) {
  const std::string dir = test::temp_dir();
  write_materials(dir);
  ObjText o;
  o.line("mtllib scene.mtl\nusemtl tex");
  const double floor_q[4][3] = {{-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, {-2, 0, -2}};
  o.quad(floor_q);
  o.line("usemtl lamp");  // Ke 1e6, facing down
  const double lamp[4][3] = {{-0.2, 1.5, -0.2}, {0.2, 1.5, -0.2}, {0.2, 1.5, 0.2}, {-0.2, 1.5, 0.2}};
  o.quad(lamp);
  o.line("usemtl M_bright");  // procedural emitter, 1e6 * |noise|
  const double back[4][3] = {{-2, 0, -2}, {2, 0, -2}, {2, 2, -2}, {-2, 2, -2}};
  o.quad(back);
  o.line("usemtl M_noise");
  const double left[4][3] = {{-2, 0, 2}, {-2, 0, -2}, {-2, 2, -2}, {-2, 2, 2}};
  o.quad(left);
  o.line("usemtl M_tiled");
  const double right[4][3] = {{2, 0, -2}, {2, 0, 2}, {2, 2, 2}, {2, 2, -2}};
  o.quad(right);
  test::write_file(dir + "/bright.obj", o.str());
  const RenderCase c{dir + "/bright.obj", {dir + "/materials.mtlx"}, ""};
  RenderConfig s = hard::small_config(32, 32, 8, 5);
  hard::set_camera(s, 0, 1.0, 3.5, 0, 0.5, 0, 70.0f);
  for (bool cache : {false, true}) {
    SCOPED_TRACE(label(c, cache));
    hard::Rendered r = hard::render(c, s, cache);
    hard::expect_clean(r.out, label(c, cache));
    double mean = test::image_mean(r.out.image);
    EXPECT_GT(mean, 1.0) << "the 1e6 emitters light the scene";
    float peak = *std::max_element(r.out.image.pixels.begin(), r.out.image.pixels.end());
    EXPECT_GE(peak, 1e5f) << "pixels that see the emitters directly are ~1e6";
    if (cache) {
      const CacheStats& cs = r.out.stats.cache;
      // 1e6 * |noise| mostly exceeds RGB9E5's 65408: those values are not
      // inserted (and are counted), never stored clamped.
      EXPECT_GT(cs.not_encodable, 0u);
      EXPECT_GT(cs.inserts, 0u) << "the other networks' values are cached";
      EXPECT_LE(cs.inserts + cs.not_encodable + cs.dropped_full, cs.lookups - cs.hits);
    }
  }
}

// ---------------------------------------------------------------- scale

// Floor, a block standing on it (contact edges), a floating slab casting a
// shadow, a thin fin; grey Lambert (albedo 0.5), lit only by a unit
// environment. Everything, camera included, scaled by `k`.
std::string scaled_scene(double k) {
  ObjText o;
  o.line("mtllib scene.mtl\nusemtl grey");
  auto q = [&](double a[4][3]) {
    for (int i = 0; i < 4; ++i)
      for (int c = 0; c < 3; ++c) a[i][c] *= k;
    o.quad(a);
  };
  double floor_q[4][3] = {{-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}};
  q(floor_q);
  double lo[3] = {-0.3 * k, 0.0, -0.3 * k}, hi[3] = {0.3 * k, 0.6 * k, 0.3 * k};
  o.box(lo, hi);
  double lo2[3] = {0.4 * k, 0.5 * k, -0.2 * k}, hi2[3] = {0.9 * k, 0.52 * k, 0.6 * k};
  o.box(lo2, hi2);
  double fin[4][3] = {{-0.8, 0, 0.3}, {-0.8, 0, -0.5}, {-0.8, 0.4, -0.5}, {-0.8, 0.4, 0.3}};
  q(fin);
  // A low shelf 0.06 above the front of the floor: a crevice whose height is
  // 6e-6 at scale 1e-4 (ray offsets must stay below that there).
  double lo3[3] = {-1.0 * k, 0.06 * k, 0.5 * k}, hi3[3] = {1.0 * k, 0.08 * k, 1.0 * k};
  o.box(lo3, hi3);
  return o.str();
}

TEST(Numerical, SceneScaleFromTenToTheMinusFourToTenToTheFive) {
  // Radiance is scale invariant: the same scene and camera scaled by k give
  // the same image in expectation, and with the same seed the same random
  // numbers drive the same paths, so only rounding-dependent decisions
  // (ray offsets, hit/miss at edges) can differ.
  //
  // Tolerance: every path's value lies in [0, 1] here (albedo 0.5 < 1, Russian
  // roulette keeps a grey throughput <= 1, the only light is the unit
  // environment, no emitters), so a path's variance is at most 1/4 and the
  // image mean over N = W*H*spp paths has a standard error of at most
  // 0.5 / sqrt(N). Even if every path at scale k were independent of the
  // scale-1 paths, the difference of the two means would have a standard
  // deviation of at most sqrt(2) * 0.5 / sqrt(N); we allow 4 of those
  // (false-failure probability < 1e-4). A scale bug (self-intersection acne,
  // leaking through contacts, offsets larger than the geometry) shifts the
  // mean by far more: e.g. shadow acne on the floor darkens a third of the image.
  const std::string dir = test::temp_dir();
  write_materials(dir);
  RenderConfig s = hard::small_config(32, 32, 16, 6);
  s.env[0] = s.env[1] = s.env[2] = 1.0f;
  const double n_paths = double(s.width) * s.height * s.spp;
  const double tolerance = 4.0 * std::sqrt(2.0) * 0.5 / std::sqrt(n_paths);
  // Two views: the whole scene, and a close-up of the crevice under the
  // shelf (lit only through its open front, so an offset that jumps over
  // the shelf brightens it at once).
  struct View {
    const char* name;
    double from[3], at[3];
    float fov;
  };
  const View views[] = {{"overview", {0.6, 0.3, 2.2}, {0, 0.1, 0}, 50.0f},
                        {"crevice", {0.1, 0.035, 1.3}, {-0.1, 0.03, 0.5}, 60.0f}};
  for (const View& v : views) {
    SCOPED_TRACE(v.name);
    double reference = -1.0;
    std::string summary;
    for (double k : {1.0, 1e-4, 1e-3, 1e-2, 1e2, 1e4, 1e5}) {
      SCOPED_TRACE("scale " + hard::num(k));
      const std::string obj = dir + "/scene_" + hard::num(k) + ".obj";
      if (!test::file_exists(obj)) test::write_file(obj, scaled_scene(k));
      hard::set_camera(s, v.from[0] * k, v.from[1] * k, v.from[2] * k, v.at[0] * k, v.at[1] * k, v.at[2] * k,
                       v.fov);
      hard::Rendered r = hard::render(RenderCase{obj, {}, ""}, s, false);
      hard::expect_clean(r.out, "scale " + hard::num(k));
      double mean = test::image_mean(r.out.image);
      summary += hard::num(k) + ":" + hard::num(mean) + " ";
      if (reference < 0) reference = mean;
      EXPECT_NEAR(mean, reference, tolerance) << v.name << ": image mean at scale " << k << " vs scale 1";
    }
    RecordProperty(std::string("means_") + v.name, summary);
  }
  RecordProperty("tolerance", hard::num(tolerance));
}

// The ray offset is scale-covariant below scale 1: scaling a hit point, its
// triangle's scale and the scene by a power of two scales the offset point
// by exactly that factor (so a scene at 1e-4 behaves like the scene at 1),
// and at scale >= 1 it is the classic Wächter-Binder offset.
TEST(Numerical, RayOffsetScalesWithTheScene) {
  const float3 n = make_float3(0.48f, 0.6f, -0.64f);
  const float3 points[] = {make_float3(0, 0, 0), make_float3(0.3f, -0.01f, 0.002f),
                           make_float3(0.9f, 0.5f, -0.7f), make_float3(1e-3f, 0.02f, -0.031f)};
  for (const float3& p : points) {
    const float3 ref = pmc_offset_ray(p, n, 1.0f);
    for (int e : {-4, -10, -14, -17}) {  // 2^-17 ~ 7.6e-6
      const float k = std::ldexp(1.0f, e);
      const float3 q = pmc_offset_ray(make_float3(p.x * k, p.y * k, p.z * k), n, k);
      EXPECT_EQ(q.x, ref.x * k) << e;
      EXPECT_EQ(q.y, ref.y * k) << e;
      EXPECT_EQ(q.z, ref.z * k) << e;
      // The offset point is strictly off the surface, on the side of n.
      EXPECT_GT((q.x - p.x * k) * n.x + (q.y - p.y * k) * n.y + (q.z - p.z * k) * n.z, 0.0f) << e;
    }
    // At and above scale 1 the scale argument changes nothing.
    const float3 big = pmc_offset_ray(p, n, 1e5f);
    EXPECT_EQ(big.x, ref.x);
    EXPECT_EQ(big.y, ref.y);
    EXPECT_EQ(big.z, ref.z);
  }
  // Degenerate scales stay finite and off the surface.
  for (float sc : {0.0f, 1e-45f, kNaN, kInf}) {
    const float3 q = pmc_offset_ray(make_float3(0, 0, 0), n, sc);
    EXPECT_TRUE(std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z)) << sc;
    EXPECT_GT(q.x * n.x + q.y * n.y + q.z * n.z, 0.0f) << sc;
  }
}

// ---------------------------------------------------------------- enclosed

TEST(Numerical, CameraInsideAClosedMeshSeesNoLightFromOutside) {
  // A watertight box around the camera, bright environment outside, no
  // emitter inside: every path stays inside and the image must be exactly
  // black at every scale (any light is a leak through an edge or an offset
  // ray escaping the box).
  const std::string dir = test::temp_dir();
  write_materials(dir);
  for (double k : {1e-4, 1.0, 1e5}) {
    SCOPED_TRACE("scale " + hard::num(k));
    ObjText o;
    o.line("mtllib scene.mtl\nusemtl white");
    double lo[3] = {-k, -k, -k}, hi[3] = {k, k, k};
    o.box(lo, hi);
    const std::string obj = dir + "/closed_" + hard::num(k) + ".obj";
    test::write_file(obj, o.str());
    RenderConfig s = hard::small_config(32, 32, 4, 16);
    s.env[0] = s.env[1] = s.env[2] = 100.0f;
    hard::set_camera(s, 0.3 * k, 0.2 * k, 0.1 * k, 1.0 * k, 1.0 * k, 1.0 * k, 100.0f);  // looks into a corner
    hard::Rendered r = hard::render(RenderCase{obj, {}, ""}, s, false);
    hard::expect_clean(r.out, "inside");
    float peak = *std::max_element(r.out.image.pixels.begin(), r.out.image.pixels.end());
    EXPECT_EQ(peak, 0.0f) << "light leaked into the closed box";
  }
}

TEST(Numerical, MaximumPathDepthReachedByEveryPath) {
  // Closed box, albedo 1, every wall emitting Le = 1, max depth 3. No path can
  // escape or be absorbed before its 3rd hit (Russian roulette starts there),
  // so every path makes 3 hits, and the 3rd hit's BSDF sample is traced
  // (unless Russian roulette ends it: 5% at throughput 1) for the emission it
  // meets alone. Expected pixel value: Le at the first hit (seen directly),
  // plus the direct light of hits 1, 2 and 3 (NEE + BSDF hits, MIS-weighted:
  // together exactly albedo * Le = Le each). Exactly 4 Le in expectation; 3.5
  // would mean hit 3 kept only its light sample's MIS share.
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/box.mtl", "newmtl glow\nKd 1 1 1\nKs 0 0 0\nKe 1 1 1\n");
  ObjText o;
  o.line("mtllib box.mtl\nusemtl glow");
  double lo[3] = {-1, -1, -1}, hi[3] = {1, 1, 1};
  o.box(lo, hi);
  test::write_file(dir + "/box.obj", o.str());
  // 64 spp: at 8 the image mean's own noise (a standard deviation of about
  // 0.045 over seeds when light sampling took full weight at the last hit,
  // with fireflies near the box's edges) was as wide as the tolerance, with
  // either light selection; at 64 it is about 0.02.
  RenderConfig s = hard::small_config(32, 32, 64, 3);
  hard::set_camera(s, 0.1, -0.2, 0.3, 1, 0.5, -1, 90.0f);
  for (bool cache : {false, true}) {
    SCOPED_TRACE(cache ? "cache on" : "cache off");
    hard::Rendered r = hard::render(RenderCase{dir + "/box.obj", {}, ""}, s, cache);
    hard::expect_clean(r.out, "max depth");
    const RenderStats& st = r.out.stats;
    EXPECT_EQ(st.paths, uint64_t(32 * 32 * 64));
    // 3 hits a path, then the last hit's BSDF ray unless Russian roulette
    // (q = 0.95 at throughput 1) ended it: about 3.95 rays a path
    EXPECT_GT(st.rays - st.shadow_rays, 3 * st.paths + st.paths * 9 / 10)
        << "every path makes max-depth hits";
    EXPECT_LE(st.rays - st.shadow_rays, 4 * st.paths);
    double mean = test::image_mean(r.out.image);
    EXPECT_NEAR(mean, 4.0, 0.04);
    RecordProperty(cache ? "mean_cache_on" : "mean_cache_off", hard::num(mean));
  }
}

}  // namespace
}  // namespace pmc
