// cutout.h — cut-out opacity evaluated on the host for Embree's filters.
//
// For triangles whose material's opacity depends on the shading point (MTL
// map_d, a MaterialX opacity network), CutoutTester runs the material's
// opacity program (MaterialSet::cutout_program: the nodes that feed opacity,
// nothing else) with the CPU interpreter at the candidate hit's uv and reports the
// hit transparent when opacity < 0.5 (a binary mask: deterministic, no noise).
// Only materials that have a cut-out are flagged, so opaque scenes pay nothing.
#pragma once

#include "core/alpha_test.h"
#include "core/device/pmc_texture.h"
#include "core/scene.h"
#include "materials/material_set.h"

struct PmcShadingInputs;  // core/device/pmc_interp.h (materials/cpu_interpreter.h includes it)

namespace pmc {

// The shading inputs of a candidate hit at barycentrics (u, v) of scene
// triangle `prim`: interpolated uv and position, a flat frame, and the
// finest mip level (masks keep their edges).
PmcShadingInputs cutout_shading_inputs(const Scene& scene, uint32_t prim, float u, float v);

class CutoutTester : public AlphaTester {
 public:
  CutoutTester(const Scene& scene, const MaterialSet& materials);
  bool transparent(uint32_t prim, float u, float v) const override;
  const std::vector<char>& cutout_triangles() const override { return flags_; }
  bool any() const { return count_ > 0; }

 private:
  const Scene& scene_;
  const MaterialSet& materials_;
  PmcTextureSet textures_;
  std::vector<char> flags_;
  size_t count_ = 0;
};

}  // namespace pmc
