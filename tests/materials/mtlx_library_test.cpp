// mtlx_library_test.cpp — MaterialX as others write it: nodes expanded from the
// MaterialX library's nodegraphs, custom nodes, multi-output nodes, the
// other surface shaders, filename search paths, older documents, shaders
// behind nodegraph outputs, and the errors when something cannot be built.
//
// Independent answers: values computed here from the MaterialX specification
// (separate3 splits channels, switch picks its `which`-th input, checkerboard
// alternates) and the library's own nodedef defaults read here with
// pugixml. (Upgrades compared with the materialx package's own:
// mtlx_upgrade_reference_test.cpp.)
#include "materials/mtlx_library.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <pugixml.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/device/pmc_interp.h"
#include "core/error.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"
#include "materials/node_table.h"
#include "tests/support/material_eval.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

const std::string kPath = "/docs/test_doc.mtlx";

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_MENTIONS(message, part) \
  EXPECT_NE((message).find(part), std::string::npos) << "expected \"" << (part) << "\" in: " << (message)

// A document with `body` and a standard_surface whose base_color is `color_node`'s output.
std::string doc_with_color(const std::string& body, const std::string& color_input) {
  return "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n" + body +
         "\n<standard_surface name=\"SR\" type=\"surfaceshader\">" + color_input +
         "</standard_surface>\n<surfacematerial name=\"M\" type=\"material\">"
         "<input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR\"/></surfacematerial>\n"
         "</materialx>\n";
}

// Compiles `g` and evaluates it at uv on the host.
void evaluate(Graph g, float u, float v, float params[PMC_P_COUNT], CompiledMaterial* out = nullptr) {
  test::surface_params_at(std::move(g), u, v, params, out);
}

const Graph& only(const std::vector<Graph>& graphs) {
  EXPECT_EQ(graphs.size(), 1u);
  EXPECT_EQ(graphs[0].error, "");
  return graphs[0];
}

TEST(MtlxLibrary, TheBuildFindsMaterialXsLibraries) {
  const std::string dir = find_mtlx_library("");
  ASSERT_NE(dir, "") << "no MaterialX library: run scripts/setup (installs the materialx package into .venv) "
                        "and reconfigure, or set PMC_MTLX_LIBRARY";
  const MtlxLibrary& lib = MtlxLibrary::load(dir);
  EXPECT_GE(lib.files(), 4u);
  EXPECT_TRUE(lib.definitions().nodedef("ND_separate3_color3"));
  EXPECT_TRUE(lib.definitions().implementation("ND_separate3_color3"));
  EXPECT_MENTIONS(error_of([] { find_mtlx_library("/nonexistent/libraries"); }), "/nonexistent/libraries");
}

TEST(MtlxLibrary, MultiOutputNodesFromTheLibraryPickTheNamedOutput) {
  // separate3 is a nodegraph of extracts in stdlib_ng.mtlx: (r, g, b) -> combine3(b, g, r).
  std::string xml = doc_with_color(
      "<constant name=\"c\" type=\"color3\"><input name=\"value\" type=\"color3\" value=\"0.1, 0.2, 0.3\"/>"
      "</constant>"
      "<texcoord name=\"uv\" type=\"vector2\"/>"
      "<multiply name=\"m\" type=\"color3\"><input name=\"in1\" type=\"color3\" nodename=\"c\"/>"
      "<input name=\"in2\" type=\"float\" value=\"1\"/></multiply>"
      "<separate3 name=\"sep\" type=\"multioutput\"><input name=\"in\" type=\"color3\" "
      "nodename=\"m\"/></separate3>"
      "<combine3 name=\"swap\" type=\"color3\">"
      "<input name=\"in1\" type=\"float\" nodename=\"sep\" output=\"outb\"/>"
      "<input name=\"in2\" type=\"float\" nodename=\"sep\" output=\"outg\"/>"
      "<input name=\"in3\" type=\"float\" nodename=\"sep\" output=\"outr\"/></combine3>",
      "<input name=\"base_color\" type=\"color3\" nodename=\"swap\"/>");
  float p[PMC_P_COUNT];
  evaluate(only(read_mtlx_string(xml, kPath)), 0.5f, 0.5f, p);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR + 0], 0.3f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR + 1], 0.2f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR + 2], 0.1f, 1e-6f);
}

