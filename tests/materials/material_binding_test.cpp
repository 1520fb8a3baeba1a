// material_binding_test.cpp — which material each OBJ triangle gets
// (materials/material_set.h): usemtl names bind MaterialX materials whether
// or not an MTL defines them, MaterialX <look>/<materialassign> assigns
// materials to OBJ objects and groups by the specification's geometry paths
// and wins over usemtl, and unmatched names are reported.
//
// The answer for each triangle is checked by evaluating its bound program on
// the host: every material here has a distinct constant base colour.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/error.h"
#include "core/obj_loader.h"
#include "materials/cpu_interpreter.h"
#include "materials/material_set.h"
#include "materials/mtlx_reader.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

// A document with materials named `names`, material i having base colour (i + 1) / 10.
std::string materials_doc(const std::vector<std::string>& names, const std::string& extra = "") {
  std::string xml = "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n";
  for (size_t i = 0; i < names.size(); ++i) {
    std::string v = std::to_string(float(i + 1) / 10.0f);
    xml += "<standard_surface name=\"S" + std::to_string(i) +
           "\" type=\"surfaceshader\"><input name=\"base_color\" "
           "type=\"color3\" value=\"" +
           v + ", " + v + ", " + v + "\"/></standard_surface>\n";
    xml += "<surfacematerial name=\"" + names[i] +
           "\" type=\"material\"><input name=\"surfaceshader\" "
           "type=\"surfaceshader\" nodename=\"S" +
           std::to_string(i) + "\"/></surfacematerial>\n";
  }
  return xml + extra + "</materialx>\n";
}

// Base colour (red channel) of each triangle's bound material.
std::vector<float> bound_colors(Scene& scene, const MaterialSet& set) {
  PmcTextureSet ts = host_texture_set(scene, set);
  std::vector<float> out;
  for (const PmcTriangle& t : scene.triangles) {
    PmcShadingInputs in{};
    in.normal = make_float3(0, 0, 1);
    float p[PMC_P_COUNT];
    evaluate_material(set, ts, t.material, in, p);
    out.push_back(p[PMC_P_BASE_COLOR]);
  }
  return out;
}

const char* kTri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST(MaterialBinding, UsemtlBindsMaterialXWithoutAnyMtl) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/a.obj", std::string(kTri) + "usemtl M_Brick\nf 1 2 3\nusemtl Other\nf 1 3 2\n");
  test::write_file(dir + "/m.mtlx", materials_doc({"Other", "M_Brick"}));
  Scene scene = load_obj(dir + "/a.obj");
  MaterialOptions opts;
  opts.mtlx_files = {dir + "/m.mtlx"};
  MaterialSet set = build_material_set(scene, opts);
  std::vector<float> c = bound_colors(scene, set);
  EXPECT_NEAR(c[0], 0.2f, 1e-6f) << "M_Brick, not the default grey";
  EXPECT_NEAR(c[1], 0.1f, 1e-6f);
}

TEST(MaterialBinding, UsemtlNamesThatMatchNothingAreListedInOneWarning) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/a.obj", std::string(kTri) + "usemtl Typo1\nf 1 2 3\nusemtl Typo2\nf 1 3 2\n");
  test::write_file(dir + "/m.mtlx", materials_doc({"Real"}));
  std::string out;
  int rc = test::run_pmc("info --scene " + dir + "/a.obj --mtlx " + dir + "/m.mtlx --dump-bytecode", &out);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("usemtl names that match no MTL or MaterialX material (rendered with the default "
                     "material): Typo1, Typo2"),
            std::string::npos)
      << out;
}

TEST(MaterialBinding, LooksAssignByObjectAndGroupAndWinOverUsemtl) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/a.obj", std::string(kTri) +
                                       "o wall_north\nusemtl Plain\nf 1 2 3\n"
                                       "o wall_south\nusemtl Plain\nf 1 3 2\n"
                                       "g shelf\nusemtl Plain\nf 2 1 3\n"
                                       "o floor\nusemtl Plain\nf 2 3 1\n"
                                       "o lamp\nf 3 1 2\n");
  const std::string looks =
      "<collection name=\"C_walls\" includegeom=\"/wall_*\" excludegeom=\"/wall_south\"/>\n"
      "<look name=\"L\">\n"
      "  <materialassign name=\"a1\" material=\"Walls\" collection=\"C_walls\"/>\n"
      "  <materialassign name=\"a2\" material=\"Wood\" geom=\"/shelf, /nothing\"/>\n"
      "  <materialassign name=\"a3\" material=\"Everything\" geom=\"/l?mp\"/>\n"
      "</look>\n";
  test::write_file(dir + "/m.mtlx", materials_doc({"Plain", "Walls", "Wood", "Everything"}, looks));
  Scene scene = load_obj(dir + "/a.obj");
  MaterialOptions opts;
  opts.mtlx_files = {dir + "/m.mtlx"};
  MaterialSet set = build_material_set(scene, opts);
  std::vector<float> c = bound_colors(scene, set);
  ASSERT_EQ(c.size(), 5u);
  EXPECT_NEAR(c[0], 0.2f, 1e-6f) << "/wall_north: the collection's wildcard";
  EXPECT_NEAR(c[1], 0.1f, 1e-6f) << "/wall_south is excluded: its usemtl";
  EXPECT_NEAR(c[2], 0.3f, 1e-6f) << "/shelf (a group)";
  EXPECT_NEAR(c[3], 0.1f, 1e-6f) << "/floor: no assignment, its usemtl";
  EXPECT_NEAR(c[4], 0.4f, 1e-6f) << "/lamp: '?' wildcard, no usemtl at all";
}

TEST(MaterialBinding, GeometryPathRules) {
  EXPECT_TRUE(mtlx_geom_matches("/", "/anything"));
  EXPECT_TRUE(mtlx_geom_matches("/wall", "/wall"));
  EXPECT_FALSE(mtlx_geom_matches("/wall", "/wall2"));
  EXPECT_TRUE(mtlx_geom_matches("/wall*", "/wall2"));
  EXPECT_TRUE(mtlx_geom_matches("/a", "/a/b")) << "an ancestor covers its descendants";
  EXPECT_FALSE(mtlx_geom_matches("/a/b", "/a"));
  EXPECT_FALSE(mtlx_geom_matches("/*/b", "/a"));
  EXPECT_TRUE(mtlx_geom_matches("/*/b", "/x/b"));
  EXPECT_TRUE(mtlx_geom_matches("/w?ll", "/wall"));
}

TEST(MaterialBinding, AnAssignmentOfAnUnknownMaterialNamesIt) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/a.obj", std::string(kTri) + "o wall\nf 1 2 3\n");
  test::write_file(dir + "/m.mtlx", materials_doc({"Plain"},
                                                  "<look name=\"L\"><materialassign name=\"a\" "
                                                  "material=\"Nope\" geom=\"/wall\"/></look>"));
  Scene scene = load_obj(dir + "/a.obj");
  MaterialOptions opts;
  opts.mtlx_files = {dir + "/m.mtlx"};
  try {
    build_material_set(scene, opts);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("materialassign 'a'"), std::string::npos) << m;
    EXPECT_NE(m.find("'Nope'"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace pmc
