// obj_loader.cpp — tinyobjloader's output flattened into pmc::Scene.
#include "core/obj_loader.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/background.h"
#include "core/error.h"

namespace pmc {
namespace {

std::string dirname_of(const std::string& path) {
  size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// First line of tinyobj's warnings that starts with `prefix`, or "". Only
// line starts count: tinyobj quotes names from the files in the middle of its
// lines (`usemtl X` -> "material [ 'X' ] not found in .mtl", an MTL material
// with both d and Tr -> "... defined for \"X\". ..."), so an MTL material
// called "Degenerated face found" must not read as that warning (fuzz_mtl
// found this). tinyobj ends its degenerate-face warning with "\n.", so one
// leading '.' is skipped.
std::string warning_line(const std::string& warnings, const std::string& prefix) {
  for (size_t begin = 0; begin < warnings.size();) {
    size_t end = warnings.find('\n', begin);
    if (end == std::string::npos) end = warnings.size();
    size_t at = begin + (warnings[begin] == '.' ? 1 : 0);
    if (warnings.compare(at, prefix.size(), prefix) == 0) return warnings.substr(at, end - at);
    begin = end + 1;
  }
  return {};
}

// tinyobjloader's number parser reads "nan" and "inf" as 0, which would move
// such a vertex to the origin without a word. Re-read the `v` lines that hold
// letters and store NaN/inf where strtod sees one, so those triangles are
// skipped like any other non-finite position. `vn`/`vt` components spelled
// nan/inf are 0 already (the value the loader repairs them to); they are
// returned as a count, for the warning. The scan reads the file by itself,
// so it runs beside tinyobj's parse (scan_non_finite on a Background job,
// then apply_non_finite).
struct NonFiniteScan {
  std::vector<std::pair<size_t, float>> fixes;  // (component, value)
  size_t vertices = 0, spelled_attributes = 0;
};

NonFiniteScan scan_non_finite(const std::string& path) {
  NonFiniteScan scan;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return scan;  // tinyobj read no vertices either
  const uintmax_t size = std::filesystem::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  if (ec || !in) return scan;
  std::string text(size_t(size), '\0');
  in.read(text.data(), std::streamsize(text.size()));
  text.resize(size_t(in.gcount()));
  std::vector<std::pair<size_t, float>>& fixes = scan.fixes;
  size_t& vertex = scan.vertices;
  size_t& spelled_attributes = scan.spelled_attributes;
  for (size_t begin = 0; begin < text.size();) {
    // tinyobj splits lines at \r, \n and \r\n.
    const char* line_start = text.data() + begin;
    const char* nl = static_cast<const char*>(std::memchr(line_start, '\n', text.size() - begin));
    size_t end = nl ? size_t(nl - text.data()) : text.size();
    const char* cr = static_cast<const char*>(std::memchr(line_start, '\r', end - begin));
    if (cr) end = size_t(cr - text.data());
    size_t at = begin;
    while (at < end && (text[at] == ' ' || text[at] == '\t')) ++at;
    if (at + 1 < end && text[at] == 'v' && (text[at + 1] == ' ' || text[at + 1] == '\t')) {
      bool letters = false;
      for (size_t i = at + 2; i < end && !letters; ++i)
        letters = std::isalpha(static_cast<unsigned char>(text[i]));
      if (letters) {
        std::string line = text.substr(at + 2, end - at - 2);
        const char* s = line.c_str();
        for (int c = 0; c < 3; ++c) {
          char* stop = nullptr;
          double d = std::strtod(s, &stop);
          if (stop == s) break;
          if (!std::isfinite(d)) fixes.emplace_back(3 * vertex + size_t(c), float(d));
          s = stop;
        }
      }
      ++vertex;
    } else if (at + 2 < end && text[at] == 'v' && (text[at + 1] == 'n' || text[at + 1] == 't') &&
               (text[at + 2] == ' ' || text[at + 2] == '\t')) {
      std::string line = text.substr(at + 3, end - at - 3);
      const char* s = line.c_str();
      for (int c = 0; c < (text[at + 1] == 'n' ? 3 : 2); ++c) {
        char* stop = nullptr;
        double d = std::strtod(s, &stop);
        if (stop == s) break;
        // Spelled out (nan, inf): tinyobj stored 0. Overflowing digits (1e39)
        // became inf there and are counted where they are repaired.
        bool spelled = false;
        for (const char* q = s; q < stop; ++q) spelled = spelled || std::strchr("nNiI", *q) != nullptr;
        if (!std::isfinite(d) && spelled) ++spelled_attributes;
        s = stop;
      }
    }
    begin = end + 1;
  }
  return scan;
}

// Stores the scan's NaN/inf positions; returns the spelled-out attribute count.
size_t apply_non_finite(const NonFiniteScan& scan, std::vector<float>& positions) {
  if (3 * scan.vertices != positions.size()) return scan.spelled_attributes;  // counted differently
  for (const auto& [component, value] : scan.fixes) positions[component] = value;
  return scan.spelled_attributes;
}

// The first whitespace-separated word after `keyword` on each line that
// starts with it (how tinyobj reads usemtl names), or every word (mtllib).
std::vector<std::vector<std::string>> directive_words(const std::string& text, const char* keyword) {
  std::vector<std::vector<std::string>> out;
  const size_t klen = std::strlen(keyword);
  for (size_t begin = 0; begin < text.size();) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    size_t at = begin;
    while (at < end && (text[at] == ' ' || text[at] == '\t')) ++at;
    if (text.compare(at, klen, keyword) == 0 && at + klen < end &&
        std::isspace((unsigned char)text[at + klen])) {
      std::vector<std::string> words;
      size_t w = at + klen;
      while (w < end) {
        while (w < end && std::isspace((unsigned char)text[w])) ++w;
        size_t e = w;
        while (e < end && !std::isspace((unsigned char)text[e])) ++e;
        if (e > w) words.push_back(text.substr(w, e - w));
        w = e;
      }
      if (!words.empty()) out.push_back(words);
    }
    begin = end + 1;
  }
  return out;
}

// True for a name that opens a regular file. A name with a NUL byte would
// open only its prefix (often the OBJ's folder), and reading a directory
// throws from inside libstdc++.
bool is_readable_file(const std::string& path) {
  std::error_code ec;
  return path.find('\0') == std::string::npos && std::filesystem::is_regular_file(path, ec);
}

// The whole file, or "" when `path` is not a readable regular file.
std::string read_text(const std::string& path) {
  if (!is_readable_file(path)) return "";
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// tinyobj drops a `usemtl` name that no MTL defines (its faces get no
// material), but a MaterialX material of that name must still bind to them.
// So when tinyobj warned about one, the OBJ is parsed again from memory with
// its MTL libraries and a `newmtl` for every such name: the faces keep the
// name. Returns the names added.
std::vector<std::string> reparse_keeping_usemtl_names(const std::string& path, tinyobj::ObjReader& out,
                                                      const tinyobj::ObjReaderConfig& config) {
  tinyobj::ObjReader reader;  // a fresh one: tinyobj appends to what a reader holds
  std::string obj = read_text(path);
  std::string mtl;
  for (const auto& files : directive_words(obj, "mtllib"))
    for (const std::string& f : files) {  // tinyobj takes the first file of a line that loads
      if (!is_readable_file(dirname_of(path) + f)) continue;
      mtl += read_text(dirname_of(path) + f) + "\n";
      break;
    }
  std::set<std::string> defined;
  for (const auto& words : directive_words(mtl, "newmtl")) defined.insert(words[0]);
  std::vector<std::string> added;
  for (const auto& words : directive_words(obj, "usemtl"))
    if (defined.insert(words[0]).second) {
      added.push_back(words[0]);
      mtl += "newmtl " + words[0] + "\n";
    }
  // One mtllib, first, reading `mtl`; the others blanked (line numbers kept but for the first line).
  for (size_t begin = 0; begin < obj.size();) {
    size_t end = obj.find('\n', begin);
    if (end == std::string::npos) end = obj.size();
    size_t at = begin;
    while (at < end && (obj[at] == ' ' || obj[at] == '\t')) ++at;
    if (obj.compare(at, 6, "mtllib") == 0) obj.replace(at, end - at, std::string(end - at, ' '));
    begin = end + 1;
  }
  if (!reader.ParseFromString("mtllib pmc_bindings.mtl\n" + obj, mtl, config))
    fail(path, ": cannot parse OBJ: ", reader.Error());
  out = std::move(reader);
  return added;
}

}  // namespace

std::string normalize_texture_path(const std::string& raw) {
  std::string p = raw;
  for (char& c : p)
    if (c == '\\') c = '/';
  while (p.rfind("./", 0) == 0) p = p.substr(2);
  return p;
}

Scene load_obj(const std::string& path, const ObjLoadOptions& options) {
  {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) fail(path, ": cannot open OBJ file (it is a directory)");
    std::ifstream probe(path);
    if (!probe) fail(path, ": cannot open OBJ file");
  }
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  config.mtl_search_path = dirname_of(path);
  Background<NonFiniteScan> non_finite([path] { return scan_non_finite(path); });
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) {
    std::string why = reader.Error();
    while (!why.empty() && why.back() == '\n') why.pop_back();
    fail(path, ": cannot parse OBJ: ", why.empty() ? "unknown error" : why);
  }
  const std::string& warnings = reader.Warning();
  for (const char* needle : {"Material file [", "Failed to load material file"}) {
    std::string line = warning_line(warnings, needle);
    if (!line.empty()) fail(path, ": MTL library missing or unreadable (", line, ")");
  }
  // tinyobj drops a quad with an out-of-range vertex index with only this warning.
  std::string bad_quad = warning_line(warnings, "Face with invalid vertex index");
  if (!bad_quad.empty()) fail(path, ": a quad uses a vertex index out of range (", bad_quad, ")");
  // tinyobj drops a face with fewer than 3 corners (a file cut mid-line) with only this warning.
  if (!warning_line(warnings, "Degenerated face found").empty())
    fail(path, ": a face has fewer than 3 corners (is the file truncated?)");
  std::vector<std::string> undefined_names;
  if (!warning_line(warnings, "material [ ").empty())
    undefined_names = reparse_keeping_usemtl_names(path, reader, config);

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  Scene scene;
  scene.obj_path = path;
  scene.positions.assign(attrib.vertices.begin(), attrib.vertices.end());
  const size_t spelled_non_finite = apply_non_finite(non_finite.get(), scene.positions);
  scene.normals.assign(attrib.normals.begin(), attrib.normals.end());
  scene.uvs.assign(attrib.texcoords.begin(), attrib.texcoords.end());
  const long nv = long(attrib.vertices.size() / 3);
  const long nn = long(attrib.normals.size() / 3);
  const long nt = long(attrib.texcoords.size() / 2);

