// closure_flatten.h — generic MaterialX closure graphs onto pmc's one BSDF.
//
// pmc's BSDF (core/device/pmc_bsdf.h) is a Lambert lobe, one GGX lobe with a
// Schlick F0, and emission. MaterialX also lets a document build its own
// shader from closures: pbrlib's `surface` over `layer`, `mix`, `add` and
// `multiply` of *_bsdf and *_edf nodes, and `mix` of whole surface shaders.
// The reader keeps such closure nodes in the graph as they are written; this
// pass flattens the closure tree under a shader into a pmc_mtl_surface node
// whose inputs are ordinary data nodes:
//   - each closure becomes (diffuse albedo, specular F0, roughness, emission,
//     and the fraction of light it lets through to a layer below);
//   - layer(top, base) adds the base attenuated by what the top lets through;
//     mix interpolates, add sums, multiply scales;
//   - a data input that varies stays a link; arithmetic on constants folds.
// Roughness: MaterialX BSDFs take GGX alpha (vector2); pmc takes the
// standard_surface roughness r = sqrt(alpha), isotropic. Lobes pmc cannot
// model (transmission, sheen, thin film, volumes, hair, anisotropy, a
// Fresnel curve other than Schlick's) are named in `unmodelled`, once each,
// for the reader's one warning per material. The closure nodes are left
// dead.
#pragma once

#include <string>
#include <vector>

#include "materials/node_graph.h"

namespace pmc {

// BSDF, EDF, VDF and surfaceshader: values that are closures, not data.
bool is_closure_type(ValueType t);

// Flattens the closure tree rooted at `shader` (a `surface`, a closure
// operator of type surfaceshader, or a surface shader node pmc maps) into a
// new pmc_mtl_surface node, and returns its index.
int flatten_closure_shader(Graph& g, int shader, std::vector<std::string>& unmodelled);

}  // namespace pmc
