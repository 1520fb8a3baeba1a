// lights_file_test.cpp — reading lights files (core/lights.cpp) and
// environment maps (core/env_map.cpp): what a good file means, and that every
// kind of bad file is refused with a message naming the file and the field.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/image_io.h"
#include "core/lights.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

std::string write_lights(const std::string& dir, const std::string& text,
                         const std::string& name = "l.json") {
  const std::string path = dir + "/" + name;
  test::write_file(path, text);
  return path;
}

void write_small_map(const std::string& path, float value, float nan_at_texel = -1) {
  Image img;
  img.width = 8;
  img.height = 4;
  img.channels = 3;
  img.pixels.assign(8 * 4 * 3, value);
  if (nan_at_texel >= 0) img.pixels[3 * size_t(nan_at_texel) + 1] = std::numeric_limits<float>::quiet_NaN();
  write_exr(path, img);
}

TEST(LightsFile, ReadsEveryLightTypeWithItsDefaultsAndConventions) {
  const std::string dir = test::temp_dir();
  write_small_map(dir + "/sky.exr", 0.5f);
  const std::string path = write_lights(dir, R"({
    "environment": {"map": "sky.exr", "scale": 2.0, "rotate_y_deg": 90},
    "lights": [
      {"type": "point", "name": "bulb", "position": [1, 2, 3], "intensity": [10, 20, 30]},
      {"type": "spot", "position": [0, 3, 0], "direction": [0, -2, 0], "intensity": [5, 5, 5]},
      {"type": "spot", "position": [0, 3, 0], "direction": [1, 0, 0], "intensity": [5, 5, 5],
       "cone_angle_deg": 30, "blend": 0.5},
      {"type": "directional", "direction": [0, -3, 4], "irradiance": [1, 1, 1], "angle_deg": 0.53},
      {"type": "directional", "direction": [0, -1, 0], "irradiance": [2, 2, 2]},
      {"type": "quad", "corner": [0, 2, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1], "radiance": [4, 4, 4],
       "two_sided": true}
    ]})");
  SceneLights sl = read_lights_file(path);
  EXPECT_EQ(sl.source, path);
  ASSERT_EQ(sl.lights.size(), 6u);
  EXPECT_EQ(sl.lights[0].type, LightSpec::Type::Point);
  EXPECT_EQ(sl.lights[0].position[2], 3.0f);
  EXPECT_EQ(sl.lights[0].rgb[1], 20.0f);
  EXPECT_EQ(sl.lights[1].type, LightSpec::Type::Spot);
  EXPECT_EQ(sl.lights[1].direction[1], -1.0f);    // normalised
  EXPECT_EQ(sl.lights[1].cone_angle_deg, 45.0f);  // defaults
  EXPECT_EQ(sl.lights[1].blend, 0.15f);
  EXPECT_EQ(sl.lights[2].cone_angle_deg, 30.0f);
  EXPECT_EQ(sl.lights[2].blend, 0.5f);
  EXPECT_NEAR(sl.lights[3].direction[1], -0.6f, 1e-7f);
  EXPECT_NEAR(sl.lights[3].direction[2], 0.8f, 1e-7f);
  EXPECT_EQ(sl.lights[3].angle_deg, 0.53f);
  EXPECT_EQ(sl.lights[4].angle_deg, 0.0f);  // a delta light
  EXPECT_TRUE(sl.lights[5].two_sided);
  ASSERT_TRUE(sl.environment.present);
  ASSERT_TRUE(sl.environment.map);  // resolved beside the lights file
  EXPECT_EQ(sl.environment.map->width, 8);
  EXPECT_EQ(sl.environment.scale, 2.0f);
  EXPECT_EQ(sl.environment.rotate_y_deg, 90.0f);
  // The table: environment, sun | directional delta | quad | the rest.
  LightTable t = build_light_table(Scene{}, {}, sl);
  ASSERT_EQ(t.lights.size(), 7u);
  EXPECT_EQ(t.lights[0].type, PMC_LIGHT_ENV);
  EXPECT_EQ(t.lights[1].type, PMC_LIGHT_SUN);
  EXPECT_EQ(t.lights[2].type, PMC_LIGHT_DIRECTIONAL);
  EXPECT_EQ(t.lights[3].type, PMC_LIGHT_QUAD);
  EXPECT_EQ(t.header.at_infinity, 2);
  EXPECT_EQ(t.header.distant_end, 3);
  EXPECT_EQ(t.header.quad_end, 4);
  EXPECT_EQ(t.header.tree_nodes, 2 * 4 - 1);  // over the quad, the point and the two spots
  EXPECT_EQ(t.header.env, PMC_ENV_MAP);
  // The sun's radiance: irradiance / (pi sin^2(half angle)).
  const double half = 0.265 * 3.14159265358979 / 180.0;
  EXPECT_NEAR(t.lights[1].rgb[0], 1.0 / (3.14159265358979 * std::sin(half) * std::sin(half)), 1.0);
  EXPECT_NEAR(t.lights[1].one_minus_cos, 1.0 - std::cos(half), 1e-10);
  // A constant environment instead of a map.
  SceneLights c = read_lights_file(write_lights(dir, R"({"environment": {"radiance": [0.1, 0.2, 0.3]}})"));
  EXPECT_TRUE(c.environment.present);
  EXPECT_FALSE(c.environment.map);
  EXPECT_EQ(c.environment.radiance[2], 0.3f);
  EXPECT_TRUE(c.lights.empty());
}

