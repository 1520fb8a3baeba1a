// material_set.cpp — binding usemtl names to networks and compiling them.
#include "materials/material_set.h"

#include <map>
#include <sstream>

#include "core/abi/pmc_bytecode.h"
#include "core/error.h"
#include "materials/mtl_graph.h"
#include "materials/mtlx_reader.h"
#include "materials/node_table.h"

namespace pmc {

namespace {

// A copy of an optimised graph whose surface keeps only its opacity input:
// compiled, it is the program the cut-out test runs in Embree's filters,
// where a candidate hit needs nothing else. The whole material there would
// also fetch its colour textures and run its BSDF inputs' networks.
Graph opacity_only(const Graph& g) {
  Graph o = g;
  Node& surface = o.nodes[size_t(o.surface)];
  std::vector<Input> kept;
  for (const SurfaceParam& p : surface_params(surface.category))
    if (p.param == PMC_P_OPACITY)
      if (const Input* in = surface.input(p.input)) kept.push_back(*in);
  surface.inputs = std::move(kept);
  return o;
}

// MaterialX <look> assignments: each OBJ object/group "/NAME" (a shape name
// of several words, as tinyobj names `g a b`, is each "/word") takes the
// material of the last materialassign that covers it; this wins over usemtl.
void assign_by_looks(Scene& scene, const std::map<std::string, Graph>& mtlx,
                     const std::vector<MtlxAssignment>& assignments) {
  for (const MtlxAssignment& a : assignments)
    if (!mtlx.count(a.material))
      fail_config(a.origin, ": material '", a.material, "' is not in the ", setting("mtlx"), " documents");
  if (scene.triangle_shapes.size() != scene.triangles.size()) return;  // a scene built without shapes
  auto material_index = [&](const std::string& name) {
    for (size_t i = 0; i < scene.materials.size(); ++i)
      if (scene.materials[i].name == name) return int(i);
    MtlMaterial m;
    m.name = name;
    m.defined_by_mtl = false;
    scene.materials.push_back(m);
    return int(scene.materials.size()) - 1;
  };
  std::vector<int> shape_material(scene.shape_names.size(), -1);
  for (size_t s = 0; s < scene.shape_names.size(); ++s) {
    std::vector<std::string> paths;
    std::istringstream words(scene.shape_names[s]);
    for (std::string w; words >> w;) paths.push_back("/" + w);
    const MtlxAssignment* chosen = nullptr;
    for (const MtlxAssignment& a : assignments)
      for (const std::string& p : paths)
        if (mtlx_assignment_covers(a, p)) chosen = &a;
    if (chosen) shape_material[s] = material_index(chosen->material);
  }
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    int m = shape_material[scene.triangle_shapes[i]];
    if (m >= 0) scene.triangles[i].material = m;
  }
}

}  // namespace

