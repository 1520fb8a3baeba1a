// mtlx_upgrade_reference_test.cpp — pmc's upgrade of MaterialX 1.36-1.38
// documents (mtlx_upgrade.h, mtlx_upgrade_bsdf.h) against the materialx
// Python package's own (Document::upgradeVersion), which scripts/setup
// installs in .venv: each old document is upgraded both ways and the two
// results must give the same surface parameters, plus values worked by hand.
// These tests run the project's Python, so the GPU bundle's suite
// (pmc_device_tests) leaves this file out.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/abi/pmc_bytecode.h"
#include "materials/mtlx_reader.h"
#include "tests/support/material_eval.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

void evaluate(Graph g, float u, float v, float params[PMC_P_COUNT]) {
  test::surface_params_at(std::move(g), u, v, params);
}

const Graph& only(const std::vector<Graph>& graphs) {
  EXPECT_EQ(graphs.size(), 1u);
  EXPECT_EQ(graphs[0].error, "");
  return graphs[0];
}

// Writes the materialx package's upgrade of `old_doc` to `upgraded`; false
// (and a failure naming the command) when it could not run.
bool upgraded_by_materialx(const std::string& old_doc, const std::string& upgraded) {
  const std::string cmd = test::source_path("scripts/python") +
                          " -c \"import MaterialX as mx, sys; d = mx.createDocument(); "
                          "mx.readFromXmlFile(d, sys.argv[1]); mx.writeToXmlFile(d, sys.argv[2])\" " +
                          old_doc + " " + upgraded;
  if (std::system(cmd.c_str()) == 0) return true;
  ADD_FAILURE() << "the materialx Python package (scripts/setup installs it): " << cmd;
  return false;
}

