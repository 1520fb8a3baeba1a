// hextile_test.cpp — hextiledimage and hextilednormalmap (core/device/pmc_hextile.h)
// from MaterialX documents through the reader, compiler and host interpreter,
// against independent answers:
//  - without randomness (rotationrange 0 0, scalerange 1 1, offsetrange 0 0)
//    every tile reads the point itself and the blend weights sum to one: the
//    node equals `tiledimage` with the same tiling, and the normal map equals
//    `normalmap` of that tiled image;
//  - with the default randomness the value is a convex blend of texels (within
//    the image's range), the same on every call, and not the tiled image;
//  - at a tile centre the weights are (1, 0, 0), so with random rotation and
//    scale but no offset the value is the tiled image there; at the centroid
//    of a lattice triangle the three weights are 1/3 each;
//  - a common offset for every tile shifts the whole image;
//  - strength 0 leaves the normal unperturbed; a normal map tilted towards +u
//    read by tiles turned by 90 degrees tilts towards -v, as the height field
//    turned the same way does.
// The device runs the same two opcodes against this host code in
// tests/gpu/interpreter_parity_test.cpp; tests/gpu/render_test.cpp renders a
// document with them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/device/pmc_interp.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"
#include "tests/hard_cases/hard_support.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

// Compiles a document whose standard_surface reads node "n" at `input`
// (base_color or normal) and evaluates it on the host.
class Doc {
 public:
  Doc(const std::string& nodes, const std::string& input, const std::string& type) {
    std::string doc = R"(<?xml version="1.0"?><materialx version="1.39">)" + nodes +
                      R"(<standard_surface name="S" type="surfaceshader"><input name=")" + input +
                      R"(" type=")" + type + R"(" nodename="n"/></standard_surface>
<surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial></materialx>)";
    std::vector<Graph> graphs = read_mtlx_string(doc, "mem.mtlx");
    entry_ = compile_material(graphs[0], pool_, program_).entry;
    param_ = input == "normal" ? PMC_P_NORMAL : PMC_P_BASE_COLOR;
    const TexelBytes b = pool_.texels();
    for (size_t i = 0; i + 3 < b.size(); i += 4)
      words_.push_back(uint32_t(b[i]) | uint32_t(b[i + 1]) << 8 | uint32_t(b[i + 2]) << 16 |
                       uint32_t(b[i + 3]) << 24);
  }
  float3 eval(float2 uv, float footprint) const {
    PmcShadingInputs in{};
    in.uv = uv;
    in.normal = make_float3(0, 0, 1);
    in.tangent = make_float3(1, 0, 0);
    in.bitangent = make_float3(0, 1, 0);
    in.footprint = footprint;
    PmcTextureSet ts{};
    ts.textures = pool_.textures().data();
    ts.texels = words_.data();
    ts.srgb_lut = lut_.data();
    ts.count = uint32_t(pool_.size());
    float stack[PMC_STACK_SIZE], params[PMC_P_COUNT];
    pmc_surface_defaults(params, in.normal);
    pmc_interp_run(program_.code.data(), entry_, &in, &ts, stack, params, nullptr);
    return make_float3(params[param_], params[param_ + 1], params[param_ + 2]);
  }

 private:
  TexturePool pool_;
  MaterialProgram program_;
  uint32_t entry_ = 0;
  int param_ = 0;
  std::vector<uint32_t> words_;
  std::vector<float> lut_ = srgb_decode_table();
};

float max_diff(float3 a, float3 b) {
  return std::max({std::fabs(a.x - b.x), std::fabs(a.y - b.y), std::fabs(a.z - b.z)});
}

std::string file_input(const std::string& path) {
  return R"(<input name="file" type="filename" value=")" + path + R"("/>)";
}

// A hex-tiled image node "n" of `type` with extra inputs.
std::string hex(const std::string& path, const std::string& inputs, const std::string& type = "color3") {
  return R"(<hextiledimage name="n" type=")" + type + R"(">)" + file_input(path) + inputs +
         "</hextiledimage>";
}
std::string tiled(const std::string& path, const std::string& tiling, const std::string& type = "color3",
                  const std::string& name = "n") {
  return R"(<tiledimage name=")" + name + R"(" type=")" + type + R"(">)" + file_input(path) +
         R"(<input name="uvtiling" type="vector2" value=")" + tiling + R"("/></tiledimage>)";
}
const std::string kNoRandomness =
    R"(<input name="rotationrange" type="vector2" value="0, 0"/><input name="scalerange" type="vector2" value="1, 1"/><input name="offsetrange" type="vector2" value="0, 0"/>)";
