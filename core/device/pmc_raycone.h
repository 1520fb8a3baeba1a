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
 * The shade kernel computes the gradients of a batch's hits eight at a time
 * (PMC_RAY_CONE_GRADIENTS: one source for the scalar and the float8 form).
 */
#ifndef PMC_RAYCONE_H
#define PMC_RAYCONE_H

#include "../abi/pmc_vec.h"

/* The gradients' arithmetic, one source for two forms: F is float (the
 * scalar pmc_ray_cone_gradients_at below) or float8 (eight lanes of a batch
 * at once, the shade kernel's pmc_ray_cone_gradients8), I its integer type
 * (a comparison's result), SEL(c, a, b) its select (pmc_vec.h). Straight-line,
 * the dot and cross products written out, so that every lane of the float8
 * form equals the scalar value bit for bit (a batch of 1 and a batch of 64
 * render the same image). In: the unit ray direction d, the unit geometric
 * normal n, the cone radius at the hit, the triangle's edges e1 = p1 - p0 and
 * e2 = p2 - p0 and its uv edges (d1u, d1v) = t1 - t0, (d2u, d2v) = t2 - t0.
 * Out: the gradients g1 = (g1u, g1v), g2 = (g2u, g2v); 0 without a cone, for
 * a triangle without area, and where they would not be finite. */
#define PMC_RAY_CONE_GRADIENTS(NAME, F, I, SEL)                                                            \
  PMC_FN void NAME(F dx, F dy, F dz, F nx, F ny, F nz, F radius, F e1x, F e1y, F e1z, F e2x, F e2y, F e2z, \
                   F d1u, F d1v, F d2u, F d2v, F* g1u, F* g1v, F* g2u, F* g2v) {                           \
    const F zero = (F)(0.0f), one = (F)(1.0f);                                                             \
    const F cos_n = nx * dx + ny * dy + nz * dz;                                                           \
    F a1x = dx - nx * cos_n, a1y = dy - ny * cos_n, a1z = dz - nz * cos_n;                                 \
    const F l1 = sqrt(a1x * a1x + a1y * a1y + a1z * a1z);                                                  \
    /* looking straight down the normal: any tangent axis (pmc_basis's first) */                           \
    const F sign = SEL(nz >= zero, one, -one);                                                             \
    const F ba = -one / (sign + nz);                                                                       \
    const I tilted = l1 > (F)(1e-6f);                                                                      \
    const F inv_l1 = one / l1;                                                                             \
    a1x = SEL(tilted, a1x * inv_l1, one + sign * nx * nx * ba);                                            \
    a1y = SEL(tilted, a1y * inv_l1, sign * (nx * ny * ba));                                                \
    a1z = SEL(tilted, a1z * inv_l1, -sign * nx);                                                           \
    /* a2 = n x a1, unit: a1 is a unit vector orthogonal to n */                                           \
    F a2x = ny * a1z - nz * a1y, a2y = nz * a1x - nx * a1z, a2z = nx * a1y - ny * a1x;                     \
    const F stretch = radius / fmax((F)(1e-4f), fabs(cos_n));                                              \
    a1x = a1x * stretch, a1y = a1y * stretch, a1z = a1z * stretch;                                         \
    a2x = a2x * radius, a2y = a2y * radius, a2z = a2z * radius;                                            \
    const F area =                                                                                         \
        nx * (e1y * e2z - e1z * e2y) + ny * (e1z * e2x - e1x * e2z) + nz * (e1x * e2y - e1y * e2x);        \
    /* Barycentric rates of an in-plane offset a: n.(a x e2) / area and                                    \
     * n.(e1 x a) / area, as dot products with c_u = (e2 x n) / area and                                   \
     * c_v = (n x e1) / area. */                                                                           \
    const F inv = one / area;                                                                              \
    const F cux = (e2y * nz - e2z * ny) * inv, cuy = (e2z * nx - e2x * nz) * inv,                          \
            cuz = (e2x * ny - e2y * nx) * inv;                                                             \
    const F cvx = (ny * e1z - nz * e1y) * inv, cvy = (nz * e1x - nx * e1z) * inv,                          \
            cvz = (nx * e1y - ny * e1x) * inv;                                                             \
    const F du1 = a1x * cux + a1y * cuy + a1z * cuz, dv1 = a1x * cvx + a1y * cvy + a1z * cvz;              \
    const F du2 = a2x * cux + a2y * cuy + a2z * cuz, dv2 = a2x * cvx + a2y * cvy + a2z * cvz;              \
    const F r1u = d1u * du1 + d2u * dv1, r1v = d1v * du1 + d2v * dv1;                                      \
    const F r2u = d1u * du2 + d2u * dv2, r2v = d1v * du2 + d2v * dv2;                                      \
    const I ok = (radius > zero) & isfinite(radius) & (fabs(area) > (F)(1e-30f)) & isfinite(area);         \
    const I ok1 = ok & isfinite(r1u) & isfinite(r1v), ok2 = ok & isfinite(r2u) & isfinite(r2v);            \
    *g1u = SEL(ok1, r1u, zero);                                                                            \
    *g1v = SEL(ok1, r1v, zero);                                                                            \
    *g2u = SEL(ok2, r2u, zero);                                                                            \
    *g2v = SEL(ok2, r2v, zero);                                                                            \
  }