// Old documents: pmc's upgrade against the materialx Python package's.
TEST(MtlxUpgradeReference, OldDocumentsUpgradeLikeMaterialXDoes) {
  const std::string dir = test::temp_dir();
  const std::string old_doc = dir + "/old.mtlx", upgraded = dir + "/upgraded.mtlx";
  test::write_file(
      old_doc,
      "<?xml version=\"1.0\"?>\n<materialx version=\"1.37\">\n"
      "  <nodegraph name=\"NG\">\n"
      "    <constant name=\"c\" type=\"color3\"><parameter name=\"value\" type=\"color3\" "
      "value=\"0.2, 0.4, 0.6\"/></constant>\n"
      "    <multiply name=\"m\" type=\"color3\"><input name=\"in1\" type=\"color3\" nodename=\"c\" "
      "channels=\"bgr\"/><input name=\"in2\" type=\"float\" value=\"0.5\"/></multiply>\n"
      "    <atan2 name=\"a\" type=\"float\"><input name=\"in1\" type=\"float\" value=\"1\"/>"
      "<input name=\"in2\" type=\"float\" value=\"2\"/></atan2>\n"
      "    <output name=\"out\" type=\"color3\" nodename=\"m\"/>\n"
      "    <output name=\"angle\" type=\"float\" nodename=\"a\"/>\n"
      "  </nodegraph>\n"
      "  <material name=\"Mat\">\n"
      "    <shaderref name=\"SR\" node=\"standard_surface\">\n"
      "      <bindinput name=\"base_color\" type=\"color3\" nodegraph=\"NG\" output=\"out\"/>\n"
      "      <bindinput name=\"specular_roughness\" type=\"float\" nodegraph=\"NG\" output=\"angle\"/>\n"
      "      <bindinput name=\"metalness\" type=\"float\" value=\"0.75\"/>\n"
      "    </shaderref>\n"
      "  </material>\n"
      "</materialx>\n");
  ASSERT_TRUE(upgraded_by_materialx(old_doc, upgraded));
  const Graph mine = only(read_mtlx_file(old_doc)), theirs = only(read_mtlx_file(upgraded));
  EXPECT_EQ(mine.material, "Mat");
  EXPECT_EQ(theirs.material, "Mat");
  float a[PMC_P_COUNT], b[PMC_P_COUNT];
  evaluate(mine, 0.3f, 0.6f, a);
  evaluate(theirs, 0.3f, 0.6f, b);
  for (int k = 0; k < PMC_P_COUNT; ++k) EXPECT_EQ(a[k], b[k]) << "parameter " << k;
  EXPECT_NEAR(a[PMC_P_BASE_COLOR], 0.3f, 1e-6f);  // channels "bgr": 0.6 * 0.5
  EXPECT_NEAR(a[PMC_P_SPECULAR_ROUGHNESS], std::atan2(2.0f, 1.0f),
              1e-6f);  // 1.37's atan2(in1, in2) = atan(in2/in1)
  EXPECT_NEAR(a[PMC_P_METALNESS], 0.75f, 1e-6f);

  // 1.38: `channels` on an input fed by a nodegraph output (glTF's packed occlusion/roughness/metal).
  const std::string old38 = dir + "/old38.mtlx", upgraded38 = dir + "/upgraded38.mtlx";
  test::write_file(
      old38,
      "<?xml version=\"1.0\"?>\n<materialx version=\"1.38\">\n"
      "  <nodegraph name=\"NG\">\n"
      "    <constant name=\"orm\" type=\"vector3\"><input name=\"value\" type=\"vector3\" "
      "value=\"1, 0.25, 0.5\"/></constant>\n"
      "    <output name=\"out_orm\" type=\"vector3\" nodename=\"orm\"/>\n"
      "  </nodegraph>\n"
      "  <gltf_pbr name=\"SR\" type=\"surfaceshader\">\n"
      "    <input name=\"metallic\" type=\"float\" nodegraph=\"NG\" output=\"out_orm\" channels=\"z\"/>\n"
      "    <input name=\"roughness\" type=\"float\" nodegraph=\"NG\" output=\"out_orm\" channels=\"y\"/>\n"
      "  </gltf_pbr>\n"
      "  <surfacematerial name=\"M38\" type=\"material\"><input name=\"surfaceshader\" "
      "type=\"surfaceshader\" nodename=\"SR\"/></surfacematerial>\n"
      "</materialx>\n");
  ASSERT_TRUE(upgraded_by_materialx(old38, upgraded38));
  evaluate(only(read_mtlx_file(old38)), 0.3f, 0.6f, a);
  evaluate(only(read_mtlx_file(upgraded38)), 0.3f, 0.6f, b);
  for (int k = 0; k < PMC_P_COUNT; ++k) EXPECT_EQ(a[k], b[k]) << "1.38 parameter " << k;
  EXPECT_NEAR(a[PMC_P_METALNESS], 0.5f, 1e-6f);
  EXPECT_NEAR(a[PMC_P_SPECULAR_ROUGHNESS], 0.25f, 1e-6f);

  // 1.37's color2 (channels r and a) became vector2: separate2's outputs, a
  // swizzle's channels and an input's `channels` follow.
  const std::string old37 = dir + "/old37.mtlx", upgraded37 = dir + "/upgraded37.mtlx";
  test::write_file(
      old37,
      "<?xml version=\"1.0\"?>\n<materialx version=\"1.37\">\n"
      "  <nodegraph name=\"NG\">\n"
      "    <constant name=\"c\" type=\"color2\"><parameter name=\"value\" type=\"color2\" "
      "value=\"0.25, 0.75\"/></constant>\n"
      "    <separate2 name=\"s\" type=\"multioutput\"><input name=\"in\" type=\"color2\" "
      "nodename=\"c\"/></separate2>\n"
      "    <combine3 name=\"k\" type=\"color3\"><input name=\"in1\" type=\"float\" nodename=\"s\" "
      "output=\"outa\"/><input name=\"in2\" type=\"float\" nodename=\"s\" output=\"outr\"/>"
      "<input name=\"in3\" type=\"float\" value=\"0.5\"/></combine3>\n"
      "    <swizzle name=\"w\" type=\"color3\"><input name=\"in\" type=\"color2\" nodename=\"c\"/>"
      "<parameter name=\"channels\" type=\"string\" value=\"arr\"/></swizzle>\n"
      "    <multiply name=\"m\" type=\"float\"><input name=\"in1\" type=\"float\" nodename=\"c\" "
      "channels=\"a\"/><input name=\"in2\" type=\"float\" value=\"0.5\"/></multiply>\n"
      "    <output name=\"out\" type=\"color3\" nodename=\"k\"/>\n"
      "    <output name=\"out2\" type=\"color3\" nodename=\"w\"/>\n"
      "    <output name=\"out3\" type=\"float\" nodename=\"m\"/>\n"
      "  </nodegraph>\n"
      "  <standard_surface name=\"SR\" type=\"surfaceshader\">\n"
      "    <input name=\"base_color\" type=\"color3\" nodegraph=\"NG\" output=\"out\"/>\n"
      "    <input name=\"specular_color\" type=\"color3\" nodegraph=\"NG\" output=\"out2\"/>\n"
      "    <input name=\"specular_roughness\" type=\"float\" nodegraph=\"NG\" output=\"out3\"/>\n"
      "  </standard_surface>\n"
      "  <surfacematerial name=\"M37\" type=\"material\"><input name=\"surfaceshader\" "
      "type=\"surfaceshader\" nodename=\"SR\"/></surfacematerial>\n"
      "</materialx>\n");
  ASSERT_TRUE(upgraded_by_materialx(old37, upgraded37));
  ASSERT_EQ(test::read_file(upgraded37).find("color2"), std::string::npos) << "MaterialX kept a color2";
  evaluate(only(read_mtlx_file(old37)), 0.3f, 0.6f, a);
  evaluate(only(read_mtlx_file(upgraded37)), 0.3f, 0.6f, b);
  for (int k = 0; k < PMC_P_COUNT; ++k) EXPECT_EQ(a[k], b[k]) << "1.37 color2 parameter " << k;
  EXPECT_NEAR(a[PMC_P_BASE_COLOR + 0], 0.75f, 1e-6f);      // outa
  EXPECT_NEAR(a[PMC_P_BASE_COLOR + 1], 0.25f, 1e-6f);      // outr
  EXPECT_NEAR(a[PMC_P_SPECULAR_COLOR + 0], 0.75f, 1e-6f);  // "arr"
  EXPECT_NEAR(a[PMC_P_SPECULAR_COLOR + 1], 0.25f, 1e-6f);
  EXPECT_NEAR(a[PMC_P_SPECULAR_ROUGHNESS], 0.375f, 1e-6f);  // channels "a" x 0.5
}