const std::string kTiling = R"(<input name="tiling" type="vector2" value="3, 2"/>)";

// Points spread over several tiles and image repeats, with negative uvs.
std::vector<float2> sample_uvs(int n) {
  std::vector<float2> uvs;
  for (int i = 0; i < n; ++i)
    uvs.push_back(make_float2(-2.0f + 5.0f * std::fmod(0.6180339f * float(i), 1.0f),
                              -1.5f + 4.0f * std::fmod(0.7548777f * float(i) + 0.31f, 1.0f)));
  return uvs;
}

class HexTile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir();
    checker_ = dir_ + "/checker.png";
    hard::write_checker_png(checker_);
    // A normal map with every texel's z well above 0.5 (normals facing out).
    std::vector<float> px;
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        px.push_back(0.3f + 0.05f * float(x));
        px.push_back(0.65f - 0.04f * float(y));
        px.push_back(0.85f + 0.015f * float(x + y) / 2.0f);
      }
    normals_ = dir_ + "/normals.png";
    hard::write_image(normals_, 8, 8, 3, px);
    std::vector<float> tilt;  // (0.8, 128 / 255, 0.8) everywhere: a slope towards +u
    for (int k = 0; k < 16; ++k) tilt.insert(tilt.end(), {0.8f, 128.0f / 255.0f, 0.8f});
    tilt_ = dir_ + "/tilt.png";
    hard::write_image(tilt_, 4, 4, 3, tilt);
  }
  std::string dir_, checker_, normals_, tilt_;
};

TEST_F(HexTile, WithoutRandomnessEqualsTiledImage) {
  Doc h(hex(checker_, kTiling + kNoRandomness), "base_color", "color3");
  Doc t(tiled(checker_, "3, 2"), "base_color", "color3");
  Doc wrong(tiled(checker_, "2, 3"), "base_color", "color3");
  int differs_from_wrong = 0;
  for (float fp : {0.0f, 0.004f, 0.03f})
    for (float2 uv : sample_uvs(300)) {
      float3 a = h.eval(uv, fp), b = t.eval(uv, fp);
      EXPECT_LT(max_diff(a, b), 2e-5f) << "uv " << uv.x << " " << uv.y << " footprint " << fp;
      differs_from_wrong += max_diff(a, wrong.eval(uv, fp)) > 0.05f;
    }
  EXPECT_GT(differs_from_wrong, 300);  // the comparison can fail
}

TEST_F(HexTile, RandomTilesStayInRangeAreDeterministicAndDiffer) {
  Doc h(hex(checker_, kTiling), "base_color", "color3");  // MaterialX's default randomness
  Doc t(tiled(checker_, "3, 2"), "base_color", "color3");
  // The image's range: the checker's two colours, read at texel centres.
  float3 lo = make_float3(1e9f, 1e9f, 1e9f), hi = make_float3(-1e9f, -1e9f, -1e9f);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      float3 c = t.eval(make_float2((float(x) + 0.5f) / 48.0f, (float(y) + 0.5f) / 32.0f), 0.0f);
      lo = make_float3(std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z));
      hi = make_float3(std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z));
    }
  ASSERT_GT(hi.x - lo.x, 0.3f);
  int differ = 0;
  const std::vector<float2> uvs = sample_uvs(400);
  for (float2 uv : uvs) {
    float3 a = h.eval(uv, 0.002f);
    float3 again = h.eval(uv, 0.002f);
    EXPECT_EQ(a.x, again.x);
    EXPECT_EQ(a.y, again.y);
    EXPECT_EQ(a.z, again.z);
    const float e = 1e-5f;
    EXPECT_TRUE(a.x >= lo.x - e && a.x <= hi.x + e && a.y >= lo.y - e && a.y <= hi.y + e && a.z >= lo.z - e &&
                a.z <= hi.z + e)
        << "uv " << uv.x << " " << uv.y << ": " << a.x << " " << a.y << " " << a.z;
    differ += max_diff(a, t.eval(uv, 0.002f)) > 0.05f;
  }
  EXPECT_GT(differ, int(uvs.size()) / 4);
}

