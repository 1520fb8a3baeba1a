// height_normal_test.cpp — heighttonormal and bump (materials/height_normal.cpp).
//
// Documents are read, compiled and run on the host interpreter; the normals
// are compared with the analytic gradient of the height field:
//  - a linear ramp h = a u + b v gives n = normalize(-s a, -s b, 1), encoded
//    as n / 2 + 1/2 (forward differences are exact up to float rounding);
//  - a quadratic h = u^2 gives the slope 2u (+ the step's O(d) bias);
//  - bump turns the shading normal by the same gradient through normalmap;
//  - a constant height is flat, uvs of 1e7 give a finite flat normal;
//  - a non-float height and a texcoord that is not the surface's uv are
//    clear errors.
// With the material cache (centre mode), the shifted copies of the height
// sub-graph are never the centre's cache point: the height drives the base
// colour too, the plan has separate points for the colour and the normal,
// their keys differ, and a cached evaluation returns the tilted normal of the
// texel centre — a normal computed from the centre's cached height alone
// would be flat and fail.
#include "materials/height_normal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/device/pmc_interp.h"
#include "core/error.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"

namespace pmc {
namespace {

std::string document(const std::string& nodes, const std::string& surface_inputs) {
  return R"(<?xml version="1.0"?><materialx version="1.39">)" + nodes +
         R"(<standard_surface name="S" type="surfaceshader">)" + surface_inputs +
         R"(</standard_surface><surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial></materialx>)";
}

struct Compiled {
  TexturePool textures;
  MaterialProgram program;
  CompiledMaterial material;
};

void compile(const std::string& doc, Compiled& c, const CompileOptions& options = {}) {
  std::vector<Graph> graphs = read_mtlx_string(doc, "mem.mtlx");
  ASSERT_EQ(graphs.size(), 1u);
  c.material = compile_material(graphs[0], c.textures, c.program, options);
}

void run(const Compiled& c, float2 uv, float params[PMC_P_COUNT], PmcCacheContext* cache = nullptr) {
  PmcShadingInputs in{};
  in.uv = uv;
  in.position = make_float3(0.2f, 0.3f, 0.4f);
  in.normal = make_float3(0, 0, 1);
  in.tangent = make_float3(1, 0, 0);
  in.bitangent = make_float3(0, 1, 0);
  in.footprint = 1e-3f;
  PmcTextureSet ts{};
  float stack[PMC_STACK_SIZE] = {0};
  pmc_surface_defaults(params, in.normal);
  pmc_interp_run(c.program.code.data(), c.material.entry, &in, &ts, stack, params, cache);
}

float3 param3(const float* p, int i) { return make_float3(p[i], p[i + 1], p[i + 2]); }

float3 encoded_normal(float sx, float sy) {
  float3 n = normalize(make_float3(sx, sy, 1.0f));
  return make_float3(n.x * 0.5f + 0.5f, n.y * 0.5f + 0.5f, n.z * 0.5f + 0.5f);
}

void expect_near3(float3 a, float3 b, float tol, const std::string& what) {
  EXPECT_NEAR(a.x, b.x, tol) << what;
  EXPECT_NEAR(a.y, b.y, tol) << what;
  EXPECT_NEAR(a.z, b.z, tol) << what;
}

// h = a u + b v through a dot product with the uv.
std::string ramp(float a, float b) {
  return R"(<texcoord name="uv" type="vector2"/><dotproduct name="h" type="float"><input name="in1" type="vector2" nodename="uv"/><input name="in2" type="vector2" value=")" +
         std::to_string(a) + ", " + std::to_string(b) + R"("/></dotproduct>)";
}

TEST(HeightToNormal, LinearRampTiltsAgainstTheSlope) {
  const float a = 2.0f, b = -0.75f, s = 1.5f;
  Compiled c;
  compile(
      document(
          ramp(a, b) +
              R"(<heighttonormal name="n" type="vector3"><input name="in" type="float" nodename="h"/><input name="scale" type="float" value="1.5"/></heighttonormal>)",
          R"(<input name="base_color" type="color3" nodename="n"/>)"),
      c);
  for (float u : {0.1f, 0.37f, 0.9f, -3.25f}) {
    float p[PMC_P_COUNT];
    run(c, make_float2(u, 0.6f), p);
    expect_near3(param3(p, PMC_P_BASE_COLOR), encoded_normal(-s * a, -s * b), 2e-4f,
                 "u = " + std::to_string(u));
  }
}