// 1.37's BSDF nodes (renamed, nested `base` layering, conductor_brdf's
// artistic parameters) and 1.38's thin-film layers, upgraded by pmc and by
// the materialx package: the same closure graph, so the same parameters.
TEST(MtlxUpgradeReference, OldClosureGraphsUpgradeLikeMaterialXDoes) {
  const std::string dir = test::temp_dir();
  const char* docs[] = {
      "<?xml version=\"1.0\"?>\n<materialx version=\"1.37\">\n"
      "  <nodegraph name=\"NG\">\n"
      "    <diffuse_brdf name=\"d\" type=\"BSDF\"><input name=\"color\" type=\"color3\" "
      "value=\"0.5, 0.25, 0.125\"/></diffuse_brdf>\n"
      "    <dielectric_brdf name=\"c\" type=\"BSDF\"><input name=\"ior\" type=\"float\" value=\"1.7\"/>"
      "<input name=\"base\" type=\"BSDF\" nodename=\"d\"/></dielectric_brdf>\n"
      "    <conductor_brdf name=\"m\" type=\"BSDF\"><input name=\"reflectivity\" type=\"color3\" "
      "value=\"0.9, 0.5, 0.2\"/><input name=\"edge_color\" type=\"color3\" value=\"1, 1, "
      "1\"/></conductor_brdf>\n"
      "    <diffuse_btdf name=\"t\" type=\"BSDF\"/>\n"
      "    <add name=\"a\" type=\"BSDF\"><input name=\"in1\" type=\"BSDF\" nodename=\"c\"/>"
      "<input name=\"in2\" type=\"BSDF\" nodename=\"t\"/></add>\n"
      "    <mix name=\"x\" type=\"BSDF\"><input name=\"fg\" type=\"BSDF\" nodename=\"m\"/>"
      "<input name=\"bg\" type=\"BSDF\" nodename=\"a\"/><input name=\"mix\" type=\"float\" "
      "value=\"0.25\"/></mix>\n"
      "    <surface name=\"s\" type=\"surfaceshader\"><input name=\"bsdf\" type=\"BSDF\" nodename=\"x\"/>"
      "<input name=\"opacity\" type=\"float\" value=\"1\"/></surface>\n"
      "    <output name=\"out\" type=\"surfaceshader\" nodename=\"s\"/>\n"
      "  </nodegraph>\n</materialx>\n",
      "<?xml version=\"1.0\"?>\n<materialx version=\"1.38\">\n"
      "  <nodegraph name=\"NG\">\n"
      "    <oren_nayar_diffuse_bsdf name=\"d\" type=\"BSDF\"/>\n"
      "    <dielectric_bsdf name=\"c\" type=\"BSDF\"><input name=\"ior\" type=\"float\" "
      "value=\"1.4\"/></dielectric_bsdf>\n"
      "    <layer name=\"l\" type=\"BSDF\"><input name=\"top\" type=\"BSDF\" nodename=\"c\"/>"
      "<input name=\"base\" type=\"BSDF\" nodename=\"d\"/></layer>\n"
      "    <thin_film_bsdf name=\"film\" type=\"BSDF\"><input name=\"thickness\" type=\"float\" "
      "value=\"500\"/>"
      "<input name=\"ior\" type=\"float\" value=\"1.3\"/></thin_film_bsdf>\n"
      "    <layer name=\"fl\" type=\"BSDF\"><input name=\"top\" type=\"BSDF\" nodename=\"film\"/>"
      "<input name=\"base\" type=\"BSDF\" nodename=\"l\"/></layer>\n"
      "    <surface name=\"s\" type=\"surfaceshader\"><input name=\"bsdf\" type=\"BSDF\" "
      "nodename=\"fl\"/></surface>\n"
      "    <output name=\"out\" type=\"surfaceshader\" nodename=\"s\"/>\n"
      "  </nodegraph>\n</materialx>\n"};
  for (int i = 0; i < 2; ++i) {
    const std::string old_doc = dir + "/old" + std::to_string(i) + ".mtlx";
    const std::string upgraded = dir + "/upgraded" + std::to_string(i) + ".mtlx";
    test::write_file(old_doc, docs[i]);
    ASSERT_TRUE(upgraded_by_materialx(old_doc, upgraded));
    testing::internal::CaptureStderr();  // the flattening's notes (transmission, thin film)
    const Graph mine = only(read_mtlx_file(old_doc)), theirs = only(read_mtlx_file(upgraded));
    const std::string notes = testing::internal::GetCapturedStderr();
    EXPECT_NE(notes.find(i == 0 ? "translucent_bsdf" : "dielectric_bsdf thin film"), std::string::npos)
        << notes;
    float a[PMC_P_COUNT], b[PMC_P_COUNT];
    evaluate(mine, 0.3f, 0.6f, a);
    evaluate(theirs, 0.3f, 0.6f, b);
    for (int k = 0; k < PMC_P_COUNT; ++k) EXPECT_EQ(a[k], b[k]) << "document " << i << " parameter " << k;
  }
  // By hand, the 1.37 document: mix 0.25 of the conductor (F0 = reflectivity)
  // over the coated diffuse (F0(1.7) over a base that keeps 1 - F0).
  float p[PMC_P_COUNT];
  testing::internal::CaptureStderr();
  evaluate(only(read_mtlx_file(dir + "/old0.mtlx")), 0.3f, 0.6f, p);
  testing::internal::GetCapturedStderr();
  const float f0 = std::pow(0.7f / 2.7f, 2.0f);
  EXPECT_NEAR(p[PMC_P_SPECULAR_COLOR], 0.25f * 0.9f + 0.75f * f0, 1e-6f);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR + 1], 0.75f * 0.25f * (1 - f0), 1e-6f);
}

}  // namespace
}  // namespace pmc
