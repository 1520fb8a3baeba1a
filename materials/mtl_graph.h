// mtl_graph.h — a plain MTL material as a small standard_surface network.
//
// The mapping follows Blender's OBJ importer (the Cycles peer reads OBJ
// scenes through it); docs/MTL.md has the table, statement by statement.
// In short: Kd (times map_Kd) is the base colour, Pm / map_Pm the
// metalness, Pr / map_Pr (PBR materials) or Ns (1 - sqrt(Ns / 1000)) the
// roughness, mean(Ks) the specular level folded into specular_IOR (from
// Ni), map_Ks scales the specular weight, Ke (times map_Ke) the emission,
// d / map_d the cut-out opacity, illum 4/6/7/9 glass (transmission, Tf),
// Pc/Pcr the coat, Ps / map_Ps the sheen, aniso/anisor the anisotropy, norm
// and bump / map_Bump the shading normal (normal map, or height bump).
// Everything goes through the same compiler and interpreter as MaterialX.
// What pmc cannot model (map_Ka, map_Ns, disp, refl, Tf without a glass
// illum, unknown illum models ...) is named in one warning per material,
// never silently dropped.
#pragma once

#include "core/scene.h"
#include "materials/node_graph.h"

namespace pmc {

Graph mtl_to_graph(const MtlMaterial& m, const std::string& mtl_file);

// The formulas of the mapping (docs/MTL.md):
// roughness from a Phong exponent, 1 - sqrt(clamp(Ns, 0, 1000) / 1000);
float mtl_ns_roughness(float ns);
// the dielectric IOR: Ni when it is finite and > 1, else 1.5;
float mtl_ior(float ni);
// the IOR whose F0 is min(0.999, 2 * level * F0(n)), F0(n) = ((n - 1) / (n + 1))^2.
float mtl_level_ior(float n, float level);

}  // namespace pmc