PMC_RAY_CONE_GRADIENTS(pmc_ray_cone_gradients_at, float, int, PMC_SEL_SCALAR)

/* uv gradients along the footprint's axes. `ng` is the unit geometric normal,
 * `dir` the unit ray direction, `radius` the cone radius at the hit. */
PMC_FN void pmc_ray_cone_gradients(float3 dir, float3 ng, float radius, float3 p0, float3 p1, float3 p2,
                                   float2 t0, float2 t1, float2 t2, float2* g1, float2* g2) {
  const float3 e1 = p1 - p0, e2 = p2 - p0;
  const float2 d1 = t1 - t0, d2 = t2 - t0;
  float g1u, g1v, g2u, g2v; /* (OpenCL C takes no address of a vector's component) */
  pmc_ray_cone_gradients_at(dir.x, dir.y, dir.z, ng.x, ng.y, ng.z, radius, e1.x, e1.y, e1.z, e2.x, e2.y, e2.z,
                            d1.x, d1.y, d2.x, d2.y, &g1u, &g1v, &g2u, &g2v);
  *g1 = make_float2(g1u, g1v);
  *g2 = make_float2(g2u, g2v);
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

/* Whether a hit's texture lookups need its footprint's ellipse
 * (anisotropic taps) or may take the round lookup of the ellipse's major
 * width (pmc_shading_footprint). What a later hit's textures add to the image
 * is averaged over the lobe that sampled its ray: from the footprint of width
 * `origin_width` at the ray's origin, a cone of full angle
 * pmc_lobe_spread(lobe_pdf, 1), `origin_width + t * angle` wide at the hit,
 * against the texture cone's `origin_width + t * spread` there. Where the
 * lobe's footprint is at least `ratio` times the texture cone's, the round
 * lookup's extra blur across the ellipse (its major width where the ellipse
 * filter takes the minor, at most `ratio` times apart within the filter's tap
 * limit) lies inside that average: the round lookup then reads one coarser
 * mip level with one bilinear tap (PMC_FOOTPRINT_ONE_LEVEL) instead of up to
 * `ratio` trilinear ones. Camera rays (no lobe: pdf 0) and near-mirror
 * bounces keep the ellipse; a diffuse bounce (about 2 radians) is round at
 * any screen size. */
PMC_FN int pmc_texture_ellipse_needed(float origin_width, float t, float spread, float lobe_pdf,
                                      float ratio) {
  const float lobe = origin_width + t * pmc_lobe_spread(lobe_pdf, 1.0f);
  return !(lobe >= ratio * (origin_width + t * spread)); /* NaN: the ellipse */
}

/* The scale of a texture ellipse's major axis at a pixel's sample `sample`
 * (pmc_shading_footprint): 1/sqrt(sample + 1), 1 for its first sample. It
 * depends on the sample's index alone, so a sample filters alike whatever
 * the frame's spp: sample ranges and farm chunks merge exactly, and a pixel
 * adaptive sampling stopped after n samples is the n-spp render's. */
PMC_FN float pmc_footprint_major_scale(pmc_u32 sample) { return 1.0f / sqrt((float)sample + 1.0f); }

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
