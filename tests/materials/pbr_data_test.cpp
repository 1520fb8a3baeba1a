// pbr_data_test.cpp — the pbrlib data nodes (core/device/pmc_pbr_data.h)
// against answers computed independently here, and through documents on the
// host reference interpreter.
//
//  - blackbody: the chromaticity of Planck's law integrated against the CIE
//    1931 observer (the multi-lobe Gaussian fit of Wyman, Sloan and Shirley,
//    JCGT 2013), anchored by CIE illuminant A (a 2856 K Planckian radiator,
//    published x = 0.44757, y = 0.40745); 6504 K is near white.
//  - artistic_ior: the complex IOR (n, k) it returns must have the normal-
//    incidence Fresnel reflectance ((n-1)^2 + k^2) / ((n+1)^2 + k^2) equal to
//    the reflectivity (Gulbrandsen's construction), and n must sit at the
//    edge_color's place between n_max (k = 0 ... ) and n_min.
//  - roughness_anisotropy / roughness_dual: hand-computed values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/device/pmc_interp.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"

namespace pmc {
namespace {

// ---- CIE 1931 chromaticity of a blackbody, computed here ------------------

double lobe(double l, double mu, double s1, double s2) {
  double t = (l - mu) / (l < mu ? s1 : s2);
  return std::exp(-0.5 * t * t);
}
// Wyman, Sloan, Shirley 2013, "Simple Analytic Approximations to the CIE XYZ
// Color Matching Functions", multi-lobe fit (lambda in nm).
void cmf(double l, double* x, double* y, double* z) {
  *x = 1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) -
       0.065 * lobe(l, 501.1, 20.4, 26.2);
  *y = 0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1);
  *z = 1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8);
}
// xy of Planck's spectral exitance at `kelvin` (the constant factors cancel).
void planck_xy(double kelvin, double* x, double* y) {
  const double c2 = 1.4388e7;  // nm K
  double X = 0, Y = 0, Z = 0;
  for (double l = 360; l <= 830; l += 0.5) {
    double m = std::pow(l, -5.0) / std::expm1(c2 / (l * kelvin));
    double a, b, c;
    cmf(l, &a, &b, &c);
    X += m * a, Y += m * b, Z += m * c;
  }
  *x = X / (X + Y + Z);
  *y = Y / (X + Y + Z);
}
// Linear Rec.709 RGB -> xy (the sRGB/Rec.709 primaries with D65, IEC 61966-2-1).
void rgb_xy(float4 c, double* x, double* y) {
  double X = 0.4124 * c.x + 0.3576 * c.y + 0.1805 * c.z;
  double Y = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
  double Z = 0.0193 * c.x + 0.1192 * c.y + 0.9505 * c.z;
  *x = X / (X + Y + Z);
  *y = Y / (X + Y + Z);
}

TEST(PbrData, BlackbodyIntegratorReproducesIlluminantA) {
  double x, y;
  planck_xy(2856, &x, &y);
  EXPECT_NEAR(x, 0.44757, 2e-3);
  EXPECT_NEAR(y, 0.40745, 2e-3);
}

TEST(PbrData, BlackbodyFollowsThePlanckianLocus) {
  for (double T : {1500.0, 2000.0, 2856.0, 3500.0, 4500.0, 5000.0, 6504.0, 8000.0, 12000.0, 20000.0}) {
    float4 c = pmc_blackbody(float(T));
    double px, py, bx, by;
    planck_xy(T, &px, &py);
    if (c.z <= 0.0f) {  // outside the Rec.709 gamut (blue clamped): only red > green > blue = 0
      EXPECT_GT(c.x, c.y) << T;
      continue;
    }
    rgb_xy(c, &bx, &by);
    EXPECT_NEAR(bx, px, 3e-3) << T << " K";
    EXPECT_NEAR(by, py, 3e-3) << T << " K";
    // Y = 1: the luminance of the Rec.709 colour is 1 (up to the 4-digit matrix).
    EXPECT_NEAR(0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z, 1.0, 2e-3) << T << " K";
  }
}