TEST(HeightToNormal, QuadraticMatchesTheAnalyticGradient) {
  Compiled c;
  compile(
      document(
          R"(<texcoord name="uv" type="vector2"/><extract name="u" type="float"><input name="in" type="vector2" nodename="uv"/><input name="index" type="integer" value="0"/></extract>
<multiply name="h" type="float"><input name="in1" type="float" nodename="u"/><input name="in2" type="float" nodename="u"/></multiply>
<heighttonormal name="n" type="vector3"><input name="in" type="float" nodename="h"/></heighttonormal>)",
          R"(<input name="base_color" type="color3" nodename="n"/>)"),
      c);
  for (float u : {0.0f, 0.3f, 0.8f}) {
    float p[PMC_P_COUNT];
    run(c, make_float2(u, 0.5f), p);
    // Forward difference: ((u + d)^2 - u^2) / d = 2u + d.
    expect_near3(param3(p, PMC_P_BASE_COLOR), encoded_normal(-(2.0f * u + kHeightStep), 0.0f), 2e-4f,
                 "u = " + std::to_string(u));
    float exact_x = encoded_normal(-2.0f * u, 0.0f).x;
    EXPECT_NEAR(p[PMC_P_BASE_COLOR], exact_x, 2e-3f) << "close to the exact slope 2u";
  }
}

TEST(HeightToNormal, BumpTurnsTheShadingNormal) {
  const float a = 0.8f, b = 0.3f, s = 0.5f;
  Compiled c;
  compile(
      document(
          ramp(a, b) +
              R"(<bump name="n" type="vector3"><input name="height" type="float" nodename="h"/><input name="scale" type="float" value="0.5"/></bump>)",
          R"(<input name="normal" type="vector3" nodename="n"/>)"),
      c);
  float p[PMC_P_COUNT];
  run(c, make_float2(0.25f, 0.75f), p);
  // heighttonormal (scale 1) then normalmap (scale s) in the frame t = x, b = y, n = z.
  float3 m = normalize(make_float3(-a, -b, 1.0f));
  float3 expected = normalize(make_float3(m.x * s, m.y * s, m.z));
  expect_near3(param3(p, PMC_P_NORMAL), expected, 2e-4f, "bumped normal");
  EXPECT_LT(p[PMC_P_NORMAL], -0.1f) << "tilted away from the rising u";
}

TEST(HeightToNormal, ConstantHeightIsFlatAndHugeUvsStayFinite) {
  Compiled flat;
  compile(
      document(
          R"(<heighttonormal name="n" type="vector3"><input name="in" type="float" value="3"/></heighttonormal>)",
          R"(<input name="base_color" type="color3" nodename="n"/>)"),
      flat);
  float p[PMC_P_COUNT];
  run(flat, make_float2(0.5f, 0.5f), p);
  expect_near3(param3(p, PMC_P_BASE_COLOR), make_float3(0.5f, 0.5f, 1.0f), 0.0f, "constant height");

  Compiled ramp_c;
  compile(
      document(
          ramp(2.0f, 1.0f) +
              R"(<heighttonormal name="n" type="vector3"><input name="in" type="float" nodename="h"/></heighttonormal>)",
          R"(<input name="base_color" type="color3" nodename="n"/>)"),
      ramp_c);
  for (float u : {1e7f, -1e7f}) {
    run(ramp_c, make_float2(u, u), p);
    // uv + d == uv in float beyond 2^12 / d: the differences vanish.
    expect_near3(param3(p, PMC_P_BASE_COLOR), make_float3(0.5f, 0.5f, 1.0f), 0.0f,
                 "u = " + std::to_string(u));
  }
  // A height that overflows (2u + v = inf) has no gradient (inf - inf): the
  // encoded value is NaN, and a bump built on it keeps the surface normal.
  Compiled bumped;
  compile(
      document(ramp(2.0f, 1.0f) +
                   R"(<bump name="n" type="vector3"><input name="height" type="float" nodename="h"/></bump>)",
               R"(<input name="normal" type="vector3" nodename="n"/>)"),
      bumped);
  run(bumped, make_float2(3e38f, 3e38f), p);
  expect_near3(param3(p, PMC_P_NORMAL), make_float3(0.0f, 0.0f, 1.0f), 0.0f, "overflowing height");
}

TEST(HeightToNormal, BadInputsAreClearErrors) {
  Compiled c;
  try {
    compile(
        document(
            R"(<texcoord name="uv" type="vector2"/><combine3 name="h" type="color3"/><heighttonormal name="n" type="vector3"><input name="in" type="float" nodename="h"/></heighttonormal>)",
            R"(<input name="base_color" type="color3" nodename="n"/>)"),
        c);
    FAIL() << "a color3 height compiled";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("type mismatch"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mem.mtlx"), std::string::npos) << e.what();
  }
  try {
    compile(
        document(
            ramp(1, 1) +
                R"(<place2d name="p" type="vector2"/><heighttonormal name="n" type="vector3"><input name="in" type="float" nodename="h"/><input name="texcoord" type="vector2" nodename="p"/></heighttonormal>)",
            R"(<input name="base_color" type="color3" nodename="n"/>)"),
        c);
    FAIL() << "a place2d texcoord compiled";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not supported"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'p'"), std::string::npos) << e.what();
  }
}

