// material_eval.cpp — one shading point through the reference interpreter.
#include "tests/support/material_eval.h"

namespace pmc::test {

void run_program_at(const MaterialProgram& p, const CompiledMaterial& m, float u, float v,
                    float params[PMC_P_COUNT], const float3& pos, PmcCacheContext* cache, float footprint) {
  PmcShadingInputs in{};
  in.uv = make_float2(u, v);
  in.position = pos;
  in.normal = make_float3(0, 0, 1);
  in.tangent = make_float3(1, 0, 0);
  in.bitangent = make_float3(0, 1, 0);
  in.footprint = footprint;
  PmcTextureSet ts{};
  float stack[PMC_STACK_SIZE] = {0};
  pmc_surface_defaults(params, in.normal);
  pmc_interp_run(p.code.data(), m.entry, &in, &ts, stack, params, cache);
}

void surface_params_at(Graph g, float u, float v, float params[PMC_P_COUNT], CompiledMaterial* compiled) {
  TexturePool tex;
  MaterialProgram prog;
  const CompiledMaterial& cm = compile_material(g, tex, prog);
  run_program_at(prog, cm, u, v, params);
  if (compiled) *compiled = cm;
}

}  // namespace pmc::test
