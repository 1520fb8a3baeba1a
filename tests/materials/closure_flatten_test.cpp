// closure_flatten_test.cpp — pbrlib closure graphs (surface over layer, mix,
// add and multiply of *_bsdf and *_edf nodes) flattened onto pmc's BSDF.
//
// Independent answers: the BSDF each closure is, worked by hand from the
// MaterialX PBR specification's definitions and pmc's model (a Lambert
// albedo, a Schlick F0, GGX alpha, emission): a dielectric's F0 is
// ((ior−1)/(ior+1))², a conductor's ((n−1)²+k²)/((n+1)²+k²), a layer lets
// its base through scaled by 1 − weight·F0, mix interpolates, add sums and
// multiply scales. A mix of two standard_surfaces is checked against pmc's
// own reading of each shader alone, and MaterialX's own standard_surface
// nodegraph (its library's closure graph) against pmc's native mapping.
#include <gtest/gtest.h>

#include <cmath>
#include <pugixml.hpp>
#include <sstream>
#include <string>

#include "core/device/pmc_interp.h"
#include "core/error.h"
#include "materials/mtlx_library.h"
#include "materials/mtlx_reader.h"
#include "tests/support/material_eval.h"

namespace pmc {
namespace {

const std::string kPath = "/docs/closures.mtlx";

std::string doc(const std::string& body) {
  return "<?xml version=\"1.0\"?><materialx version=\"1.39\">" + body + "</materialx>";
}

// A material whose shader is `surface` node S (or any surfaceshader node S).
std::string material(const std::string& nodes) {
  return doc(nodes +
             "<surfacematerial name=\"M\" type=\"material\"><input name=\"surfaceshader\" "
             "type=\"surfaceshader\" nodename=\"S\"/></surfacematerial>");
}

std::string surface_of(const std::string& bsdf, const std::string& extra = "") {
  return "<surface name=\"S\" type=\"surfaceshader\"><input name=\"bsdf\" type=\"BSDF\" nodename=\"" + bsdf +
         "\"/>" + extra + "</surface>";
}

// The error reading `xml` gives ("" and a failure when it reads).
std::string read_error(const std::string& xml) {
  try {
    read_mtlx_string(xml, kPath);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

// What the flattener's lobes hold: a diffuse albedo under a constant
// (1 - F0), a Schlick F0, a GGX alpha and emission. A flattened graph's
// PmcBsdf holds them as they are (model 1); a native standard_surface is
// read the way closure_flatten.cpp's surface_shader() reads it, so that the
// two can be compared (the device then layers either with albedo scaling).
struct Lobes {
  float3 diffuse, specular, emission;
  float alpha;
};
struct Result {
  Lobes bsdf;
  float opacity;
  float transmission, ior;
};

Lobes lobes_of(const float* p) {
  PmcBsdf b = pmc_surface_to_bsdf(p);
  Lobes l;
  l.emission = b.emission;
  l.alpha = b.ax;
  if (b.flat) {
    l.diffuse = b.diffuse;
    l.specular = b.spec_f0;
    return l;
  }
  const float spec = std::min(1.0f, p[PMC_P_SPECULAR]), f0 = b.spec_f0.x;
  l.specular = b.spec_tint * f0 * (1.0f - b.metal) + b.metal_f0 * b.metal +
               (b.coat > 0.0f ? b.coat_color * (0.04f * b.coat) : make_float3(0, 0, 0));
  l.diffuse = b.diffuse * ((1.0f - b.metal) * (1.0f - f0 * spec));
  return l;
}

// Material M of `xml`, evaluated at one shading point with this uv.
Result evaluate(const std::string& xml, float u = 0.5f, float v = 0.5f) {
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  Result r{};
  EXPECT_EQ(graphs.size(), 1u);
  if (graphs.empty()) return r;
  EXPECT_EQ(graphs[0].error, "");
  if (!graphs[0].error.empty()) return r;
  float p[PMC_P_COUNT];
  test::surface_params_at(graphs[0], u, v, p);
  r.bsdf = lobes_of(p);
  r.transmission = p[PMC_P_TRANSMISSION];
  r.ior = p[PMC_P_SPECULAR_IOR];
  r.opacity = p[PMC_P_OPACITY];
  return r;
}

void expect_color(float3 got, float r, float g, float b, const char* what) {
  EXPECT_NEAR(got.x, r, 1e-5f) << what;
  EXPECT_NEAR(got.y, g, 1e-5f) << what;
  EXPECT_NEAR(got.z, b, 1e-5f) << what;
}

float f0(float ior) { return std::pow((ior - 1) / (ior + 1), 2.0f); }

TEST(ClosureFlatten, DiffuseAlone) {
  Result r = evaluate(
      material("<oren_nayar_diffuse_bsdf name=\"d\" type=\"BSDF\"><input name=\"weight\" type=\"float\" "
               "value=\"0.5\"/>"
               "<input name=\"color\" type=\"color3\" value=\"0.8, 0.4, 0.2\"/></oren_nayar_diffuse_bsdf>" +
               surface_of("d")));
  expect_color(r.bsdf.diffuse, 0.4f, 0.2f, 0.1f, "diffuse");
  expect_color(r.bsdf.specular, 0, 0, 0, "specular");
  expect_color(r.bsdf.emission, 0, 0, 0, "emission");
  EXPECT_NEAR(r.opacity, 1.0f, 1e-6f);
}

TEST(ClosureFlatten, DielectricOverDiffuseIsTheSpecularLayer) {
  // alpha 0.09 is roughness 0.3 for pmc; the base keeps 1 − F0 of the light.
  Result r = evaluate(
      material("<oren_nayar_diffuse_bsdf name=\"d\" type=\"BSDF\"><input name=\"color\" type=\"color3\" "
               "value=\"0.5, 0.6, 0.7\"/></oren_nayar_diffuse_bsdf>"
               "<dielectric_bsdf name=\"c\" type=\"BSDF\"><input name=\"ior\" type=\"float\" value=\"1.8\"/>"
               "<input name=\"tint\" type=\"color3\" value=\"1, 0.5, 1\"/>"
               "<input name=\"roughness\" type=\"vector2\" value=\"0.09, 0.09\"/></dielectric_bsdf>"
               "<layer name=\"l\" type=\"BSDF\"><input name=\"top\" type=\"BSDF\" nodename=\"c\"/>"
               "<input name=\"base\" type=\"BSDF\" nodename=\"d\"/></layer>" +
               surface_of("l")));
  const float F = f0(1.8f);
  // The tint colours the reflection; what passes on is 1 − weight·avg(F0·tint).
  const float pass = 1 - F * (1 + 0.5f + 1) / 3;
  expect_color(r.bsdf.specular, F, 0.5f * F, F, "specular");
  expect_color(r.bsdf.diffuse, 0.5f * pass, 0.6f * pass, 0.7f * pass, "diffuse");
  EXPECT_NEAR(r.bsdf.alpha, 0.09f, 1e-6f);
}

TEST(ClosureFlatten, ConductorFromComplexIorAndFromArtisticIor) {
  // Gold-like n and k: F0 per channel is ((n−1)² + k²) / ((n+1)² + k²).
  const float n[3] = {0.183f, 0.421f, 1.373f}, k[3] = {3.424f, 2.346f, 1.770f};
  Result r = evaluate(material("<conductor_bsdf name=\"m\" type=\"BSDF\"/>" + surface_of("m")));
  float want[3];
  for (int c = 0; c < 3; ++c)
    want[c] = ((n[c] - 1) * (n[c] - 1) + k[c] * k[c]) / ((n[c] + 1) * (n[c] + 1) + k[c] * k[c]);
  expect_color(r.bsdf.specular, want[0], want[1], want[2], "F0 of the default conductor");
  expect_color(r.bsdf.diffuse, 0, 0, 0, "diffuse");
  EXPECT_NEAR(r.bsdf.alpha, 0.05f, 1e-6f);
  // artistic_ior's reflectivity is the F0 it stands for.
  Result a = evaluate(material(
      "<artistic_ior name=\"a\" type=\"multioutput\"><input name=\"reflectivity\" type=\"color3\" "
      "value=\"0.9, 0.6, 0.3\"/><input name=\"edge_color\" type=\"color3\" value=\"1, 1, 1\"/></artistic_ior>"
      "<conductor_bsdf name=\"m\" type=\"BSDF\"><input name=\"weight\" type=\"float\" value=\"0.5\"/>"
      "<input name=\"ior\" type=\"color3\" nodename=\"a\" output=\"ior\"/>"
      "<input name=\"extinction\" type=\"color3\" nodename=\"a\" output=\"extinction\"/></conductor_bsdf>" +
      surface_of("m")));
  expect_color(a.bsdf.specular, 0.45f, 0.3f, 0.15f, "weight x reflectivity");
}

TEST(ClosureFlatten, MixAddMultiplyAndEmission) {
  const std::string leaves =
      "<oren_nayar_diffuse_bsdf name=\"red\" type=\"BSDF\"><input name=\"color\" type=\"color3\" "
      "value=\"1, 0, 0\"/></oren_nayar_diffuse_bsdf>"
      "<dielectric_bsdf name=\"gloss\" type=\"BSDF\"/>"
      "<uniform_edf name=\"e\" type=\"EDF\"><input name=\"color\" type=\"color3\" value=\"2, 3, "
      "4\"/></uniform_edf>";
  Result m = evaluate(material(
      leaves +
      "<mix name=\"x\" type=\"BSDF\"><input name=\"fg\" type=\"BSDF\" nodename=\"red\"/>"
      "<input name=\"bg\" type=\"BSDF\" nodename=\"gloss\"/><input name=\"mix\" type=\"float\" "
      "value=\"0.25\"/></mix>" +
      surface_of("x",
                 "<input name=\"edf\" type=\"EDF\" nodename=\"e\"/><input name=\"opacity\" type=\"float\" "
                 "value=\"0.5\"/>")));
  expect_color(m.bsdf.diffuse, 0.25f, 0, 0, "mix diffuse");
  expect_color(m.bsdf.specular, 0.75f * 0.04f, 0.75f * 0.04f, 0.75f * 0.04f, "mix specular");
  expect_color(m.bsdf.emission, 2, 3, 4, "uniform_edf");
  EXPECT_NEAR(m.opacity, 0.5f, 1e-6f);

  Result a = evaluate(
      material(leaves +
               "<add name=\"x\" type=\"BSDF\"><input name=\"in1\" type=\"BSDF\" nodename=\"red\"/>"
               "<input name=\"in2\" type=\"BSDF\" nodename=\"red\"/></add>"
               "<multiply name=\"y\" type=\"BSDF\"><input name=\"in1\" type=\"BSDF\" nodename=\"x\"/>"
               "<input name=\"in2\" type=\"color3\" value=\"0.25, 1, 1\"/></multiply>" +
               surface_of("y")));
  expect_color(a.bsdf.diffuse, 0.5f, 0, 0, "add then multiply by a colour");
}

TEST(ClosureFlatten, VaryingInputsStayLinks) {
  // The diffuse weight is the texture coordinate's u: evaluated per point.
  const std::string xml = material(
      "<texcoord name=\"uv\" type=\"vector2\"/>"
      "<extract name=\"u\" type=\"float\"><input name=\"in\" type=\"vector2\" nodename=\"uv\"/>"
      "<input name=\"index\" type=\"integer\" value=\"0\"/></extract>"
      "<burley_diffuse_bsdf name=\"d\" type=\"BSDF\"><input name=\"weight\" type=\"float\" nodename=\"u\"/>"
      "<input name=\"color\" type=\"color3\" value=\"0.2, 0.4, 0.8\"/></burley_diffuse_bsdf>"
      "<dielectric_bsdf name=\"c\" type=\"BSDF\"><input name=\"ior\" type=\"float\" nodename=\"u\"/>"
      "<input name=\"weight\" type=\"float\" value=\"1\"/></dielectric_bsdf>"
      "<mix name=\"x\" type=\"BSDF\"><input name=\"fg\" type=\"BSDF\" nodename=\"d\"/>"
      "<input name=\"bg\" type=\"BSDF\" nodename=\"c\"/><input name=\"mix\" type=\"float\" "
      "nodename=\"u\"/></mix>" +
      surface_of("x"));
  for (float u : {0.25f, 0.8f}) {
    Result r = evaluate(xml, u, 0.5f);
    expect_color(r.bsdf.diffuse, u * u * 0.2f, u * u * 0.4f, u * u * 0.8f, "u * u * colour");
    const float s = (1 - u) * f0(u);
    expect_color(r.bsdf.specular, s, s, s, "(1 - u) * F0(ior = u)");
  }
}

TEST(ClosureFlatten, MixOfStandardSurfacesIsTheMixOfTheirBsdfs) {
  const std::string a =
      "<standard_surface name=\"A\" type=\"surfaceshader\"><input name=\"base_color\" type=\"color3\" "
      "value=\"0.9, 0.2, 0.1\"/><input name=\"specular_IOR\" type=\"float\" value=\"1.6\"/>"
      "<input name=\"specular_roughness\" type=\"float\" value=\"0.3\"/></standard_surface>";
  const std::string b =
      "<standard_surface name=\"B\" type=\"surfaceshader\"><input name=\"base_color\" type=\"color3\" "
      "value=\"0.3, 0.5, 0.9\"/><input name=\"metalness\" type=\"float\" value=\"1\"/>"
      "<input name=\"emission\" type=\"float\" value=\"2\"/>"
      "<input name=\"specular_roughness\" type=\"float\" value=\"0.3\"/></standard_surface>";
  auto alone = [&](const std::string& shader, const char* name) {
    return evaluate(doc(shader +
                        "<surfacematerial name=\"M\" type=\"material\"><input name=\"surfaceshader\" "
                        "type=\"surfaceshader\" nodename=\"" +
                        name + "\"/></surfacematerial>"));
  };
  Result ra = alone(a, "A"), rb = alone(b, "B");
  Result m =
      evaluate(material(a + b +
                        "<mix name=\"S\" type=\"surfaceshader\"><input name=\"fg\" type=\"surfaceshader\" "
                        "nodename=\"A\"/><input name=\"bg\" type=\"surfaceshader\" nodename=\"B\"/>"
                        "<input name=\"mix\" type=\"float\" value=\"0.7\"/></mix>"));
  auto mixed = [](float3 fg, float3 bg) { return fg * 0.7f + bg * 0.3f; };
  float3 d = mixed(ra.bsdf.diffuse, rb.bsdf.diffuse), s = mixed(ra.bsdf.specular, rb.bsdf.specular),
         e = mixed(ra.bsdf.emission, rb.bsdf.emission);
  expect_color(m.bsdf.diffuse, d.x, d.y, d.z, "diffuse");
  expect_color(m.bsdf.specular, s.x, s.y, s.z, "specular");
  expect_color(m.bsdf.emission, e.x, e.y, e.z, "emission");
  EXPECT_NEAR(m.bsdf.alpha, ra.bsdf.alpha, 1e-6f);
}

// MaterialX's library implements standard_surface as a closure graph
// (bxdf/standard_surface.mtlx). That graph, flattened, must be the BSDF
// pmc's native standard_surface mapping gives (without a coat, whose colour
// the graph applies to the layers below, and with a white specular colour).
TEST(ClosureFlatten, MaterialXsStandardSurfaceGraphMatchesTheNativeMapping) {
  const std::string dir = find_mtlx_library("");
  ASSERT_FALSE(dir.empty()) << "the build found no MaterialX library";
  pugi::xml_document lib;
  ASSERT_TRUE(lib.load_file((dir + "/bxdf/standard_surface.mtlx").c_str()));
  pugi::xml_node root = lib.child("materialx");
  pugi::xml_node nd =
      root.find_child_by_attribute("nodedef", "name", "ND_standard_surface_surfaceshader_100");
  pugi::xml_node ng =
      root.find_child_by_attribute("nodegraph", "name", "NG_standard_surface_surfaceshader_100");
  ASSERT_TRUE(nd && ng);
  // The same definition and graph under another name, so pmc expands the graph.
  nd.attribute("name").set_value("ND_ss_graph");
  nd.attribute("node").set_value("ss_graph");
  ng.append_attribute("nodedef").set_value("ND_ss_graph");
  std::ostringstream defs;
  nd.print(defs, "", pugi::format_raw);
  ng.print(defs, "", pugi::format_raw);
  // Version 1.0.0's definition, whose graph this is, has other defaults for
  // base and base_color than 1.0.1's (pmc's): every case sets both.
  const char* cases[] = {
      "<input name=\"base\" type=\"float\" value=\"1\"/><input name=\"base_color\" type=\"color3\" "
      "value=\"0.9, 0.2, 0.1\"/>",
      "<input name=\"base\" type=\"float\" value=\"0.6\"/><input name=\"base_color\" type=\"color3\" "
      "value=\"0.8, 0.8, 0.8\"/><input name=\"specular_IOR\" type=\"float\" value=\"1.9\"/>"
      "<input name=\"specular_roughness\" type=\"float\" value=\"0.45\"/>",
      "<input name=\"base\" type=\"float\" value=\"0.9\"/><input name=\"metalness\" type=\"float\" "
      "value=\"0.3\"/><input name=\"base_color\" type=\"color3\" value=\"0.2, 0.5, 0.9\"/>"
      "<input name=\"specular\" type=\"float\" value=\"0.5\"/>",
      "<input name=\"base\" type=\"float\" value=\"1\"/><input name=\"base_color\" type=\"color3\" "
      "value=\"0.7, 0.6, 0.5\"/><input name=\"metalness\" type=\"float\" value=\"1\"/>"
      "<input name=\"emission\" type=\"float\" value=\"2\"/>"
      "<input name=\"emission_color\" type=\"color3\" value=\"1, 0.5, 0.25\"/>",
  };
  for (const char* inputs : cases) {
    Result native = evaluate(material("<standard_surface name=\"S\" type=\"surfaceshader\">" +
                                      std::string(inputs) + "</standard_surface>"));
    testing::internal::CaptureStderr();  // the graph's unmodelled lobes (transmission ...), at weight 0 here
    Result graph = evaluate(
        material(defs.str() + "<ss_graph name=\"S\" type=\"surfaceshader\">" + inputs + "</ss_graph>"));
    testing::internal::GetCapturedStderr();
    expect_color(graph.bsdf.diffuse, native.bsdf.diffuse.x, native.bsdf.diffuse.y, native.bsdf.diffuse.z,
                 inputs);
    expect_color(graph.bsdf.specular, native.bsdf.specular.x, native.bsdf.specular.y, native.bsdf.specular.z,
                 inputs);
    expect_color(graph.bsdf.emission, native.bsdf.emission.x, native.bsdf.emission.y, native.bsdf.emission.z,
                 inputs);
    EXPECT_NEAR(graph.bsdf.alpha, native.bsdf.alpha, 1e-5f) << inputs;
    EXPECT_GT(native.bsdf.diffuse.x + native.bsdf.specular.x, 0.0f)
        << "a case that shows nothing: " << inputs;
  }
}

TEST(ClosureFlatten, CustomNodeWithAClosureGraphExpands) {
  // A document's own BSDF node, implemented by a nodegraph of pbrlib closures.
  Result r = evaluate(material(
      "<nodedef name=\"ND_my_bsdf\" node=\"my_bsdf\"><input name=\"tone\" type=\"color3\" value=\"1, 1, 1\"/>"
      "<output name=\"out\" type=\"BSDF\"/></nodedef>"
      "<nodegraph name=\"NG_my_bsdf\" nodedef=\"ND_my_bsdf\">"
      "<oren_nayar_diffuse_bsdf name=\"d\" type=\"BSDF\"><input name=\"color\" type=\"color3\" "
      "interfacename=\"tone\"/></oren_nayar_diffuse_bsdf>"
      "<output name=\"out\" type=\"BSDF\" nodename=\"d\"/></nodegraph>"
      "<my_bsdf name=\"mine\" type=\"BSDF\"><input name=\"tone\" type=\"color3\" value=\"0.1, 0.2, "
      "0.3\"/></my_bsdf>" +
      surface_of("mine")));
  expect_color(r.bsdf.diffuse, 0.1f, 0.2f, 0.3f, "the instance's tone");
}

TEST(ClosureFlatten, WhatCannotBeModelledIsNamedOnce) {
  testing::internal::CaptureStderr();
  Result r = evaluate(material(
      "<oren_nayar_diffuse_bsdf name=\"d\" type=\"BSDF\"/><sheen_bsdf name=\"sh\" type=\"BSDF\"/>"
      "<layer name=\"l1\" type=\"BSDF\"><input name=\"top\" type=\"BSDF\" nodename=\"sh\"/>"
      "<input name=\"base\" type=\"BSDF\" nodename=\"d\"/></layer>"
      "<dielectric_bsdf name=\"g\" type=\"BSDF\"><input name=\"scatter_mode\" type=\"string\" value=\"RT\"/>"
      "</dielectric_bsdf>"
      "<layer name=\"l2\" type=\"BSDF\"><input name=\"top\" type=\"BSDF\" nodename=\"g\"/>"
      "<input name=\"base\" type=\"BSDF\" nodename=\"l1\"/></layer>" +
      surface_of("l2")));
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("not modelled: "), std::string::npos) << err;
  EXPECT_NE(err.find("sheen_bsdf"), std::string::npos) << err;
  EXPECT_EQ(err.find("dielectric_bsdf"), std::string::npos) << "RT glass is modelled: " << err;
  EXPECT_EQ(err.find("warning", err.find("warning") + 1), std::string::npos) << "one warning: " << err;
  // A full-weight glass layer lets nothing through to the diffuse below: it
  // is the glass lobe (weight 1, white, IOR 1.5).
  expect_color(r.bsdf.diffuse, 0, 0, 0, "nothing under full-weight glass");
  EXPECT_NEAR(r.transmission, 1.0f, 1e-6f);
  EXPECT_NEAR(r.ior, 1.5f, 1e-6f);
}

TEST(ClosureFlatten, AnEdfWhereABsdfBelongsIsAnError) {
  const std::string what =
      read_error(material("<uniform_edf name=\"glow\" type=\"EDF\"/>" + surface_of("glow")));
  EXPECT_NE(what.find("input 'bsdf' takes a BSDF but node 'glow'"), std::string::npos) << what;
  EXPECT_NE(what.find("type mismatch"), std::string::npos) << what;
}

TEST(ClosureFlatten, DataWhereAClosureBelongsIsAnError) {
  // The document's only material fails, so the document does, naming the node.
  const std::string what = read_error(material(
      "<constant name=\"k\" type=\"color3\"/>"
      "<surface name=\"S\" type=\"surfaceshader\"><input name=\"bsdf\" type=\"BSDF\" nodename=\"k\"/>"
      "</surface>"));
  EXPECT_NE(what.find("surface 'S'"), std::string::npos) << what;
  EXPECT_NE(what.find("not a closure"), std::string::npos) << what;
}

TEST(ClosureFlatten, ConvertToAShaderAndDotPassThrough) {
  // convert color3 -> surfaceshader is an unlit surface (stdlib's own graph);
  // dot forwards its input.
  Result r =
      evaluate(material("<convert name=\"c\" type=\"surfaceshader\"><input name=\"in\" type=\"color3\" "
                        "value=\"0.5, 1, 2\"/></convert>"
                        "<dot name=\"S\" type=\"surfaceshader\"><input name=\"in\" type=\"surfaceshader\" "
                        "nodename=\"c\"/></dot>"));
  expect_color(r.bsdf.emission, 0.5f, 1, 2, "unlit emission");
  expect_color(r.bsdf.diffuse, 0, 0, 0, "no diffuse");
  expect_color(r.bsdf.specular, 0, 0, 0, "no specular");
}

TEST(ClosureFlatten, AHostileDepthIsAnErrorNotAStackOverflow) {
  std::string nodes = "<oren_nayar_diffuse_bsdf name=\"b0\" type=\"BSDF\"/>";
  for (int i = 1; i <= 300; ++i)
    nodes += "<multiply name=\"b" + std::to_string(i) +
             "\" type=\"BSDF\"><input name=\"in1\" type=\"BSDF\" nodename=\"b" + std::to_string(i - 1) +
             "\"/><input name=\"in2\" type=\"float\" value=\"1\"/></multiply>";
  const std::string what = read_error(material(nodes + surface_of("b300")));
  EXPECT_NE(what.find("nested deeper than 256"), std::string::npos) << what;
}

}  // namespace
}  // namespace pmc
