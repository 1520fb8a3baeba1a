// mtlx_reader_test.cpp — MaterialX documents into graphs (materials/mtlx_reader.h).
//
// Users write these documents by hand or export them from other tools, so a
// broken one must produce a message that says where and what: every error
// case here (not XML, an unsupported node, a type mismatch, a dangling
// nodename / nodegraph / interfacename, a cycle) must give a pmc::Error whose
// message names the file, the node and the problem. The reader's semantics
// are checked on small documents: nodegraph inlining with interface values,
// library defaults (an unconnected texcoord becomes a texcoord node, noise
// amplitude defaults to 1), and preview materials for documents without
// materials. Finally every document in ../shared/scenes/materialx loads,
// compiles, evaluates to finite parameters on the host and renders the
// teapot without NaN/Inf pixels — one render per material the document
// defines.
#include "materials/mtlx_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "gpu/render_session.h"
#include "materials/compiler.h"
#include "materials/cpu_interpreter.h"
#include "materials/material_set.h"
#include "tests/support/material_eval.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

const std::string kPath = "/docs/looks/test_doc.mtlx";

// Reads `xml` (as if from kPath) and compiles every material it defines.
std::vector<Graph> read_and_compile(const std::string& xml, MaterialProgram* program = nullptr) {
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  TexturePool textures;
  MaterialProgram local;
  for (Graph& g : graphs) compile_material(g, textures, program ? *program : local);
  return graphs;
}

// The message of the pmc::Error `fn` throws ("" if it does not throw).
std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// A document with one material "M" whose standard_surface "SR" has `inputs`,
// plus the top-level `body`.
std::string doc(const std::string& body, const std::string& surface_inputs) {
  return "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n" + body +
         "\n<standard_surface name=\"SR\" type=\"surfaceshader\">\n" + surface_inputs +
         "\n</standard_surface>\n<surfacematerial name=\"M\" type=\"material\">\n"
         "  <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR\"/>\n</surfacematerial>\n"
         "</materialx>\n";
}

#define EXPECT_MENTIONS(message, part) \
  EXPECT_NE((message).find(part), std::string::npos) << "expected \"" << (part) << "\" in: " << (message)

TEST(MtlxReader, NotXmlNamesTheFile) {
  std::string e = error_of([] { read_mtlx_string("<materialx><nodegraph name=\"x\">", kPath); });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "not valid XML");
  e = error_of([] { read_mtlx_string("<?xml version=\"1.0\"?><scene/>", kPath); });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "not a MaterialX document");
  e = error_of([] { read_mtlx_file("/nonexistent/dir/missing.mtlx"); });
  EXPECT_MENTIONS(e, "/nonexistent/dir/missing.mtlx");
}

TEST(MtlxReader, UnsupportedNodeNamesTheNodeAndItsCategory) {
  std::string xml =
      doc("<nodegraph name=\"NG\">\n"
          "  <fancyblur name=\"blur1\" type=\"color3\"/>\n"
          "  <output name=\"out\" type=\"color3\" nodename=\"blur1\"/>\n"
          "</nodegraph>",
          "<input name=\"base_color\" type=\"color3\" nodegraph=\"NG\" output=\"out\"/>");
  std::string e = error_of([&] { read_and_compile(xml); });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "nodegraph 'NG'");
  EXPECT_MENTIONS(e, "'blur1'");
  EXPECT_MENTIONS(e, "unsupported node 'fancyblur'");
}

TEST(MtlxReader, LinkedTypeMismatchNamesBothNodes) {
  // A vector2 output linked into a color3 input (the input's declared type
  // agrees with the node, so only the link is wrong).
  std::string xml =
      doc("<texcoord name=\"uv\" type=\"vector2\"/>\n"
          "<multiply name=\"tint\" type=\"color3\">\n"
          "  <input name=\"in1\" type=\"color3\" nodename=\"uv\"/>\n"
          "  <input name=\"in2\" type=\"color3\" value=\"1, 0.5, 0.5\"/>\n"
          "</multiply>",
          "<input name=\"base_color\" type=\"color3\" nodename=\"tint\"/>");
  std::string e = error_of([&] { read_and_compile(xml); });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "'tint'");
  EXPECT_MENTIONS(e, "'uv'");
  EXPECT_MENTIONS(e, "vector2");
  EXPECT_MENTIONS(e, "type mismatch");
}

