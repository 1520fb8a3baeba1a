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
 * |coordinate| of its triangle's vertices, from their components (float, or
 * float8 for eight hits: PMC_HIT_GEOMETRY computes it). */
#define PMC_HIT_SCALE(p0x, p0y, p0z, p1x, p1y, p1z, p2x, p2y, p2z) \
  fmax(fmax(fabs(p0x), fmax(fabs(p1x), fabs(p2x))),                \
       fmax(fmax(fabs(p0y), fmax(fabs(p1y), fabs(p2y))), fmax(fabs(p0z), fmax(fabs(p1z), fabs(p2z)))))

/* Offset p along the (unit) normal n, to the side n points to; `scale` from
 * PMC_HIT_SCALE (clamped to [1e-30, 1]: at or above 1 the classic constants). */
PMC_FN float3 pmc_offset_ray(float3 p, float3 n, float scale) {
  float s = fmax(1e-30f, fmin(1.0f, scale)); /* NaN -> 1 */
  return make_float3(pmc_offset_1(p.x, n.x, s), pmc_offset_1(p.y, n.y, s), pmc_offset_1(p.z, n.z, s));
}

#endif /* PMC_GEOMETRY_H */
