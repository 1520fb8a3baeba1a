// vertex_tangents.h — smooth tangents from the uv parameterisation.
//
// A normal map or an anisotropic lobe needs a tangent frame that is
// continuous across the triangles of a smooth surface, as the normals are;
// one triangle's own dp/du changes at every edge. For each triangle corner
// this gives the area-weighted mean of the unit dp/du (the +u direction) of
// the triangles that share the corner's position, normal and uv indices and
// the orientation of their uv mapping (mirrored charts are kept apart, as
// MikkTSpace does), made orthogonal to the corner's normal.
#pragma once

#include <array>
#include <vector>

#include "core/scene.h"

namespace pmc {

// Per triangle, its three corners' tangents (unit, x y z); `valid[i]` is
// false where a triangle has no uvs or a corner's tangent degenerates (the
// renderer then keeps the triangle's own dp/du).
struct VertexTangents {
  std::vector<std::array<float, 9>> corners;
  std::vector<bool> valid;
};

VertexTangents vertex_tangents(const Scene& scene);

}  // namespace pmc
