// mtl_mapping_test.cpp — MTL materials as standard_surface networks (docs/MTL.md).
//
// Each test writes a small OBJ + MTL (and images) into a temp folder, loads it
// with load_obj, builds the material set as the renderer does and runs the
// material on the host interpreter at one shading point (facing +z, tangent
// +x, bitangent +y). The expected values are the documented formulas,
// computed here independently of materials/mtl_graph.cpp.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/obj_loader.h"
#include "materials/cpu_interpreter.h"
#include "materials/material_set.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

// A quad over [0, 1]^2 with uvs and +z normals, all faces in material `m`.
const char* kQuad =
    "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
    "usemtl m\nf 1/1/1 2/2/1 3/3/1 4/4/1\n";

struct Params {
  float p[PMC_P_COUNT];
  float operator[](int i) const { return p[i]; }
};

// Material `m` of the MTL text `mtl` at uv (u, v); `warnings` gets stderr.
Params eval_mtl(const std::string& dir, const std::string& mtl, float u = 0.5f, float v = 0.5f,
                std::string* warnings = nullptr) {
  test::write_file(dir + "/m.mtl", mtl);
  test::write_file(dir + "/m.obj", kQuad);
  testing::internal::CaptureStderr();
  Scene scene = load_obj(dir + "/m.obj");
  MaterialSet set = build_material_set(scene, MaterialOptions{});
  const std::string err = testing::internal::GetCapturedStderr();
  if (warnings) *warnings = err;
  PmcTextureSet ts = host_texture_set(scene, set);
  PmcShadingInputs in{};
  in.uv = make_float2(u, v);
  in.position = make_float3(u, v, 0);
  in.normal = make_float3(0, 0, 1);
  in.tangent = make_float3(1, 0, 0);
  in.bitangent = make_float3(0, 1, 0);
  Params out{};
  evaluate_material(set, ts, scene.triangles[0].material, in, out.p);
  return out;
}

// An 8-bit image of w x h pixels, `channels` each, every pixel `px` (or the given pixels).
void write_png(const std::string& path, int w, int h, int channels, const std::vector<uint8_t>& data) {
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(w, h, channels, OIIO::TypeDesc::UINT8);
  ASSERT_TRUE(out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, data.data()));
  ASSERT_TRUE(out->close());
}

void write_uniform_png(const std::string& path, int channels, const std::vector<uint8_t>& px) {
  std::vector<uint8_t> data;
  for (int i = 0; i < 4 * 4; ++i) data.insert(data.end(), px.begin(), px.end());
  write_png(path, 4, 4, channels, data);
}

// F0 of a dielectric of index n, and the index of an F0.
float f0_of(float n) { return ((n - 1) / (n + 1)) * ((n - 1) / (n + 1)); }
float ior_of(float f0) { return (1 + std::sqrt(f0)) / (1 - std::sqrt(f0)); }

TEST(MtlMapping, KdIsTheBaseColourAndNsTheRoughness) {
  const std::string dir = test::temp_dir();
  Params p = eval_mtl(dir, "newmtl m\nKd 0.2 0.4 0.6\nNs 250\nKa 0.9 0.9 0.9\n");
  EXPECT_FLOAT_EQ(p[PMC_P_BASE], 1.0f);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR], 0.2f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR + 1], 0.4f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR + 2], 0.6f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_SPECULAR_ROUGHNESS], 0.5f, 1e-6f);  // 1 - sqrt(250 / 1000)
  EXPECT_EQ(p[PMC_P_METALNESS], 0.0f) << "Ka is not the metalness";
  EXPECT_EQ(p[PMC_P_TRANSMISSION], 0.0f);
  EXPECT_EQ(p[PMC_P_SPECULAR], 0.0f) << "no Ks: no specular";
  // Ns is clamped to [0, 1000].
  EXPECT_NEAR(eval_mtl(dir, "newmtl m\nNs 5000\n")[PMC_P_SPECULAR_ROUGHNESS], 0.0f, 1e-6f);
  EXPECT_NEAR(eval_mtl(dir, "newmtl m\nNs -3\n")[PMC_P_SPECULAR_ROUGHNESS], 1.0f, 1e-6f);
  EXPECT_NEAR(eval_mtl(dir, "newmtl m\nNs 10\n")[PMC_P_SPECULAR_ROUGHNESS], 1.0f - std::sqrt(0.01f), 1e-6f);
}

