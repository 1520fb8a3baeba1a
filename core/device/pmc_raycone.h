/* pmc_raycone.h — ray-cone texture footprints, shared by host and kernels.
 *
 * A path carries a cone (width at its origin, spread angle); at a hit the
 * width is w + t * spread. Following Akenine-Möller et al. 2021 ("Improved
 * Shader and Texture Level of Detail Using Ray Cones", anisotropic variant),
 * the cone's elliptical footprint on the triangle has half-axes a1, a2; mapped
 * through the triangle's barycentrics they give uv-space gradients g1, g2.
 * The texture LOD uses them now; the material cache derives its virtual mip
 * level from the same g1, g2. Guards: a ray along the normal (a1 would be 0:
 * any tangent direction serves, the footprint is a circle), grazing angles
 * (the projection is clamped), zero-area position or uv triangles (g = 0).
 */
#ifndef PMC_RAYCONE_H
#define PMC_RAYCONE_H

#include "../abi/pmc_vec.h"

/* uv gradients along the footprint's axes. `ng` is the unit geometric normal,
 * `dir` the unit ray direction, `radius` the cone radius at the hit. */
PMC_FN void pmc_ray_cone_gradients(float3 dir, float3 ng, float radius, float3 p0, float3 p1, float3 p2,
                                   float2 t0, float2 t1, float2 t2, float2* g1, float2* g2) {
  *g1 = make_float2(0.0f, 0.0f);
  *g2 = make_float2(0.0f, 0.0f);
  if (!(radius > 0.0f) || !isfinite(radius)) return;
  const float cos_n = dot(ng, dir);
  float3 a1 = dir - ng * cos_n;
  float l1 = length(a1);
  if (!(l1 > 1e-6f)) { /* looking straight down the normal: any tangent axis */
    float3 t, b;
    pmc_basis(ng, &t, &b);
    a1 = t;
  } else {
    a1 = a1 * (1.0f / l1);
  }
  /* Each unit axis is stretched by the inverse of its projection onto the
   * plane orthogonal to dir (grazing angles elongate the ellipse), clamped.
   * dir lies in the plane of ng and a1, so that projection of a1 has length
   * |cos_n| (dir . a1 = sin) and a2 = ng x a1, orthogonal to both, keeps
   * its length 1. */
  float3 a2 = cross(ng, a1); /* unit: a1 is a unit vector orthogonal to ng */
  a1 = a1 * (radius / fmax(1e-4f, fabs(cos_n)));
  a2 = a2 * radius;
  float3 e1 = p1 - p0, e2 = p2 - p0;
  float area = dot(ng, cross(e1, e2));
  if (!(fabs(area) > 1e-30f) || !isfinite(area)) return;
  /* Barycentric rates of an in-plane offset a: ng.(a x e2) / area and
   * ng.(e1 x a) / area, as dot products with two vectors built once. */
  const float inv = 1.0f / area;
  const float3 c_u = cross(e2, ng) * inv, c_v = cross(ng, e1) * inv;
  float du1 = dot(a1, c_u), dv1 = dot(a1, c_v);
  float du2 = dot(a2, c_u), dv2 = dot(a2, c_v);
  float2 d1 = t1 - t0, d2 = t2 - t0;
  float2 r1 = d1 * du1 + d2 * dv1;
  float2 r2 = d1 * du2 + d2 * dv2;
  if (isfinite(r1.x) && isfinite(r1.y)) *g1 = r1;
  if (isfinite(r2.x) && isfinite(r2.y)) *g2 = r2;
}

/* The footprint's ellipse in uv. g1, g2 are the images of the cone's
 * orthogonal half-axes, so conjugate half-diameters of the uv ellipse
 * {g1 cos t + g2 sin t}: its axes are the eigenvectors of
 * M = g1 g1^T + g2 g2^T, its half-axes the square roots of M's eigenvalues
 * l1 >= l2, and l1 l2 = det(g1, g2)^2. Out: the major half-axis (length
 * sqrt(l1)) and the minor width 2 sqrt(l2); a round ellipse takes the u axis,
 * a degenerate or non-finite one gives zeros (an isotropic lookup). */
PMC_FN void pmc_ray_cone_ellipse(float2 g1, float2 g2, float2* axis, float* minor) {
  *axis = make_float2(0.0f, 0.0f);
  *minor = 0.0f;
  const float a = g1.x * g1.x + g2.x * g2.x, b = g1.x * g1.y + g2.x * g2.y, c = g1.y * g1.y + g2.y * g2.y;
  const float h = 0.5f * (a - c);
  const float r = sqrt(h * h + b * b);
  const float l1 = 0.5f * (a + c) + r;
  if (!(l1 > 0.0f) || !(l1 < 1e30f)) return;
  /* l1's eigenvector, (l1 - c, b) or (b, l1 - a), whichever is the larger */
  float2 e = h >= 0.0f ? make_float2(h + r, b) : make_float2(b, r - h);
  const float le = sqrt(e.x * e.x + e.y * e.y);
  const float major = sqrt(l1);
  e = le > 0.0f ? e * (major / le) : make_float2(major, 0.0f);
  const float det = g1.x * g2.y - g1.y * g2.x;
  const float m = 2.0f * fabs(det) / major;
  if (!isfinite(e.x) || !isfinite(e.y) || !isfinite(m)) return;
  *axis = e;
  *minor = m;
}

/* The material cache's cone (beyond the paper, whose cones grow with distance
 * alone): at each bounce its spread also grows by c times the angle of the
 * lobe that one sample stands for. A direction sampled with solid-angle pdf p
 * stands for about 1/p steradians, a cone of half-angle sqrt(1 / (pi p))
 * (small-angle form of 2 pi (1 - cos h) = 1/p). A diffuse bounce (p ~ 1/pi)
 * widens it by about 2c radians, a mirror-like one by almost nothing. What a
 * later hit reads is integrated over that lobe, so detail finer than a
 * fraction c of the lobe's footprint there is averaged out anyway: cells that
 * size cost bias that the lobe hides, and save the misses of cells finer than
 * anything the image can show. The result is capped at pi; c <= 0, a pdf <= 0
 * or not finite give 0 (the paper's cone). */
PMC_FN float pmc_lobe_spread(float pdf, float c) {
  if (!(c > 0.0f) || !(pdf > 0.0f) || !isfinite(pdf) || !isfinite(c)) return 0.0f;
  float angle = 2.0f * sqrt(1.0f / (PMC_PI * pdf));
  return fmin(c * angle, PMC_PI); /* also when 1 / (pi p) overflows */
}

/* The extra cone a path carries for position cells, in the one word of its
 * state: width (low half) and spread (high half) as bfloat16s, a float's top
 * 16 bits: a float's range, 8 bits of precision, truncated toward zero (the
 * cone comes out at most 2^-7 narrower, a level choice at most that off). */
PMC_FN pmc_u32 pmc_pack_cone(float width, float spread) {
  return ((pmc_u32)as_int(spread) & 0xffff0000u) | ((pmc_u32)as_int(width) >> 16);
}
PMC_FN float pmc_cone_width(pmc_u32 packed) { return as_float((int)(packed << 16)); }
PMC_FN float pmc_cone_spread(pmc_u32 packed) { return as_float((int)(packed & 0xffff0000u)); }

#endif /* PMC_RAYCONE_H */