TEST(MtlxLibrary, SwitchAndCheckerboardFollowTheSpecification) {
  // switch: the which-th input (0-based); checkerboard: color1 where
  // floor(u * 2) + floor(v * 2) is even (uvtiling 2), else color2.
  std::string xml = doc_with_color(
      "<switch name=\"sw\" type=\"float\"><input name=\"in1\" type=\"float\" value=\"0.1\"/>"
      "<input name=\"in2\" type=\"float\" value=\"0.2\"/><input name=\"in3\" type=\"float\" value=\"0.3\"/>"
      "<input name=\"which\" type=\"integer\" value=\"2\"/></switch>"
      "<checkerboard name=\"ck\" type=\"color3\"><input name=\"color1\" type=\"color3\" value=\"1, 0, 0\"/>"
      "<input name=\"color2\" type=\"color3\" value=\"0, 0, 1\"/>"
      "<input name=\"uvtiling\" type=\"vector2\" value=\"2, 2\"/></checkerboard>",
      "<input name=\"base_color\" type=\"color3\" nodename=\"ck\"/>"
      "<input name=\"metalness\" type=\"float\" nodename=\"sw\"/>");
  const Graph g = only(read_mtlx_string(xml, kPath));
  float p[PMC_P_COUNT];
  CompiledMaterial cm;
  for (auto [u, v] :
       {std::pair<float, float>{0.25f, 0.25f}, {0.75f, 0.25f}, {0.25f, 0.75f}, {0.75f, 0.75f}}) {
    evaluate(g, u, v, p, &cm);
    EXPECT_NEAR(p[PMC_P_METALNESS], 0.3f, 1e-6f);
    const bool even = (int(std::floor(u * 2)) + int(std::floor(v * 2))) % 2 == 0;
    const bool red = p[PMC_P_BASE_COLOR] > 0.5f && p[PMC_P_BASE_COLOR + 2] < 0.5f;
    const bool blue = p[PMC_P_BASE_COLOR] < 0.5f && p[PMC_P_BASE_COLOR + 2] > 0.5f;
    EXPECT_TRUE(red || blue) << u << " " << v;
    EXPECT_NE(red, blue);
    // Adjacent squares differ; diagonal ones agree.
    static bool first_red = red;
    EXPECT_EQ(red, even ? first_red : !first_red) << u << " " << v;
  }
  // The expanded graph's dependency bits: the checkerboard reads uv only, the switch is constant.
  bool found = false;
  for (const auto& [input, bits] : cm.param_dependencies) {
    if (input == "base_color") {
      EXPECT_EQ(bits, uint32_t(kDepUv));
      found = true;
    }
    if (input == "metalness") EXPECT_EQ(bits, 0u);
  }
  EXPECT_TRUE(found);
}

TEST(MtlxLibrary, ExpandedUvOnlyGraphsAreCachePoints) {
  // A checkerboard behind a fractal: uv-only, large enough to be worth a cache point.
  std::string xml = doc_with_color(
      "<checkerboard name=\"ck\" type=\"color3\"><input name=\"uvtiling\" type=\"vector2\" value=\"8, 8\"/>"
      "</checkerboard>"
      "<fractal2d name=\"f\" type=\"color3\"/>"
      "<multiply name=\"m\" type=\"color3\"><input name=\"in1\" type=\"color3\" nodename=\"ck\"/>"
      "<input name=\"in2\" type=\"color3\" nodename=\"f\"/></multiply>"
      "<position name=\"p\" type=\"vector3\"/>"
      "<noise3d name=\"n3\" type=\"float\"><input name=\"position\" type=\"vector3\" "
      "nodename=\"p\"/></noise3d>",
      "<input name=\"base_color\" type=\"color3\" nodename=\"m\"/>"
      "<input name=\"specular_roughness\" type=\"float\" nodename=\"n3\"/>");
  Graph g = only(read_mtlx_string(xml, kPath));
  TexturePool tex;
  MaterialProgram prog;
  CompileOptions opts;
  opts.cache = true;
  const CompiledMaterial& cm = compile_material(g, tex, prog, opts);
  ASSERT_EQ(cm.cache_plan.points.size(), 1u);
  EXPECT_EQ(g.nodes[size_t(cm.cache_plan.points[0].node)].name, "m");
  for (const auto& [input, bits] : cm.param_dependencies)
    if (input == "specular_roughness") EXPECT_EQ(bits, uint32_t(kDepPosition));
}

