// hair_data_test.cpp — pbrlib's hair data nodes (core/device/pmc_hair_data.h)
// through documents: chiang_hair_roughness (three outputs),
// deon_hair_absorption_from_melanin, chiang_hair_absorption_from_color.
//
// Independent answers: values worked by hand from the papers' formulas
// (Chiang et al. 2016, "A Practical and Controllable Hair and Fur Model for
// Production Path Tracing", eqs. 7-9), and d'Eon et al. 2011's published
// absorption coefficients of eumelanin (0.419, 0.697, 1.37) and pheomelanin
// (0.187, 0.4, 1.05), of which MaterialX's default colours are exp(-sigma).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/device/pmc_interp.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"
#include "tests/support/material_eval.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

const std::string kPath = "/docs/hair_doc.mtlx";

// metalness and base_color of a document whose material reads them from `body`'s nodes.
struct Params {
  float metal, color[3];
};
Params evaluate(const std::string& body, const std::string& inputs) {
  const std::string xml = "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n" + body +
                          "\n<standard_surface name=\"SR\" type=\"surfaceshader\">" + inputs +
                          "</standard_surface>\n<surfacematerial name=\"M\" type=\"material\">"
                          "<input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR\"/>"
                          "</surfacematerial>\n</materialx>\n";
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  EXPECT_EQ(graphs[0].error, "");
  float p[PMC_P_COUNT];
  test::surface_params_at(graphs[0], 0.5f, 0.5f, p);
  return {p[PMC_P_METALNESS], {p[PMC_P_BASE_COLOR], p[PMC_P_BASE_COLOR + 1], p[PMC_P_BASE_COLOR + 2]}};
}

// Lane `index` of `output` of a chiang_hair_roughness with the given inputs, as metalness.
float roughness(const std::string& output, int index, const std::string& inputs) {
  return evaluate("<chiang_hair_roughness name=\"h\" type=\"multioutput\">" + inputs +
                      "</chiang_hair_roughness><extract name=\"e\" type=\"float\"><input name=\"in\" "
                      "type=\"vector2\" nodename=\"h\" output=\"" +
                      output + "\"/><input name=\"index\" type=\"integer\" value=\"" + std::to_string(index) +
                      "\"/></extract>",
                  "<input name=\"metalness\" type=\"float\" nodename=\"e\"/>")
      .metal;
}

TEST(HairData, ChiangRoughnessByHand) {
  const std::string in =
      "<input name=\"longitudinal\" type=\"float\" value=\"0.3\"/>"
      "<input name=\"azimuthal\" type=\"float\" value=\"0.5\"/>";
  // v = (0.726 * 0.3 + 0.812 * 0.09 + 3.7 * 0.3^20)^2 = (0.2178 + 0.07308 + 1.3e-10)^2 = 0.29088^2
  const double v = 0.0846111745;
  // s = 0.265 * 0.5 + 1.194 * 0.25 + 5.372 * 0.5^22 = 0.1325 + 0.2985 + 1.2808e-6
  const double s = 0.4310012808;
  EXPECT_NEAR(roughness("roughness_R", 0, in), v, 1e-6);
  EXPECT_NEAR(roughness("roughness_R", 1, in), s, 1e-6);
  EXPECT_NEAR(roughness("roughness_TT", 0, in), v * 0.25, 1e-6);  // scale_TT 0.5 by default
  EXPECT_NEAR(roughness("roughness_TT", 1, in), s, 1e-6);
  EXPECT_NEAR(roughness("roughness_TRT", 0, in), v * 4.0, 1e-6);  // scale_TRT 2
  EXPECT_NEAR(roughness("roughness_TRT", 0, in + "<input name=\"scale_TRT\" type=\"float\" value=\"3\"/>"),
              v * 9.0, 1e-6);
  // Clamped to [0.001, 1]: at 1, (0.726 + 0.812 + 3.7)^2 = 27.436644; at 0, (0.000726 + 8.12e-7)^2.
  EXPECT_NEAR(roughness("roughness_R", 0, "<input name=\"longitudinal\" type=\"float\" value=\"1.5\"/>"),
              27.436644, 27.436644 * 1e-6);
  EXPECT_NEAR(roughness("roughness_R", 0, "<input name=\"longitudinal\" type=\"float\" value=\"-1\"/>"),
              5.2825568e-7, 1e-12);
  // Defaults (0.1, 0.2): v = (0.0726 + 0.00812 + 3.7e-20)^2, s = 0.053 + 0.04776 + 5.372 * 0.2^22.
  EXPECT_NEAR(roughness("roughness_R", 0, ""), 0.08072 * 0.08072, 1e-7);
  EXPECT_NEAR(roughness("roughness_R", 1, ""), 0.10076, 1e-6);
}