// A tile centre in uv for lattice index (a, b) and tiling 1.
float2 centre(int a, int b) {
  const float k = 1.0f / (2.0f * std::sqrt(3.0f));
  return make_float2((float(a) + 0.5f * float(b)) * k, float(b) * std::sqrt(3.0f) * 0.5f * k);
}

TEST_F(HexTile, TileCentresShowTheirOwnTileAndTriangleCentroidsWeighThreeEqually) {
  // Random rotation and scale turn each tile about its own centre: the
  // centre itself reads the plain image.
  Doc h(hex(checker_, R"(<input name="offsetrange" type="vector2" value="0, 0"/>)"), "base_color", "color3");
  Doc t(tiled(checker_, "1, 1"), "base_color", "color3");
  int checked = 0;
  for (int a = -3; a <= 3; ++a)
    for (int b = -3; b <= 3; ++b) {
      float2 uv = centre(a, b);
      EXPECT_LT(max_diff(h.eval(uv, 0.0f), t.eval(uv, 0.0f)), 1e-4f) << "centre " << a << " " << b;
      ++checked;
    }
  EXPECT_EQ(checked, 49);
  // The weights by hand: (1, 0, 0) at a centre (bary^7 of the others is 0),
  // 1/3 each at a triangle's centroid, whatever the falloff gain.
  PmcHexTiles at_centre =
      pmc_hextile_tiles(centre(2, 1), 1, make_float2(0, 360), 1, make_float2(0.5f, 2), 1, make_float2(0, 1));
  float3 w = pmc_hextile_weights(&at_centre, make_float3(1, 1, 1), 0.5f);
  EXPECT_NEAR(std::max({w.x, w.y, w.z}), 1.0f, 1e-6f);
  EXPECT_NEAR(w.x + w.y + w.z, 1.0f, 1e-6f);
  float2 c0 = centre(0, 0), c1 = centre(0, 1), c2 = centre(1, 0);
  PmcHexTiles mid = pmc_hextile_tiles(make_float2((c0.x + c1.x + c2.x) / 3, (c0.y + c1.y + c2.y) / 3), 1,
                                      make_float2(0, 360), 1, make_float2(0.5f, 2), 1, make_float2(0, 1));
  for (float falloff : {0.5f, 0.2f, 0.8f}) {
    w = pmc_hextile_weights(&mid, make_float3(1, 1, 1), falloff);
    EXPECT_NEAR(w.x, 1.0f / 3, 1e-5f);
    EXPECT_NEAR(w.y, 1.0f / 3, 1e-5f);
    EXPECT_NEAR(w.z, 1.0f / 3, 1e-5f);
  }
  // Schlick's gain by hand: r = 0.8, x = 0.25: a = (1 / 0.8 - 2) (1 - 0.5) =
  // -0.375, x / (a + 1) = 0.4; r = 0.2: a = 1.5, 0.1.
  EXPECT_NEAR(pmc_hextile_gain(0.25f, 0.8f), 0.4f, 1e-6f);
  EXPECT_NEAR(pmc_hextile_gain(0.25f, 0.2f), 0.1f, 1e-6f);
  EXPECT_NEAR(pmc_hextile_gain(0.5f, 0.3f), 0.5f, 1e-6f);
}

TEST_F(HexTile, ACommonOffsetShiftsTheWholeImage) {
  // offsetrange (0.25, 0.25): every tile is offset by 0.25 whatever its hash.
  Doc h(
      hex(checker_,
          R"(<input name="rotationrange" type="vector2" value="0, 0"/><input name="scalerange" type="vector2" value="1, 1"/><input name="offsetrange" type="vector2" value="0.25, 0.25"/>)"),
      "base_color", "color3");
  Doc t(tiled(checker_, "1, 1"), "base_color", "color3");
  for (float2 uv : sample_uvs(200))
    EXPECT_LT(max_diff(h.eval(uv, 0.0f), t.eval(make_float2(uv.x + 0.25f, uv.y + 0.25f), 0.0f)), 2e-5f);
}

std::string hex_normal(const std::string& path, const std::string& inputs) {
  return R"(<hextilednormalmap name="n" type="vector3">)" + file_input(path) + inputs +
         "</hextilednormalmap>";
}