TEST(MtlxLibrary, CustomNodesExpandFromTheDocumentsOwnNodegraph) {
  std::string xml = doc_with_color(
      "<nodedef name=\"ND_tint_color3\" node=\"tint\"><input name=\"in\" type=\"color3\" value=\"1, 1, 1\"/>"
      "<input name=\"gain\" type=\"float\" value=\"0.5\"/><output name=\"out\" type=\"color3\"/></nodedef>"
      "<nodegraph name=\"NG_tint_color3\" nodedef=\"ND_tint_color3\">"
      "<multiply name=\"m\" type=\"color3\"><input name=\"in1\" type=\"color3\" interfacename=\"in\"/>"
      "<input name=\"in2\" type=\"float\" interfacename=\"gain\"/></multiply>"
      "<output name=\"out\" type=\"color3\" nodename=\"m\"/></nodegraph>"
      "<tint name=\"t\" type=\"color3\"><input name=\"in\" type=\"color3\" value=\"0.2, 0.4, 0.8\"/></tint>",
      "<input name=\"base_color\" type=\"color3\" nodename=\"t\"/>");
  float p[PMC_P_COUNT];
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  ASSERT_EQ(graphs.size(), 1u) << "an implementation graph is not a preview";
  evaluate(only(graphs), 0.5f, 0.5f, p);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR + 0], 0.1f, 1e-6f);  // gain's default 0.5
  EXPECT_NEAR(p[PMC_P_BASE_COLOR + 2], 0.4f, 1e-6f);
}

// (BSDF and EDF graphs are flattened: closure_flatten_test.cpp. A light
// shader where a surface shader belongs is not.)
TEST(MtlxLibrary, UnrenderableClosuresAndUnknownNodesFailNamingTheNode) {
  std::string light =
      "<?xml version=\"1.0\"?><materialx version=\"1.39\">"
      "<uniform_edf name=\"glow\" type=\"EDF\"/>"
      "<light name=\"lamp\" type=\"lightshader\"><input name=\"edf\" type=\"EDF\" nodename=\"glow\"/>"
      "</light><surfacematerial name=\"M\" type=\"material\">"
      "<input name=\"surfaceshader\" type=\"surfaceshader\" "
      "nodename=\"lamp\"/></surfacematerial></materialx>";
  std::string e = error_of([&] { read_mtlx_string(light, kPath); });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "'lamp'");
  EXPECT_MENTIONS(e, "lightshader");
  EXPECT_MENTIONS(e, "closure");
  e = error_of([] {
    read_mtlx_string(doc_with_color("<sparkle name=\"sp\" type=\"color3\"/>",
                                    "<input name=\"base_color\" type=\"color3\" nodename=\"sp\"/>"),
                     kPath);
  });
  EXPECT_MENTIONS(e, "'sp'");
  EXPECT_MENTIONS(e, "unsupported node 'sparkle'");
}

