// cutout_program_test.cpp — the cut-out test in Embree's filters runs a
// program of the opacity's nodes alone (MaterialSet::cutout_program).
//
// The independent answer is the material's whole program, run by the same
// host interpreter: at every candidate hit the opacity-only program must say
// "transparent" exactly where the whole material's opacity is below 0.5,
// while running fewer instructions (no base-colour network).
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "core/obj_loader.h"
#include "materials/cpu_interpreter.h"
#include "materials/cutout.h"
#include "materials/material_set.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

// Opacity: a checkerboard (white and black squares); base
// colour: a position-driven fractal noise that the cut-out test never needs.
const char* kCutoutDoc = R"(<?xml version="1.0"?>
<materialx version="1.39">
  <checkerboard name="chk" type="color3">
    <input name="uvtiling" type="vector2" value="6, 6"/>
  </checkerboard>
  <fractal3d name="fbm" type="color3">
    <input name="octaves" type="integer" value="5"/>
  </fractal3d>
  <standard_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodename="fbm"/>
    <input name="opacity" type="color3" nodename="chk"/>
  </standard_surface>
  <surfacematerial name="Leaf" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S"/>
  </surfacematerial>
  <standard_surface name="S2" type="surfaceshader">
    <input name="base_color" type="color3" nodename="fbm"/>
  </standard_surface>
  <surfacematerial name="Solid" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S2"/>
  </surfacematerial>
</materialx>
)";

TEST(CutoutProgram, OpacityAloneAgreesWithTheWholeMaterial) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/m.mtlx", kCutoutDoc);
  test::write_file(dir + "/q.obj",
                   "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                   "usemtl Leaf\nf 1/1 2/2 3/3 4/4\nusemtl Solid\nf 1/1 3/3 4/4\n");
  Scene scene = load_obj(dir + "/q.obj");
  MaterialOptions opts;
  opts.mtlx_files = {dir + "/m.mtlx"};
  MaterialSet set = build_material_set(scene, opts);
  ASSERT_EQ(scene.triangles.size(), 3u);
  const int leaf = scene.triangles[0].material, solid = scene.triangles[2].material;
  ASSERT_GE(set.cutout_entry[size_t(leaf)], 0) << "a patterned opacity is a cut-out";
  EXPECT_EQ(set.cutout_entry[size_t(solid)], -1) << "no opacity input, no cut-out program";

  const CompiledMaterial& whole = set.program.materials[size_t(set.compiled[size_t(leaf)])];
  ASSERT_EQ(set.cutout_program.materials.size(), 1u);
  const std::string opacity_listing = disassemble(set.cutout_program, set.cutout_program.materials[0]);
  EXPECT_EQ(opacity_listing.find("FRACTAL3D"), std::string::npos) << opacity_listing;
  EXPECT_NE(disassemble(set.program, whole).find("FRACTAL3D"), std::string::npos);
  // position, fractal and the base colour's output are left out
  EXPECT_LE(set.cutout_program.materials[0].instructions + 3, whole.instructions) << opacity_listing;

  CutoutTester tester(scene, set);
  ASSERT_TRUE(tester.any());
  EXPECT_TRUE(tester.cutout_triangles()[0] && tester.cutout_triangles()[1]);
  EXPECT_FALSE(tester.cutout_triangles()[2]);

  const PmcTextureSet ts = host_texture_set(scene, set);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int transparent = 0, opaque = 0;
  for (uint32_t prim = 0; prim < 2; ++prim) {
    const PmcTriangle& t = scene.triangles[prim];
    for (int k = 0; k < 500; ++k) {
      float u = unit(rng), v = unit(rng);
      if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
      const PmcShadingInputs in = cutout_shading_inputs(scene, prim, u, v);
      float p[PMC_P_COUNT];
      evaluate_material(set, ts, t.material, in, p);
      const float opacity = (p[PMC_P_OPACITY] + p[PMC_P_OPACITY + 1] + p[PMC_P_OPACITY + 2]) / 3.0f;
      const bool expect = !(opacity >= 0.5f);
      EXPECT_EQ(tester.transparent(prim, u, v), expect)
          << "prim " << prim << " uv " << in.uv.x << ", " << in.uv.y;
      (expect ? transparent : opaque) += 1;
    }
  }
  EXPECT_GT(transparent, 300) << "the checkerboard must cut out about half";
  EXPECT_GT(opaque, 300);
}

}  // namespace
}  // namespace pmc
