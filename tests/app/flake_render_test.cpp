// flake_render_test.cpp — a MaterialX document with flake2d renders through
// `pmc render` (OpenCL on PoCL): the MaterialX sphere, its base colour a mix of
// gold flakes over dark blue by the flakes' presence, its normal their
// flakenormal. With coverage 0 there are no flakes (the sphere is blue: red
// minus blue is negative); with coverage 0.8 the gold shows (red minus blue
// turns positive), and no pixel is NaN or infinite. Measured on PoCL: mean
// red - blue over the sphere -0.17 without flakes, +0.27 with them.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/image_io.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

std::string flake_document(float coverage) {
  return R"(<?xml version="1.0"?>
<materialx version="1.39">
  <flake2d name="flakes" type="multioutput">
    <input name="size" type="float" value="0.02"/>
    <input name="roughness" type="float" value="0.4"/>
    <input name="coverage" type="float" value=")" +
         std::to_string(coverage) + R"("/>
  </flake2d>
  <mix name="paint" type="color3">
    <input name="fg" type="color3" value="1.0, 0.75, 0.2"/>
    <input name="bg" type="color3" value="0.02, 0.03, 0.2"/>
    <input name="mix" type="float" nodename="flakes" output="presence"/>
  </mix>
  <standard_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodename="paint"/>
    <input name="normal" type="vector3" nodename="flakes" output="flakenormal"/>
    <input name="specular_roughness" type="float" value="0.3"/>
  </standard_surface>
  <surfacematerial name="M_Flakes" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S"/>
  </surfacematerial>
</materialx>
)";
}

TEST(FlakeRender, Flake2dDocumentRendersOnTheSphere) {
  const std::string sphere = test::shared_scene("materialx/geometry/sphere.obj");
  const std::string dir = test::temp_dir();
  double red[2];  // mean red - blue
  int i = 0;
  for (float coverage : {0.0f, 0.8f}) {
    const std::string doc = dir + "/flakes" + std::to_string(i) + ".mtlx";
    test::write_file(doc, flake_document(coverage));
    const std::string out = dir + "/flakes" + std::to_string(i) + ".exr";
    std::string log;
    ASSERT_EQ(test::run_pmc("render " + sphere + " --mtlx " + doc +
                                " --material M_Flakes --env 1,1,1 --width 64 --height 64 --spp 4 --seed 1 "
                                "--quiet -o " +
                                out,
                            &log),
              0)
        << log;
    Image img = read_image(out);
    ASSERT_EQ(test::non_finite(img), 0u);
    // Mean red - blue over the sphere's pixels (the background is the white
    // environment, exactly 1).
    double sum = 0;
    size_t n = 0;
    for (size_t p = 0; p + 2 < img.pixels.size(); p += size_t(img.channels)) {
      const float* c = &img.pixels[p];
      if (std::fabs(c[0] - 1.0f) + std::fabs(c[1] - 1.0f) + std::fabs(c[2] - 1.0f) < 1e-4f) continue;
      sum += c[0] - c[2];
      ++n;
    }
    ASSERT_GT(n, 200u) << "the sphere covers too few pixels";
    red[i++] = sum / double(n);
  }
  // Blue paint: red - blue < 0; gold flakes on much of the sphere make it positive.
  RecordProperty("red_minus_blue_no_flakes", std::to_string(red[0]));
  RecordProperty("red_minus_blue_coverage_0_8", std::to_string(red[1]));
  EXPECT_LT(red[0], -0.05) << "no flakes";
  EXPECT_GT(red[1], 0.05) << "coverage 0.8";
}

}  // namespace
}  // namespace pmc