// As MaterialX reads them: an interfacename with no enclosing nodegraph
// input leaves the input's own value; a custom node's filename defaults
// resolve like the document's own filenames.
TEST(MtlxLibrary, LenientInterfaceNamesAndDefinitionFilenames) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/grid.png", "x");
  std::string xml =
      "<?xml version=\"1.0\"?><materialx version=\"1.39\">"
      "<constant name=\"c\" type=\"color3\"><input name=\"value\" type=\"color3\" interfacename=\"tint\" "
      "value=\"0.5, 0.25, 0.125\"/></constant>"
      "<nodedef name=\"ND_tex\" node=\"tex\"><input name=\"f\" type=\"filename\" value=\"grid.png\"/>"
      "<output name=\"out\" type=\"color3\"/></nodedef>"
      "<nodegraph name=\"NG_tex\" nodedef=\"ND_tex\"><image name=\"i\" type=\"color3\">"
      "<input name=\"file\" type=\"filename\" interfacename=\"f\"/></image>"
      "<output name=\"out\" type=\"color3\" nodename=\"i\"/></nodegraph>"
      "<tex name=\"t\" type=\"color3\"/>"
      "<standard_surface name=\"SR\" type=\"surfaceshader\"><input name=\"base_color\" type=\"color3\" "
      "nodename=\"c\"/><input name=\"coat_color\" type=\"color3\" nodename=\"t\"/></standard_surface>"
      "<surfacematerial name=\"M\" type=\"material\"><input name=\"surfaceshader\" type=\"surfaceshader\" "
      "nodename=\"SR\"/></surfacematerial></materialx>";
  const Graph g = only(read_mtlx_string(xml, dir + "/doc.mtlx"));
  bool found_image = false;
  for (const Node& n : g.nodes) {
    if (n.name == "c") EXPECT_EQ(n.input("value")->value.f[1], 0.25f);
    if (n.category == "image") {
      found_image = true;
      EXPECT_EQ(n.input("file")->value.text, dir + "/grid.png");
    }
  }
  EXPECT_TRUE(found_image);
}

TEST(MtlxLibrary, AMaterialThatCannotBeBuiltFailsOnlyWhenUsed) {
  std::string xml =
      "<?xml version=\"1.0\"?><materialx version=\"1.39\">"
      "<standard_surface name=\"good\" type=\"surfaceshader\"/>"
      "<sparkle name=\"sp\" type=\"color3\"/>"
      "<standard_surface name=\"bad\" type=\"surfaceshader\">"
      "<input name=\"base_color\" type=\"color3\" nodename=\"sp\"/></standard_surface>"
      "<surfacematerial name=\"Good\" type=\"material\"><input name=\"surfaceshader\" type=\"surfaceshader\" "
      "nodename=\"good\"/></surfacematerial>"
      "<surfacematerial name=\"Bad\" type=\"material\"><input name=\"surfaceshader\" type=\"surfaceshader\" "
      "nodename=\"bad\"/></surfacematerial></materialx>";
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  ASSERT_EQ(graphs.size(), 2u);
  EXPECT_EQ(graphs[0].error, "");
  EXPECT_MENTIONS(graphs[1].error, "unsupported node 'sparkle'");
  EXPECT_MENTIONS(graphs[1].error, "'sp'");
}

TEST(MtlxLibrary, WithoutALibraryTableNodesLoadAndOthersSayHowToGetOne) {
  const char* old = std::getenv("PMC_MTLX_LIBRARY");
  std::string saved = old ? old : "";
  const std::string empty_dir = test::temp_dir();
  setenv("PMC_MTLX_LIBRARY", empty_dir.c_str(), 1);
  // Only table nodes: the library is never needed.
  EXPECT_NO_THROW(
      read_mtlx_string(doc_with_color("<noise2d name=\"n\" type=\"color3\"/>",
                                      "<input name=\"base_color\" type=\"color3\" nodename=\"n\"/>"),
                       kPath));
  std::string e = error_of([] {
    read_mtlx_string(doc_with_color("<checkerboard name=\"ck\" type=\"color3\"/>",
                                    "<input name=\"base_color\" type=\"color3\" nodename=\"ck\"/>"),
                     kPath);
  });
  EXPECT_MENTIONS(e, "PMC_MTLX_LIBRARY=" + empty_dir);
  EXPECT_MENTIONS(e, "not a MaterialX data library");
  if (old)
    setenv("PMC_MTLX_LIBRARY", saved.c_str(), 1);
  else
    unsetenv("PMC_MTLX_LIBRARY");
}

