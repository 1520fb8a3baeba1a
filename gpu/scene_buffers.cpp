// scene_buffers.cpp — uploads geometry, bytecode, textures and lights.
#include "gpu/scene_buffers.h"

namespace pmc {

SceneBuffers::SceneBuffers(const ClContext& cl, const Scene& scene, const MaterialSet& mats) {
  for (const PmcMaterialInfo& m : mats.infos)
    for (int i = 0; i < 3; ++i) emission.push_back(m.emission[i]);
  texture_count = uint32_t(scene.textures.size());
  triangle_material.reserve(scene.triangles.size());
  for (const PmcTriangle& t : scene.triangles) triangle_material.push_back(t.material);
  material_count = int(mats.infos.size());
  buffers[kScene_positions] = cl.shared_buffer_of(scene.positions);
  buffers[kScene_normals] = cl.shared_buffer_of(scene.normals);
  buffers[kScene_uvs] = cl.shared_buffer_of(scene.uvs);
  buffers[kScene_triangles] = cl.shared_buffer_of(scene.triangles);
  buffers[kScene_code] = cl.shared_buffer_of(mats.program.code);
  buffers[kScene_materials] = cl.shared_buffer_of(mats.infos);
  buffers[kScene_textures] = cl.shared_buffer_of(scene.textures.textures());
  buffers[kScene_texels] = cl.shared_buffer_of(*mats.texel_words);
  buffers[kScene_srgb_lut] = cl.shared_buffer_of(mats.srgb_lut);
  upload_lights(cl, build_light_table(scene, emission, SceneLights{}));
}

void SceneBuffers::upload_lights(const ClContext& cl, LightTable table) {
  lights = std::move(table);
  buffers[kScene_lights] = cl.buffer_of(lights.lights);
  buffers[kScene_tri_light_pmf] = cl.buffer_of(lights.triangle_pmf);
  buffers[kScene_env] = cl.buffer_of(lights.env_data);
}

}  // namespace pmc