TEST(PbrData, BlackbodyShape) {
  float4 w = pmc_blackbody(6504.0f);  // near D65: near white
  for (float v : {w.x, w.y, w.z}) EXPECT_NEAR(v, 1.0f, 0.06f);
  float4 warm = pmc_blackbody(2000.0f), cool = pmc_blackbody(15000.0f);
  EXPECT_GT(warm.x, warm.y);
  EXPECT_GT(warm.y, warm.z);
  EXPECT_GT(cool.z, cool.x);
  // Clamped to [800, 25000] K, as MaterialX: beyond the ends nothing changes.
  float4 a = pmc_blackbody(100.0f), b = pmc_blackbody(800.0f);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  float4 c = pmc_blackbody(1e6f), d = pmc_blackbody(25000.0f);
  EXPECT_EQ(c.z, d.z);
  float4 n = pmc_blackbody(NAN);
  EXPECT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
}

TEST(PbrData, ArtisticIorHasTheReflectivityAtNormalIncidence) {
  for (float r : {0.02f, 0.2f, 0.5f, 0.776f, 0.944f, 0.98f})
    for (float g : {0.0f, 0.3f, 0.751f, 1.0f}) {
      float4 refl = make_float4(r, r, r, 0), edge = make_float4(g, g, g, 0);
      double n = pmc_artistic_ior(refl, edge, 0).x, k = pmc_artistic_ior(refl, edge, 1).x;
      double F0 = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
      const double n_min = (1.0 - r) / (1.0 + r),
                   n_max = (1 + std::sqrt(double(r))) / (1 - std::sqrt(double(r)));
      // n between n_min (g = 1) and n_max (g = 0); where that n cannot reach r
      // with k >= 0 (k^2 < 0, clamped), k = 0.
      EXPECT_NEAR(n, n_max + (n_min - n_max) * g, 1e-4 * n_max) << r << " " << g;
      const double k2 = ((n + 1) * (n + 1) * r - (n - 1) * (n - 1)) / (1 - r);
      if (k2 > 1e-4)
        EXPECT_NEAR(F0, r, 2e-5) << "reflectivity " << r << " edge " << g;
      else
        EXPECT_NEAR(k, 0.0, 1e-2) << r << " " << g;
    }
  // Reflectivity above 0.99 is clamped to 0.99 (MaterialX).
  float4 one = make_float4(1, 1, 1, 0), half = make_float4(0.5f, 0.5f, 0.5f, 0);
  EXPECT_EQ(pmc_artistic_ior(one, half, 0).x, pmc_artistic_ior(make_float4(0.99f, 0, 0, 0), half, 0).x);
}

TEST(PbrData, RoughnessNodes) {
  float2 iso = pmc_roughness_anisotropy(0.5f, 0.0f);
  EXPECT_FLOAT_EQ(iso.x, 0.25f);
  EXPECT_FLOAT_EQ(iso.y, 0.25f);
  float2 an = pmc_roughness_anisotropy(0.5f, 0.5f);  // aspect sqrt(1/2)
  EXPECT_NEAR(an.x, 0.25 / std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(an.y, 0.25 * std::sqrt(0.5), 1e-6);
  float2 capped = pmc_roughness_anisotropy(0.9f, 1.0f);  // anisotropy capped at 0.98, x at 1
  EXPECT_FLOAT_EQ(capped.x, 1.0f);
  EXPECT_NEAR(capped.y, 0.81 * std::sqrt(0.02), 1e-6);
  float2 zero = pmc_roughness_anisotropy(0.0f, 0.0f);  // never below FLT_EPSILON
  EXPECT_FLOAT_EQ(zero.x, 1.1920928955078125e-7f);
  float2 dual = pmc_roughness_dual(make_float2(0.3f, 0.6f));
  EXPECT_NEAR(dual.x, 0.09, 1e-7);
  EXPECT_NEAR(dual.y, 0.36, 1e-7);
  float2 same = pmc_roughness_dual(make_float2(0.3f, -1.0f));  // y < 0 takes x
  EXPECT_NEAR(same.y, 0.09, 1e-7);
}

// ---- through documents ------------------------------------------------------

// Runs material M of a document (nodes, then a standard_surface whose
// base_color comes from node `color`) at uv (0.5, 0.5), normal +Z; returns base_color.
float4 base_color(const std::string& nodes, const std::string& color_input) {
  std::string doc = R"(<?xml version="1.0"?><materialx version="1.39">)" + nodes +
                    R"(<standard_surface name="S" type="surfaceshader">)" + color_input +
                    R"(</standard_surface><surfacematerial name="M" type="material">
<input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial></materialx>)";
  std::vector<Graph> graphs = read_mtlx_string(doc, "mem.mtlx");
  EXPECT_EQ(graphs[0].error, "");
  TexturePool textures;
  MaterialProgram program;
  const CompiledMaterial& m = compile_material(graphs[0], textures, program);
  PmcShadingInputs in{};
  in.uv = make_float2(0.5f, 0.5f);
  in.normal = make_float3(0, 0, 1);
  in.tangent = make_float3(1, 0, 0);
  in.bitangent = make_float3(0, 1, 0);
  PmcTextureSet ts{};
  float stack[PMC_STACK_SIZE], params[PMC_P_COUNT];
  pmc_surface_defaults(params, in.normal);
  pmc_interp_run(program.code.data(), m.entry, &in, &ts, stack, params, nullptr);
  return make_float4(params[PMC_P_BASE_COLOR], params[PMC_P_BASE_COLOR + 1], params[PMC_P_BASE_COLOR + 2], 0);
}

