// material_set.h — every material of a scene, compiled into one program.
//
// build_material_set() binds each material the scene's triangles use: an OBJ
// `usemtl NAME` takes the MaterialX `surfacematerial` called NAME from the
// --mtlx documents, else its own MTL entry turned into a network. Only used
// materials are compiled and only their textures loaded. The result holds
// what the kernels need (the bytecode, a PmcMaterialInfo per material) and a
// host-side evaluator for the CPU reference and cut-out opacity.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/abi/pmc_interp.h"
#include "core/scene.h"
#include "materials/compiler.h"

namespace pmc {

struct MaterialOptions {
  std::vector<std::string> mtlx_files;
  std::string override_material;  // --material: one material for every triangle
  CompileOptions compile;         // cache instructions on/off, cache threshold
};

struct MaterialSet {
  MaterialProgram program;
  std::vector<PmcMaterialInfo> infos;  // per scene material
  std::vector<int> compiled;           // per scene material: index into program.materials, -1 if unused
  std::vector<Graph> graphs;           // optimised graphs, parallel to program.materials
  std::vector<uint32_t> texel_words;   // the scene's texel pool as 32-bit RGBA words
  std::vector<float> srgb_lut;

  // Host evaluation of one material (the CPU reference interpreter).
  void evaluate(const PmcTextureSet& textures, int scene_material, const PmcShadingInputs& in,
                float params[PMC_P_COUNT]) const;
  PmcTextureSet host_textures(const Scene& scene) const;
};

MaterialSet build_material_set(Scene& scene, const MaterialOptions& options);

}  // namespace pmc
