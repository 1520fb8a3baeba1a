// lights_cli_test.cpp — lights and the view transform through the pmc binary:
// SCENE.lights.json beside the OBJ is used (and `--lights none` ignores it),
// images with every light type and a map are bit-identical for any thread
// count, the PNG is the EXR through --exposure/--view, and bad lights input
// exits with code 2, names the file and field, and leaves no output.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "core/image_io.h"
#include "core/tone_map.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

// A grey plane y = 0 seen from above (SCENE.camera), with a ball on it.
std::string make_scene(const std::string& dir) {
  test::write_file(dir + "/scene.mtl", "newmtl m\nKd 0.5 0.5 0.5\nKs 0 0 0\n");
  test::write_file(dir + "/scene.camera", "from 0 4 0.01\nat 0 0 0\nup 0 0 -1\nfov 60\n");
  test::write_file(dir + "/scene.obj",
                   "mtllib scene.mtl\nusemtl m\nv -4 0 -4\nv 4 0 -4\nv 4 0 4\nv -4 0 4\nf 1 4 3\nf 1 3 2\n"
                   "v -0.5 0 -0.5\nv 0.5 0 -0.5\nv 0 1 0\nv 0 0 0.5\nf 5 7 6\nf 6 7 8\nf 8 7 5\n");
  return dir + "/scene.obj";
}

void write_map(const std::string& path) {
  Image img;
  img.width = 16;
  img.height = 8;
  img.channels = 3;
  img.pixels.resize(16 * 8 * 3);
  for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = 0.1f + 0.05f * float(i % 7);
  img.pixels[3 * 20] = 80.0f;  // a bright texel high in the sky
  write_exr(path, img);
}

const char* kAllLights = R"({
  "environment": {"map": "sky.exr", "scale": 0.8, "rotate_y_deg": 30},
  "lights": [
    {"type": "point", "position": [1, 1.5, 0], "intensity": [2, 1.5, 1]},
    {"type": "spot", "position": [-1, 2, 0], "direction": [0.3, -1, 0], "intensity": [4, 4, 4],
     "cone_angle_deg": 50, "blend": 0.3},
    {"type": "directional", "direction": [-0.3, -1, -0.2], "irradiance": [1, 1, 0.9], "angle_deg": 2},
    {"type": "directional", "direction": [0.2, -1, 0.1], "irradiance": [0.3, 0.3, 0.3]},
    {"type": "quad", "corner": [-0.5, 1.2, 0.5], "edge_u": [1, 0, 0], "edge_v": [0, 0, 0.5],
     "radiance": [3, 3, 3]}]})";

TEST(LightsCli, LightsFileBesideTheSceneIsUsedAndNoneIgnoresIt) {
  const std::string dir = test::temp_dir();
  const std::string obj = make_scene(dir);
  test::write_file(dir + "/scene.lights.json",
                   R"({"lights": [{"type": "point", "position": [0, 2, 1], "intensity": [3, 3, 3]}]})");
  const std::string common = obj + " --width 16 --height 16 --spp 2 --quiet";
  std::string log;
  ASSERT_EQ(test::run_pmc("render " + common + " -o " + dir + "/lit.exr", &log), 0) << log;
  EXPECT_GT(test::image_mean(read_image(dir + "/lit.exr")), 0.01);
  ASSERT_EQ(test::run_pmc("render " + common + " --lights none -o " + dir + "/dark.exr", &log), 0) << log;
  EXPECT_EQ(test::image_mean(read_image(dir + "/dark.exr")), 0.0);
  // --env replaces the file's environment, not its lights; --lights FILE replaces the file beside.
  test::write_file(dir + "/other.json", R"({"environment": {"radiance": [1, 1, 1]}})");
  ASSERT_EQ(
      test::run_pmc("render " + common + " --lights " + dir + "/other.json -o " + dir + "/env.exr", &log), 0)
      << log;
  Image env = read_image(dir + "/env.exr");
  EXPECT_NEAR(env.pixels[0], 0.5f, 1e-3f);  // a corner of the plane: albedo x radiance, nothing above it
}