TEST(MtlMapping, KsLevelScalesTheDielectricF0ThroughTheIor) {
  const std::string dir = test::temp_dir();
  // L = 0.5 leaves F0(1.5).
  Params half = eval_mtl(dir, "newmtl m\nKs 0.5 0.5 0.5\nNi 1.5\n");
  EXPECT_FLOAT_EQ(half[PMC_P_SPECULAR], 1.0f);
  EXPECT_NEAR(half[PMC_P_SPECULAR_IOR], 1.5f, 1e-4f);
  EXPECT_EQ(half[PMC_P_SPECULAR_COLOR], 1.0f);
  // L = 1, no Ni (tinyobjloader's 1.0): F0 = 2 * 0.04 = 0.08.
  Params one = eval_mtl(dir, "newmtl m\nKs 1 1 1\n");
  EXPECT_NEAR(one[PMC_P_SPECULAR_IOR], ior_of(0.08f), 1e-4f);
  EXPECT_NEAR(f0_of(one[PMC_P_SPECULAR_IOR]), 0.08f, 1e-5f);
  // L is the mean of Ks; Ni 1.33 gives F0(1.33).
  Params mixed = eval_mtl(dir, "newmtl m\nKs 0.1 0.2 0.6\nNi 1.33\n");
  EXPECT_NEAR(mixed[PMC_P_SPECULAR_IOR], ior_of(2.0f * 0.3f * f0_of(1.33f)), 1e-4f);
  // Ni <= 1 reads as not given (1.5).
  EXPECT_NEAR(eval_mtl(dir, "newmtl m\nKs 0.5 0.5 0.5\nNi 0.8\n")[PMC_P_SPECULAR_IOR], 1.5f, 1e-4f);
  // F0 is clamped below 1: a huge level stays a finite IOR.
  Params huge = eval_mtl(dir, "newmtl m\nKs 100 100 100\nNi 3\n");
  EXPECT_NEAR(huge[PMC_P_SPECULAR_IOR], ior_of(0.999f), 0.05f);
  EXPECT_TRUE(std::isfinite(huge[PMC_P_SPECULAR_IOR]));
  // Ks 0: no specular at all.
  EXPECT_EQ(eval_mtl(dir, "newmtl m\nKs 0 0 0\nNi 1.7\n")[PMC_P_SPECULAR], 0.0f);
}

TEST(MtlMapping, GlassIllumModelsTransmit) {
  const std::string dir = test::temp_dir();
  for (int illum : {4, 6, 7, 9}) {
    Params g = eval_mtl(dir, "newmtl m\nKd 0.3 0.3 0.3\nKs 0.1 0.1 0.1\nNi 1.45\nTf 0.8 0.9 1\nillum " +
                                 std::to_string(illum) + "\n");
    EXPECT_EQ(g[PMC_P_TRANSMISSION], 1.0f) << illum;
    EXPECT_NEAR(g[PMC_P_TRANSMISSION_COLOR], 0.8f, 1e-6f) << illum;
    EXPECT_NEAR(g[PMC_P_TRANSMISSION_COLOR + 1], 0.9f, 1e-6f) << illum;
    EXPECT_NEAR(g[PMC_P_TRANSMISSION_COLOR + 2], 1.0f, 1e-6f) << illum;
    EXPECT_NEAR(g[PMC_P_SPECULAR_IOR], 1.45f, 1e-5f) << "glass keeps Ni, without the Ks level";
    EXPECT_EQ(g[PMC_P_SPECULAR], 1.0f) << illum;
  }
  // No Tf (tinyobjloader's 0 0 0): white; no Ni: 1.5.
  Params white = eval_mtl(dir, "newmtl m\nillum 4\n");
  EXPECT_EQ(white[PMC_P_TRANSMISSION], 1.0f);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(white[PMC_P_TRANSMISSION_COLOR + k], 1.0f);
  EXPECT_NEAR(white[PMC_P_SPECULAR_IOR], 1.5f, 1e-6f);
  // Tf with an opaque illum stays opaque, and the warning says so.
  std::string log;
  Params opaque = eval_mtl(dir, "newmtl m\nTf 0.5 0.5 0.5\nillum 2\n", 0.5f, 0.5f, &log);
  EXPECT_EQ(opaque[PMC_P_TRANSMISSION], 0.0f);
  EXPECT_NE(log.find("Tf 0.5 0.5 0.5"), std::string::npos) << log;
  EXPECT_NE(log.find("not modelled"), std::string::npos) << log;
  // White Tf without illum is what many exporters write: no warning.
  eval_mtl(dir, "newmtl m\nTf 1 1 1\n", 0.5f, 0.5f, &log);
  EXPECT_EQ(log.find("not modelled"), std::string::npos) << log;
}