  // Materials: the MTL's, then a default one for faces without a material.
  for (const tinyobj::material_t& m : reader.GetMaterials()) {
    MtlMaterial mm;
    mm.name = m.name;
    for (int i = 0; i < 3; ++i) {
      mm.kd[i] = float(m.diffuse[i]);
      mm.ks[i] = float(m.specular[i]);
      mm.ke[i] = float(m.emission[i]);
    }
    mm.ns = float(m.shininess);
    mm.dissolve = float(m.dissolve);
    auto resolve = [&](const std::string& t) {
      return t.empty() ? t : dirname_of(path) + normalize_texture_path(t);
    };
    mm.map_kd = resolve(m.diffuse_texname);
    mm.map_d = resolve(m.alpha_texname);
    mm.map_bump = resolve(!m.bump_texname.empty() ? m.bump_texname : m.normal_texname);
    mm.map_ks = resolve(m.specular_texname);
    // What the MTL says that pmc's network leaves out (named in mtl_to_graph's warning).
    auto unused = [&](bool present, const std::string& what) {
      if (present) mm.not_modelled.push_back(what);
    };
    unused(!m.ambient_texname.empty(), "ambient map (map_Ka " + m.ambient_texname + ")");
    unused(!m.emissive_texname.empty(), "emission map (map_Ke " + m.emissive_texname + ")");
    unused(!m.specular_highlight_texname.empty(),
           "shininess map (map_Ns " + m.specular_highlight_texname + ")");
    unused(!m.displacement_texname.empty(), "displacement map (disp " + m.displacement_texname + ")");
    unused(!m.reflection_texname.empty(), "reflection map (refl " + m.reflection_texname + ")");
    unused(m.roughness != 0.0 || m.metallic != 0.0 || m.sheen != 0.0 || m.clearcoat_thickness != 0.0 ||
               !m.roughness_texname.empty() || !m.metallic_texname.empty() || !m.sheen_texname.empty(),
           "PBR extension (Pr/Pm/Ps/Pc and their maps)");
    unused(m.illum >= 3, "illum " + std::to_string(m.illum) + " (ray-traced reflection/refraction)");
    if (std::find(undefined_names.begin(), undefined_names.end(), m.name) != undefined_names.end()) {
      mm = MtlMaterial();  // no MTL entry: the default material's values, under its own name
      mm.name = m.name;
      mm.defined_by_mtl = false;
    }
    scene.materials.push_back(mm);
  }
  const int default_material = int(scene.materials.size());
  {
    MtlMaterial def;
    def.name = "(default)";
    scene.materials.push_back(def);
  }

