// obj_loader.h — Wavefront OBJ + MTL into a pmc::Scene.
//
// The OBJ's geometry is parsed by pmc (core/obj_parser.h, in parallel); MTL
// libraries are read by tinyobjloader. Polygons are triangulated, `usemtl`
// switches materials within a mesh (a name no MTL defines keeps its name,
// with the default material's values, so a MaterialX material of that name
// can bind to it), objects and groups (`o`/`g`) are kept as shape names per
// triangle for MaterialX looks, missing normals fall back to geometric
// normals in the kernel (index -1), texture paths are resolved relative to
// the OBJ's folder with backslashes mapped to slashes, and only textures of
// materials that faces use are loaded. Triangles with a non-finite corner
// are skipped, non-finite normal and uv components become 0, each with a
// warning. Errors (unreadable OBJ, missing MTL, missing texture, no faces,
// malformed faces, indices out of range) throw pmc::Error naming the file.
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
