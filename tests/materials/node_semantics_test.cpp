// node_semantics_test.cpp — MaterialX inputs reach the right operands.
//
// The node library lists inputs in the order the opcode reads its operands.
// Here documents with non-default amplitudes, pivots and octaves compile and
// run on the host interpreter, and the result must equal the noise functions
// called directly with the position and those parameters. A wrong operand
// order (amplitude read as the position) fails these tests.
#include <gtest/gtest.h>

#include "core/device/pmc_interp.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"

namespace pmc {
namespace {

float eval_base_color_r(const std::string& node_xml, float2 uv, float3 pos) {
  std::string doc =
      R"(<?xml version="1.0"?><materialx version="1.39">)" + node_xml +
      R"(<standard_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="n"/></standard_surface>
<surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial></materialx>)";
  std::vector<Graph> graphs = read_mtlx_string(doc, "mem.mtlx");
  TexturePool textures;
  MaterialProgram program;
  const CompiledMaterial& m = compile_material(graphs[0], textures, program);
  PmcShadingInputs in{};
  in.uv = uv;
  in.position = pos;
  in.normal = make_float3(0, 0, 1);
  PmcTextureSet ts{};
  float stack[PMC_STACK_SIZE], params[PMC_P_COUNT];
  pmc_surface_defaults(params, in.normal);
  pmc_interp_run(program.code.data(), m.entry, &in, &ts, stack, params, nullptr);
  return params[PMC_P_BASE_COLOR];
}

TEST(NodeSemantics, NoiseAndFractalReadPositionAmplitudePivotInOrder) {
  const float2 uv = make_float2(0.37f, 0.81f);
  const float3 pos = make_float3(1.3f, -0.4f, 2.2f);
  float n2 = eval_base_color_r(
      R"(<noise2d name="n" type="color3"><input name="amplitude" type="color3" value="3,3,3"/><input name="pivot" type="float" value="0.5"/></noise2d>)",
      uv, pos);
  EXPECT_NEAR(n2, pmc_op_noise2d(uv, 3).x * 3.0f + 0.5f, 1e-5f);
  float n3 = eval_base_color_r(
      R"(<noise3d name="n" type="color3"><input name="amplitude" type="float" value="2"/><input name="pivot" type="float" value="0.25"/></noise3d>)",
      uv, pos);
  EXPECT_NEAR(n3, pmc_op_noise3d(pos, 3).x * 2.0f + 0.25f, 1e-5f);
  float f2 = eval_base_color_r(
      R"(<fractal2d name="n" type="color3"><input name="amplitude" type="float" value="1.5"/><input name="octaves" type="integer" value="4"/><input name="lacunarity" type="float" value="2.5"/><input name="diminish" type="float" value="0.4"/></fractal2d>)",
      uv, pos);
  EXPECT_NEAR(f2, pmc_op_fractal2d(uv, 4, 2.5f, 0.4f, 3).x * 1.5f, 1e-5f);
  float f3 = eval_base_color_r(
      R"(<fractal3d name="n" type="color3"><input name="amplitude" type="float" value="0.7"/><input name="octaves" type="integer" value="2"/></fractal3d>)",
      uv, pos);
  EXPECT_NEAR(f3, pmc_op_fractal3d(pos, 2, 2.0f, 0.5f, 3).x * 0.7f, 1e-5f);
}

}  // namespace
}  // namespace pmc