TEST(MtlMapping, PbrExtension) {
  const std::string dir = test::temp_dir();
  Params p = eval_mtl(dir,
                      "newmtl m\nKd 0.9 0.5 0.1\nNs 900\nPr 0.3\nPm 1\nPc 0.4\nPcr 0.2\nPs 0.6\naniso 0.5\n"
                      "anisor 0.25\n");
  EXPECT_NEAR(p[PMC_P_SPECULAR_ROUGHNESS], 0.3f, 1e-6f) << "Pr wins over Ns";
  EXPECT_EQ(p[PMC_P_METALNESS], 1.0f);
  EXPECT_NEAR(p[PMC_P_COAT], 0.4f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_COAT_ROUGHNESS], 0.2f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_SHEEN], 0.6f, 1e-6f);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(p[PMC_P_SHEEN_COLOR + k], 1.0f);
  EXPECT_NEAR(p[PMC_P_SPECULAR_ANISOTROPY], 0.5f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_SPECULAR_ROTATION], 0.25f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR], 0.9f, 1e-6f);
  // A PBR material without Pr is smooth (Pr's default 0), whatever Ns says.
  Params metal = eval_mtl(dir, "newmtl m\nNs 10\nPm 1\n");
  EXPECT_EQ(metal[PMC_P_SPECULAR_ROUGHNESS], 0.0f);
  EXPECT_EQ(metal[PMC_P_METALNESS], 1.0f);
  // Values outside [0, 1] are clamped.
  Params wild = eval_mtl(dir, "newmtl m\nPm 3\nPr -1\n");
  EXPECT_EQ(wild[PMC_P_METALNESS], 1.0f);
  EXPECT_EQ(wild[PMC_P_SPECULAR_ROUGHNESS], 0.0f);
}

TEST(MtlMapping, EmissionAndOpacity) {
  const std::string dir = test::temp_dir();
  Params p = eval_mtl(dir, "newmtl m\nKe 4 5 6.5\nd 0.25\n");
  EXPECT_EQ(p[PMC_P_EMISSION], 1.0f);
  EXPECT_NEAR(p[PMC_P_EMISSION_COLOR], 4.0f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_EMISSION_COLOR + 1], 5.0f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_EMISSION_COLOR + 2], 6.5f, 1e-6f);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[PMC_P_OPACITY + k], 0.25f, 1e-6f);
}

