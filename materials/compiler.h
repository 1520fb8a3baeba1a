// compiler.h — material graphs into one flat bytecode buffer.
//
// compile_material() optimises a graph (passes.h) and appends its program to
// a MaterialProgram: nodes are emitted in topological order, each output gets
// contiguous stack slots chosen first-fit and freed after the last consumer
// is emitted, unlinked inputs become inline constants stored after the
// material's END, and the surface's inputs become OUTPUT instructions. All
// materials share one buffer; each has an entry offset. Images are loaded
// into the scene's texture pool here, so only textures a live node reads are
// ever loaded. A program that needs more stack than PMC_STACK_SIZE is
// refused with an error naming the material.
//
// With the cache on, a material's cache points form a group per key kind at
// the start of its program, its uv points' (which share the shading point's
// texel) before its position points' (which share its cell): a CACHE_LOOKUP
// per point, then the union of their sub-graphs (each node once, its own
// texcoord included, in group-local slots), then a CACHE_STORE per point
// that inserts and delivers the values that missed. A group's last lookup
// jumps past it when every lookup hit. The kinds miss apart (a new cell is
// not a new texel), so each group runs for the points that missed its own
// kind only. A group is
// self-contained, so a hit skips all of its work and cache_eval center can
// re-evaluate it at a texel centre, or replay it at K sub-sample points
// (cache_supersample; each LOOKUP's skip word carries its point's K). With the cache off the program has no
// cache instructions at all.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/texture.h"
#include "materials/cache_plan.h"
#include "materials/emit.h"
#include "materials/node_graph.h"
#include "materials/passes.h"

namespace pmc {

struct CompileOptions {
  bool cache = false;  // emit the cache group (CACHE_LOOKUP/CACHE_STORE) for cache points
  int cache_min_nodes = kDefaultCacheMinNodes;
  bool cache_position_keys = true;  // position-only sub-graphs become position-keyed points
  // Level floors: texels across a pattern's smallest feature (bandwidth.h);
  // 0: none (the default, as cache_bandwidth off).
  double cache_feature_texels = 0;
  // With a model, a point must also pay on the device for the frame
  // (materials/node_costs.h); none: the node count alone decides.
  std::optional<CacheCostModel> cache_model;
  // Sub-samples per supersampled miss in cache_eval center, per key kind
  // (resolve_supersample); carried in each CACHE_LOOKUP's skip word.
  CacheSupersample cache_supersample;
};

struct CompiledMaterial {
  std::string name;
  std::string file;
  uint32_t entry = 0;       // first instruction word
  uint32_t code_words = 0;  // instructions + constants
  uint32_t instructions = 0;
  uint32_t peak_stack = 0;  // floats
  std::vector<PassStat> passes;
  std::vector<std::pair<std::string, uint32_t>> param_dependencies;  // surface input -> dep bits
  bool has_cutout = false;                                           // opacity depends on the shading point
  bool reads_footprint = false;  // an instruction filters an image by the ray cone (PMC_MAT_FOOTPRINT)
  bool uniform = false;  // no instruction reads the shading point, none writes the normal (PMC_MAT_UNIFORM)
  float constant_emission[3] = {0, 0, 0};  // for light sampling
  bool may_emit = false;                   // an instruction writes the emission or its colour (PMC_MAT_EMITS)
  CachePlan cache_plan;                    // the cache points emitted when the cache is on
};

struct MaterialProgram {
  std::vector<uint32_t> code;
  std::vector<CompiledMaterial> materials;
};

// Optimises `graph` in place and appends its program. Throws pmc::Error.
const CompiledMaterial& compile_material(Graph& graph, TexturePool& textures, MaterialProgram& program,
                                         const CompileOptions& options = {});

// Whether a program (its words from its first instruction) gives every
// shading point the same surface parameters (CompiledMaterial::uniform): no
// instruction reads the point and none writes the normal.
bool program_is_uniform(const std::vector<uint32_t>& code);

// Human-readable listing of one material's program.
std::string disassemble(const MaterialProgram& program, const CompiledMaterial& m);

}  // namespace pmc
