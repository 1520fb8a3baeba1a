// material_eval.h — a material's surface parameters at one shading point,
// on the CPU reference interpreter (core/device/pmc_interp.h): one point
// facing +z (tangent +x, bitangent +y), without textures.
#pragma once

#include "core/abi/pmc_bytecode.h"
#include "core/abi/pmc_vec.h"
#include "core/device/pmc_interp.h"
#include "materials/compiler.h"
#include "materials/node_graph.h"

namespace pmc::test {

// Runs material `m` of program `p` at uv (u, v) and position `pos`, with a
// cache context (null: every lookup misses) and a uv footprint; fills
// params[PMC_P_COUNT] with its surface parameters.
void run_program_at(const MaterialProgram& p, const CompiledMaterial& m, float u, float v,
                    float params[PMC_P_COUNT], const float3& pos = make_float3(0.3f, -0.2f, 0.7f),
                    PmcCacheContext* cache = nullptr, float footprint = 0.0f);

// Compiles `g` alone (a copy: compiling optimises the graph) and runs it at
// uv (u, v); `compiled`, if given, receives the compiled material.
void surface_params_at(Graph g, float u, float v, float params[PMC_P_COUNT],
                       CompiledMaterial* compiled = nullptr);

}  // namespace pmc::test
