// harness.h — the checks behind the fuzz targets, shared with the regression
// test (tests/hard_cases/fuzz_regression_test.cpp) so that a crash input
// found by libFuzzer replays through exactly the same code in the normal
// test suite. Each function returns "" when the input was handled properly
// (loaded, or refused with pmc::Error) and a description of the problem
// otherwise; a crash or sanitizer report is, of course, also a finding.
// Targets: check_obj (fuzz_obj), check_mtlx (fuzz_mtlx), check_mtl (fuzz_mtl),
// check_image (fuzz_image).
#pragma once

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "core/device/pmc_interp.h"
#include "core/error.h"
#include "core/lights.h"
#include "core/native_images.h"
#include "core/obj_loader.h"
#include "core/texture.h"
#include "materials/compiler.h"
#include "materials/cpu_interpreter.h"
#include "materials/cutout.h"
#include "materials/material_set.h"
#include "materials/mtlx_reader.h"

namespace pmc::fuzz {

// ---- OBJ ------------------------------------------------------------------
// The input is written to a per-process temp folder as scene.obj next to a
// fixed small scene.mtl, then loaded with pmc::load_obj. Textures are not
// loaded: a fuzzed file could name a device such as /dev/stdin through an
// MTL, and reading that would hang.

// A per-process temp folder that goes away at a normal exit (the end of a
// fuzz run, the test suite); a crash leaves it for a look at the last input.
struct ProcessFolder {
  std::string path;
  ~ProcessFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

inline const std::string& obj_folder() {
  static const ProcessFolder folder = [] {
    std::string d =
        std::filesystem::temp_directory_path().string() + "/pmc_fuzz_obj_" + std::to_string(getpid());
    std::filesystem::create_directories(d);
    std::ofstream(d + "/scene.mtl") << "newmtl red\nKd 0.8 0.1 0.1\nKs 0.2 0.2 0.2\nNs 50\n"
                                       "newmtl lamp\nKe 5 5 5\nnewmtl glass\nd 0.5\n";
    return ProcessFolder{d};  // a prvalue: no temporary whose destructor would remove it
  }();
  return folder.path;
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

// `textures` is the scene's texture set (host_texture_set) when the program
// samples images; without it every IMAGE returns its default.
inline void run_program(const MaterialProgram& program, const CompiledMaterial& m, bool cached,
                        const PmcTextureSet* textures = nullptr) {
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
    PmcTextureSet ts = textures ? *textures : PmcTextureSet{};
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
      if (!original.error.empty()) continue;  // a material the reader could not build (fails when used)
      Graph g = original;                     // compile_material optimises in place
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

// ---- MTL -------------------------------------------------------------------
// The input is written as scene.mtl next to a fixed scene.obj (below) in a
// per-process temp folder and loaded with pmc::load_obj (textures not
// loaded, as the renderer does); then build_material_set — MTL entry ->
// network (mtl_to_graph) -> passes -> compiler, the renderer's own path —
// runs three times: cache off, cache on with the default threshold, and
// cache on with a threshold of 2 nodes so that map_Kd (times Kd) becomes a
// cache point. Each used material's program runs on the host interpreter
// (run_program, with the scene's textures), and the cut-out tester and the
// light table are built from the set as the renderer builds them.
//
// Texture paths: only three fixture images in the folder are real (tex.png
// RGB 4x2, alpha.png RGBA 3x3, textures/grey.png grey 2x2). Every other
// texture path (MtlMaterial::maps()) is rewritten, before the networks are built, to a
// name in a folder that does not exist: a fuzzed MTL must not make pmc open
// /dev/stdin or a FIFO (mtl_to_graph opens map_d and bump maps, the compiler loads every
// live image).
//
// Stricter than "no crash": the OBJ is valid and its MTL always exists, so
// no MTL may make load_obj refuse it; MTL values are plain numbers, so the
// only acceptable refusal of the material set is an unreadable texture of a
// material that faces use. And what the renderer takes from the set must
// match the MTL: a material is a cut-out exactly when it has a map_d, and
// its light-table emission is max(0, Ke) wherever Ke is finite.

inline constexpr const char* kMissingTextureDir = "/nonexistent-pmc-fuzz/";

inline void write_fixture_png(const std::string& path, int w, int h, int channels) {
  std::vector<uint8_t> px(size_t(w) * size_t(h) * size_t(channels));
  for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(29 + 97 * i);  // alpha above and below 0.5
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(w, h, channels, OIIO::TypeDesc::UINT8);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, px.data()) || !out->close())
    std::abort();  // the harness itself is broken, not the input
}

inline const std::string& mtl_folder() {
  static const ProcessFolder folder = [] {
    std::string d =
        std::filesystem::temp_directory_path().string() + "/pmc_fuzz_mtl_" + std::to_string(getpid());
    std::filesystem::create_directories(d + "/textures");
    write_fixture_png(d + "/tex.png", 4, 2, 3);
    write_fixture_png(d + "/alpha.png", 3, 3, 4);
    write_fixture_png(d + "/textures/grey.png", 2, 2, 1);
    // Faces without a material, with uvs and normals, uvs only, normals
    // only; `usemtl` names the seeds define (and `unknown`, which none do).
    std::ofstream(d + "/scene.obj") << "mtllib scene.mtl\n"
                                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                       "vn 0 0 1\nvn 0 -0.7071 0.7071\n"
                                       "f 1/1/1 2/2/1 3/3/1\n"
                                       "usemtl red\nf 1/1/1 2/2/1 3/3/1 4/4/1\n"
                                       "usemtl lamp\nf 1/1/2 2/2/2 5/3/2\n"
                                       "usemtl glass\nf 2/2/1 3/3/1 5/4/1\n"
                                       "usemtl wood\nf 1/1/1 3/3/1 4/4/1\n"
                                       "usemtl leaf\nf 1/1/1 2/2/1 4/4/1\nf 2//2 3//2 5//2\n"
                                       "usemtl metal\nf 3/3/1 4/4/1 5/1/1\n"
                                       "usemtl brick\nf 4/4 1/1 5/2\n"
                                       "usemtl Material.001\nf 1/1/1 4/4/1 5/3/1\n"
                                       "usemtl unknown\nf 2/2/1 4/4/1 5/3/1\n";
    return ProcessFolder{d};  // a prvalue: no temporary whose destructor would remove it
  }();
  return folder.path;
}

inline const char* const kFixtureTextures[] = {"tex.png", "alpha.png", "textures/grey.png"};

// The fixtures decoded once, in both colour spaces, for every input's scene
// to start from: TexturePool::load then finds them in its cache. (Reading a
// PNG through OpenImageIO allocates a large conversion buffer that
// AddressSanitizer clears on every load: 20 ms an input, most of the time.)
inline const TexturePool& fixture_textures() {
  static const TexturePool pool = [] {
    TexturePool p;
    for (const char* fixture : kFixtureTextures)
      for (bool srgb : {true, false}) p.load(mtl_folder() + "/" + fixture, srgb, "fuzz harness");
    return p;
  }();
  return pool;
}

// A fixture's path as load_obj resolved it, else a name that cannot exist.
inline std::string harmless_texture(const std::string& resolved) {
  if (resolved.empty()) return resolved;
  for (const char* fixture : kFixtureTextures)
    if (resolved == mtl_folder() + "/" + fixture) return resolved;
  std::string name = resolved.substr(std::min(resolved.size(), mtl_folder().size() + 1));
  std::replace(name.begin(), name.end(), '/', '_');
  return kMissingTextureDir + name;
}

inline std::string check_material_set(const Scene& scene, const MaterialSet& set, bool cached) {
  const size_t n = scene.materials.size();
  if (set.infos.size() != n || set.compiled.size() != n) return "per-material arrays of the wrong size";
  if (set.graphs.size() != set.program.materials.size()) return "graphs and programs out of step";
  std::vector<char> used(n, 0);
  for (const PmcTriangle& t : scene.triangles) used[size_t(t.material)] = 1;
  const PmcTextureSet textures = host_texture_set(scene, set);
  for (size_t i = 0; i < n; ++i) {
    const MtlMaterial& mm = scene.materials[i];
    const PmcMaterialInfo& info = set.infos[i];
    if (info.entry >= set.program.code.size()) return "material entry outside the program";
    if (!used[i]) {
      if (set.compiled[i] != -1) return "an unused material was compiled";
      if (set.program.code[info.entry] != pmc_op_header(PMC_OP_END, 1, 0, 0)) return "unused entry is no END";
      continue;
    }
    if (set.compiled[i] < 0 || size_t(set.compiled[i]) >= set.program.materials.size())
      return "used material without a program";
    const CompiledMaterial& cm = set.program.materials[size_t(set.compiled[i])];
    if (cm.entry != info.entry) return "material info and program disagree on the entry";
    if (size_t(cm.entry) + cm.code_words > set.program.code.size()) return "program runs past the code";
    if (cm.peak_stack > PMC_STACK_SIZE) return "peak stack beyond PMC_STACK_SIZE";
    if (((info.flags & PMC_MAT_CUTOUT) != 0) != !mm.map_d.empty())
      return "cut-out flag does not follow map_d (material '" + mm.name + "')";
    for (int k = 0; k < 3; ++k)  // a map_Ke emission is left to BSDF sampling: not in the light table
      if (std::isfinite(mm.ke[k]) &&
          info.emission[k] != (mm.map_ke.empty() ? std::max(0.0f, mm.ke[k]) : 0.0f))
        return "light-table emission is not max(0, Ke) (material '" + mm.name + "')";
    run_program(set.program, cm, cached, &textures);
    (void)disassemble(set.program, cm);
  }
  // What the renderer builds from the set besides the kernels' program.
  CutoutTester cutout(scene, set);
  for (size_t t = 0; t < scene.triangles.size(); ++t)
    if (cutout.cutout_triangles()[t]) {
      (void)cutout.transparent(uint32_t(t), 0.25f, 0.25f);
      (void)cutout.transparent(uint32_t(t), 0.9f, 0.05f);
    }
  std::vector<float> emission;
  for (const PmcMaterialInfo& m : set.infos)
    for (int k = 0; k < 3; ++k) emission.push_back(m.emission[k]);
  LightTable lights = build_light_table(scene, emission, SceneLights{});
  float previous = 0.0f;
  for (const PmcLight& l : lights.lights) {
    if (!(l.cdf >= previous && l.cdf <= 1.0f)) return "light CDF not increasing within [0, 1]";
    previous = l.cdf;
  }
  if (!lights.lights.empty() && lights.lights.back().cdf != 1.0f) return "light CDF does not end at 1";
  for (int32_t k : lights.triangle_light)
    if (k < -1 || k >= int32_t(lights.lights.size())) return "triangle's light index outside the table";
  if (lights.header.tree_nodes != 0 &&
      lights.header.tree_nodes != 2 * (lights.header.count - lights.header.distant_end) - 1)
    return "light tree does not have 2n - 1 nodes";
  return "";
}

inline std::string check_mtl(const uint8_t* data, size_t size) {
  const std::string& dir = mtl_folder();
  {
    std::ofstream out(dir + "/scene.mtl", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  ObjLoadOptions load;
  load.load_textures = false;
  Scene scene;
  try {
    scene = load_obj(dir + "/scene.obj", load);
  } catch (const Error& e) {
    return std::string("the fixed OBJ was refused because of its MTL: ") + e.what();
  }
  scene.textures = fixture_textures();
  bool may_miss_texture = false;  // a used material names a texture that does not exist
  std::vector<char> used(scene.materials.size(), 0);
  for (const PmcTriangle& t : scene.triangles) used[size_t(t.material)] = 1;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    MtlMaterial& m = scene.materials[i];
    for (std::string* map : m.maps()) {
      *map = harmless_texture(*map);
      may_miss_texture = may_miss_texture || (used[i] && map->rfind(kMissingTextureDir, 0) == 0);
    }
  }
  for (int config = 0; config < 3; ++config) {
    MaterialOptions options;
    options.compile.cache = config > 0;
    if (config == 2) options.compile.cache_min_nodes = 2;
    MaterialSet set;
    try {
      set = build_material_set(scene, options);
    } catch (const Error& e) {
      const std::string why = e.what();
      if (may_miss_texture &&
          why.find(std::string("cannot read texture '") + kMissingTextureDir) != std::string::npos)
        return "";  // the same refusal for every configuration
      return "an MTL material set was refused: " + why;
    }
    std::string problem = check_material_set(scene, set, options.compile.cache);
    if (!problem.empty()) return problem;
  }
  return "";
}

// ---- images ---------------------------------------------------------------
// The input is written to a per-process temp file and opened with pmc's own
// readers (core/native_images.h: OpenEXR, PNG, JPEG, Radiance HDR); the
// OpenImageIO plugin is not called (not our code to fuzz). A refusal must
// say why, or be a format the plugin takes (null, `why` empty). A reader
// must report a sane header (a size under the native limit, channels
// named), and reading every channel as Float, and as U8 for 8-bit files,
// must succeed or fail with error() set.
inline std::string check_image(const uint8_t* data, size_t size) {
  static const ProcessFolder folder = [] {
    std::string d =
        std::filesystem::temp_directory_path().string() + "/pmc_fuzz_image_" + std::to_string(getpid());
    std::filesystem::create_directories(d);
    return ProcessFolder{d};
  }();
  const std::string path = folder.path + "/input";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  std::string why;
  std::unique_ptr<ImageReader> in;
  try {
    in = open_native_image(path, true, why);
  } catch (const std::exception& e) {
    return std::string("open threw: ") + e.what();
  }
  if (!in) return "";  // refused (why says so) or left to the plugin
  const ImageHeader& h = in->header();
  if (h.width <= 0 || h.height <= 0 || h.channels <= 0 || !native_size_problem(h.width, h.height).empty())
    return "a reader with an impossible header: " + std::to_string(h.width) + "x" + std::to_string(h.height) +
           "x" + std::to_string(h.channels);
  if (int(h.channel_names.size()) != h.channels) return "channel names do not match the channel count";
  const size_t values = size_t(h.width) * size_t(h.height) * size_t(h.channels);
  if (values > (size_t(1) << 22)) return "";  // a big image: reading it would only slow the fuzzer down
  std::vector<float> f(values);
  try {
    if (!in->read(0, h.channels, PixelFormat::Float, f.data()) && in->error().empty())
      return "a Float read failed without a reason";
    if (h.format == PixelFormat::U8) {
      std::vector<unsigned char> b(values);
      if (!in->read(0, h.channels, PixelFormat::U8, b.data()) && in->error().empty())
        return "a U8 read failed without a reason";
    }
  } catch (const std::exception& e) {
    return std::string("read threw: ") + e.what();
  }
  return "";
}

}  // namespace pmc::fuzz