struct BadFile {
  const char* json;
  std::vector<const char*> mentions;  // besides the file's path
};

TEST(LightsFile, BadFilesNameTheFileAndTheField) {
  const std::string dir = test::temp_dir();
  write_small_map(dir + "/nan.exr", 1.0f, 5);
  test::write_file(dir + "/corrupt.exr", "this is not an OpenEXR file at all, just text");
  const BadFile cases[] = {
      {"{", {"malformed JSON", "line"}},
      {R"({"lights": [{"type": "point", "position": [0, 1, 0], "intensity": [1, 1, 1]},]})",
       {"malformed JSON"}},
      {R"({"lights": [{"type": "point", "position": [NaN, 1, 0], "intensity": [1, 1, 1]}]})",
       {"malformed JSON"}},
      {"[1, 2]", {"JSON object"}},
      {R"({"light": []})", {"unknown field 'light'"}},
      {R"({"lights": {}})", {"'lights' must be an array"}},
      {R"({"lights": [3]})", {"lights[0]", "JSON object"}},
      {R"({"lights": [{"position": [0, 1, 0]}]})", {"lights[0]", "missing 'type'"}},
      {R"({"lights": [{"type": 7}]})", {"lights[0]", "'type' must be a string"}},
      {R"({"lights": [{"type": "area"}]})", {"lights[0]", "unknown light type 'area'"}},
      {R"({"lights": [{"type": "point", "intensity": [1, 1, 1]}]})",
       {"lights[0] (point)", "missing 'position'"}},
      {R"({"lights": [{"type": "point", "position": [0, 1], "intensity": [1, 1, 1]}]})",
       {"lights[0] (point)", "'position'", "3 numbers"}},
      {R"({"lights": [{"type": "point", "position": [0, 1, 0, 2], "intensity": [1, 1, 1]}]})",
       {"'position'", "3 numbers"}},
      {R"({"lights": [{"type": "point", "position": [0, "1", 0], "intensity": [1, 1, 1]}]})",
       {"'position'", "3 numbers"}},
      {R"({"lights": [{"type": "point", "position": [0, 1e400, 0], "intensity": [1, 1, 1]}]})",
       {"malformed JSON", "1e400"}},
      {R"({"lights": [{"type": "point", "position": [0, 1e39, 0], "intensity": [1, 1, 1]}]})",
       {"'position'", "not a finite float"}},
      {R"({"lights": [{"type": "point", "position": [0, 1, 0], "intensity": [1, -1, 1]}]})",
       {"'intensity'", "negative"}},
      {R"({"lights": [{"type": "point", "position": [0, 1, 0], "intensty": [1, 1, 1], "intensity": [1, 1, 1]}]})",
       {"unknown field 'intensty'"}},
      {R"({"lights": [{"type": "point", "position": [0, 1, 0], "intensity": [1, 1, 1]},
                      {"type": "spot", "position": [0, 1, 0], "direction": [0, 0, 0], "intensity": [1, 1, 1]}]})",
       {"lights[1] (spot)", "'direction'", "zero vector"}},
      {R"({"lights": [{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "intensity": [1, 1, 1],
                       "cone_angle_deg": 0}]})",
       {"'cone_angle_deg'", "(0, 180]"}},
      {R"({"lights": [{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "intensity": [1, 1, 1],
                       "cone_angle_deg": 200}]})",
       {"'cone_angle_deg'"}},
      {R"({"lights": [{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "intensity": [1, 1, 1],
                       "blend": 1.5}]})",
       {"'blend'", "[0, 1]"}},
      {R"({"lights": [{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "intensity": [1, 1, 1],
                       "blend": "soft"}]})",
       {"'blend'", "must be a number"}},
      {R"({"lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1], "angle_deg": -1}]})",
       {"lights[0] (directional)", "'angle_deg'"}},
      {R"({"lights": [{"type": "directional", "direction": [0, -1, 0]}]})", {"missing 'irradiance'"}},
      {R"({"lights": [{"type": "quad", "corner": [0, 1, 0], "edge_u": [1, 0, 0], "edge_v": [2, 0, 0],
                       "radiance": [1, 1, 1]}]})",
       {"lights[0] (quad)", "span no area"}},
      {R"({"lights": [{"type": "quad", "corner": [0, 1, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1],
                       "radiance": [1, 1, 1], "two_sided": "yes"}]})",
       {"'two_sided'", "true or false"}},
      {R"({"environment": {}})", {"environment", "needs 'radiance' or 'map'"}},
      {R"({"environment": {"radiance": [1, 1, 1], "map": "sky.exr"}})", {"environment", "not both"}},
      {R"({"environment": {"radiance": [1, -1, 1]}})", {"environment", "'radiance'", "negative"}},
      {R"({"environment": {"radiance": [1, 1, 1], "scale": -2}})", {"environment", "'scale'"}},
      {R"({"environment": {"radiance": [1, 1, 1], "brightness": 2}})",
       {"environment", "unknown field 'brightness'"}},
      {R"({"environment": {"map": 5}})", {"environment", "'map'", "string"}},
      {R"({"environment": {"map": "missing.exr"}})", {"environment.map", "missing.exr"}},
      {R"({"environment": {"map": "corrupt.exr"}})", {"environment.map", "corrupt.exr"}},
      {R"({"environment": {"map": "nan.exr"}})", {"environment.map", "nan.exr", "NaN"}},
  };
  for (const BadFile& c : cases) {
    const std::string path = write_lights(dir, c.json, "bad.lights.json");
    try {
      read_lights_file(path);
      ADD_FAILURE() << "accepted: " << c.json;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      for (const char* m : c.mentions)
        EXPECT_NE(what.find(m), std::string::npos) << "'" << m << "' not in: " << what;
    }
  }
  EXPECT_THROW(read_lights_file(dir + "/absent.json"), Error);
}