TEST(MtlxReader, DeclaredTypeMismatchNamesTheInput) {
  std::string xml =
      doc("<texcoord name=\"uv\" type=\"vector2\"/>\n"
          "<multiply name=\"tint\" type=\"color3\">\n"
          "  <input name=\"in1\" type=\"vector2\" nodename=\"uv\"/>\n"
          "</multiply>",
          "<input name=\"base_color\" type=\"color3\" nodename=\"tint\"/>");
  std::string e = error_of([&] { read_and_compile(xml); });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "'tint'");
  EXPECT_MENTIONS(e, "'in1'");
  EXPECT_MENTIONS(e, "type mismatch");
  // On a surface input as well.
  e = error_of([] {
    read_and_compile(doc("<texcoord name=\"uv\" type=\"vector2\"/>",
                         "<input name=\"base_color\" type=\"vector2\" nodename=\"uv\"/>"));
  });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "'SR'");
  EXPECT_MENTIONS(e, "'base_color'");
  EXPECT_MENTIONS(e, "type mismatch");
}

TEST(MtlxReader, DanglingReferencesNameWhatIsMissing) {
  std::string e = error_of(
      [] { read_and_compile(doc("", "<input name=\"base_color\" type=\"color3\" nodename=\"nope\"/>")); });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "'SR'");
  EXPECT_MENTIONS(e, "'nope'");
  EXPECT_MENTIONS(e, "dangling reference");

  e = error_of([] {
    read_and_compile(
        doc("", "<input name=\"base_color\" type=\"color3\" nodegraph=\"NG_missing\" output=\"out\"/>"));
  });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "'SR'");
  EXPECT_MENTIONS(e, "'NG_missing'");
  EXPECT_MENTIONS(e, "dangling reference");

  e = error_of([] {
    read_and_compile(
        doc("<nodegraph name=\"NG\">\n"
            "  <constant name=\"c\" type=\"color3\"><input name=\"value\" type=\"color3\" "
            "value=\"1,1,1\"/></constant>\n"
            "  <output name=\"out\" type=\"color3\" nodename=\"c\"/>\n"
            "</nodegraph>",
            "<input name=\"base_color\" type=\"color3\" nodegraph=\"NG\" output=\"other\"/>"));
  });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "'NG'");
  EXPECT_MENTIONS(e, "'other'");
  EXPECT_MENTIONS(e, "dangling reference");

  e = error_of([] {
    read_and_compile(
        doc("<nodegraph name=\"NG\">\n"
            "  <input name=\"gain\" type=\"float\" value=\"2\"/>\n"
            "  <multiply name=\"m\" type=\"color3\">\n"
            "    <input name=\"in2\" type=\"float\" interfacename=\"gian\"/>\n"
            "  </multiply>\n"
            "  <output name=\"out\" type=\"color3\" nodename=\"m\"/>\n"
            "</nodegraph>",
            "<input name=\"base_color\" type=\"color3\" nodegraph=\"NG\"/>"));
  });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "nodegraph 'NG'");
  EXPECT_MENTIONS(e, "'m'");
  EXPECT_MENTIONS(e, "'gian'");
  EXPECT_MENTIONS(e, "dangling reference");

  e = error_of([] {
    read_and_compile(
        "<materialx><surfacematerial name=\"M\" type=\"material\">"
        "<input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR\"/>"
        "</surfacematerial></materialx>");
  });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "'M'");
  EXPECT_MENTIONS(e, "'SR'");
  EXPECT_MENTIONS(e, "dangling reference");
}

TEST(MtlxReader, CycleNamesTheNodesOnIt) {
  std::string xml =
      doc("<add name=\"a\" type=\"float\"><input name=\"in1\" type=\"float\" nodename=\"b\"/></add>\n"
          "<add name=\"b\" type=\"float\"><input name=\"in1\" type=\"float\" nodename=\"a\"/></add>",
          "<input name=\"base\" type=\"float\" nodename=\"a\"/>");
  std::string e = error_of([&] { read_and_compile(xml); });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "cycle");
  EXPECT_MENTIONS(e, "'a' -> 'b' -> 'a'");
}

// Runs a compiled material on the host at uv (u, v).
void evaluate(const MaterialProgram& p, const CompiledMaterial& m, float u, float v,
              float params[PMC_P_COUNT]) {
  test::run_program_at(p, m, u, v, params);
}

