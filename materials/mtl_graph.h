// mtl_graph.h — a plain MTL material as a small node network.
//
// Kd (times map_Kd) becomes the base colour, Ks the specular colour, Ns the
// roughness (Phong exponent to GGX alpha, Walter et al. 2007), Ke the
// emission, d / map_d the cut-out opacity (map_d's alpha channel if it has
// one, else its first channel). Everything goes through the same compiler and
// interpreter as MaterialX. What pmc cannot model (bump and normal maps from
// MTL, specular, ambient, emission and shininess maps, the PBR extension,
// illum models with ray-traced reflection or refraction ...) is named in one
// warning per material, never silently dropped.
#pragma once

#include "core/scene.h"
#include "materials/node_graph.h"

namespace pmc {

Graph mtl_to_graph(const MtlMaterial& m, const std::string& mtl_file);

}  // namespace pmc
