// hextile_render_test.cpp — a MaterialX document with hextiledimage (base
// colour) and hextilednormalmap (normal), MaterialX's default tile
// randomness, rendered on a plane through the OpenCL renderer with the
// material cache off and on: every pixel finite, the image not black, and the
// hex-tiled material not the plain tiled one (tests/materials/hextile_test.cpp
// checks the nodes' values on the host, interpreter_parity_test.cpp the
// device against the host).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/hard_cases/hard_support.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

const char* kPlane = R"(v -1 -1 0
v 1 -1 0
v 1 1 0
v -1 1 0
vt 0 0
vt 2 0
vt 2 2
vt 0 2
vn 0 0 1
usemtl M
f 1/1/1 2/2/1 3/3/1
f 1/1/1 3/3/1 4/4/1
)";

std::string document(const std::string& image, const std::string& normals, bool hex) {
  const std::string color =
      hex ? R"(<hextiledimage name="c" type="color3"><input name="file" type="filename" value=")" + image +
                R"("/><input name="tiling" type="vector2" value="3, 3"/></hextiledimage>)"
          : R"(<tiledimage name="c" type="color3"><input name="file" type="filename" value=")" + image +
                R"("/><input name="uvtiling" type="vector2" value="3, 3"/></tiledimage>)";
  return R"(<?xml version="1.0"?><materialx version="1.39">)" + color +
         R"(<hextilednormalmap name="n" type="vector3"><input name="file" type="filename" value=")" +
         normals +
         R"("/><input name="tiling" type="vector2" value="3, 3"/></hextilednormalmap>
<standard_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="c"/><input name="normal" type="vector3" nodename="n"/></standard_surface>
<surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial></materialx>)";
}

TEST(HexTileRender, DocumentRendersFinitePixels) {
  const std::string dir = test::temp_dir();
  hard::write_checker_png(dir + "/checker.png");
  std::vector<float> px;
  for (int k = 0; k < 64; ++k) px.insert(px.end(), {0.4f + 0.003f * float(k), 0.55f, 0.9f});
  hard::write_image(dir + "/normals.png", 8, 8, 3, px);
  test::write_file(dir + "/plane.obj", kPlane);
  test::write_file(dir + "/hex.mtlx", document(dir + "/checker.png", dir + "/normals.png", true));
  test::write_file(dir + "/tiled.mtlx", document(dir + "/checker.png", dir + "/normals.png", false));
  RenderConfig s = hard::small_config(48, 48, 4, 3);
  hard::set_camera(s, 0, 0, 3, 0, 0, 0, 30.0f);
  s.env = {1.0f, 1.0f, 1.0f};
  std::vector<float> means;
  for (bool cache : {false, true}) {
    hard::Rendered r = hard::render({dir + "/plane.obj", {dir + "/hex.mtlx"}, ""}, s, cache);
    hard::expect_clean(r.out, cache ? "hex, cache on" : "hex, cache off");
    EXPECT_GT(test::image_mean(r.out.image), 0.01);
    hard::Rendered t = hard::render({dir + "/plane.obj", {dir + "/tiled.mtlx"}, ""}, s, cache);
    hard::expect_clean(t.out, "tiled");
    const auto& a = r.out.image.pixels;
    const auto& b = t.out.image.pixels;
    ASSERT_EQ(a.size(), b.size());
    double diff = 0;
    for (size_t i = 0; i < a.size(); ++i) diff += std::fabs(double(a[i]) - double(b[i]));
    EXPECT_GT(diff / double(a.size()), 1e-3) << "the hex-tiled plane looks like the tiled one";
  }
}

}  // namespace
}  // namespace pmc