TEST(PbrData, DocumentsReachTheNodes) {
  // blackbody(6504 K): near white.
  float4 bb = base_color(
      R"(<blackbody name="b" type="color3"><input name="temperature" type="float" value="6504"/></blackbody>)",
      R"(<input name="base_color" type="color3" nodename="b"/>)");
  float4 want = pmc_blackbody(6504.0f);
  EXPECT_NEAR(bb.x, want.x, 1e-6f);
  EXPECT_NEAR(bb.z, want.z, 1e-6f);
  // artistic_ior: both outputs of one node, each selected by output="...".
  const std::string ior =
      R"(<artistic_ior name="a" type="multioutput"><input name="reflectivity" type="color3" value="0.9, 0.5, 0.2"/></artistic_ior>
<combine3 name="c" type="color3"><input name="in1" type="float" nodename="xi"/><input name="in2" type="float" nodename="xk"/></combine3>
<extract name="xi" type="float"><input name="in" type="color3" nodename="a" output="ior"/><input name="index" type="integer" value="1"/></extract>
<extract name="xk" type="float"><input name="in" type="color3" nodename="a" output="extinction"/><input name="index" type="integer" value="1"/></extract>)";
  float4 got = base_color(ior, R"(<input name="base_color" type="color3" nodename="c"/>)");
  // Green channel: r = 0.5, default edge_color g = 0.981; n and k by Gulbrandsen.
  const double r = 0.5, g = 0.981;
  const double n = g * (1 - r) / (1 + r) + (1 - g) * (1 + std::sqrt(r)) / (1 - std::sqrt(r));
  const double k = std::sqrt(std::max(0.0, ((n + 1) * (n + 1) * r - (n - 1) * (n - 1)) / (1 - r)));
  EXPECT_NEAR(got.x, n, 1e-5);
  EXPECT_NEAR(got.y, k, 1e-5);
  // roughness_anisotropy through glossiness_anisotropy's nodegraph (pbrlib_ng.mtlx:
  // roughness = 1 - glossiness), then roughness_dual of a constant.
  float4 ga = base_color(
      R"(<glossiness_anisotropy name="g" type="vector2"><input name="glossiness" type="float" value="0.7"/><input name="anisotropy" type="float" value="0.5"/></glossiness_anisotropy>
<roughness_dual name="d" type="vector2"><input name="roughness" type="vector2" value="0.4, -1"/></roughness_dual>
<combine3 name="c" type="color3"><input name="in1" type="float" nodename="gx"/><input name="in2" type="float" nodename="gy"/><input name="in3" type="float" nodename="dy"/></combine3>
<extract name="gx" type="float"><input name="in" type="vector2" nodename="g"/><input name="index" type="integer" value="0"/></extract>
<extract name="gy" type="float"><input name="in" type="vector2" nodename="g"/><input name="index" type="integer" value="1"/></extract>
<extract name="dy" type="float"><input name="in" type="vector2" nodename="d"/><input name="index" type="integer" value="1"/></extract>)",
      R"(<input name="base_color" type="color3" nodename="c"/>)");
  EXPECT_NEAR(ga.x, 0.09 / std::sqrt(0.5), 1e-5);
  EXPECT_NEAR(ga.y, 0.09 * std::sqrt(0.5), 1e-5);
  EXPECT_NEAR(ga.z, 0.16, 1e-6);
}

}  // namespace
}  // namespace pmc