TEST(MtlxReader, InlinesNodegraphsWithInterfaceValues) {
  std::string xml =
      doc("<nodegraph name=\"NG_tint\">\n"
          "  <input name=\"gain\" type=\"float\" value=\"0.25\"/>\n"
          "  <input name=\"left\" type=\"color3\" value=\"1, 0.5, 0\"/>\n"
          "  <ramplr name=\"ramp\" type=\"color3\">\n"
          "    <input name=\"valuel\" type=\"color3\" interfacename=\"left\"/>\n"
          "    <input name=\"valuer\" type=\"color3\" value=\"0, 0, 1\"/>\n"
          "  </ramplr>\n"
          "  <multiply name=\"m\" type=\"color3\">\n"
          "    <input name=\"in1\" type=\"color3\" nodename=\"ramp\"/>\n"
          "    <input name=\"in2\" type=\"float\" interfacename=\"gain\"/>\n"
          "  </multiply>\n"
          "  <output name=\"out\" type=\"color3\" nodename=\"m\"/>\n"
          "</nodegraph>",
          "<input name=\"base_color\" type=\"color3\" nodegraph=\"NG_tint\" output=\"out\"/>");
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  ASSERT_EQ(graphs.size(), 1u);
  const Graph& g = graphs[0];
  EXPECT_EQ(g.material, "M");
  EXPECT_EQ(g.file, kPath);
  // The nodegraph's nodes are in the material's graph, with origins naming it.
  const Node* m = nullptr;
  for (const Node& n : g.nodes)
    if (n.name == "m") m = &n;
  ASSERT_NE(m, nullptr);
  EXPECT_MENTIONS(m->origin, "nodegraph 'NG_tint'");
  ASSERT_FALSE(m->input("in2")->linked);
  EXPECT_EQ(m->input("in2")->value.f[0], 0.25f);

  Graph copy = g;
  TexturePool tex;
  MaterialProgram prog;
  const CompiledMaterial& cm = compile_material(copy, tex, prog);
  float params[PMC_P_COUNT];
  evaluate(prog, cm, 0.5f, 0.5f, params);  // 0.25 * ((1, 0.5, 0) + ((0, 0, 1) - (1, 0.5, 0)) * 0.5)
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 0], 0.125f, 1e-6f);
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 1], 0.0625f, 1e-6f);
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 2], 0.125f, 1e-6f);
}

// An input with only `output="NAME"` reads the document's top-level output
// NAME (MaterialX's Input::getConnectedOutput; its PostShaderComposite
// example wires a custom shader's mix amount this way).
TEST(MtlxReader, OutputAloneConnectsToTheDocumentsTopLevelOutput) {
  const std::string top =
      "<ramplr name=\"ramp\" type=\"color3\">\n"
      "  <input name=\"valuel\" type=\"color3\" value=\"1, 0.5, 0\"/>\n"
      "  <input name=\"valuer\" type=\"color3\" value=\"0, 0, 1\"/>\n"
      "</ramplr>\n"
      "<output name=\"o_ramp\" type=\"color3\" nodename=\"ramp\"/>";
  std::vector<Graph> graphs =
      read_mtlx_string(doc(top, "<input name=\"base_color\" type=\"color3\" output=\"o_ramp\"/>"), kPath);
  ASSERT_EQ(graphs.size(), 1u);
  TexturePool tex;
  MaterialProgram prog;
  const CompiledMaterial& cm = compile_material(graphs[0], tex, prog);
  float params[PMC_P_COUNT];
  evaluate(prog, cm, 0.25f, 0.5f, params);  // (1, 0.5, 0) + ((0, 0, 1) - (1, 0.5, 0)) * 0.25
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 0], 0.75f, 1e-6f);
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 1], 0.375f, 1e-6f);
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 2], 0.25f, 1e-6f);

  std::string e = error_of([&] {
    read_and_compile(doc(top, "<input name=\"base_color\" type=\"color3\" output=\"o_missing\"/>"));
  });
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "'o_missing'");
  EXPECT_MENTIONS(e, "dangling reference");
}

