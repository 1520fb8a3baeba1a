// harness.h — the checks behind the fuzz targets, shared with the regression
// test (tests/hard_cases/fuzz_regression_test.cpp) so that a crash input
// found by libFuzzer replays through exactly the same code in the normal
// test suite. Each function returns "" when the input was handled properly
// (loaded, or refused with pmc::Error) and a description of the problem
// otherwise; a crash or sanitizer report is, of course, also a finding.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/abi/pmc_interp.h"
#include "core/error.h"
#include "core/obj_loader.h"
#include "core/texture.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"

namespace pmc::fuzz {

// ---- OBJ ------------------------------------------------------------------
// The input is written to a per-process temp folder as scene.obj next to a
// fixed small scene.mtl, then loaded with pmc::load_obj. Textures are not
// loaded: a fuzzed file could name a device such as /dev/stdin through an
// MTL, and reading that would hang.

inline const std::string& obj_folder() {
  static const std::string dir = [] {
    std::string d =
        std::filesystem::temp_directory_path().string() + "/pmc_fuzz_obj_" + std::to_string(getpid());
    std::filesystem::create_directories(d);
    std::ofstream(d + "/scene.mtl") << "newmtl red\nKd 0.8 0.1 0.1\nKs 0.2 0.2 0.2\nNs 50\n"
                                       "newmtl lamp\nKe 5 5 5\nnewmtl glass\nd 0.5\n";
    return d;
  }();
  return dir;
}

inline std::string check_obj(const uint8_t* data, size_t size) {
  const std::string path = obj_folder() + "/scene.obj";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  ObjLoadOptions options;
  options.load_textures = false;
  try {
    Scene s = load_obj(path, options);
    // What the renderer relies on: in-range indices, finite used data.
    const long nv = long(s.positions.size() / 3), nn = long(s.normals.size() / 3),
               nt = long(s.uvs.size() / 2);
    if (s.triangles.empty()) return "a scene without triangles was returned";
    for (const PmcTriangle& t : s.triangles) {
      if (t.material < 0 || size_t(t.material) >= s.materials.size()) return "material index out of range";
      for (int k = 0; k < 3; ++k) {
        if (t.v[k] < 0 || t.v[k] >= nv) return "vertex index out of range";
        if (t.n[k] < -1 || t.n[k] >= nn) return "normal index out of range";
        if (t.t[k] < -1 || t.t[k] >= nt) return "uv index out of range";
        for (int c = 0; c < 3; ++c)
          if (!std::isfinite(s.positions[3 * size_t(t.v[k]) + c])) return "non-finite position kept";
      }
      if ((t.n[0] < 0) != (t.n[1] < 0) || (t.n[0] < 0) != (t.n[2] < 0)) return "partial normals";
      if ((t.t[0] < 0) != (t.t[1] < 0) || (t.t[0] < 0) != (t.t[2] < 0)) return "partial uvs";
    }
    for (float x : s.normals)
      if (!std::isfinite(x)) return "non-finite normal kept";
    for (float x : s.uvs)
      if (!std::isfinite(x)) return "non-finite uv kept";
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(s.bounds.lo[i]) || !std::isfinite(s.bounds.hi[i]) || s.bounds.lo[i] > s.bounds.hi[i])
        return "bad scene bounds";
  } catch (const Error&) {
    // bad input, reported as such
  }
  return "";
}

// ---- MaterialX --------------------------------------------------------------
// The input is parsed as a document at a path inside a folder that does not
// exist; every graph it yields is compiled twice (cache instructions off and
// on) and each program is run by the host interpreter at a few shading
// points (with a small host-side cache table for the cached program). The
// interpreter's stack is a fixed PMC_STACK_SIZE array, so a compiler that
// hands out slots past it shows up under AddressSanitizer. Parameter values
// are not checked: a material may legitimately compute NaN (sqrt of a
// negative input); the renderer guards against that. Filenames are blanked
// before compiling — a document can name any path (/dev/stdin would block) —
// so an image node compiles to its default value, as MaterialX specifies
// for a missing file.

inline void run_program(const MaterialProgram& program, const CompiledMaterial& m, bool cached) {
  std::vector<uint64_t> entries(64 * 4, 0);
  PmcCacheContext cache{};
  cache.table.entries = entries.data();
  cache.table.cells = 64;
  cache.table.ways = 4;
  cache.g1 = make_float2(0.01f, 0.0f);
  cache.g2 = make_float2(0.0f, 0.02f);
  cache.material = 1;
  const float uvs[][2] = {{0.25f, 0.75f}, {-3.5f, 1e7f}, {0.25f, 0.75f}};
  for (int i = 0; i < 3; ++i) {  // the third point hits what the first stored
    PmcShadingInputs in{};
    in.uv = make_float2(uvs[i][0], uvs[i][1]);
    in.position = make_float3(0.3f * float(i), -0.2f, 0.7f);
    in.normal = make_float3(0, 0, 1);
    in.tangent = make_float3(1, 0, 0);
    in.bitangent = make_float3(0, 1, 0);
    in.footprint = 0.01f;
    PmcTextureSet ts{};
    float stack[PMC_STACK_SIZE];
    float params[PMC_P_COUNT];
    pmc_surface_defaults(params, in.normal);
    cache.center = uint32_t(i == 1);
    pmc_interp_run(program.code.data(), m.entry, &in, &ts, stack, params, cached ? &cache : nullptr);
  }
}

inline std::string check_mtlx(const uint8_t* data, size_t size) {
  const std::string xml(reinterpret_cast<const char*>(data), size);
  std::vector<Graph> graphs;
  try {
    graphs = read_mtlx_string(xml, "/nonexistent-pmc-fuzz/doc.mtlx");
  } catch (const Error&) {
    return "";
  }
  if (graphs.empty()) return "no graphs and no error";
  for (Graph& g : graphs)
    for (Node& n : g.nodes)
      for (Input& in : n.inputs)
        if (in.type == ValueType::Filename) in.value.text.clear();
  for (bool cached : {false, true}) {
    TexturePool textures;
    MaterialProgram program;
    for (const Graph& original : graphs) {
      Graph g = original;  // compile_material optimises in place
      CompileOptions options;
      options.cache = cached;
      options.cache_min_nodes = 2;
      const size_t words = program.code.size();
      try {
        const CompiledMaterial& m = compile_material(g, textures, program, options);
        if (m.peak_stack > PMC_STACK_SIZE) return "peak stack beyond PMC_STACK_SIZE";
        if (m.entry + m.code_words != program.code.size()) return "program size mismatch";
        run_program(program, m, cached);
        (void)disassemble(program, m);
      } catch (const Error&) {
        if (program.code.size() != words) return "a refused material left code behind";
      }
    }
  }
  return "";
}

}  // namespace pmc::fuzz
