// scene_buffers.cpp — uploads geometry, bytecode, textures and lights.
#include "gpu/scene_buffers.h"

#include "core/device/pmc_octahedral.h"
#include "core/parallel.h"
#include "core/vertex_tangents.h"

namespace pmc {

std::vector<PmcTriangleRecord> triangle_records_of(const Scene& scene) {
  std::vector<PmcTriangleRecord> records(scene.triangles.size());
  const VertexTangents tangents = vertex_tangents(scene);
  parallel_for_each_index(records.size(), [&](size_t i) {
    const PmcTriangle& t = scene.triangles[i];
    PmcTriangleRecord r{};
    r.material = t.material;
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) r.p[3 * k + c] = scene.positions[3 * size_t(t.v[k]) + size_t(c)];
    if (t.n[0] >= 0) {
      r.flags |= PMC_TRI_NORMALS;
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) r.n[3 * k + c] = scene.normals[3 * size_t(t.n[k]) + size_t(c)];
    }
    if (t.t[0] >= 0) {
      r.flags |= PMC_TRI_UVS;
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 2; ++c) r.t[2 * k + c] = scene.uvs[2 * size_t(t.t[k]) + size_t(c)];
      if (tangents.valid[i]) {
        r.flags |= PMC_TRI_TANGENTS;
        for (int k = 0; k < 3; ++k) {
          const float* c = &tangents.corners[i][size_t(3 * k)];
          r.tangent[k] = pmc_oct_encode(make_float3(c[0], c[1], c[2]));
        }
      }
    }
    records[i] = r;
  });
  return records;
}

SceneBuffers::SceneBuffers(const ClContext& cl, const Scene& scene, const MaterialSet& mats) {
  for (const PmcMaterialInfo& m : mats.infos)
    for (int i = 0; i < 3; ++i) emission.push_back(m.emission[i]);
  texture_count = uint32_t(scene.textures.size());
  triangle_material.reserve(scene.triangles.size());
  for (const PmcTriangle& t : scene.triangles) triangle_material.push_back(t.material);
  material_count = int(mats.infos.size());
  triangle_records = triangle_records_of(scene);
  buffers[kScene_triangles] = cl.shared_buffer_of(triangle_records);
  buffers[kScene_code] = cl.shared_buffer_of(mats.program.code);
  buffers[kScene_materials] = cl.shared_buffer_of(mats.infos);
  buffers[kScene_textures] = cl.shared_buffer_of(scene.textures.textures());
  buffers[kScene_texels] = cl.shared_buffer_of(*mats.texel_words);
  buffers[kScene_srgb_lut] = cl.shared_buffer_of(mats.srgb_lut);
  upload_lights(cl, empty_light_table());  // each render uploads its own (WavefrontRenderer::render)
}

void SceneBuffers::upload_lights(const ClContext& cl, LightTable table) {
  // The sky map's data can be hundreds of megabytes. It belongs to the map
  // (core/env_map.h), which every render's table shares: a table of the
  // same map keeps the buffer (on a GPU, no second upload). A new map's
  // buffer replaces the old one before the old table lets its map go, since
  // CPU devices read the map's own memory.
  const bool same_map = table.env_map && table.env_map == lights.env_map && buffers[kScene_env].get();
  if (!same_map) buffers[kScene_env] = ClBuffer();
  lights = std::move(table);
  buffers[kScene_lights] = cl.buffer_of(lights.lights);
  buffers[kScene_tri_light] = cl.buffer_of(lights.triangle_light);
  buffers[kScene_light_tree] = cl.buffer_of(lights.tree_nodes);
  if (!same_map)
    buffers[kScene_env] = cl.shared_buffer(lights.env_float_count() * sizeof(float), lights.env_floats());
}

}  // namespace pmc