// nodename= naming a nodegraph is no connection to MaterialX
// (Input::getConnectedOutput is null), so the input keeps its value or its
// definition's default; pmc reads it the same way, with a warning.
TEST(MtlxReader, NodenameNamingANodegraphIsNoConnection) {
  const std::string graph =
      "<nodegraph name=\"NG\">\n"
      "  <constant name=\"c\" type=\"color3\"><input name=\"value\" type=\"color3\" value=\"0, 1, "
      "0\"/></constant>\n"
      "  <output name=\"out\" type=\"color3\" nodename=\"c\"/>\n"
      "</nodegraph>";
  for (const std::string& input :
       {std::string("<input name=\"base_color\" type=\"color3\" nodename=\"NG\"/>"),
        std::string("<input name=\"base_color\" type=\"color3\" nodename=\"NG\" "
                    "value=\"0.1, 0.2, 0.3\"/>")}) {
    SCOPED_TRACE(input);
    std::vector<Graph> graphs = read_mtlx_string(doc(graph, input), kPath);
    ASSERT_EQ(graphs.size(), 1u);
    TexturePool tex;
    MaterialProgram prog;
    const CompiledMaterial& cm = compile_material(graphs[0], tex, prog);
    float params[PMC_P_COUNT];
    evaluate(prog, cm, 0.5f, 0.5f, params);
    const bool has_value = input.find("value=") != std::string::npos;
    EXPECT_NEAR(params[PMC_P_BASE_COLOR + 0], has_value ? 0.1f : 0.8f, 1e-6f);  // standard_surface's 0.8
    EXPECT_NEAR(params[PMC_P_BASE_COLOR + 1], has_value ? 0.2f : 0.8f, 1e-6f);
    EXPECT_NEAR(params[PMC_P_BASE_COLOR + 2], has_value ? 0.3f : 0.8f, 1e-6f);
  }
}

// A nodegraph nested in another: its inputs read the enclosing graph's
// interface, and the enclosing graph's nodes and outputs read its outputs
// (MaterialX's test suite, nodegraph_inputs/nested_nodegraph.mtlx).
TEST(MtlxReader, NestedNodegraphsReadTheEnclosingInterface) {
  const std::string graph =
      "<nodegraph name=\"outer\">\n"
      "  <input name=\"a\" type=\"color3\" value=\"1, 1, 0.2\"/>\n"
      "  <input name=\"b\" type=\"color3\" value=\"0.2, 1, 1\"/>\n"
      "  <input name=\"c\" type=\"color3\" value=\"1, 0.5, 1\"/>\n"
      "  <nodegraph name=\"inner\">\n"
      "    <input name=\"x\" type=\"color3\" interfacename=\"a\"/>\n"
      "    <input name=\"y\" type=\"color3\" interfacename=\"b\"/>\n"
      "    <multiply name=\"m\" type=\"color3\">\n"
      "      <input name=\"in1\" type=\"color3\" interfacename=\"x\"/>\n"
      "      <input name=\"in2\" type=\"color3\" interfacename=\"y\"/>\n"
      "    </multiply>\n"
      "    <output name=\"product\" type=\"color3\" nodename=\"m\"/>\n"
      "  </nodegraph>\n"
      "  <multiply name=\"m\" type=\"color3\">\n"  // same name as the inner node
      "    <input name=\"in1\" type=\"color3\" nodegraph=\"inner\" output=\"product\"/>\n"
      "    <input name=\"in2\" type=\"color3\" interfacename=\"c\"/>\n"
      "  </multiply>\n"
      "  <output name=\"direct\" type=\"color3\" nodegraph=\"inner\"/>\n"
      "  <output name=\"scaled\" type=\"color3\" nodename=\"m\"/>\n"
      "</nodegraph>";
  struct Case {
    const char* output;
    float r, g, b;
  };
  for (const Case& c : {Case{"direct", 0.2f, 1.0f, 0.2f}, Case{"scaled", 0.2f, 0.5f, 0.2f}}) {
    SCOPED_TRACE(c.output);
    std::vector<Graph> graphs = read_mtlx_string(
        doc(graph, std::string("<input name=\"base_color\" type=\"color3\" nodegraph=\"outer\" output=\"") +
                       c.output + "\"/>"),
        kPath);
    ASSERT_EQ(graphs.size(), 1u);
    ASSERT_TRUE(graphs[0].error.empty()) << graphs[0].error;
    TexturePool tex;
    MaterialProgram prog;
    const CompiledMaterial& cm = compile_material(graphs[0], tex, prog);
    float params[PMC_P_COUNT];
    evaluate(prog, cm, 0.5f, 0.5f, params);
    EXPECT_NEAR(params[PMC_P_BASE_COLOR + 0], c.r, 1e-6f);
    EXPECT_NEAR(params[PMC_P_BASE_COLOR + 1], c.g, 1e-6f);
    EXPECT_NEAR(params[PMC_P_BASE_COLOR + 2], c.b, 1e-6f);
  }
}

