// obj_loader.cpp — parsed OBJ geometry (core/obj_parser.h) and tinyobj's MTL materials into pmc::Scene.
#include "core/obj_loader.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/obj_parser.h"

namespace pmc {
namespace {

std::string dirname_of(const std::string& path) {
  size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// True for a name that opens a regular file. A name with a NUL byte would
// open only its prefix (often the OBJ's folder), and reading a directory
// throws from inside libstdc++.
bool is_readable_file(const std::string& path) {
  std::error_code ec;
  return path.find('\0') == std::string::npos && std::filesystem::is_regular_file(path, ec);
}

// The MTL libraries of the OBJ's mtllib lines, as tinyobj loads them: the
// first file of a line that opens (a file loaded before counts), searched in
// the OBJ's folder. A name that is listed more than once keeps its first
// definition.
void load_mtl_libraries(const std::string& path, const std::vector<std::vector<std::string>>& mtllibs,
                        std::vector<tinyobj::material_t>& materials, std::map<std::string, int>& by_name) {
  tinyobj::MaterialFileReader read(dirname_of(path));
  std::set<std::string> loaded;
  for (const std::vector<std::string>& files : mtllibs) {
    bool found = false;
    std::string why;
    for (const std::string& f : files) {
      if (f.empty()) continue;
      if (loaded.count(f)) {
        found = true;
        continue;
      }
      std::string warn, err;
      if (is_readable_file(dirname_of(path) + f) && read(f, &materials, &by_name, &warn, &err)) {
        loaded.insert(f);
        found = true;
        break;
      }
      why += (why.empty() ? "" : ", ") + printable(dirname_of(path) + f);
    }
    if (!found && !why.empty())  // (a line without names is passed over)
      fail(path, ": MTL library missing or unreadable (", why, ")");
  }
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
  std::string text;
  {
    std::ifstream in(path, std::ios::binary);
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec) text.resize(size_t(size));
    if (!in.read(text.data(), std::streamsize(text.size())) && !in.eof())
      fail(path, ": cannot read OBJ file");
    text.resize(size_t(in.gcount()));
  }
  ObjGeometry geometry = parse_obj(path, text);
  text = std::string();
  if (geometry.approximate_polygons > 0)
    warn(path + ": " + std::to_string(geometry.approximate_polygons) +
         " concave polygons (over 1024 corners, or too irregular) were split partly as fans around their "
         "first corner: their triangles may cover more or less than the polygon");
  std::vector<tinyobj::material_t> mtl_materials;
  std::map<std::string, int> mtl_by_name;
  load_mtl_libraries(path, geometry.mtllibs, mtl_materials, mtl_by_name);
  // usemtl names no MTL defines keep their names (a MaterialX material binds
  // to them) with the default material's values, after the MTL's materials.
  std::vector<std::string> undefined_names;
  std::vector<int> usemtl_material(geometry.usemtl_names.size());
  for (size_t i = 0; i < geometry.usemtl_names.size(); ++i) {
    const std::string& name = geometry.usemtl_names[i];
    auto found = mtl_by_name.find(name);
    if (found != mtl_by_name.end()) {
      usemtl_material[i] = found->second;
    } else {
      usemtl_material[i] = int(mtl_materials.size() + undefined_names.size());
      undefined_names.push_back(name);
    }
  }

  Scene scene;
  scene.obj_path = path;
  scene.positions = std::move(geometry.positions);
  scene.normals = std::move(geometry.normals);
  scene.uvs = std::move(geometry.uvs);

  // Materials: the MTL's, then a default one for faces without a material.
  for (const tinyobj::material_t& m : mtl_materials) {
    MtlMaterial mm;
    mm.name = m.name;
    for (int i = 0; i < 3; ++i) {
      mm.kd[i] = float(m.diffuse[i]);
      mm.ks[i] = float(m.specular[i]);
      mm.ke[i] = float(m.emission[i]);
      mm.tf[i] = float(m.transmittance[i]);
    }
    mm.ns = float(m.shininess);
    mm.ni = float(m.ior);
    mm.dissolve = float(m.dissolve);
    mm.illum = m.illum;
    mm.pr = float(m.roughness);
    mm.pm = float(m.metallic);
    mm.ps = float(m.sheen);
    mm.pc = float(m.clearcoat_thickness);
    mm.pcr = float(m.clearcoat_roughness);
    mm.aniso = float(m.anisotropy);
    mm.anisor = float(m.anisotropy_rotation);
    auto resolve = [&](const std::string& t) {
      if (t.empty()) return t;
      const std::string p = normalize_texture_path(t);
      return p[0] == '/' ? p : dirname_of(path) + p;  // an absolute path stays as written
    };
    mm.map_kd = resolve(m.diffuse_texname);
    mm.map_d = resolve(m.alpha_texname);
    mm.map_bump = resolve(m.bump_texname);
    mm.map_norm = resolve(m.normal_texname);
    mm.map_ks = resolve(m.specular_texname);
    mm.map_ke = resolve(m.emissive_texname);
    mm.map_pr = resolve(m.roughness_texname);
    mm.map_pm = resolve(m.metallic_texname);
    mm.map_ps = resolve(m.sheen_texname);
    mm.bump_multiplier = float(m.bump_texopt.bump_multiplier);
    mm.norm_multiplier = float(m.normal_texopt.bump_multiplier);
    // What the MTL says that pmc's network leaves out (named in mtl_to_graph's
    // warning, with what mtl_to_graph itself decides to leave out).
    auto unused = [&](bool present, const std::string& what) {
      if (present) mm.not_modelled.push_back(what);
    };
    unused(!m.ambient_texname.empty(), "ambient map (map_Ka " + m.ambient_texname + ")");
    unused(!m.specular_highlight_texname.empty(),
           "shininess map (map_Ns " + m.specular_highlight_texname + ")");
    unused(!m.displacement_texname.empty(), "displacement map (disp " + m.displacement_texname + ")");
    unused(!m.reflection_texname.empty(), "reflection map (refl " + m.reflection_texname + ")");
    scene.materials.push_back(mm);
  }
  for (const std::string& name : undefined_names) {
    MtlMaterial mm;  // no MTL entry: the default material's values, under its own name
    mm.name = name;
    mm.defined_by_mtl = false;
    scene.materials.push_back(mm);
  }
  const int default_material = int(scene.materials.size());
  {
    MtlMaterial def;
    def.name = "(default)";
    scene.materials.push_back(def);
  }

  std::vector<bool> material_used(scene.materials.size(), false);
  scene.shape_names = std::move(geometry.shape_names);
  scene.triangles.reserve(geometry.triangles.size());
  scene.triangle_shapes.reserve(geometry.triangles.size());
  for (const ObjTriangle& t : geometry.triangles) {
    PmcTriangle tri{};
    bool finite = true;
    for (int k = 0; k < 3; ++k) {
      tri.v[k] = t.v[k];
      tri.n[k] = t.n[k];
      tri.t[k] = t.t[k];
      for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(scene.positions[3 * size_t(t.v[k]) + c]);
    }
    // Normals and uvs are all-or-nothing per triangle.
    if (tri.n[0] < 0 || tri.n[1] < 0 || tri.n[2] < 0) tri.n[0] = tri.n[1] = tri.n[2] = -1;
    if (tri.t[0] < 0 || tri.t[1] < 0 || tri.t[2] < 0) tri.t[0] = tri.t[1] = tri.t[2] = -1;
    if (!finite) {
      ++scene.skipped_triangles;
      continue;
    }
    tri.material = t.usemtl >= 0 ? usemtl_material[size_t(t.usemtl)] : default_material;
    material_used[size_t(tri.material)] = true;
    scene.triangles.push_back(tri);
    scene.triangle_shapes.push_back(uint32_t(t.shape));
    for (int k = 0; k < 3; ++k) scene.bounds.extend(&scene.positions[3 * size_t(tri.v[k])]);
  }
  if (scene.skipped_triangles > 0)
    warn(path + ": skipped " + std::to_string(scene.skipped_triangles) +
         " faces with non-finite vertex positions");
  if (scene.triangles.empty()) fail(path, ": no faces (nothing to render)");

  // Non-finite normals and uvs are repaired in the kernel (geometric normal, uv 0);
  // make them finite here so nothing downstream sees NaN.
  size_t repaired = 0;
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
