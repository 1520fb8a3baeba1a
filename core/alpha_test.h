// alpha_test.h — cut-out opacity during traversal, as an interface.
//
// Some materials (MTL map_d, MaterialX opacity driven by a texture) make parts
// of a triangle transparent: leaves, chains, fences. The tracer asks an
// AlphaTester, from inside Embree's intersection and occlusion filters, whether
// a candidate hit on such a triangle is transparent; transparent hits are
// skipped as if the triangle were not there. core/ only knows the interface;
// materials/cutout.h evaluates the material's opacity with the CPU interpreter.
#pragma once

#include <cstdint>
#include <vector>

namespace pmc {

class AlphaTester {
 public:
  virtual ~AlphaTester() = default;
  // True if scene triangle `prim` is transparent at barycentrics (u, v).
  virtual bool transparent(uint32_t prim, float u, float v) const = 0;
  // Per scene triangle: does it need testing at all?
  virtual const std::vector<char>& cutout_triangles() const = 0;
};

}  // namespace pmc