// Filename substitutions: "[token]" takes the nearest <token> of the
// filename's node or enclosing nodegraphs (not the document's), else the
// expanded instance's, else its definition's default (the specification's
// "Filename Substitutions"; MaterialX's test suite texture/token_graph.mtlx).
TEST(MtlxReader, FilenameTokensComeFromTheNearestInterface) {
  const std::string xml = R"(<?xml version="1.0"?>
<materialx version="1.39">
  <token name="ext" type="string" value="jpg"/>
  <nodegraph name="NG_own">
    <image name="own" type="color3">
      <token name="name" type="string" value="wood"/>
      <token name="ext" type="string" value="png"/>
      <input name="file" type="filename" value="tex/[name].[ext]"/>
    </image>
    <output name="out" type="color3" nodename="own"/>
  </nodegraph>
  <nodegraph name="NG_graph">
    <token name="name" type="string" value="cloth"/>
    <token name="ext" type="string" value="exr"/>
    <input name="file" type="filename" value="tex/[name].[ext]"/>
    <image name="graph" type="color3"><input name="file" type="filename" interfacename="file"/></image>
    <output name="out" type="color3" nodename="graph"/>
  </nodegraph>
  <nodegraph name="NG_top">
    <image name="top" type="color3"><input name="file" type="filename" value="tex/grid.[ext]"/></image>
    <output name="out" type="color3" nodename="top"/>
  </nodegraph>
  <nodedef name="ND_tokened" node="tokened">
    <token name="name" type="string" value="grid"/>
    <output name="out" type="color3"/>
  </nodedef>
  <nodegraph name="NG_tokened" nodedef="ND_tokened">
    <image name="def" type="color3"><input name="file" type="filename" value="tex/[name].png"/></image>
    <output name="out" type="color3" nodename="def"/>
  </nodegraph>
  <tokened name="by_default" type="color3"/>
  <tokened name="by_instance" type="color3"><token name="name" type="string" value="brick"/></tokened>
  <output name="o_own" type="color3" nodegraph="NG_own"/>
  <output name="o_graph" type="color3" nodegraph="NG_graph"/>
  <output name="o_top" type="color3" nodegraph="NG_top"/>
  <output name="o_default" type="color3" nodename="by_default"/>
  <output name="o_instance" type="color3" nodename="by_instance"/>
</materialx>
)";
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  auto file_of = [&](const std::string& material) {
    for (const Graph& g : graphs)
      if (g.material == material)
        for (const Node& n : g.nodes)
          if (n.category == "image") return n.input("file")->value.text;
    return std::string("(no image in " + material + ")");
  };
  EXPECT_EQ(file_of("o_own"), "/docs/looks/tex/wood.png");
  EXPECT_EQ(file_of("o_graph"), "/docs/looks/tex/cloth.exr");
  EXPECT_EQ(file_of("o_top"), "/docs/looks/tex/grid.[ext]") << "top-level tokens do not apply";
  EXPECT_EQ(file_of("o_default"), "/docs/looks/tex/grid.png");
  EXPECT_EQ(file_of("o_instance"), "/docs/looks/tex/brick.png");
}

// An interface input may stand for a geometric property (defaultgeomprop
// on a nodegraph's <input>), and a top-level node's interfacename may name a
// top-level <input> (MaterialX's test suite: defaultgeomprop.mtlx,
// nodegraphs/top_level_input.mtlx).
TEST(MtlxReader, InterfaceInputsWithGeomDefaultsAndAtTheTopLevel) {
  const std::string graph =
      "<input name=\"tint\" type=\"color3\" value=\"0, 0.25, 1\"/>\n"
      "<nodegraph name=\"NG\">\n"
      "  <input name=\"tc\" type=\"vector2\" defaultgeomprop=\"UV0\"/>\n"
      "  <extract name=\"x\" type=\"float\"><input name=\"in\" type=\"vector2\" interfacename=\"tc\"/>"
      "<input name=\"index\" type=\"integer\" value=\"0\"/></extract>\n"
      "  <output name=\"out\" type=\"float\" nodename=\"x\"/>\n"
      "</nodegraph>";
  std::vector<Graph> graphs =
      read_mtlx_string(doc(graph,
                           "<input name=\"base_color\" type=\"color3\" interfacename=\"tint\"/>\n"
                           "<input name=\"specular_roughness\" type=\"float\" nodegraph=\"NG\"/>"),
                       kPath);
  ASSERT_EQ(graphs.size(), 1u);
  TexturePool tex;
  MaterialProgram prog;
  const CompiledMaterial& cm = compile_material(graphs[0], tex, prog);
  float params[PMC_P_COUNT];
  evaluate(prog, cm, 0.375f, 0.5f, params);
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 0], 0.0f, 1e-6f);
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 1], 0.25f, 1e-6f);
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 2], 1.0f, 1e-6f);
  EXPECT_NEAR(params[PMC_P_SPECULAR_ROUGHNESS], 0.375f, 1e-6f);  // u
}