// fileprefix, then the document's folder, then MATERIALX_SEARCH_PATH, then the options' paths.
TEST(MtlxLibrary, FilenamesResolveInTheSpecifiedOrder) {
  const std::string root = test::temp_dir();
  namespace fs = std::filesystem;
  for (const char* d : {"doc", "doc/pre", "env", "opt", "env/pre"}) fs::create_directories(root + "/" + d);
  auto touch = [&](const std::string& rel) { test::write_file(root + "/" + rel, "x"); };
  touch("opt/only_opt.png");
  touch("env/env_and_opt.png");
  touch("opt/env_and_opt.png");
  touch("doc/doc_and_env.png");
  touch("env/doc_and_env.png");
  touch("doc/pre/prefixed.png");
  touch("env/pre/prefixed_env.png");
  const char* old = std::getenv("MATERIALX_SEARCH_PATH");
  std::string saved = old ? old : "";
  setenv("MATERIALX_SEARCH_PATH", (root + "/nowhere:" + root + "/env").c_str(), 1);
  auto resolved = [&](const std::string& file, const std::string& prefix) {
    std::string xml = doc_with_color(
        "<image name=\"img\" type=\"color3\"" + (prefix.empty() ? "" : " fileprefix=\"" + prefix + "\"") +
            "><input name=\"file\" type=\"filename\" value=\"" + file + "\"/></image>",
        "<input name=\"base_color\" type=\"color3\" nodename=\"img\"/>");
    MtlxReadOptions opts;
    opts.search_paths = {root + "/opt"};
    const Graph g = only(read_mtlx_string(xml, root + "/doc/d.mtlx", opts));
    for (const Node& n : g.nodes)
      if (n.name == "img") return n.input("file")->value.text;
    return std::string("?");
  };
  EXPECT_EQ(resolved("only_opt.png", ""), root + "/opt/only_opt.png");
  EXPECT_EQ(resolved("env_and_opt.png", ""), root + "/env/env_and_opt.png");
  EXPECT_EQ(resolved("doc_and_env.png", ""), root + "/doc/doc_and_env.png");
  EXPECT_EQ(resolved("prefixed.png", "pre/"), root + "/doc/pre/prefixed.png");
  EXPECT_EQ(resolved("prefixed_env.png", "pre/"), root + "/env/pre/prefixed_env.png");
  EXPECT_EQ(resolved("missing.png", ""), root + "/doc/missing.png") << "not found: the document's folder";
  if (old)
    setenv("MATERIALX_SEARCH_PATH", saved.c_str(), 1);
  else
    unsetenv("MATERIALX_SEARCH_PATH");
}

TEST(MtlxLibrary, ShadersBehindNodegraphOutputsAndShaderOutputsAreMaterials) {
  std::string xml =
      "<?xml version=\"1.0\"?><materialx version=\"1.39\">"
      "<nodegraph name=\"NG\"><input name=\"tint\" type=\"color3\" value=\"0.25, 0.5, 0.75\"/>"
      "<standard_surface name=\"s\" type=\"surfaceshader\">"
      "<input name=\"base_color\" type=\"color3\" interfacename=\"tint\"/></standard_surface>"
      "<output name=\"shader\" type=\"surfaceshader\" nodename=\"s\"/></nodegraph>"
      "<surfacematerial name=\"M\" type=\"material\"><input name=\"surfaceshader\" type=\"surfaceshader\" "
      "nodegraph=\"NG\" output=\"shader\"/></surfacematerial></materialx>";
  float p[PMC_P_COUNT];
  evaluate(only(read_mtlx_string(xml, kPath)), 0.5f, 0.5f, p);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR + 1], 0.5f, 1e-6f);
  // No material: a top-level surfaceshader output is one; a BSDF output is skipped with its reason.
  std::string outputs =
      "<?xml version=\"1.0\"?><materialx version=\"1.39\">"
      "<gltf_pbr name=\"g\" type=\"surfaceshader\"><input name=\"base_color\" type=\"color3\" "
      "value=\"0.5, 0.25, 0.125\"/></gltf_pbr>"
      "<oren_nayar_diffuse_bsdf name=\"d\" type=\"BSDF\"/>"
      "<output name=\"shader_out\" type=\"surfaceshader\" nodename=\"g\"/>"
      "<output name=\"bsdf_out\" type=\"BSDF\" nodename=\"d\"/></materialx>";
  std::vector<Graph> graphs = read_mtlx_string(outputs, kPath);
  ASSERT_EQ(graphs.size(), 2u);
  EXPECT_EQ(graphs[0].material, "shader_out");
  EXPECT_EQ(graphs[0].error, "");
  EXPECT_MENTIONS(graphs[1].error, "bsdf_out");
  evaluate(graphs[0], 0.5f, 0.5f, p);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR + 2], 0.125f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_METALNESS], 1.0f, 1e-6f) << "gltf_pbr's metallic defaults to 1";
}

