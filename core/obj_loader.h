// obj_loader.h — Wavefront OBJ + MTL into a pmc::Scene (via tinyobjloader).
//
// Polygons are triangulated, `usemtl` switches materials within a mesh (a
// name no MTL defines keeps its name, with the default material's values, so
// a MaterialX material of that name can bind to it), objects and groups
// (`o`/`g`) are kept as shape names per triangle for MaterialX looks,
// missing normals fall back to geometric normals in the kernel (index -1),
// texture paths are resolved relative to the OBJ's folder with backslashes
// mapped to slashes, and only textures of materials that faces use are loaded.
// Errors (unreadable OBJ, missing MTL, missing texture, no faces, indices out
// of range) throw pmc::Error naming the file. The file's second read (the
// NaN/inf positions tinyobj reads as 0) runs beside tinyobj's parse, on a
// Background job (core/background.h).
#pragma once

#include <string>

#include "core/scene.h"

namespace pmc {

struct ObjLoadOptions {
  bool load_textures = true;
};

Scene load_obj(const std::string& path, const ObjLoadOptions& options = {});

// "a\\b.png" -> "a/b.png", ".\\x.jpg" -> "x.jpg".
std::string normalize_texture_path(const std::string& raw);

}  // namespace pmc
