// mtlx_include_test.cpp — <xi:include> in MaterialX documents
// (materials/mtlx_include.h), read through read_mtlx_file.
//
// The specification's rules: an included file's root children join the
// including root, with its root attributes (colorspace, fileprefix) passed
// down. pmc's own: an included older document is upgraded by its own
// version, its relative filenames resolve from its folder, includes are
// found in the search paths too, a file is included once (cycles are
// harmless), and a missing file is an error naming the include.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/error.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

const Graph* graph_named(const std::vector<Graph>& graphs, const std::string& material) {
  for (const Graph& g : graphs)
    if (g.material == material) return &g;
  return nullptr;
}

const Node* node_named(const Graph& g, const std::string& name) {
  for (const Node& n : g.nodes)
    if (n.name == name) return &n;
  return nullptr;
}

std::string error_of(const std::string& path, const MtlxReadOptions& options = {}) {
  try {
    read_mtlx_file(path, options);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// lib/shared.mtlx: a 1.38 document (<parameter>s) whose root sets a
// colorspace and a fileprefix, with a material and a nodegraph reading an
// image that exists only beside it (lib/tex/wood.png).
void write_shared_library(const std::string& dir) {
  test::write_file(dir + "/lib/tex/wood.png", "");  // resolution only checks that it exists
  test::write_file(dir + "/lib/shared.mtlx", R"(<?xml version="1.0"?>
<materialx version="1.38" colorspace="srgb_texture" fileprefix="tex/">
  <nodegraph name="NG_wood">
    <image name="wood" type="color3">
      <parameter name="file" type="filename" value="wood.png"/>
    </image>
    <output name="out" type="color3" nodename="wood"/>
  </nodegraph>
  <standard_surface name="SR_inc" type="surfaceshader">
    <input name="base_color" type="color3" value="0.2, 0.4, 0.6"/>
  </standard_surface>
  <surfacematerial name="M_inc" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_inc"/>
  </surfacematerial>
  <look name="L_inc">
    <materialassign name="MA" material="M_inc" geom="/table"/>
  </look>
</materialx>
)");
}

TEST(MtlxInclude, IncludedMaterialsNodegraphsAndLooksJoinTheDocument) {
  const std::string dir = test::temp_dir();
  write_shared_library(dir);
  test::write_file(dir + "/main.mtlx", R"(<?xml version="1.0"?>
<materialx version="1.39" xmlns:xi="http://www.w3.org/2001/XInclude">
  <xi:include href="lib/shared.mtlx"/>
  <standard_surface name="SR_main" type="surfaceshader">
    <input name="base_color" type="color3" nodegraph="NG_wood" output="out"/>
  </standard_surface>
  <surfacematerial name="M_main" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_main"/>
  </surfacematerial>
</materialx>
)");
  std::vector<Graph> graphs = read_mtlx_file(dir + "/main.mtlx");
  ASSERT_NE(graph_named(graphs, "M_inc"), nullptr);
  const Graph* main = graph_named(graphs, "M_main");
  ASSERT_NE(main, nullptr);
  EXPECT_TRUE(main->error.empty()) << main->error;

  // The included 1.38 <parameter> was upgraded; the filename took the
  // included root's fileprefix and resolved in the included file's folder;
  // its colorspace came down from the included root.
  const Node* wood = node_named(*main, "wood");
  ASSERT_NE(wood, nullptr);
  ASSERT_NE(wood->input("file"), nullptr);
  EXPECT_EQ(wood->input("file")->value.text, dir + "/lib/tex/wood.png");
  EXPECT_EQ(wood->input("file")->value.f[0], 1.0f) << "srgb_texture from the included root";

  // The included look assigns the included material.
  std::vector<MtlxAssignment> looks = read_mtlx_assignments(MtlxDocument::from_file(dir + "/main.mtlx"));
  ASSERT_EQ(looks.size(), 1u);
  EXPECT_EQ(looks[0].material, "M_inc");
  EXPECT_EQ(looks[0].geom, "/table");
}

TEST(MtlxInclude, SearchPathsFindIncludesAndCyclesAddNothing) {
  const std::string dir = test::temp_dir();
  write_shared_library(dir);
  // a.mtlx and b.mtlx include each other; b also includes the library
  // through the search path.
  test::write_file(dir + "/a.mtlx", R"(<?xml version="1.0"?>
<materialx version="1.39"><xi:include href="b.mtlx"/>
  <surfacematerial name="M_a" type="material"/>
</materialx>
)");
  test::write_file(dir + "/b.mtlx", R"(<?xml version="1.0"?>
<materialx version="1.39"><xi:include href="a.mtlx"/><xi:include href="shared.mtlx"/>
  <surfacematerial name="M_b" type="material"/>
</materialx>
)");
  EXPECT_NE(error_of(dir + "/a.mtlx").find("'shared.mtlx'"), std::string::npos)
      << "without the search path the library is missing";
  MtlxReadOptions options;
  options.search_paths = {dir + "/lib"};
  std::vector<Graph> graphs = read_mtlx_file(dir + "/a.mtlx", options);
  int inc = 0, a = 0, b = 0;
  for (const Graph& g : graphs) {
    inc += g.material == "M_inc";
    a += g.material == "M_a";
    b += g.material == "M_b";
  }
  EXPECT_EQ(inc, 1);
  EXPECT_EQ(a, 1);
  EXPECT_EQ(b, 1);
}

TEST(MtlxInclude, MissingOrBrokenIncludesNameTheChain) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/main.mtlx",
                   "<materialx version=\"1.39\"><xi:include href=\"mid.mtlx\"/></materialx>");
  test::write_file(dir + "/mid.mtlx",
                   "<materialx version=\"1.39\"><xi:include href=\"nowhere.mtlx\"/></materialx>");
  std::string e = error_of(dir + "/main.mtlx");
  EXPECT_NE(e.find(dir + "/main.mtlx -> " + dir + "/mid.mtlx"), std::string::npos) << e;
  EXPECT_NE(e.find("'nowhere.mtlx'"), std::string::npos) << e;
  EXPECT_NE(e.find("no such file"), std::string::npos) << e;

  test::write_file(dir + "/mid.mtlx", "<notmaterialx/>");
  e = error_of(dir + "/main.mtlx");
  EXPECT_NE(e.find("'mid.mtlx'"), std::string::npos) << e;
  EXPECT_NE(e.find("not a MaterialX document"), std::string::npos) << e;

  test::write_file(dir + "/mid.mtlx", "<materialx><unclosed></materialx>");
  e = error_of(dir + "/main.mtlx");
  EXPECT_NE(e.find("not valid XML"), std::string::npos) << e;

  // A folder is not a document (and a device would not be read either).
  test::write_file(dir + "/main.mtlx", "<materialx version=\"1.39\"><xi:include href=\"lib\"/></materialx>");
  test::write_file(dir + "/lib/x.mtlx", "<materialx/>");
  e = error_of(dir + "/main.mtlx");
  EXPECT_NE(e.find("no such file"), std::string::npos) << e;
}

}  // namespace
}  // namespace pmc
