// lights.h — the emissive-triangle table for next-event estimation.
//
// Every triangle whose material emits becomes a light, picked with
// probability proportional to its power (area x luminance of the emission).
// The kernels get the light triangles, their CDF, and per triangle the
// probability of picking it (0 for non-emitters) for MIS on emitter hits.
#pragma once

#include <vector>

#include "core/scene.h"

namespace pmc {

struct LightTable {
  std::vector<int> triangles;
  std::vector<float> cdf;           // inclusive, last entry 1
  std::vector<float> triangle_pmf;  // per scene triangle
  float total_power = 0.0f;
};

// `emission[m]` is the (constant) emitted radiance of material m, rgb.
LightTable build_light_table(const Scene& scene, const std::vector<float>& emission);

}  // namespace pmc