// Maps of the PBR extension and map_Ks: the first channel, linear (not sRGB).
TEST(MtlMapping, ScalarMapsReadTheirFirstChannelLinearly) {
  const std::string dir = test::temp_dir();
  write_uniform_png(dir + "/s.png", 3, {64, 230, 10});
  const float first = 64.0f / 255.0f;
  Params p = eval_mtl(dir,
                      "newmtl m\nPr 0.9\nmap_Pr s.png\nmap_Pm s.png\nmap_Ps s.png\nKs 0.5 0.5 0.5\n"
                      "map_Ks s.png\n");
  EXPECT_NEAR(p[PMC_P_SPECULAR_ROUGHNESS], first, 1e-3f) << "map_Pr replaces Pr";
  EXPECT_NEAR(p[PMC_P_METALNESS], first, 1e-3f);
  EXPECT_NEAR(p[PMC_P_SHEEN], first, 1e-3f);
  EXPECT_NEAR(p[PMC_P_SPECULAR], first, 1e-3f) << "specular 1 times map_Ks";
  EXPECT_NEAR(p[PMC_P_SPECULAR_IOR], 1.5f, 1e-4f) << "the IOR from the constant Ks";
  // map_Ke times Ke, sRGB-decoded like map_Kd.
  write_uniform_png(dir + "/e.png", 3, {255, 128, 0});
  Params e = eval_mtl(dir, "newmtl m\nKe 2 2 2\nmap_Ke e.png\n");
  EXPECT_NEAR(e[PMC_P_EMISSION_COLOR], 2.0f, 1e-3f);
  const float c = 128.0f / 255.0f;
  const float srgb = std::pow((c + 0.055f) / 1.055f, 2.4f);
  EXPECT_NEAR(e[PMC_P_EMISSION_COLOR + 1], 2.0f * srgb, 2e-3f);
  EXPECT_NEAR(e[PMC_P_EMISSION_COLOR + 2], 0.0f, 1e-3f);
}

// The shading normal a tangent-space map value (r, g, b) in [0, 1] gives at
// a point facing +z (tangent +x): (2r - 1, 2g - 1) scaled, 2b - 1, normalized.
void expect_normal_map(const Params& p, float r, float g, float b, float scale, const std::string& what) {
  float x = scale * (2 * r - 1), y = scale * (2 * g - 1), z = 2 * b - 1;
  const float len = std::sqrt(x * x + y * y + z * z);
  EXPECT_NEAR(p[PMC_P_NORMAL], x / len, 2e-2f) << what;
  EXPECT_NEAR(p[PMC_P_NORMAL + 1], y / len, 2e-2f) << what;
  EXPECT_NEAR(p[PMC_P_NORMAL + 2], z / len, 2e-2f) << what;
}

TEST(MtlMapping, NormIsATangentSpaceNormalMap) {
  const std::string dir = test::temp_dir();
  write_uniform_png(dir + "/n.png", 3, {191, 128, 255});
  const float r = 191.0f / 255.0f, g = 128.0f / 255.0f;
  Params p = eval_mtl(dir, "newmtl m\nnorm n.png\n");
  EXPECT_GT(p[PMC_P_NORMAL], 0.3f) << "differs from the shading normal (0, 0, 1)";
  expect_normal_map(p, r, g, 1.0f, 1.0f, "norm");
  expect_normal_map(eval_mtl(dir, "newmtl m\nnorm -bm 0.5 n.png\n"), r, g, 1.0f, 0.5f, "norm -bm 0.5");
  // A flat map leaves the normal.
  write_uniform_png(dir + "/flat.png", 3, {128, 128, 255});
  EXPECT_NEAR(eval_mtl(dir, "newmtl m\nnorm flat.png\n")[PMC_P_NORMAL + 2], 1.0f, 1e-3f);
  // An RGB map_Bump without -bm is a normal map too (Blender's exporter writes them so).
  expect_normal_map(eval_mtl(dir, "newmtl m\nmap_Bump n.png\n"), r, g, 1.0f, 1.0f, "map_Bump RGB");
}

TEST(MtlMapping, BumpIsAHeightBumpScaledByBm) {
  const std::string dir = test::temp_dir();
  // Height rising along u: 0, 85, 170, 255 (one channel).
  std::vector<uint8_t> ramp;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) ramp.push_back(uint8_t(85 * x));
  write_png(dir + "/h.png", 4, 4, 1, ramp);
  const float u = 0.45f, v = 0.5f;
  Params one = eval_mtl(dir, "newmtl m\nbump h.png\n", u, v);
  EXPECT_LT(one[PMC_P_NORMAL], -0.05f) << "tilts against the slope";
  EXPECT_NEAR(one[PMC_P_NORMAL + 1], 0.0f, 1e-3f);
  Params half = eval_mtl(dir, "newmtl m\nbump -bm 0.5 h.png\n", u, v);
  Params two = eval_mtl(dir, "newmtl m\nbump -bm 2 h.png\n", u, v);
  // The slope x / z scales with -bm.
  const float s1 = one[PMC_P_NORMAL] / one[PMC_P_NORMAL + 2];
  EXPECT_NEAR(half[PMC_P_NORMAL] / half[PMC_P_NORMAL + 2], 0.5f * s1, 1e-3f + 1e-3f * std::fabs(s1));
  EXPECT_NEAR(two[PMC_P_NORMAL] / two[PMC_P_NORMAL + 2], 2.0f * s1, 1e-3f + 2e-3f * std::fabs(s1));
  // An RGB height map with -bm is a height bump, not a normal map.
  std::vector<uint8_t> rgb;
  for (uint8_t h : ramp) rgb.insert(rgb.end(), {h, h, h});
  write_png(dir + "/h3.png", 4, 4, 3, rgb);
  Params rgb_bump = eval_mtl(dir, "newmtl m\nmap_bump -bm 2 h3.png\n", u, v);
  EXPECT_NEAR(rgb_bump[PMC_P_NORMAL], two[PMC_P_NORMAL], 1e-4f);
}