TEST(EnvMapFile, LoadsGreyAndRgbMapsAndRefusesBadOnes) {
  const std::string dir = test::temp_dir();
  Image grey;
  grey.width = 4;
  grey.height = 2;
  grey.channels = 1;
  grey.pixels = {1, 2, 3, 4, 5, 6, 7, -8};
  write_exr(dir + "/grey.exr", grey);
  EnvMap m = load_env_map(dir + "/grey.exr");  // warns about the negative texel
  ASSERT_EQ(m.width, 4);
  EXPECT_EQ(m.rgb()[3 * 2 + 0], 3.0f);
  EXPECT_EQ(m.rgb()[3 * 2 + 2], 3.0f);
  EXPECT_EQ(m.rgb()[3 * 7 + 1], 0.0f);
  EXPECT_FLOAT_EQ(m.marginal()[m.height - 1], 1.0f);
  EXPECT_FLOAT_EQ(m.conditional()[3], 1.0f);
  // Row weights: luminance x sin(row centre) (rows at 45 and 135 degrees).
  const double s = std::sin(3.14159265358979 / 4.0);
  EXPECT_NEAR(m.integral, (1 + 2 + 3 + 4) * s + (5 + 6 + 7) * s, 1e-9);
  EXPECT_NEAR(m.marginal()[0], 10.0 / 28.0, 1e-7);
  try {
    load_env_map(dir + "/none.hdr");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("none.hdr"), std::string::npos);
  }
}

}  // namespace
}  // namespace pmc
