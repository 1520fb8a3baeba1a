// view_direction_test.cpp — the view direction pmc's materials approximate.
//
// Shading inputs carry no ray direction, so a `viewdirection` node, and an
// input whose library default is the geometric property Vworld (nprlib's
// `facingratio`), read -N: the view of the surface head-on. Checked on the host
// reference interpreter against that answer: viewdirection = -N, and
// facingratio = |V . N| = 1 (0 with invert), each with a warning naming the
// approximation.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/device/pmc_interp.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"

namespace pmc {
namespace {

// base_color of material M (nodes, then base_color from `input`) at normal n.
float4 base_color(const std::string& nodes, const std::string& input, float3 n, std::string* warnings) {
  std::string doc = R"(<?xml version="1.0"?><materialx version="1.39">)" + nodes +
                    R"(<standard_surface name="S" type="surfaceshader">)" + input +
                    R"(</standard_surface><surfacematerial name="M" type="material">
<input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial></materialx>)";
  testing::internal::CaptureStderr();
  std::vector<Graph> graphs = read_mtlx_string(doc, "mem.mtlx");
  EXPECT_EQ(graphs[0].error, "");
  TexturePool textures;
  MaterialProgram program;
  const CompiledMaterial& m = compile_material(graphs[0], textures, program);
  *warnings = testing::internal::GetCapturedStderr();
  PmcShadingInputs in{};
  in.normal = n;
  in.tangent = make_float3(1, 0, 0);
  in.bitangent = cross(n, in.tangent);
  PmcTextureSet ts{};
  float stack[PMC_STACK_SIZE], params[PMC_P_COUNT];
  pmc_surface_defaults(params, in.normal);
  pmc_interp_run(program.code.data(), m.entry, &in, &ts, stack, params, nullptr);
  return make_float4(params[PMC_P_BASE_COLOR], params[PMC_P_BASE_COLOR + 1], params[PMC_P_BASE_COLOR + 2], 0);
}

TEST(ViewDirection, IsTheNegatedNormal) {
  std::string w;
  const float3 n = make_float3(0.0f, 0.6f, 0.8f);
  float4 v = base_color(R"(<viewdirection name="v" type="vector3"/>)",
                        R"(<input name="base_color" type="vector3" nodename="v"/>)", n, &w);
  EXPECT_FLOAT_EQ(v.x, 0.0f);
  EXPECT_FLOAT_EQ(v.y, -0.6f);
  EXPECT_FLOAT_EQ(v.z, -0.8f);
  EXPECT_NE(w.find("viewdirection is approximated by the negated shading normal"), std::string::npos) << w;
}

// facingratio's viewdirection input defaults to Vworld (nprlib_defs.mtlx).
TEST(ViewDirection, VworldDefaultOfFacingRatio) {
  const float3 n = make_float3(0.36f, 0.48f, 0.8f);
  for (const char* invert : {"false", "true"})
    for (const char* faceforward : {"true", "false"}) {
      std::string w;
      float4 f = base_color(
          std::string(R"(<facingratio name="f" type="float"><input name="invert" type="boolean" value=")") +
              invert + R"("/><input name="faceforward" type="boolean" value=")" + faceforward +
              R"("/></facingratio>)",
          R"(<input name="base_color" type="float" nodename="f"/>)", n, &w);
      // V = -N: V . N = -1; faceforward takes |.|, else -(V . N); both 1. invert: 1 - 1.
      EXPECT_NEAR(f.x, std::string(invert) == "true" ? 0.0f : 1.0f, 1e-6f) << invert << " " << faceforward;
      EXPECT_NE(w.find("approximated by the negated shading normal"), std::string::npos) << w;
    }
}

}  // namespace
}  // namespace pmc