TEST(HairData, MelaninAbsorptionIsDEonsCoefficients) {
  const double eu[3] = {0.419, 0.697, 1.37}, pheo[3] = {0.187, 0.4, 1.05};
  for (auto [c, r] : {std::pair<double, double>{0.25, 0.5}, {0.8, 0.1}, {0.5, 1.0}, {0.0, 0.3}}) {
    const Params p = evaluate(
        "<deon_hair_absorption_from_melanin name=\"d\" type=\"vector3\">"
        "<input name=\"melanin_concentration\" type=\"float\" value=\"" +
            std::to_string(c) + "\"/><input name=\"melanin_redness\" type=\"float\" value=\"" +
            std::to_string(r) +
            "\"/></deon_hair_absorption_from_melanin>"
            "<convert name=\"c\" type=\"color3\"><input name=\"in\" type=\"vector3\" "
            "nodename=\"d\"/></convert>",
        "<input name=\"base_color\" type=\"color3\" nodename=\"c\"/>");
    const double melanin = -std::log(1.0 - c);
    for (int l = 0; l < 3; ++l) {
      const double want = melanin * ((1 - r) * eu[l] + r * pheo[l]);
      EXPECT_NEAR(p.color[l], want, 2e-5 * std::max(1.0, want)) << c << " " << r << " lane " << l;
    }
  }
  // A concentration of 1 is limited to -log(1e-4).
  const Params full = evaluate(
      "<deon_hair_absorption_from_melanin name=\"d\" type=\"vector3\"><input name=\"melanin_concentration\" "
      "type=\"float\" value=\"1\"/><input name=\"melanin_redness\" type=\"float\" value=\"0\"/>"
      "</deon_hair_absorption_from_melanin>"
      "<convert name=\"c\" type=\"color3\"><input name=\"in\" type=\"vector3\" nodename=\"d\"/></convert>",
      "<input name=\"base_color\" type=\"color3\" nodename=\"c\"/>");
  EXPECT_NEAR(full.color[0], -std::log(1e-4) * 0.419, 1e-3);
}

TEST(HairData, ColourAbsorptionIsChiangsEquation9) {
  // beta_n = 0.3: 5.969 - 0.0645 + 0.22788 - 0.28971 + 0.04514940 + 0.00059535 = 5.88841475.
  const Params p = evaluate(
      "<chiang_hair_absorption_from_color name=\"a\" type=\"vector3\">"
      "<input name=\"color\" type=\"color3\" value=\"0.4, 1.0, 0.0\"/>"
      "<input name=\"azimuthal_roughness\" type=\"float\" value=\"0.3\"/></chiang_hair_absorption_from_color>"
      "<convert name=\"c\" type=\"color3\"><input name=\"in\" type=\"vector3\" nodename=\"a\"/></convert>",
      "<input name=\"base_color\" type=\"color3\" nodename=\"c\"/>");
  const double fac = 5.88841475;
  EXPECT_NEAR(p.color[0], std::pow(std::log(0.4) / fac, 2), 1e-6);
  EXPECT_EQ(p.color[1], 0.0f);                                        // white hair absorbs nothing
  EXPECT_NEAR(p.color[2], std::pow(std::log(0.001) / fac, 2), 1e-5);  // black clamps to 0.001
}

}  // namespace
}  // namespace pmc