  std::vector<bool> material_used(scene.materials.size(), false);
  size_t corners = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) corners += shape.mesh.indices.size();
  scene.triangles.reserve(corners / 3);
  scene.triangle_shapes.reserve(corners / 3);
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const tinyobj::mesh_t& mesh = shape.mesh;
    const uint32_t shape_index = uint32_t(scene.shape_names.size());
    scene.shape_names.push_back(shape.name);
    size_t index_at = 0;
    for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
      const size_t fv = mesh.num_face_vertices[f];
      if (fv != 3) {  // tinyobj leaves degenerate polygons (< 3 corners) as they are
        index_at += fv;
        ++scene.skipped_triangles;
        continue;
      }
      PmcTriangle tri{};
      bool finite = true;
      for (int k = 0; k < 3; ++k) {
        const tinyobj::index_t& ix = mesh.indices[index_at + k];
        if (ix.vertex_index < 0 || ix.vertex_index >= nv)
          fail(path, ": shape '", shape.name, "' face ", f + 1, " uses vertex index ", ix.vertex_index + 1,
               " but the file has ", nv, " vertices");
        // -1 means "absent"; a relative index before the first entry resolves below -1.
        if (ix.normal_index >= nn || ix.texcoord_index >= nt || ix.normal_index < -1 ||
            ix.texcoord_index < -1)
          fail(path, ": shape '", shape.name, "' face ", f + 1,
               " uses a normal or texture-coordinate index out of range");
        tri.v[k] = ix.vertex_index;
        tri.n[k] = ix.normal_index;
        tri.t[k] = ix.texcoord_index;
        for (int c = 0; c < 3; ++c)
          finite = finite && std::isfinite(scene.positions[3 * size_t(ix.vertex_index) + c]);
      }
      index_at += 3;
      // Normals and uvs are all-or-nothing per triangle.
      if (tri.n[0] < 0 || tri.n[1] < 0 || tri.n[2] < 0) tri.n[0] = tri.n[1] = tri.n[2] = -1;
      if (tri.t[0] < 0 || tri.t[1] < 0 || tri.t[2] < 0) tri.t[0] = tri.t[1] = tri.t[2] = -1;
      if (!finite) {
        ++scene.skipped_triangles;
        continue;
      }
      int mat = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
      tri.material = (mat >= 0 && mat < default_material) ? mat : default_material;
      material_used[size_t(tri.material)] = true;
      scene.triangles.push_back(tri);
      scene.triangle_shapes.push_back(shape_index);
      for (int k = 0; k < 3; ++k) scene.bounds.extend(&scene.positions[3 * size_t(tri.v[k])]);
    }
  }
  if (scene.skipped_triangles > 0)
    warn(path + ": skipped " + std::to_string(scene.skipped_triangles) +
         " faces with non-finite vertex positions or fewer than 3 corners");
  if (scene.triangles.empty()) fail(path, ": no faces (nothing to render)");

  // Non-finite normals and uvs are repaired in the kernel (geometric normal, uv 0);
  // make them finite here so nothing downstream sees NaN.
  size_t repaired = spelled_non_finite;
  for (float& x : scene.normals)
    if (!std::isfinite(x)) x = 0.0f, ++repaired;
  for (float& x : scene.uvs)
    if (!std::isfinite(x)) x = 0.0f, ++repaired;
  if (repaired > 0)
    warn(path + ": replaced " + std::to_string(repaired) + " non-finite normal/uv components by 0");

  if (options.load_textures) {
    for (size_t m = 0; m < scene.materials.size(); ++m) {
      MtlMaterial& mm = scene.materials[m];
      if (!material_used[m] || mm.map_kd.empty()) continue;
      mm.kd_texture = scene.textures.load(mm.map_kd, true, path + ": material '" + mm.name + "'");
    }
  }
  return scene;
}

}  // namespace pmc