// An input with neither a value nor a connection (a typo such as
// "nodnname" in MaterialX's own geomattrvalue.mtlx) is unset: its
// definition's default, as MaterialX reads it.
TEST(MtlxReader, InputWithoutValueOrConnectionTakesItsDefault) {
  std::vector<Graph> graphs =
      read_mtlx_string(doc("",
                           "<input name=\"base_color\" type=\"color3\" nodnname=\"typo\"/>\n"
                           "<input name=\"specular_roughness\" type=\"float\"/>"),
                       kPath);
  ASSERT_EQ(graphs.size(), 1u);
  TexturePool tex;
  MaterialProgram prog;
  const CompiledMaterial& cm = compile_material(graphs[0], tex, prog);
  float params[PMC_P_COUNT];
  evaluate(prog, cm, 0.5f, 0.5f, params);
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 0], 0.8f, 1e-6f);  // standard_surface's defaults
  EXPECT_NEAR(params[PMC_P_SPECULAR_ROUGHNESS], 0.2f, 1e-6f);
}

// Materials that are not top-level surfacematerial nodes: a nodegraph that
// outputs a material (named after the nodegraph, so a look can assign it),
// and an instance of a custom node of type material whose definition's
// nodegraph builds one from the instance's inputs (MaterialX's test suite,
// TestSuite/stdlib/materials/material_node_discovery.mtlx and
// TestSuite/stdlib/definition/surfacematerial_definition.mtlx).
TEST(MtlxReader, NodegraphAndCustomNodeMaterials) {
  const std::string xml = R"(<?xml version="1.0"?>
<materialx version="1.39">
  <nodegraph name="NG_mat">
    <standard_surface name="sr" type="surfaceshader">
      <input name="base_color" type="color3" value="0.1, 0.2, 0.3"/>
    </standard_surface>
    <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="sr"/></surfacematerial>
    <output name="out" type="material" nodename="m"/>
  </nodegraph>
  <nodedef name="ND_tinted" node="tinted">
    <input name="tint" type="color3" value="0.5, 0.5, 0.5"/>
    <output name="out" type="material"/>
  </nodedef>
  <nodegraph name="NG_tinted" nodedef="ND_tinted">
    <standard_surface name="sr" type="surfaceshader">
      <input name="base_color" type="color3" interfacename="tint"/>
    </standard_surface>
    <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="sr"/></surfacematerial>
    <output name="out" type="material" nodename="m"/>
  </nodegraph>
  <tinted name="green" type="material"><input name="tint" type="color3" value="0, 1, 0"/></tinted>
  <tinted name="grey" type="material"/>
  <standard_surface name="SR" type="surfaceshader"/>
  <surfacematerial name="plain" type="material"><input name="surfaceshader" type="surfaceshader" nodename="SR"/></surfacematerial>
</materialx>
)";
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  auto base_color = [&](const std::string& material) {
    for (Graph& g : graphs)
      if (g.material == material) {
        EXPECT_TRUE(g.error.empty()) << g.error;
        TexturePool tex;
        MaterialProgram prog;
        const CompiledMaterial& cm = compile_material(g, tex, prog);
        float params[PMC_P_COUNT];
        evaluate(prog, cm, 0.5f, 0.5f, params);
        return std::vector<float>(params + PMC_P_BASE_COLOR, params + PMC_P_BASE_COLOR + 3);
      }
    ADD_FAILURE() << "no material " << material;
    return std::vector<float>();
  };
  EXPECT_EQ(base_color("NG_mat"), (std::vector<float>{0.1f, 0.2f, 0.3f}));
  EXPECT_EQ(base_color("green"), (std::vector<float>{0.0f, 1.0f, 0.0f}));
  EXPECT_EQ(base_color("grey"), (std::vector<float>{0.5f, 0.5f, 0.5f}));
  EXPECT_EQ(base_color("plain"), (std::vector<float>{0.8f, 0.8f, 0.8f}));
}