// The surface mappings' defaults are the MaterialX library's own nodedef values.
TEST(MtlxLibrary, SurfaceDefaultsAreTheLibrarysDefaults) {
  const std::string dir = find_mtlx_library("");
  ASSERT_NE(dir, "");
  for (auto [category, file] :
       {std::pair<const char*, const char*>{"standard_surface", "bxdf/standard_surface.mtlx"},
        {"open_pbr_surface", "bxdf/open_pbr_surface.mtlx"},
        {"gltf_pbr", "bxdf/gltf_pbr.mtlx"},
        {"disney_principled", "bxdf/disney_principled.mtlx"},
        {"UsdPreviewSurface", "bxdf/usd_preview_surface.mtlx"},
        {"surface_unlit", "stdlib/stdlib_defs.mtlx"}}) {
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_file((dir + "/" + file).c_str())) << file;
    pugi::xml_node nd;
    for (pugi::xml_node n : doc.child("materialx").children("nodedef"))
      if (std::string(n.attribute("node").as_string()) == category && !nd) nd = n;
    ASSERT_TRUE(nd) << category;
    int compared = 0;
    for (const SurfaceParam& p : surface_params(category)) {
      if (std::string(p.input).rfind("pmc_", 0) == 0) continue;
      pugi::xml_node in = nd.find_child_by_attribute("input", "name", p.input);
      for (pugi::xml_node base = nd; !in && base.attribute("inherit");) {  // nodedef inheritance
        base = doc.child("materialx")
                   .find_child_by_attribute("nodedef", "name", base.attribute("inherit").as_string());
        if (base) in = base.find_child_by_attribute("input", "name", p.input);
      }
      EXPECT_TRUE(in) << category << " has no input " << p.input;
      if (!in) continue;
      // Normals: pmc's (0, 0, 0) means "the shading normal" (what Nworld or a flat tangent-space normal is).
      if (p.param == PMC_P_NORMAL || in.attribute("defaultgeomprop") || !in.attribute("value")) continue;
      std::vector<float> want;
      std::string v = in.attribute("value").as_string();
      if (v == "true" || v == "false") continue;
      for (char& c : v)
        if (c == ',') c = ' ';
      std::istringstream is(v);
      float f;
      while (is >> f) want.push_back(f);
      for (size_t k = 0; k < want.size() && k < 3; ++k)
        EXPECT_EQ(p.def[k], want[k]) << category << "." << p.input;
      ++compared;
    }
    EXPECT_GE(compared, 3) << category;
  }
}

