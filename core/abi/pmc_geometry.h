/* pmc_geometry.h — robust ray-origin offsets, shared by host and kernels.
 *
 * A secondary ray must start off the surface it leaves, by an amount that
 * scales with the magnitude of the hit point (scenes span 1e-4 to 1e5).
 * We follow the integer-ULP offset of Wächter and Binder ("A Fast and Robust
 * Method for Avoiding Self-Intersection", Ray Tracing Gems, 2019): move the
 * point a fixed number of float ULPs along the normal, and by a small absolute
 * amount near the origin where ULPs are tiny.
 */
#ifndef PMC_GEOMETRY_H
#define PMC_GEOMETRY_H

#include "pmc_vec.h"

PMC_FN float pmc_offset_1(float p, float n) {
  const float origin = 1.0f / 32.0f;
  const float float_scale = 1.0f / 65536.0f;
  const float int_scale = 256.0f;
  int of = (int)(int_scale * n);
  float pi = as_float(as_int(p) + (p < 0.0f ? -of : of));
  return fabs(p) < origin ? p + float_scale * n : pi;
}

/* Offset p along the (unit) normal n, to the side n points to. */
PMC_FN float3 pmc_offset_ray(float3 p, float3 n) {
  return make_float3(pmc_offset_1(p.x, n.x), pmc_offset_1(p.y, n.y), pmc_offset_1(p.z, n.z));
}

#endif /* PMC_GEOMETRY_H */