MaterialSet build_material_set(Scene& scene, const MaterialOptions& options) {
  std::map<std::string, Graph> mtlx;
  std::vector<MtlxAssignment> assignments;
  for (const std::string& file : options.mtlx_files) {
    const MtlxDocument doc = MtlxDocument::from_file(file, options.mtlx);  // loaded once, read twice
    for (Graph& g : read_mtlx_graphs(doc)) {
      if (mtlx.count(g.material))
        warn(file + ": material '" + g.material + "' also defined earlier; the later one wins");
      mtlx[g.material] = std::move(g);
    }
    std::vector<MtlxAssignment> a = read_mtlx_assignments(doc);
    assignments.insert(assignments.end(), a.begin(), a.end());
  }
  if (!options.override_material.empty()) {
    if (!mtlx.count(options.override_material)) {
      std::string names;
      for (const auto& kv : mtlx) names += (names.empty() ? "" : ", ") + kv.first;
      fail_config(setting("material"), ": no material '", options.override_material, "' in the ",
                  setting("mtlx"), " documents (they define: ", names.empty() ? "nothing" : names, ")");
    }
    MtlMaterial m;
    m.name = options.override_material;
    scene.materials.push_back(m);
    for (PmcTriangle& t : scene.triangles) t.material = int(scene.materials.size()) - 1;
  }
  if (options.override_material.empty() && !assignments.empty()) assign_by_looks(scene, mtlx, assignments);
  std::vector<char> used(scene.materials.size(), 0);
  for (const PmcTriangle& t : scene.triangles) used[size_t(t.material)] = 1;

  MaterialSet set;
  set.infos.assign(scene.materials.size(), PmcMaterialInfo{});
  set.compiled.assign(scene.materials.size(), -1);
  set.cutout_entry.assign(scene.materials.size(), -1);
  const std::string mtl_file = scene.obj_path;
  uint32_t unused_entry = 0;
  bool have_unused = false;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    if (!used[i]) continue;
    const MtlMaterial& m = scene.materials[i];
    auto found = mtlx.find(m.name);
    if (found != mtlx.end() && !found->second.error.empty()) fail(found->second.error);
    Graph g = found != mtlx.end() ? found->second : mtl_to_graph(m, mtl_file);
    const CompiledMaterial& cm = compile_material(g, scene.textures, set.program, options.compile);
    set.compiled[i] = int(set.program.materials.size()) - 1;
    set.graphs.push_back(std::move(g));
    PmcMaterialInfo& info = set.infos[i];
    info.entry = cm.entry;
    info.flags = (cm.has_cutout ? PMC_MAT_CUTOUT : 0u) | (cm.reads_footprint ? PMC_MAT_FOOTPRINT : 0u) |
                 (cm.uniform ? PMC_MAT_UNIFORM : 0u) | (cm.may_emit ? PMC_MAT_EMITS : 0u);
    if (cm.has_cutout) {
      Graph opacity = opacity_only(set.graphs.back());
      set.cutout_entry[i] = int(compile_material(opacity, scene.textures, set.cutout_program).entry);
    }
    for (int k = 0; k < 3; ++k) info.emission[k] = cm.constant_emission[k];
    info.cache_points = uint32_t(cm.cache_plan.points.size());
    info.cache_position_mask = 0u;
    for (size_t p = 0; p < cm.cache_plan.points.size() && p < 32; ++p)
      if (cm.cache_plan.points[p].key == CacheKey::Position) info.cache_position_mask |= 1u << p;
    info.cache_level_floor_uv = material_level_floor(cm.cache_plan, CacheKey::Uv);
    info.cache_level_floor_position = material_level_floor(cm.cache_plan, CacheKey::Position);
  }
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    if (used[i]) continue;
    if (!have_unused) {  // one END for every unused material
      unused_entry = uint32_t(set.program.code.size());
      set.program.code.push_back(pmc_op_header(PMC_OP_END, 1, 0, 0));
      set.program.code.push_back(0);
      have_unused = true;
    }
    set.infos[i].entry = unused_entry;
  }
  // usemtl names that neither an MTL nor a MaterialX document defines.
  std::string unmatched;
  for (size_t i = 0; i < scene.materials.size(); ++i)
    if (used[i] && !scene.materials[i].defined_by_mtl && !mtlx.count(scene.materials[i].name))
      unmatched += (unmatched.empty() ? "" : ", ") + scene.materials[i].name;
  if (!unmatched.empty())
    warn(scene.obj_path +
         ": usemtl names that match no MTL or MaterialX material (rendered with the default "
         "material): " +
         unmatched);
  if (options.compiled) options.compiled(set);
  // R in the low byte: on a little-endian host the words are the pool's bytes
  // as they are, shared with it (no copy).
  set.texel_words = scene.textures.words();
#if !(defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__)
  auto words = std::make_shared<TexelWords>(*set.texel_words);
  for (uint32_t& w : *words) {
    const uint8_t* b = reinterpret_cast<const uint8_t*>(&w);
    w = uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
  }
  set.texel_words = std::move(words);
#endif
  set.srgb_lut = srgb_decode_table();
  return set;
}

}  // namespace pmc
