/* pmc_geometry.h — robust ray-origin offsets, shared by host and kernels.
 *
 * A secondary ray must start off the surface it leaves, by an amount that
 * scales with the magnitude of the hit point (scenes span 1e-4 to 1e5).
 * We follow the integer-ULP offset of Wächter and Binder ("A Fast and Robust
 * Method for Avoiding Self-Intersection", Ray Tracing Gems, 2019): move the
 * point a fixed number of float ULPs along the normal, and by a small absolute
 * amount near the origin where ULPs are tiny. Their absolute amount (and the
 * "near the origin" threshold) assume coordinates of order 1; for smaller
 * scenes both shrink with `scale`, the largest |coordinate| of the hit
 * triangle's vertices (what the hit point's rounding error is proportional
 * to), so a scene scaled by 1e-4 is offset like the same scene at scale 1
 * instead of by a constant 1.5e-5 that jumps over thin gaps. Scenes of scale
 * >= 1 are offset exactly as before.
 */
#ifndef PMC_GEOMETRY_H
#define PMC_GEOMETRY_H

#include "../abi/pmc_vec.h"

PMC_FN float pmc_offset_1(float p, float n, float s) {
  const float origin = s * (1.0f / 32.0f);
  const float float_scale = s * (1.0f / 65536.0f);
  const float int_scale = 256.0f;
  int of = (int)(int_scale * n);
  float pi = as_float(as_int(p) + (p < 0.0f ? -of : of));
  return fabs(p) < origin ? p + float_scale * n : pi;
}

/* The magnitude a hit point's rounding error scales with: the largest
 * |coordinate| of its triangle's vertices. */
PMC_FN float pmc_hit_scale(float3 p0, float3 p1, float3 p2) {
  float3 a = make_float3(fmax(fabs(p0.x), fmax(fabs(p1.x), fabs(p2.x))),
                         fmax(fabs(p0.y), fmax(fabs(p1.y), fabs(p2.y))),
                         fmax(fabs(p0.z), fmax(fabs(p1.z), fabs(p2.z))));
  return fmax(a.x, fmax(a.y, a.z));
}

/* Offset p along the (unit) normal n, to the side n points to; `scale` from
 * pmc_hit_scale() (clamped to [1e-30, 1]: at or above 1 the classic constants). */
PMC_FN float3 pmc_offset_ray(float3 p, float3 n, float scale) {
  float s = fmax(1e-30f, fmin(1.0f, scale)); /* NaN -> 1 */
  return make_float3(pmc_offset_1(p.x, n.x, s), pmc_offset_1(p.y, n.y, s), pmc_offset_1(p.z, n.z, s));
}

#endif /* PMC_GEOMETRY_H */