TEST(MtlMapping, MissingMapIsRefusedLikeAMissingMapKd) {
  const std::string dir = test::temp_dir();
  // (map_Ks scales a specular that Ks switches on, map_Ke multiplies Ke.)
  for (const char* map : {"norm", "bump", "map_Pr", "Ks 1 1 1\nmap_Ks", "Ke 1 1 1\nmap_Ke"}) {
    test::write_file(dir + "/m.mtl", std::string("newmtl m\n") + map + " nothere.png\n");
    test::write_file(dir + "/m.obj", kQuad);
    Scene scene = load_obj(dir + "/m.obj");
    try {
      build_material_set(scene, MaterialOptions{});
      ADD_FAILURE() << map << ": a missing texture was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("cannot read texture"), std::string::npos)
          << map << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("nothere.png"), std::string::npos) << e.what();
    }
  }
}

// tinyobjloader reads a number it cannot parse as the statement's default
// (0 for the PBR extension, 1 for Ni): no crash, no error.
TEST(MtlMapping, MalformedNumbersReadAsTinyobjloaderDefaults) {
  const std::string dir = test::temp_dir();
  Params p = eval_mtl(dir, "newmtl m\nPr abc\nPm x\nNi y\nKs 1 1 1\nNs 250\nanisor nan\n");
  EXPECT_NEAR(p[PMC_P_SPECULAR_ROUGHNESS], 0.5f, 1e-6f) << "Pr abc is Pr 0: not a PBR material, Ns decides";
  EXPECT_EQ(p[PMC_P_METALNESS], 0.0f);
  EXPECT_NEAR(p[PMC_P_SPECULAR_IOR], ior_of(0.08f), 1e-4f) << "Ni y is Ni 1: not given";
  for (int i = 0; i < PMC_P_COUNT; ++i) EXPECT_TRUE(std::isfinite(p[i])) << i;
  write_uniform_png(dir + "/n.png", 3, {128, 128, 255});
  Params huge = eval_mtl(dir, "newmtl m\nPc 1e39\naniso inf\nnorm -bm 1e39 n.png\n");
  for (int i = 0; i < PMC_P_COUNT; ++i) EXPECT_TRUE(std::isfinite(huge[i])) << i;
}

TEST(MtlMapping, WarningNamesOnlyWhatIsNotModelled) {
  const std::string dir = test::temp_dir();
  write_uniform_png(dir + "/n.png", 3, {128, 128, 255});
  std::string log;
  eval_mtl(dir,
           "newmtl m\nKd 0.5 0.5 0.5\nillum 7\nPm 0.5\nnorm n.png\nmap_Ks n.png\nmap_Ka n.png\nmap_Ns n.png\n"
           "refl n.png\ndisp n.png\n",
           0.5f, 0.5f, &log);
  for (const char* what : {"not modelled", "map_Ka n.png", "map_Ns n.png", "refl n.png", "disp n.png"})
    EXPECT_NE(log.find(what), std::string::npos) << what << " in:\n" << log;
  for (const char* what : {"PBR", "illum 7", "bump", "specular map", "norm"})
    EXPECT_EQ(log.find(what), std::string::npos) << what << " is modelled:\n" << log;
}

}  // namespace
}  // namespace pmc
