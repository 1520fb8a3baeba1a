// cpu_interpreter.cpp — host evaluation of one material program.
#include "materials/cpu_interpreter.h"

namespace pmc {

PmcTextureSet host_texture_set(const Scene& scene, const MaterialSet& materials) {
  PmcTextureSet ts{};
  ts.textures = scene.textures.textures().data();
  ts.texels = materials.texel_words->data();
  ts.srgb_lut = materials.srgb_lut.data();
  ts.count = uint32_t(scene.textures.size());
  return ts;
}

void evaluate_material(const MaterialSet& materials, const PmcTextureSet& textures, int scene_material,
                       const PmcShadingInputs& in, float params[PMC_P_COUNT]) {
  float stack[PMC_STACK_SIZE];
  pmc_surface_defaults(params, in.normal);
  pmc_interp_run(materials.program.code.data(), materials.infos[size_t(scene_material)].entry, &in, &textures,
                 stack, params, nullptr);
}

}  // namespace pmc
