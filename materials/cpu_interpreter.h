// cpu_interpreter.h — the host's reference interpreter of material programs.
//
// The same bytecode interpreter the shade kernel runs (core/device/pmc_interp.h),
// compiled by the C++ compiler: tests compare the kernel against it, and the
// cut-out tester evaluates opacity with it inside Embree's filters. Only the
// files that evaluate materials on the host include this header (and with it
// the device library); material_set.h does not.
#pragma once

#include "core/device/pmc_interp.h"
#include "core/scene.h"
#include "materials/material_set.h"

namespace pmc {

// The scene's textures as the interpreter reads them (pointers into `scene`
// and `materials`, which must outlive the result).
PmcTextureSet host_texture_set(const Scene& scene, const MaterialSet& materials);

// Runs scene material `scene_material`'s program at one shading point and
// fills the surface parameter block (unwritten parameters keep their defaults).
void evaluate_material(const MaterialSet& materials, const PmcTextureSet& textures, int scene_material,
                       const PmcShadingInputs& in, float params[PMC_P_COUNT]);

}  // namespace pmc