TEST_F(HexTile, NormalMapStrengthZeroKeepsTheNormal) {
  Doc h(hex_normal(normals_, R"(<input name="strength" type="float" value="0"/>)"), "normal", "vector3");
  for (float2 uv : sample_uvs(100)) {
    float3 n = h.eval(uv, 0.01f);
    EXPECT_NEAR(n.x, 0.0f, 1e-6f);
    EXPECT_NEAR(n.y, 0.0f, 1e-6f);
    EXPECT_NEAR(n.z, 1.0f, 1e-6f);
  }
}

TEST_F(HexTile, NormalMapWithoutRandomnessEqualsNormalmapOfTheTiledImage) {
  Doc h(
      hex_normal(normals_, kTiling + kNoRandomness + R"(<input name="strength" type="float" value="1.5"/>)"),
      "normal", "vector3");
  Doc t(
      tiled(normals_, "3, 2", "vector3", "t") +
          R"(<normalmap name="n" type="vector3"><input name="in" type="vector3" nodename="t"/><input name="scale" type="float" value="1.5"/></normalmap>)",
      "normal", "vector3");
  Doc flat(
      hex_normal(normals_, kTiling + kNoRandomness + R"(<input name="flip_g" type="boolean" value="true"/>)"),
      "normal", "vector3");
  int flip_differs = 0;
  for (float2 uv : sample_uvs(300)) {
    float3 a = h.eval(uv, 0.003f), b = t.eval(uv, 0.003f);
    EXPECT_LT(max_diff(a, b), 2e-5f) << "uv " << uv.x << " " << uv.y;
    EXPECT_NEAR(a.x * a.x + a.y * a.y + a.z * a.z, 1.0f, 1e-5f);
    flip_differs += max_diff(flat.eval(uv, 0.003f), b) > 0.01f;
  }
  EXPECT_GT(flip_differs, 250);
}

TEST_F(HexTile, TurnedTilesTurnTheirSlopes) {
  // The texel (0.8, 128 / 255, 0.8) is the tangent-space normal (0.6, e, 0.6)
  // with e = 1 / 255 (8-bit texels cannot hold 0.5): about the height field
  // h(q) = -q.x, falling towards +u. Tiles that read the image turned by +90
  // degrees show h(R(90) p) = -(-p.y) = p.y: a surface rising towards +v, whose
  // normal tilts towards -v: (e, -0.6, 0.6), normalised.
  const float e = 1.0f / 255.0f, len = std::sqrt(0.72f + e * e);
  Doc h(
      hex_normal(
          tilt_,
          R"(<input name="rotationrange" type="vector2" value="90, 90"/><input name="scalerange" type="vector2" value="1, 1"/>)"),
      "normal", "vector3");
  for (float2 uv : sample_uvs(50)) {
    float3 n = h.eval(uv, 0.0f);
    EXPECT_NEAR(n.x, e / len, 1e-5f);
    EXPECT_NEAR(n.y, -0.6f / len, 1e-5f);
    EXPECT_NEAR(n.z, 0.6f / len, 1e-5f);
  }
  // Unturned, the same texel tilts the normal towards +u: (0.6, e, 0.6).
  Doc plain(hex_normal(tilt_, kNoRandomness), "normal", "vector3");
  float3 n = plain.eval(make_float2(0.3f, 0.6f), 0.0f);
  EXPECT_NEAR(n.x, 0.6f / len, 1e-5f);
  EXPECT_NEAR(n.y, e / len, 1e-5f);
}

TEST_F(HexTile, NoFileReadsTheDefault) {
  Doc h(hex("", R"(<input name="default" type="color3" value="0.2, 0.4, 0.6"/>)"), "base_color", "color3");
  float3 c = h.eval(make_float2(0.3f, 0.7f), 0.0f);
  EXPECT_NEAR(c.x, 0.2f, 1e-6f);
  EXPECT_NEAR(c.y, 0.4f, 1e-6f);
  EXPECT_NEAR(c.z, 0.6f, 1e-6f);
  // A normal map without a file is flat: its default texel (0.5, 0.5, 1).
  Doc nm(hex_normal("", ""), "normal", "vector3");
  float3 n = nm.eval(make_float2(0.3f, 0.7f), 0.0f);
  EXPECT_NEAR(n.z, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace pmc