TEST(HeightToNormal, CachedShiftedHeightsAreNotTheCentresCachePoint) {
  // A wavy height (uv only) drives both the base colour and the bump.
  const std::string nodes =
      R"(<texcoord name="uv" type="vector2"/><multiply name="f" type="vector2"><input name="in1" type="vector2" nodename="uv"/><input name="in2" type="vector2" value="3, 2"/></multiply>
<noise2d name="h" type="float"><input name="texcoord" type="vector2" nodename="f"/></noise2d>
<sin name="w" type="float"><input name="in" type="float" nodename="h"/></sin>
<combine3 name="col" type="color3"><input name="in1" type="float" nodename="w"/><input name="in2" type="float" value="0.5"/><input name="in3" type="float" value="0.25"/></combine3>
<add name="col1" type="color3"><input name="in1" type="color3" nodename="col"/><input name="in2" type="float" value="1"/></add>
<bump name="n" type="vector3"><input name="height" type="float" nodename="w"/></bump>)";
  const std::string doc = document(
      nodes,
      R"(<input name="base_color" type="color3" nodename="col1"/><input name="normal" type="vector3" nodename="n"/>)");
  Compiled plain, cached;
  compile(doc, plain);
  CompileOptions on;
  on.cache = true;
  on.cache_min_nodes = 1;
  compile(doc, cached, on);
  const CachePlan& plan = cached.material.cache_plan;
  ASSERT_EQ(plan.points.size(), 2u) << "the colour and the encoded normal";

  std::vector<uint64_t> words(size_t(1) << 12, 0);
  PmcCacheContext cache{};
  cache.table.entries = words.data();
  cache.table.cells = words.size() / 8;
  cache.table.ways = 8;
  cache.g1 = make_float2(1.0f / 64.0f, 0.0f);  // level 6: texels of 1/64
  cache.g2 = make_float2(0.0f, 1.0f / 64.0f);
  cache.material = 1;
  cache.center = 1;
  const int lambda = pmc_cache_lambda(cache.g1, cache.g2, 0.0f);
  ASSERT_EQ(lambda, 6);
  // Same texel, the two points: distinct cells and fingerprints.
  PmcCacheKey a = pmc_cache_key(1u, uint32_t(plan.points[0].node), 0u, lambda, 3, 5);
  PmcCacheKey b = pmc_cache_key(1u, uint32_t(plan.points[1].node), 1u, lambda, 3, 5);
  ASSERT_NE(a.fingerprint, b.fingerprint);
  ASSERT_NE(a.h1, b.h1);
  int tilted = 0;
  for (int i = 0; i < 40; ++i) {
    const float u = 0.013f + 0.0237f * float(i), v = 0.71f - 0.0119f * float(i);
    const float2 centre = make_float2(pmc_cache_texel_center(pmc_cache_texel(u, lambda), lambda),
                                      pmc_cache_texel_center(pmc_cache_texel(v, lambda), lambda));
    float ref[PMC_P_COUNT], miss[PMC_P_COUNT], hit[PMC_P_COUNT];
    run(plain, centre, ref);
    cache.hits = 0;
    run(cached, make_float2(u, v), miss, &cache);
    ASSERT_EQ(cache.hits, 0u) << "a fresh texel misses";
    cache.hits = 0;
    run(cached, make_float2(u, v), hit, &cache);
    ASSERT_EQ(cache.hits, 2u) << "the second evaluation finds both points";
    for (const float* p : {miss, hit}) {
      // RGB9E5: 1/511.5 of the largest channel (the normal's encoding is <= 1,
      // the colour's < 2); normalmap doubles the encoded normal's error.
      expect_near3(param3(p, PMC_P_BASE_COLOR), param3(ref, PMC_P_BASE_COLOR), 2.0f / 511.5f, "colour");
      expect_near3(param3(p, PMC_P_NORMAL), param3(ref, PMC_P_NORMAL), 4.0f / 511.5f, "normal");
    }
    if (std::fabs(ref[PMC_P_NORMAL]) > 0.01f || std::fabs(ref[PMC_P_NORMAL + 1]) > 0.01f) ++tilted;
  }
  EXPECT_GT(tilted, 20) << "the bump must tilt the normal at most points for this test to mean anything";
}

}  // namespace
}  // namespace pmc
