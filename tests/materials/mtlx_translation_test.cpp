// mtlx_translation_test.cpp — MaterialX's shader-translation nodes
// (libraries/bxdf/translation: standard_surface_to_gltf_pbr ...), data nodes
// with many outputs that expand from their library nodegraphs.
//
// Independent answers: each output named by the library's nodedef (read here
// with pugixml) builds and compiles; and glTF values worked by hand from the
// translation's documented rules (base colour = base_color * base, tinted
// by the coat colour mixed by coat when a coat colour is set; metallic =
// metalness).
#include <gtest/gtest.h>

#include <pugixml.hpp>
#include <string>

#include "core/device/pmc_interp.h"
#include "materials/compiler.h"
#include "materials/mtlx_library.h"
#include "materials/mtlx_reader.h"
#include "tests/support/material_eval.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

const std::string kPath = "/docs/translation_doc.mtlx";

TEST(MtlxTranslation, EveryOutputOfEveryTranslationNodeCompiles) {
  const std::string dir = find_mtlx_library("");
  ASSERT_FALSE(dir.empty()) << "the build found no MaterialX library";
  const MtlxLibrary& lib = MtlxLibrary::load(dir);
  int outputs = 0;
  for (const char* category : {"standard_surface_to_open_pbr_surface", "open_pbr_surface_to_standard_surface",
                               "standard_surface_to_gltf_pbr", "standard_surface_to_UsdPreviewSurface"}) {
    const auto& defs = lib.definitions().nodedefs_for(category);
    ASSERT_EQ(defs.size(), 1u) << category;
    std::string body = std::string("<") + category + " name=\"t\" type=\"multioutput\"/>";
    for (pugi::xml_node o : defs[0].children("output")) {
      const std::string type = o.attribute("type").as_string();
      if (type == "boolean" || type == "integer" || type == "string") continue;  // not previewable as colour
      body += "<output name=\"o_" + std::string(o.attribute("name").as_string()) + "\" type=\"" + type +
              "\" nodename=\"t\" output=\"" + o.attribute("name").as_string() + "\"/>";
      ++outputs;
    }
    const std::string xml = "<?xml version=\"1.0\"?><materialx version=\"1.39\">" + body + "</materialx>";
    std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
    for (Graph& g : graphs) {
      EXPECT_EQ(g.error, "") << category << " " << g.material;
      if (!g.error.empty()) continue;
      TexturePool tex;
      MaterialProgram prog;
      EXPECT_NO_THROW(compile_material(g, tex, prog)) << category << " " << g.material;
    }
  }
  EXPECT_GT(outputs, 80);
}

// glTF base colour and metallic from a standard_surface's inputs.
void gltf_of(const std::string& inputs, float color[3], float* metal) {
  const std::string xml =
      "<?xml version=\"1.0\"?><materialx version=\"1.39\">"
      "<standard_surface_to_gltf_pbr name=\"t\" type=\"multioutput\">" +
      inputs +
      "</standard_surface_to_gltf_pbr>"
      "<gltf_pbr name=\"SR\" type=\"surfaceshader\">"
      "<input name=\"base_color\" type=\"color3\" nodename=\"t\" output=\"base_color_out\"/>"
      "<input name=\"metallic\" type=\"float\" nodename=\"t\" output=\"metallic_out\"/></gltf_pbr>"
      "<surfacematerial name=\"M\" type=\"material\"><input name=\"surfaceshader\" type=\"surfaceshader\" "
      "nodename=\"SR\"/></surfacematerial></materialx>";
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  ASSERT_EQ(graphs[0].error, "");
  float p[PMC_P_COUNT];
  test::surface_params_at(graphs[0], 0.0f, 0.0f, p);
  for (int i = 0; i < 3; ++i) color[i] = p[PMC_P_BASE_COLOR + i];
  *metal = p[PMC_P_METALNESS];
}

TEST(MtlxTranslation, StandardSurfaceToGltfByHand) {
  const std::string base =
      "<input name=\"base\" type=\"float\" value=\"0.5\"/>"
      "<input name=\"base_color\" type=\"color3\" value=\"0.8, 0.4, 0.2\"/>"
      "<input name=\"metalness\" type=\"float\" value=\"0.7\"/>";
  float c[3], m;
  gltf_of(base, c, &m);  // no coat colour: base_color * base
  EXPECT_NEAR(c[0], 0.4f, 1e-6f);
  EXPECT_NEAR(c[1], 0.2f, 1e-6f);
  EXPECT_NEAR(c[2], 0.1f, 1e-6f);
  EXPECT_NEAR(m, 0.7f, 1e-6f);
  // A coat colour (1, 0.5, 0.25) at coat 0.5 tints by mix(1, coat_color, 0.5) = (1, 0.75, 0.625).
  gltf_of(base +
              "<input name=\"coat\" type=\"float\" value=\"0.5\"/>"
              "<input name=\"coat_color\" type=\"color3\" value=\"1, 0.5, 0.25\"/>",
          c, &m);
  EXPECT_NEAR(c[0], 0.4f, 1e-6f);
  EXPECT_NEAR(c[1], 0.2f * 0.75f, 1e-6f);
  EXPECT_NEAR(c[2], 0.1f * 0.625f, 1e-6f);
}

}  // namespace
}  // namespace pmc
