// scene.h — the host's in-memory scene: geometry, MTL materials, textures.
//
// Geometry is kept the way the kernels read it: flat float arrays of
// positions (xyz), normals (xyz) and uvs (uv), and one PmcTriangle per
// triangle holding per-corner indices into each array (-1 when absent) and a
// material index. Embree uses the positions array and the `v` indices; the
// shade kernel uses all of it. Materials stay in their MTL form here; the
// material compiler turns them into what the kernels evaluate.
#pragma once

#include <string>
#include <vector>

#include "core/abi/pmc_types.h"
#include "core/texture.h"

namespace pmc {

struct Bounds {
  float lo[3] = {1e30f, 1e30f, 1e30f};
  float hi[3] = {-1e30f, -1e30f, -1e30f};
  bool empty() const { return lo[0] > hi[0]; }
  void extend(const float* p) {
    for (int i = 0; i < 3; ++i) {
      lo[i] = p[i] < lo[i] ? p[i] : lo[i];
      hi[i] = p[i] > hi[i] ? p[i] : hi[i];
    }
  }
};

struct MtlMaterial {
  std::string name;
  float kd[3] = {0.5f, 0.5f, 0.5f};
  float ks[3] = {0.0f, 0.0f, 0.0f};
  float ke[3] = {0.0f, 0.0f, 0.0f};
  float tf[3] = {0.0f, 0.0f, 0.0f};  // Tf (tinyobjloader's default when absent: 0 0 0)
  float ns = 0.0f;
  float ni = 1.0f;        // Ni (tinyobjloader's default 1; Ni <= 1 reads as "not given")
  float dissolve = 1.0f;  // d
  int illum = 0;          // illum (tinyobjloader's default 0)
  // The PBR extension (tinyobjloader's defaults: all 0): Pr, Pm, Ps, Pc,
  // Pcr, aniso, anisor.
  float pr = 0.0f, pm = 0.0f, ps = 0.0f, pc = 0.0f, pcr = 0.0f, aniso = 0.0f, anisor = 0.0f;
  std::string map_kd;  // resolved paths, empty when none
  std::string map_d;
  std::string map_bump;  // bump / map_bump / map_Bump
  std::string map_norm;  // norm
  std::string map_ks;
  std::string map_ke;
  std::string map_pr;
  std::string map_pm;
  std::string map_ps;
  float bump_multiplier = 1.0f;           // -bm of bump (tinyobjloader's default 1: 1 reads as "not given")
  float norm_multiplier = 1.0f;           // -bm of norm
  std::vector<std::string> not_modelled;  // other MTL statements pmc ignores, for the warning
  int kd_texture = -1;                    // index into Scene::textures once loaded
  // false for a `usemtl` name no MTL defines: it keeps its name (a MaterialX
  // material of that name binds to it) and the default material's values.
  bool defined_by_mtl = true;

  // Every texture path above, for code that checks or rewrites them all.
  std::vector<std::string*> maps() {
    return {&map_kd, &map_d, &map_bump, &map_norm, &map_ks, &map_ke, &map_pr, &map_pm, &map_ps};
  }
};

struct Scene {
  std::string obj_path;
  std::vector<float> positions;
  std::vector<float> normals;
  std::vector<float> uvs;
  std::vector<PmcTriangle> triangles;
  std::vector<MtlMaterial> materials;
  // OBJ objects and groups (`o NAME` / `g NAME`, as tinyobjloader names its
  // shapes) and which one each triangle came from: MaterialX <look>s assign
  // materials to the geometry "/NAME".
  std::vector<std::string> shape_names;
  std::vector<uint32_t> triangle_shapes;  // parallel to triangles
  TexturePool textures;
  Bounds bounds;                 // of the positions the triangles use
  size_t skipped_triangles = 0;  // non-finite positions, dropped at load
};

}  // namespace pmc