TEST(MtlxReader, UnconnectedInputsTakeLibraryDefaults) {
  std::string xml =
      doc("<ramplr name=\"ramp\" type=\"color3\">\n"
          "  <input name=\"valuel\" type=\"color3\" value=\"0, 0, 0\"/>\n"
          "  <input name=\"valuer\" type=\"color3\" value=\"1, 1, 1\"/>\n"
          "</ramplr>\n"
          "<noise2d name=\"noise\" type=\"float\"/>\n"
          "<fractal3d name=\"fractal\" type=\"vector3\"/>",
          "<input name=\"base_color\" type=\"color3\" nodename=\"ramp\"/>\n"
          "<input name=\"specular_roughness\" type=\"float\" nodename=\"noise\"/>\n"
          "<input name=\"normal\" type=\"vector3\" nodename=\"fractal\"/>");
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  ASSERT_EQ(graphs.size(), 1u);
  const Graph& g = graphs[0];
  auto node = [&](const std::string& name) -> const Node& {
    for (const Node& n : g.nodes)
      if (n.name == name) return n;
    ADD_FAILURE() << "no node " << name;
    return g.nodes[0];
  };
  const Node& ramp = node("ramp");
  const Input* tc = ramp.input("texcoord");
  ASSERT_NE(tc, nullptr);
  ASSERT_TRUE(tc->linked) << "an unconnected texcoord becomes a texcoord node";
  EXPECT_EQ(g.nodes[size_t(tc->node)].category, "texcoord");
  EXPECT_EQ(g.nodes[size_t(tc->node)].type, ValueType::Vector2);
  const Node& noise = node("noise");
  EXPECT_FALSE(noise.input("amplitude")->linked);
  EXPECT_EQ(noise.input("amplitude")->value.f[0], 1.0f);
  EXPECT_EQ(noise.input("pivot")->value.f[0], 0.0f);
  EXPECT_EQ(noise.input("texcoord")->node, tc->node) << "one implicit texcoord node is shared";
  const Node& fractal = node("fractal");
  for (int i = 0; i < 3; ++i) EXPECT_EQ(fractal.input("amplitude")->value.f[size_t(i)], 1.0f) << "broadcast";
  EXPECT_EQ(fractal.input("octaves")->value.f[0], 3.0f);
  EXPECT_EQ(fractal.input("lacunarity")->value.f[0], 2.0f);
  EXPECT_EQ(fractal.input("diminish")->value.f[0], 0.5f);
  ASSERT_TRUE(fractal.input("position")->linked);
  EXPECT_EQ(g.nodes[size_t(fractal.input("position")->node)].category, "position");
  // Surface inputs the document leaves out keep the standard_surface defaults.
  const Node& surface = g.nodes[size_t(g.surface)];
  EXPECT_EQ(surface.input("specular_IOR")->value.f[0], 1.5f);
  EXPECT_EQ(surface.input("base")->value.f[0], 1.0f);
}

TEST(MtlxReader, DocumentWithoutMaterialsYieldsPreviewsNamedAfterOutputs) {
  std::string xml =
      "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n"
      "  <constant name=\"quarter\" type=\"float\"><input name=\"value\" type=\"float\" "
      "value=\"0.25\"/></constant>\n"
      "  <output name=\"quarter_out\" type=\"float\" nodename=\"quarter\"/>\n"
      "  <nodegraph name=\"NG_one\">\n"
      "    <ramplr name=\"r\" type=\"color3\">\n"
      "      <input name=\"valuel\" type=\"color3\" value=\"1, 0, 0\"/>\n"
      "      <input name=\"valuer\" type=\"color3\" value=\"0, 1, 0\"/>\n"
      "    </ramplr>\n"
      "    <output name=\"out\" type=\"color3\" nodename=\"r\"/>\n"
      "  </nodegraph>\n"
      "  <nodegraph name=\"NG_two\">\n"
      "    <texcoord name=\"uv\" type=\"vector2\"/>\n"
      "    <output name=\"a\" type=\"vector2\" nodename=\"uv\"/>\n"
      "    <output name=\"b\" type=\"vector2\" nodename=\"uv\"/>\n"
      "  </nodegraph>\n"
      "</materialx>\n";
  MaterialProgram prog;
  std::vector<Graph> graphs = read_and_compile(xml, &prog);
  std::vector<std::string> names;
  for (const Graph& g : graphs) names.push_back(g.material);
  EXPECT_EQ(names, (std::vector<std::string>{"quarter_out", "NG_one", "NG_two/a", "NG_two/b"}));
  ASSERT_EQ(prog.materials.size(), 4u);
  float params[PMC_P_COUNT];
  evaluate(prog, prog.materials[0], 0.7f, 0.2f, params);  // float output: grey
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(params[PMC_P_BASE_COLOR + i], 0.25f, 1e-6f);
  evaluate(prog, prog.materials[1], 0.75f, 0.2f, params);  // the ramp at u = 0.75
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 0], 0.25f, 1e-6f);
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 1], 0.75f, 1e-6f);
  evaluate(prog, prog.materials[2], 0.75f, 0.2f, params);  // vector2 -> color3 (u, v, 0)
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 0], 0.75f, 1e-6f);
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 1], 0.2f, 1e-6f);
  EXPECT_NEAR(params[PMC_P_BASE_COLOR + 2], 0.0f, 1e-6f);
}

