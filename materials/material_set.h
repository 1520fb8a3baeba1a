// material_set.h — every material of a scene, compiled into one program.
//
// build_material_set() binds each material the scene's triangles use: a
// MaterialX <look>'s <materialassign> covering the triangle's OBJ object or
// group ("/NAME") wins; else its `usemtl NAME` takes the MaterialX
// `surfacematerial` called NAME from the mtlx documents (whether or not an
// MTL defines NAME), else its own MTL entry turned into a network. One
// warning lists the usemtl names that match nothing (they render with the
// default material). Only used
// materials are compiled and only their textures loaded. The result holds
// what the kernels need (the bytecode, a PmcMaterialInfo per material); the
// host's reference interpreter of it is materials/cpu_interpreter.h.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/abi/pmc_types.h"
#include "core/scene.h"
#include "core/texture.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"

namespace pmc {

struct MaterialSet;

struct MaterialOptions {
  std::vector<std::string> mtlx_files;
  MtlxReadOptions mtlx;           // mtlx_library, mtlx_search_paths
  std::string override_material;  // material: one material for every triangle
  CompileOptions compile;         // cache instructions on/off, cache threshold
  // Called once every material is compiled, before the textures decode (the
  // longest step after it): a render session starts its kernel build there.
  std::function<void(MaterialSet&)> compiled;
};

struct MaterialSet {
  MaterialProgram program;
  std::vector<PmcMaterialInfo> infos;  // per scene material
  std::vector<int> compiled;           // per scene material: index into program.materials, -1 if unused
  std::vector<Graph> graphs;           // optimised graphs, parallel to program.materials
  // Cut-out materials' opacity alone (materials/cutout.h), for the host:
  // per scene material, its entry in `cutout_program`, or -1 without a cut-out.
  MaterialProgram cutout_program;
  std::vector<int> cutout_entry;
  // The scene's texel pool as 32-bit RGBA words, shared with the pool (no copy; never changes).
  std::shared_ptr<const TexelWords> texel_words = std::make_shared<const TexelWords>();
  std::vector<float> srgb_lut;
};

MaterialSet build_material_set(Scene& scene, const MaterialOptions& options);

}  // namespace pmc