TEST(LightsCli, EveryLightAndAMapGiveBitIdenticalImagesWithOneAndTwoThreads) {
  const std::string dir = test::temp_dir();
  const std::string obj = make_scene(dir);
  write_map(dir + "/sky.exr");
  test::write_file(dir + "/all.json", kAllLights);
  const std::string common =
      obj + " --lights " + dir + "/all.json --width 32 --height 24 --spp 3 --max-depth 4 --seed 5 --quiet";
  std::string log;
  ASSERT_EQ(test::run_pmc("render " + common + " --threads 1 -o " + dir + "/t1.exr", &log), 0) << log;
  ASSERT_EQ(test::run_pmc("render " + common + " --threads 2 -o " + dir + "/t2.exr", &log), 0) << log;
  Image a = read_image(dir + "/t1.exr"), b = read_image(dir + "/t2.exr");
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  EXPECT_GT(test::image_mean(a), 0.05);
  EXPECT_EQ(test::non_finite(a), 0u);
  EXPECT_EQ(0, std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)));
}

TEST(LightsCli, PngIsTheExrThroughExposureAndView) {
  const std::string dir = test::temp_dir();
  const std::string obj = make_scene(dir);
  std::string log;
  ASSERT_EQ(test::run_pmc("render " + obj +
                              " --width 16 --height 16 --spp 2 --quiet --env 0.9,0.7,0.5 --exposure 1.5 "
                              "--view standard -o " +
                              dir + "/img.exr",
                          &log),
            0)
      << log;
  Image exr = read_image(dir + "/img.exr"), png = read_image(dir + "/img.png");
  ASSERT_EQ(exr.pixels.size(), png.pixels.size());
  ToneMap d;
  d.exposure_ev = 1.5f;
  d.view = ViewTransform::Standard;
  for (size_t i = 0; i < exr.pixels.size(); ++i)
    EXPECT_NEAR(png.pixels[i] * 255.0f, std::round(255.0f * tone_map(exr.pixels[i], d)), 1e-3f) << i;
}

struct BadCase {
  std::string args;
  std::vector<std::string> mentions;
};

TEST(LightsCli, BadLightsInputExitsWithCode2AndLeavesNoOutput) {
  const std::string dir = test::temp_dir();
  const std::string obj = make_scene(dir);
  test::write_file(dir + "/broken.json", R"({"lights": [{"type": "point", "position": [0, 1, 0]}]})");
  test::write_file(dir + "/garbage.hdr", "#?RADIANCE\nnot really\n");
  test::write_file(dir + "/malformed.json", "{\"lights\": [");
  const BadCase cases[] = {
      {"--lights " + dir + "/broken.json", {"broken.json", "lights[0] (point)", "missing 'intensity'"}},
      {"--lights " + dir + "/malformed.json", {"malformed.json", "malformed JSON"}},
      {"--lights " + dir + "/absent.json", {"absent.json"}},
      {"--env-map " + dir + "/garbage.hdr", {"--env-map", "garbage.hdr"}},
      {"--env-map " + dir + "/absent.exr", {"--env-map", "absent.exr"}},
      {"--env 1,1,1 --env-map " + dir + "/garbage.hdr", {"--env", "--env-map"}},
      {"--env-scale 2", {"--env-scale", "no environment"}},
      {"--env 1,1,1 --env-scale -1", {"--env-scale"}},
      {"--env 1,1,1 --env-rotate nan", {"--env-rotate"}},
      {"--env -1,1,1", {"--env"}},
      {"--exposure 100", {"--exposure"}},
      {"--view aces", {"--view", "filmic or standard"}},
  };
  for (const BadCase& c : cases) {
    std::string log;
    EXPECT_EQ(test::run_pmc("render " + obj + " --width 8 --height 8 --spp 1 --quiet " + c.args + " -o " +
                                dir + "/out.exr",
                            &log),
              2)
        << c.args << "\n"
        << log;
    for (const std::string& m : c.mentions)
      EXPECT_NE(log.find(m), std::string::npos) << m << " not in: " << log;
    EXPECT_FALSE(test::file_exists(dir + "/out.exr")) << c.args;
    EXPECT_FALSE(test::file_exists(dir + "/out.png")) << c.args;
  }
  // A bad file beside the scene is found and refused the same way.
  test::write_file(dir + "/scene.lights.json", R"({"lights": [{"type": "laser"}]})");
  std::string log;
  EXPECT_EQ(
      test::run_pmc("render " + obj + " --width 8 --height 8 --spp 1 --quiet -o " + dir + "/out.exr", &log),
      2);
  EXPECT_NE(log.find("scene.lights.json"), std::string::npos) << log;
  EXPECT_NE(log.find("unknown light type 'laser'"), std::string::npos) << log;
  EXPECT_FALSE(test::file_exists(dir + "/out.exr"));
}

}  // namespace
}  // namespace pmc