// Every shared MaterialX document: load, compile each material, evaluate it
// on the host at random shading points, and render it on the teapot.
constexpr uint32_t kCommonStack = 32;  // floats; the shared documents peak at 20
TEST(MtlxReader, EverySharedDocumentLoadsCompilesAndRenders) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string dir = test::shared_scene("materialx");
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".mtlx") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 5u) << "no MaterialX documents in " << dir;

  RenderConfig config;  // the teapot, framed; cacheless
  config.scene = test::shared_scene("materialx/geometry/teapot.obj");
  config.cache = false;
  config.width = 64;
  config.height = 48;
  config.spp = 2;
  config.max_depth = 3;
  config.env = {1.0f, 1.0f, 1.0f};
  // The renderer builds its kernels with -DPMC_STACK_SIZE=<peak of the
  // set>; each distinct peak costs a cold OpenCL build (seconds on PoCL,
  // ~9 distinct peaks here). Raising the peak to one common value (a larger
  // stack is always safe: it is what a scene with several materials gets)
  // lets every render reuse one build. Exact-peak builds are exercised by
  // the other render tests.
  config.min_kernel_stack = kCommonStack;

  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uni(-1.0f, 2.0f);
  int materials = 0;
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    std::vector<Graph> graphs;
    ASSERT_NO_THROW(graphs = read_mtlx_file(file));
    ASSERT_FALSE(graphs.empty());
    for (const Graph& g : graphs) {
      SCOPED_TRACE("material " + g.material);
      ++materials;
      RenderConfig c = config;
      c.mtlx = {file};
      c.material = g.material;
      std::unique_ptr<RenderSession> session;
      try {
        session = std::make_unique<RenderSession>(c, test::cl());
      } catch (const Error& e) {
        ADD_FAILURE() << e.what();
        continue;
      }
      // Host evaluation: finite parameters at random shading points
      // (uv and positions outside the unit square included).
      const MaterialSet& set = session->materials();
      const int mat = int(session->scene().materials.size()) - 1;
      PmcTextureSet ts = host_texture_set(session->scene(), set);
      for (int i = 0; i < 64; ++i) {
        PmcShadingInputs in{};
        in.uv = make_float2(uni(rng), uni(rng));
        in.position = make_float3(uni(rng), uni(rng), uni(rng));
        in.normal = make_float3(0, 0, 1);
        in.tangent = make_float3(1, 0, 0);
        in.bitangent = make_float3(0, 1, 0);
        in.footprint = i % 2 ? 0.01f : 0.0f;
        float params[PMC_P_COUNT];
        evaluate_material(set, ts, mat, in, params);
        for (int k = 0; k < PMC_P_COUNT; ++k)
          ASSERT_TRUE(std::isfinite(params[k])) << "param " << k << " at uv " << in.uv.x << " " << in.uv.y;
      }
      RenderOutput out;
      try {
        out = session->render();
      } catch (const Error& e) {
        ADD_FAILURE() << e.what();
        continue;
      }
      EXPECT_EQ(test::non_finite(out.image), 0u);
      EXPECT_EQ(out.stats.nan_pixels, 0u);
      EXPECT_EQ(out.stats.bad_samples, 0u);
      EXPECT_GT(test::image_mean(out.image), 0.0)
          << "an unlit image: the teapot or the environment is missing";
    }
  }
  EXPECT_GE(materials, int(files.size()));
  RecordProperty("materials", materials);
  RecordProperty(
      "seconds",
      std::to_string(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
}

}  // namespace
}  // namespace pmc
