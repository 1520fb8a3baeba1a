// info_command.cpp — `pmc info`: OpenCL devices, scene summaries.
#include <cstdio>

#include "app/cli_args.h"
#include "app/commands.h"
#include "core/error.h"
#include "core/obj_loader.h"
#include "gpu/cl_context.h"
#include "materials/material_set.h"

namespace pmc {
namespace {

std::string node_label(const Graph& g, int n) {
  const Node& node = g.nodes[size_t(n)];
  return (node.name.empty() ? std::string("(") + node.category + ")" : "'" + node.name + "'") + " " +
         node.category + " " + type_name(node.type);
}

void print_cache_plan(const MaterialSet& set, const CompiledMaterial& m) {
  const Graph* g = nullptr;
  for (size_t i = 0; i < set.program.materials.size(); ++i)
    if (&set.program.materials[i] == &m) g = &set.graphs[i];
  if (!g) return;
  static const char* enc[] = {"float", "rgb9e5", "half2"};
  std::printf("  cache points: %zu\n", m.cache_plan.points.size());
  for (const CachePoint& cp : m.cache_plan.points)
    std::printf("    + %s: saves a sub-graph of %d nodes, stored as %s\n", node_label(*g, cp.node).c_str(),
                cp.subgraph_nodes, enc[cp.encoding % 3]);
  for (const auto& [n, why] : m.cache_plan.not_cached)
    std::printf("    - %s: %s\n", node_label(*g, n).c_str(), why.c_str());
}

}  // namespace

int run_info(const std::vector<std::string>& args) {
  ArgParser p("pmc info [--devices] [--scene SCENE.obj [--mtlx F ...] [--dump-bytecode] [--dump-cache-plan]]",
              "Prints what pmc sees: OpenCL devices, scene contents.");
  p.flag("--devices", "list OpenCL platforms and devices");
  p.option("--scene", "SCENE.obj", "summarise a scene: triangles, materials, textures, bounds");
  p.option("--mtlx", "FILE.mtlx", "MaterialX document to bind (repeatable)", "", true);
  p.option("--material", "NAME", "use this MaterialX material for every triangle");
  p.option("--mtlx-library", "DIR", "MaterialX data libraries (see pmc render --help)");
  p.option("--mtlx-search-path", "DIR", "where MaterialX filenames are looked up (repeatable)", "", true);
  p.flag("--dump-bytecode", "per material: node counts per pass, bytecode, peak stack, dependencies");
  p.flag("--dump-cache-plan",
         "per material: cache points, the sub-graph each saves, why other nodes are not cached");
  p.option("--cache-min-nodes", "N", "smallest sub-graph worth a cache point",
           std::to_string(kDefaultCacheMinNodes));
  if (!p.parse(args)) return 0;
  if (!p.positional().empty()) fail("info: unexpected argument '", p.positional()[0], "'");
  if (!p.has("--devices") && !p.has("--scene")) {
    p.print_help();
    return 2;
  }
  if (p.has("--devices")) {
    std::vector<ClDeviceInfo> devices = list_cl_devices();
    ClContext chosen;
    for (const ClDeviceInfo& d : devices)
      std::printf("%s %s | %s | %s | %u compute units | %.1f GiB%s\n",
                  d.device_id == chosen.device() ? "*" : " ", d.platform.c_str(), d.name.c_str(),
                  d.version.c_str(), d.compute_units, double(d.global_memory) / double(1ull << 30),
                  d.is_gpu ? " | GPU" : " | CPU");
    std::printf("(* = default device; pick another with --device NAME)\n");
  }
  if (p.has("--dump-bytecode") || p.has("--dump-cache-plan")) {
    if (!p.has("--scene")) fail("--dump-bytecode/--dump-cache-plan need --scene SCENE.obj");
    ObjLoadOptions load;
    load.load_textures = false;
    Scene scene = load_obj(p.get("--scene"), load);
    MaterialOptions mo;
    mo.mtlx_files = p.all("--mtlx");
    mo.mtlx.library_dir = p.get("--mtlx-library");
    mo.mtlx.search_paths = p.all("--mtlx-search-path");
    mo.override_material = p.get("--material");
    mo.compile.cache = true;
    mo.compile.cache_min_nodes = p.get_int("--cache-min-nodes", kDefaultCacheMinNodes);
    if (mo.compile.cache_min_nodes < 1) fail("--cache-min-nodes: must be at least 1");
    MaterialSet set = build_material_set(scene, mo);
    std::printf("bytecode: %zu words for %zu materials\n", set.program.code.size(),
                set.program.materials.size());
    for (const CompiledMaterial& m : set.program.materials) {
      std::printf("\nmaterial '%s' (%s)\n  passes:", m.name.c_str(), m.file.c_str());
      for (const PassStat& ps : m.passes) std::printf(" %s %zu->%zu;", ps.pass.c_str(), ps.before, ps.after);
      std::printf("\n  %u instructions, %u code words, peak stack %u floats\n", m.instructions, m.code_words,
                  m.peak_stack);
      std::printf("  outputs depend on:");
      for (const auto& [input, bits] : m.param_dependencies)
        if (bits) std::printf(" %s=%s", input.c_str(), dependency_names(bits).c_str());
      std::printf("\n");
      if (p.has("--dump-cache-plan")) print_cache_plan(set, m);
      if (p.has("--dump-bytecode")) std::printf("%s", disassemble(set.program, m).c_str());
    }
    return 0;
  }
  if (p.has("--scene")) {
    Scene scene = load_obj(p.get("--scene"));
    std::printf("scene %s\n  triangles %zu, positions %zu, normals %zu, uvs %zu\n", scene.obj_path.c_str(),
                scene.triangles.size(), scene.positions.size() / 3, scene.normals.size() / 3,
                scene.uvs.size() / 2);
    std::printf("  bounds (%g, %g, %g) .. (%g, %g, %g)\n", scene.bounds.lo[0], scene.bounds.lo[1],
                scene.bounds.lo[2], scene.bounds.hi[0], scene.bounds.hi[1], scene.bounds.hi[2]);
    std::printf("  materials %zu, textures loaded %zu\n", scene.materials.size(), scene.textures.size());
    for (const MtlMaterial& m : scene.materials)
      std::printf("    %-24s Kd %.3g %.3g %.3g  Ks %.3g  Ke %.3g%s%s\n", m.name.c_str(), m.kd[0], m.kd[1],
                  m.kd[2], m.ks[0], m.ke[0], m.map_kd.empty() ? "" : "  map_Kd ", m.map_kd.c_str());
  }
  return 0;
}

}  // namespace pmc