TEST(MtlxLibrary, SurfaceMappingsGiveTheExpectedParameters) {
  auto params_of = [](const std::string& shader) {
    std::string xml = "<?xml version=\"1.0\"?><materialx version=\"1.39\">" + shader +
                      "<surfacematerial name=\"M\" type=\"material\"><input name=\"surfaceshader\" "
                      "type=\"surfaceshader\" nodename=\"s\"/></surfacematerial></materialx>";
    std::vector<float> p(PMC_P_COUNT);
    evaluate(only(read_mtlx_string(xml, kPath)), 0.5f, 0.5f, p.data());
    return p;
  };
  std::vector<float> p = params_of(
      "<disney_principled name=\"s\" type=\"surfaceshader\"><input name=\"specular\" type=\"float\" "
      "value=\"0.25\"/><input name=\"clearcoatGloss\" type=\"float\" value=\"0.75\"/></disney_principled>");
  EXPECT_NEAR(p[PMC_P_SPECULAR], 0.5f, 1e-6f) << "Disney specular 0.5 is pmc's specular 1 (F0 0.04)";
  EXPECT_NEAR(p[PMC_P_COAT_ROUGHNESS], 0.25f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_BASE_COLOR], 0.16f, 1e-6f);
  p = params_of(
      "<surface_unlit name=\"s\" type=\"surfaceshader\"><input name=\"emission_color\" type=\"color3\" "
      "value=\"0.2, 0.4, 0.6\"/></surface_unlit>");
  EXPECT_EQ(p[PMC_P_BASE], 0.0f);
  EXPECT_EQ(p[PMC_P_SPECULAR], 0.0f);
  EXPECT_NEAR(p[PMC_P_EMISSION], 1.0f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_EMISSION_COLOR + 2], 0.6f, 1e-6f);
  p = params_of(
      "<open_pbr_surface name=\"s\" type=\"surfaceshader\"><input name=\"emission_luminance\" type=\"float\" "
      "value=\"3\"/><input name=\"base_metalness\" type=\"float\" value=\"0.5\"/></open_pbr_surface>");
  EXPECT_NEAR(p[PMC_P_EMISSION], 3.0f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_METALNESS], 0.5f, 1e-6f);
  EXPECT_NEAR(p[PMC_P_SPECULAR_ROUGHNESS], 0.3f, 1e-6f);
  // glTF alpha is the opacity only in MASK or BLEND mode.
  p = params_of(
      "<gltf_pbr name=\"s\" type=\"surfaceshader\"><input name=\"alpha\" type=\"float\" value=\"0.25\"/>"
      "</gltf_pbr>");
  EXPECT_EQ(p[PMC_P_OPACITY], 1.0f);
  p = params_of(
      "<gltf_pbr name=\"s\" type=\"surfaceshader\"><input name=\"alpha\" type=\"float\" value=\"0.25\"/>"
      "<input name=\"alpha_mode\" type=\"integer\" value=\"2\"/></gltf_pbr>");
  EXPECT_NEAR(p[PMC_P_OPACITY], 0.25f, 1e-6f);
}

// A version number too large for an int (a fuzzer's find) is a future
// version: read as current, no upgrade, and no overflow.
TEST(MtlxLibrary, HugeVersionNumbersReadAsTheCurrentVersion) {
  auto roughness = [](const std::string& version, const char* first, const char* second) {
    const std::string doc = "<?xml version=\"1.0\"?>\n<materialx version=\"" + version +
                            "\">\n"
                            "  <atan2 name=\"a\" type=\"float\"><input name=\"" +
                            first + "\" type=\"float\" value=\"1\"/><input name=\"" + second +
                            "\" type=\"float\" value=\"2\"/></atan2>\n"
                            "  <standard_surface name=\"SR\" type=\"surfaceshader\">"
                            "<input name=\"specular_roughness\" type=\"float\" nodename=\"a\"/>"
                            "</standard_surface>\n"
                            "  <surfacematerial name=\"M\" type=\"material\"><input "
                            "name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR\"/>"
                            "</surfacematerial>\n</materialx>\n";
    float p[PMC_P_COUNT];
    evaluate(only(read_mtlx_string(doc, kPath)), 0.5f, 0.5f, p);
    return p[PMC_P_SPECULAR_ROUGHNESS];
  };
  // 1.39's atan2(iny, inx) = atan(iny/inx); 1.37's in1 is inx.
  EXPECT_NEAR(roughness("1.39", "iny", "inx"), std::atan2(1.0f, 2.0f), 1e-6f);
  EXPECT_NEAR(roughness("1.37", "in1", "in2"), std::atan2(2.0f, 1.0f), 1e-6f);
  // A future document keeps in1/in2, which 1.39's atan2 does not have (ignored,
  // with a warning), exactly as a 1.39 document does.
  const float current = roughness("1.39", "in1", "in2");
  for (const char* future : {"66666666661.39", "4294967297.37", "1.4294967333", "2.0"})
    EXPECT_EQ(roughness(future, "in1", "in2"), current) << future;
}

}  // namespace
}  // namespace pmc
