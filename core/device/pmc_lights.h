/* pmc_lights.h — sampling and evaluating every light, shared by the shade
 * kernel and host tests.
 *
 * The light table (PmcLight[], built by core/lights.cpp) holds emissive
 * triangles, the lights of a lights file and the environment. Which light
 * next-event estimation picks depends on the header's sampler:
 *   PMC_LIGHT_SAMPLER_POWER: by power, one pmf for the whole scene;
 *   PMC_LIGHT_SAMPLER_TREE : at shading point p with normal n, first a
 *     strategy: each light at infinity ([0, distant_end): environment, sun
 *     disks, directional deltas) with weight distant_weight x a bound of its
 *     cosine at n (an irradiance estimate), or the light tree with the root's
 *     importance (pmc_tree_importance, an irradiance estimate too: intensity
 *     x cosine bounds / d^2), each in proportion to its weight; then in the
 *     tree, one child per level in proportion to its importance, the one
 *     random number rescaled at each level.
 * pmc_light_pick_pmf(p, n, light) gives the probability that the pick took
 * a light; the tree's part walks the light's trail from the root. A path
 * keeps the normal it picked with (PmcPathState.light_normal) and its ray's origin is p,
 * so when a BSDF ray meets an emitter the weight uses the exact probability
 * with which that vertex would have picked it.
 * The shade kernel uses three entry points:
 *   pmc_light_sample  : at a hit, pick one light and sample a direction toward
 *                       it -> one shadow ray (delta lights: pdf 0, no MIS);
 *   pmc_lights_seen   : for every traced ray, the radiance of quads it passes
 *                       before its hit and, if it escapes, of the environment
 *                       and sun disks, MIS-weighted against light sampling
 *                       from the ray's origin (pmc_env_light_pdf);
 *   pmc_light_pick_pmf: emissive triangles reached by a ray are shaded as
 *                       surfaces (their material emits); with
 *                       pmc_area_light_pdf it gives their light-sampling pdf.
 *
 * Environment map (PMC_ENV_MAP): lat-long, +Y up, u = 0.5 + atan2(x, -z)/2pi,
 * v = acos(y)/pi, v = 0 the top row (the image centre is seen looking along
 * -Z, +X at u = 0.75), turned about +Y by the header's rotation. Texels are
 * constant over their solid angle (nearest lookup, so the sampled density
 * matches exactly). `env` holds, for a w x h map: w*h rgb texels (times
 * the header's env_scale when read), the marginal CDF of the h rows, then
 * h conditional CDFs of w columns (inclusive running sums, last entry 1),
 * of luminance x sin(theta).
 */
#ifndef PMC_LIGHTS_H
#define PMC_LIGHTS_H

#include "../abi/pmc_types.h"
#include "pmc_bsdf.h"

typedef struct PmcLightSet {
  PMC_GLOBAL const PmcLight* lights;
  PMC_GLOBAL const PmcLightTreeNode* tree; /* h.tree_nodes nodes (core/light_tree.h) */
  PMC_GLOBAL const float* env;             /* the map's texels and CDFs (PMC_ENV_MAP only) */
  PmcLightHeader h;
} PmcLightSet;

/* One light sample as seen from a shading point. */
typedef struct PmcLightSample {
  float3 wi;     /* unit direction toward the light */
  float dist;    /* distance to the sampled point (INFINITY at infinity) */
  float3 weight; /* arriving radiance (point/spot: I/d^2, directional: E) / pdf */
  float pdf;     /* solid-angle pdf, pick probability included; 0: a delta light (no MIS) */
} PmcLightSample;

/* --- the lat-long map -------------------------------------------------- */

PMC_FN float2 pmc_env_dir_to_uv(float3 d) {
  float u = 0.5f + pmc_atan2(d.x, -d.z) * (0.5f * PMC_INV_PI);
  float v = pmc_acos(d.y) * PMC_INV_PI;
  return make_float2(u, v);
}

PMC_FN float3 pmc_env_uv_to_dir(float u, float v) {
  /* phi = 2 pi (u - 0.5) and theta = pi v, as turns (pmc_sincos_turns) */
  float st, ct, sp, cp;
  pmc_sincos_turns(0.5f * v, &st, &ct);
  pmc_sincos_turns(u - 0.5f, &sp, &cp);
  return make_float3(st * sp, ct, -st * cp);
}

/* World direction -> map direction (the inverse of the rotation about +Y). */
PMC_FN float3 pmc_env_to_map(const PmcLightHeader* h, float3 d) {
  float c = h->env_rot_cos, s = h->env_rot_sin;
  return make_float3(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
}

PMC_FN float3 pmc_env_to_world(const PmcLightHeader* h, float3 m) {
  float c = h->env_rot_cos, s = h->env_rot_sin;
  return make_float3(c * m.x + s * m.z, m.y, -s * m.x + c * m.z);
}

/* Index of the texel holding map direction m, and its row. */
PMC_FN int pmc_env_texel_at(const PmcLightHeader* h, float3 m, int* row_out) {
  float2 uv = pmc_env_dir_to_uv(m);
  int col = (int)(uv.x * (float)h->env_width);
  int row = (int)(uv.y * (float)h->env_height);
  col = col < 0 ? 0 : (col >= h->env_width ? h->env_width - 1 : col);
  row = row < 0 ? 0 : (row >= h->env_height ? h->env_height - 1 : row);
  *row_out = row;
  return row * h->env_width + col;
}

PMC_FN int pmc_env_texel_index(const PmcLightHeader* h, float3 m) {
  int row;
  return pmc_env_texel_at(h, m, &row);
}

PMC_FN float3 pmc_env_texel(const PmcLightSet* ls, int i) {
  return ls->h.env_scale * make_float3(ls->env[3 * i], ls->env[3 * i + 1], ls->env[3 * i + 2]);
}

/* The map's data after its texels (EnvMap::data, core/env_map.h): the
 * marginal CDF over the rows (height floats), each row's conditional CDF
 * (width floats a row), each row's sine, then the CDFs' guide tables
 * (cdf_guide: the marginal's, height + 1 floats, then each row's, width + 1
 * floats a row). */
PMC_FN PMC_GLOBAL const float* pmc_env_marginal(const PmcLightSet* ls) {
  return ls->env + 3 * ls->h.env_width * ls->h.env_height;
}
PMC_FN PMC_GLOBAL const float* pmc_env_row_cdf(const PmcLightSet* ls, int row) {
  return pmc_env_marginal(ls) + ls->h.env_height + row * ls->h.env_width;
}
PMC_FN PMC_GLOBAL const float* pmc_env_row_sines(const PmcLightSet* ls) {
  return pmc_env_marginal(ls) + ls->h.env_height + ls->h.env_width * ls->h.env_height;
}
PMC_FN PMC_GLOBAL const float* pmc_env_marginal_guide(const PmcLightSet* ls) {
  return pmc_env_row_sines(ls) + ls->h.env_height;
}
PMC_FN PMC_GLOBAL const float* pmc_env_row_guide(const PmcLightSet* ls, int row) {
  return pmc_env_marginal_guide(ls) + ls->h.env_height + 1 + row * (ls->h.env_width + 1);
}

/* Solid-angle density of the map's importance sampling at map direction m
 * in texel i of row `row` (pmc_env_texel_at(m), passed in where the caller
 * has it), without the pick probability: p(texel) w h / (2 pi^2 sin(theta)),
 * with p(texel) the texel's sampling weight, luminance x the sine of its
 * row's centre (the table after the CDFs, core/env_map.h: the sines the
 * host weighed the rows with), over their sum. */
PMC_FN float pmc_env_map_pdf_in(const PmcLightSet* ls, float3 m, int i, int row) {
  const PmcLightHeader* h = &ls->h;
  if (h->env_uniform) return 0.25f * PMC_INV_PI;
  float sin_theta = sqrt(fmax(0.0f, 1.0f - m.y * m.y));
  if (!(sin_theta > 0.0f)) return 0.0f;
  float f = pmc_luminance(pmc_env_texel(ls, i)) * pmc_env_row_sines(ls)[row];
  float texels = (float)h->env_width * (float)h->env_height;
  return f * h->env_inv_integral * texels / (2.0f * PMC_PI * PMC_PI * sin_theta);
}

PMC_FN float pmc_env_map_pdf(const PmcLightSet* ls, float3 m) {
  if (ls->h.env_uniform) return 0.25f * PMC_INV_PI;
  int row;
  const int i = pmc_env_texel_at(&ls->h, m, &row);
  return pmc_env_map_pdf_in(ls, m, i, row);
}

/* First index in cdf[0, n) whose value exceeds u (the last one if none). */
PMC_FN int pmc_cdf_search(PMC_GLOBAL const float* cdf, int n, float u) {
  int lo = 0, hi = n - 1;
  while (lo < hi) {
    int mid = (lo + hi) >> 1;
    if (cdf[mid] > u)
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo;
}

/* pmc_cdf_search started from the CDF's guide table (cdf_guide in
 * core/env_map.h: guide[k] the first index whose value exceeds k / n): the
 * answer for u in [k / n, (k + 1) / n) lies in [guide[k], guide[k + 1]],
 * which the search checks (the entry below the range at most u, the range's
 * last above it) so that rounding in u n or in the table can cost time but
 * never change the answer; outside them, or for u outside [0, 1), it
 * searches the whole CDF. The same index as pmc_cdf_search, after about two
 * dependent reads of a bucket instead of log2(n): the two searches of a map
 * sample were 4% of the default room's samples under a 256x128 sky. */
PMC_FN int pmc_cdf_search_guided(PMC_GLOBAL const float* cdf, PMC_GLOBAL const float* guide, int n, float u) {
  if (!(u >= 0.0f && u < 1.0f)) return pmc_cdf_search(cdf, n, u);
  int k = (int)(u * (float)n);
  k = k < n ? k : n - 1;
  const int lo = (int)guide[k], hi = (int)guide[k + 1];
  if ((lo > 0 && !(cdf[lo - 1] <= u)) || !(cdf[hi] > u)) return pmc_cdf_search(cdf, n, u);
  return lo + pmc_cdf_search(cdf + lo, hi - lo + 1, u);
}

/* Where u falls inside bin i of an inclusive CDF, in [0, 1). */
PMC_FN float pmc_cdf_fraction(PMC_GLOBAL const float* cdf, int i, float u) {
  float lo = i > 0 ? cdf[i - 1] : 0.0f;
  float width = cdf[i] - lo;
  float f = width > 0.0f ? (u - lo) / width : 0.5f;
  return clamp(f, 0.0f, 0.99999994f);
}

/* Sample a map direction (world space) by luminance x sin(theta); returns
 * its density (without the pick probability), 0 on failure. The texel is the
 * one the CDFs picked (its radiance and density are the sample's; finding it
 * again from the direction took an atan2 and an acos, and near a texel's edge
 * could name its neighbour). */
PMC_FN float pmc_env_map_sample(const PmcLightSet* ls, float u1, float u2, float3* wi, float3* le) {
  const PmcLightHeader* h = &ls->h;
  int w = h->env_width, hh = h->env_height;
  float3 m;
  int texel, row = 0;
  if (h->env_uniform) {
    float z = 1.0f - 2.0f * u1, r = sqrt(fmax(0.0f, 1.0f - z * z)), sin_phi, cos_phi;
    pmc_sincos_turns(u2, &sin_phi, &cos_phi);
    m = make_float3(r * cos_phi, z, r * sin_phi);
    texel = pmc_env_texel_index(h, m);
  } else {
    PMC_GLOBAL const float* marginal = pmc_env_marginal(ls);
    row = pmc_cdf_search_guided(marginal, pmc_env_marginal_guide(ls), hh, u1);
    float fv = pmc_cdf_fraction(marginal, row, u1);
    PMC_GLOBAL const float* conditional = pmc_env_row_cdf(ls, row);
    int col = pmc_cdf_search_guided(conditional, pmc_env_row_guide(ls, row), w, u2);
    float fu = pmc_cdf_fraction(conditional, col, u2);
    m = pmc_env_uv_to_dir(((float)col + fu) / (float)w, ((float)row + fv) / (float)hh);
    texel = row * w + col;
  }
  float pdf = pmc_env_map_pdf_in(ls, m, texel, row);
  *wi = pmc_env_to_world(h, m);
  *le = pmc_env_texel(ls, texel);
  return pdf;
}

/* --- one light ----------------------------------------------------------- */

/* Spot falloff at angle `angle` from the axis: 1 inside the inner angle, 0
 * beyond the outer one, smoothstep in the angle between. */
PMC_FN float pmc_spot_falloff(PMC_GLOBAL const PmcLight* l, float cos_angle) {
  if (cos_angle <= l->cos_outer) return 0.0f;
  float angle = acos(clamp(cos_angle, -1.0f, 1.0f));
  if (angle <= l->spot_inner) return 1.0f;
  float s = clamp((l->spot_outer - angle) / (l->spot_outer - l->spot_inner), 0.0f, 1.0f);
  return s * s * (3.0f - 2.0f * s);
}

/* Light-sampling pdf (solid angle) of a point on an area light seen at
 * distance `t` under cosine `cos_light` from its normal. */
PMC_FN float pmc_area_light_pdf(float pmf, float t, float area, float cos_light) {
  float c = fabs(cos_light);
  return c > 0.0f && area > 0.0f ? pmf * t * t / (area * c) : 0.0f;
}

/* --- rectangles by solid angle ------------------------------------------ */

/* A rectangular quad seen from a point (Urena, Fajardo and King 2013, "An
 * Area-Preserving Parametrization for Spherical Rectangles"): the local frame
 * x, y along the edges and z toward the side the point is on (so z0 <= 0),
 * the rectangle's extent [x0, x1] x [y0, y1] at height z0 in it, and the
 * spherical rectangle's solid angle `solid_angle` with what sampling needs
 * (b0, b1, k). Sampling it is uniform in solid angle: next to the light,
 * where the 1/d^2 and cosine of area sampling vary across the quad, it has
 * far less variance (the Cornell box's walls and ceiling). */
typedef struct PmcSphRect {
  float3 x, y, z;
  float x0, x1, y0, y1, z0;
  float b0, b1, k, solid_angle;
} PmcSphRect;

/* Below this solid angle (sr) a quad is sampled by area: the sum of four
 * angles minus 2 pi loses its float precision there, and the variance that
 * solid-angle sampling saves is small. The decision depends only on the
 * point and the light, so the sampler and the MIS weight agree. */
#define PMC_SPH_RECT_MIN_SOLID_ANGLE 1e-3f

/* The set-up's arithmetic, one source for two forms (as PMC_TREE_IMPORTANCE):
 * F is float (pmc_sph_rect_init below) or float8 (eight lanes of a batch at
 * once in the shade kernel), I its comparison type, SEL(c, a, b) its select,
 * ACOS4(a, b, c, d, ga, gb, gc, gd) the four angles' arc cosines: one float4
 * call in the scalar form, four float8 calls in the vector one (PoCL's
 * float4 and float8 acos agree bit for bit; its scalar acos does not).
 * Straight-line, the products written out, so that both forms give the same
 * bits: a light sample's solid angle and its MIS recomputation
 * (pmc_quad_light_pdf) must agree exactly. In: the quad's edges eu, ev and
 * d = corner - p. Declares the frame's axes (xx, xy, xz), (yx, yy, yz),
 * (zx, zy, zz), the extents z0, x0, x1, y0, y1, the sampling terms b0, b1,
 * k and the solid angle omega (0 where p is in the quad's plane). */
#define PMC_SPH_RECT_SETUP(F, I, SEL, ACOS4, eux, euy, euz, evx, evy, evz, dx, dy, dz)                     \
  const F one_ = (F)(1.0f), zero_ = (F)(0.0f);                                                             \
  const F lu = sqrt(eux * eux + euy * euy + euz * euz), lv = sqrt(evx * evx + evy * evy + evz * evz);      \
  const F iu = one_ / lu, iv = one_ / lv;                                                                  \
  const F xx = eux * iu, xy = euy * iu, xz = euz * iu, yx = evx * iv, yy = evy * iv, yz = evz * iv;        \
  /* z = x cross y, turned toward p's side (z0 <= 0) */                                                    \
  const F cx_ = xy * yz - xz * yy, cy_ = xz * yx - xx * yz, cz_ = xx * yy - xy * yx;                       \
  const F c0_ = dx * cx_ + dy * cy_ + dz * cz_;                                                            \
  const I flip_ = c0_ > zero_;                                                                             \
  const F zx = SEL(flip_, -cx_, cx_), zy = SEL(flip_, -cy_, cy_), zz = SEL(flip_, -cz_, cz_);              \
  const F z0 = SEL(flip_, -c0_, c0_);                                                                      \
  const F x0 = dx * xx + dy * xy + dz * xz, y0 = dx * yx + dy * yy + dz * yz;                              \
  const F x1 = x0 + lu, y1 = y0 + lv, z2_ = z0 * z0;                                                       \
  /* the inward normals of the great circles through the edges, n0 = (0, z0, -y0) i0, n1 = (-z0, 0,        \
   * x1) i1, n2 = (0, -z0, y1) i2, n3 = (z0, 0, -x0) i3, and the angles between them: acos(-n0.n1) ...  */ \
  const F i0_ = one_ / sqrt(z2_ + y0 * y0), i1_ = one_ / sqrt(z2_ + x1 * x1);                              \
  const F i2_ = one_ / sqrt(z2_ + y1 * y1), i3_ = one_ / sqrt(z2_ + x0 * x0);                              \
  F g0_, g1_, g2_, g3_;                                                                                    \
  ACOS4(clamp((y0 * i0_) * (x1 * i1_), -1.0f, 1.0f), clamp(-((x1 * i1_) * (y1 * i2_)), -1.0f, 1.0f),       \
        clamp((y1 * i2_) * (x0 * i3_), -1.0f, 1.0f), clamp(-((x0 * i3_) * (y0 * i0_)), -1.0f, 1.0f), g0_,  \
        g1_, g2_, g3_);                                                                                    \
  const F b0 = -y0 * i0_, b1 = y1 * i2_;                                                                   \
  const F k = (F)(2.0f * PMC_PI) - g2_ - g3_;                                                              \
  const F omega = SEL(z0 < zero_, fmax(zero_, g0_ + g1_ - k), zero_);
#define PMC_ACOS4_SCALAR(a, b, c, d, ga, gb, gc, gd)  \
  do {                                                \
    const float4 g4_ = acos(make_float4(a, b, c, d)); \
    ga = g4_.x, gb = g4_.y, gc = g4_.z, gd = g4_.w;   \
  } while (0)

/* The spherical rectangle of rectangular quad l seen from p; returns its
 * solid angle (0 when l is not a rectangle or p is in its plane). */
PMC_FN float pmc_sph_rect_init(PMC_GLOBAL const PmcLight* l, float3 p, PmcSphRect* r) {
  r->solid_angle = 0.0f;
  if (!(l->flags & PMC_LIGHT_RECTANGLE)) return 0.0f;
  const float3 eu = pmc_load3(l->axis), ev = pmc_load3(l->edge_v), d = pmc_load3(l->pos) - p;
  PMC_SPH_RECT_SETUP(float, int, PMC_SEL_SCALAR, PMC_ACOS4_SCALAR, eu.x, eu.y, eu.z, ev.x, ev.y, ev.z, d.x,
                     d.y, d.z)
  r->x = make_float3(xx, xy, xz);
  r->y = make_float3(yx, yy, yz);
  r->z = make_float3(zx, zy, zz);
  r->z0 = z0, r->x0 = x0, r->x1 = x1, r->y0 = y0, r->y1 = y1;
  r->b0 = b0, r->b1 = b1, r->k = k, r->solid_angle = omega;
  return omega;
}

/* The point in direction (u, v) of the unit square, mapped uniformly over
 * a spherical rectangle (its fields as PmcSphRect's, solid angle omega), as
 * its coordinates xu, yv along the rectangle's edges. Scalars in,
 * straight-line (selects, no branches); the shade kernel runs it for a
 * batch's lanes together, eight at a time in its float8 twin
 * (pmc_sph_rect_sample_xy8 in gpu/kernels/samplers8.cl: keep the two alike). */
PMC_FN float2 pmc_sph_rect_sample_xy(float omega, float k, float b0, float b1, float z0, float x0, float x1,
                                     float y0, float y1, float u, float v) {
  float au = u * omega + k;
  float sin_au, cos_au; /* au is in [0, 4 pi) */
  pmc_sincos_turns(au * (0.5f * PMC_INV_PI), &sin_au, &cos_au);
  float fu = (cos_au * b0 - b1) / sin_au;
  float cu = (fu >= 0.0f ? 1.0f : -1.0f) / sqrt(fu * fu + b0 * b0);
  cu = clamp(cu, -1.0f, 1.0f);
  float xu = -(cu * z0) / sqrt(fmax(1e-30f, 1.0f - cu * cu));
  xu = clamp(xu, x0, x1);
  float dd = sqrt(xu * xu + z0 * z0);
  float h0 = y0 / sqrt(dd * dd + y0 * y0);
  float h1 = y1 / sqrt(dd * dd + y1 * y1);
  float hv = h0 + v * (h1 - h0), hv2 = hv * hv;
  float yv = hv2 < 1.0f - 1e-6f ? hv * dd / sqrt(1.0f - hv2) : y1;
  return make_float2(xu, clamp(yv, y0, y1));
}

/* The rectangle's point at coordinates xy (pmc_sph_rect_sample_xy) seen from p. */
PMC_FN float3 pmc_sph_rect_point(const PmcSphRect* r, float3 p, float2 xy) {
  return p + r->x * xy.x + r->y * xy.y + r->z * r->z0;
}

/* A rectangle sample's end, one source for two forms as PMC_SPH_RECT_SETUP:
 * the point at coordinates (xu, yv) of the spherical rectangle's frame (x,
 * y, z, z0: the set-up's) lies at d = x xu + y yv + z z0 from the shading
 * point (taken directly, not as q - p, which cancels far from the origin);
 * declares the distance dist to it, the unit direction (wx, wy, wz) toward
 * it and the cosine cos_light at the light of normal (nx, ny, nz).
 * Straight-line, the products written out: pmc_light_sample_rect_end and
 * the shade kernel's eight-lane form (pmc_rect_lights_lanes) agree bit for
 * bit. */
#define PMC_RECT_SAMPLE_END(F, xx, xy, xz, yx, yy, yz, zx, zy, zz, z0, xu, yv, nx, ny, nz) \
  const F dx_ = xx * xu + yx * yv + zx * z0;                                               \
  const F dy_ = xy * xu + yy * yv + zy * z0;                                               \
  const F dz_ = xz * xu + yz * yv + zz * z0;                                               \
  const F dist = sqrt(dx_ * dx_ + dy_ * dy_ + dz_ * dz_);                                  \
  const F inv_dist_ = (F)(1.0f) / dist;                                                    \
  const F wx = dx_ * inv_dist_, wy = dy_ * inv_dist_, wz = dz_ * inv_dist_;                \
  const F cos_light = -(nx * wx + ny * wy + nz * wz);

/* The point of the rectangle in direction (u, v) of the unit square, mapped
 * uniformly over the spherical rectangle r seen from p. */
PMC_FN float3 pmc_sph_rect_sample(const PmcSphRect* r, float3 p, float u, float v) {
  return pmc_sph_rect_point(
      r, p,
      pmc_sph_rect_sample_xy(r->solid_angle, r->k, r->b0, r->b1, r->z0, r->x0, r->x1, r->y0, r->y1, u, v));
}

/* Light-sampling pdf (solid angle, pick probability pmf included) of quad l
 * seen from p at distance t under cosine cos_light from its normal: 1 over
 * the spherical rectangle's solid angle where pmc_light_sample samples it
 * so, else the area pdf. */
PMC_FN float pmc_quad_light_pdf(PMC_GLOBAL const PmcLight* l, float3 p, float pmf, float t, float cos_light) {
  PmcSphRect r;
  float omega = pmc_sph_rect_init(l, p, &r);
  if (omega >= PMC_SPH_RECT_MIN_SOLID_ANGLE) return pmf / omega;
  return pmc_area_light_pdf(pmf, t, l->area, cos_light);
}

/* Solid-angle pdf of a sun disk's cone sampling, times the pick probability pmf. */
PMC_FN float pmc_sun_pdf(PMC_GLOBAL const PmcLight* l, float pmf) {
  return pmf / (2.0f * PMC_PI * l->one_minus_cos);
}

/* Is unit direction d inside the sun disk (around -axis)? Compares sines,
 * which keep their precision for tiny disks where cosines round to 1. */
PMC_FN int pmc_sun_contains(PMC_GLOBAL const PmcLight* l, float3 d) {
  float3 s = -pmc_load3(l->axis);
  if (dot(s, d) <= 0.0f) return 0;
  float3 c = cross(s, d);
  float sin2 = dot(c, c);
  /* sin^2 of the half angle from 1 - cos: (1-c)(1+c) = omc (2 - omc) */
  return sin2 <= l->one_minus_cos * (2.0f - l->one_minus_cos);
}

/* --- the pick ------------------------------------------------------------ */

/* cos(a - b) of angles a, b in [0, pi], 1 when a < b. */
PMC_FN float pmc_cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
  return cos_a > cos_b ? 1.0f : cos_a * cos_b + sin_a * sin_b;
}

/* Slack on the receiver's cosine bounds (2e-3, about 0.1 degrees), so that a
 * light at the horizon of the shading normal keeps a small probability
 * instead of 0 under the bounds' float rounding. It was sized for the 32-bit
 * octahedral normal that path states once stored (error below 1e-3
 * radians); they now store the normal whole, and the slack stays. */
#define PMC_PICK_NORMAL_SLACK 2e-3f

/* The importance's arithmetic, one source for two forms: F is float (the
 * scalar pmc_tree_importance below) or float8 (eight lanes of a batch at
 * once, the shade kernel's pmc_tree_importance8), I its integer type (a
 * comparison's result), SEL(c, a, b) its select. Straight-line: each bound
 * that rules the node out selects 0 at the end instead of returning early,
 * and both forms run the same operations in the same order, so every lane
 * of the float8 form equals the scalar value bit for bit: a pick and its
 * recomputation for MIS (pmc_light_pick_pmf) must agree exactly. Dot
 * products are written out for the same reason. two_sided: a comparison's
 * result, true where PMC_TREE_TWO_SIDED is set. */
#define PMC_TREE_IMPORTANCE(NAME, F, I, SEL)                                                                \
  PMC_FN F NAME(F lox, F loy, F loz, F hix, F hiy, F hiz, F ax, F ay, F az, F energy, F cos_o, F cos_e_max, \
                I two_sided, F px, F py, F pz, F nx, F ny, F nz) {                                          \
    const F zero = (F)(0.0f), one = (F)(1.0f), one_half = (F)(0.5f);                                        \
    const F tx = px - (lox + hix) * one_half, ty = py - (loy + hiy) * one_half,                             \
            tz = pz - (loz + hiz) * one_half;                                                               \
    const F dx = hix - lox, dy = hiy - loy, dz = hiz - loz;                                                 \
    const F r2 = (F)(0.25f) * (dx * dx + dy * dy + dz * dz);                                                \
    const F d2 = tx * tx + ty * ty + tz * tz;                                                               \
    /* theta_b: pi when p is inside the bounding sphere */                                                  \
    const I far = d2 > r2;                                                                                  \
    const F sin2_b = r2 / d2;                                                                               \
    const F sin_b = SEL(far, sqrt(sin2_b), zero);                                                           \
    const F cos_b = SEL(far, sqrt(fmax(zero, one - sin2_b)), -one);                                         \
    /* the box's highest point above the plane through p, less the normal's slack */                        \
    const F ex = dx * one_half, ey = dy * one_half, ez = dz * one_half;                                     \
    const F above = -(nx * tx + ny * ty + nz * tz) + fabs(nx) * ex + fabs(ny) * ey + fabs(nz) * ez;         \
    const F dist = sqrt(d2), radius = sqrt(r2);                                                             \
    I dead = above + (F)(PMC_PICK_NORMAL_SLACK) * (dist + radius) <= zero;                                  \
    /* max over the box of axis . (p - e), plus |n_e - axis| <= sqrt(2 (1 - cos theta_o)) times |p - e|,    \
     * bounds n_e . (p - e) from above for every emitter point e and normal n_e */                          \
    const F ahead = (ax * tx + ay * ty + az * tz) + fabs(ax) * ex + fabs(ay) * ey + fabs(az) * ez;          \
    const F spread = sqrt(fmax(zero, (F)(2.0f) * (one - cos_o))) + (F)(1e-5f); /* + the float axis */       \
    dead = dead | ((two_sided == 0) & (cos_e_max >= zero) & (ahead + spread * (dist + radius) <= zero));    \
    const I beside = d2 > zero;                                                                             \
    const F inv = one / dist;                                                                               \
    const F wx = SEL(beside, tx * inv, zero), wy = SEL(beside, ty * inv, zero),                             \
            wz = SEL(beside, tz * inv, one);                                                                \
    F cos_w = ax * wx + ay * wy + az * wz;                                                                  \
    cos_w = SEL(two_sided, fabs(cos_w), cos_w);                                                             \
    const F sin_w = sqrt(fmax(zero, one - cos_w * cos_w));                                                  \
    const F sin_o = sqrt(fmax(zero, one - cos_o * cos_o));                                                  \
    /* cos and sin of theta_w - theta_o, clamped as pmc_cos_sub_clamped */                                  \
    const I within = cos_w > cos_o;                                                                         \
    const F cos_x = SEL(within, one, cos_w * cos_o + sin_w * sin_o);                                        \
    const F sin_x = SEL(within, zero, sin_w * cos_o - cos_w * sin_o);                                       \
    const F cos_e = SEL(cos_x > cos_b, one, cos_x * cos_b + sin_x * sin_b);                                 \
    dead = dead | (cos_e <= cos_e_max);                                                                     \
    const F cos_i = -(nx * wx + ny * wy + nz * wz);                                                         \
    const F sin_i = sqrt(fmax(zero, one - cos_i * cos_i));                                                  \
    const F cos_r = SEL(cos_i > cos_b, one, cos_i * cos_b + sin_i * sin_b) + (F)(PMC_PICK_NORMAL_SLACK);    \
    dead = dead | !(cos_r > zero);                                                                          \
    const F importance = energy * cos_e * fmin(cos_r, one) / fmax(fmax(d2, r2), (F)(1e-30f));               \
    return SEL(dead, zero, fmin(importance, (F)(1e30f))); /* a point light at p: large, but finite */       \
  }
PMC_TREE_IMPORTANCE(pmc_tree_importance_at, float, int, PMC_SEL_SCALAR)

/* Importance of a tree node for the point p with normal n (Conty Estevez &
 * Kulla 2018, as pbrt-v4's LightBounds::Importance): intensity bound x the
 * cosine at the emitters (the angle to p less the cone's spread theta_o and
 * the box's angular radius theta_b; 0 beyond theta_e) x the cosine at the
 * receiver (less theta_b) / squared distance to the box's centre (at least
 * its bounding sphere's radius squared). One-sided at the receiver: light
 * sampling only takes directions above n, so a box wholly below the plane
 * through p (tested corner by corner, tighter than theta_b) gets 0. One-sided
 * at the emitters, likewise: where every emitter's normal is within theta_o
 * of the axis and none emits past 90 degrees from its normal (theta_e <=
 * pi/2), a p behind every point of the box (p - e below the plane of every
 * such normal through e) gets 0. theta_b alone cannot say so when p is near
 * the box: a ceiling point just above a downward quad light was given most
 * of the picks against a point light in the room, and its light samples
 * all carried nothing. The arithmetic: PMC_TREE_IMPORTANCE. */
PMC_FN float pmc_tree_importance(PMC_GLOBAL const PmcLightTreeNode* node, float3 p, float3 n) {
  return pmc_tree_importance_at(node->lo[0], node->lo[1], node->lo[2], node->hi[0], node->hi[1], node->hi[2],
                                node->axis[0], node->axis[1], node->axis[2], node->energy, node->cos_theta_o,
                                node->cos_theta_e, (node->flags & PMC_TREE_TWO_SIDED) != 0u, p.x, p.y, p.z,
                                n.x, n.y, n.z);
}

/* The probability of taking node a's first child (a interior), by the
 * children's importance. Where neither can light p (the node's looser
 * bounds said it might), by their energy: the pick then lands on a light
 * that gives nothing, as it would have failed, but every probability stays
 * defined and they sum to one. */
PMC_FN float pmc_first_share_of(float i0, float i1, float energy0, float energy1) {
  if (!(i0 + i1 > 0.0f)) i0 = energy0, i1 = energy1;
  float sum = i0 + i1;
  return sum > 0.0f ? i0 / sum : 0.5f;
}
PMC_FN float pmc_tree_first_share(const PmcLightSet* ls, int a, float3 p, float3 n) {
  PMC_GLOBAL const PmcLightTreeNode* c0 = &ls->tree[a + 1];
  PMC_GLOBAL const PmcLightTreeNode* c1 = &ls->tree[ls->tree[a].second];
  return pmc_first_share_of(pmc_tree_importance(c0, p, n), pmc_tree_importance(c1, p, n), c0->energy,
                            c1->energy);
}

/* Weight of a light at infinity at normal (nx, ny, nz): its irradiance at
 * normal incidence (`weight`) x a bound of the cosine (a sun disk's widened
 * by its radius, 1 - cos of which is `one_minus_cos`), from the light's
 * fields alone, so that the pick's loop over a batch's lanes
 * (pmc_pick_distant_lanes) computes the same bits as a single pick. */
PMC_FN_INLINE float pmc_distant_weight_at(pmc_u32 type, float weight, float one_minus_cos, float ax, float ay,
                                          float az, float nx, float ny, float nz) {
  if (type == PMC_LIGHT_ENV) return weight;
  float cos_i = -(nx * ax + ny * ay + nz * az);
  if (type == PMC_LIGHT_SUN) {
    float sin_i = sqrt(fmax(0.0f, 1.0f - cos_i * cos_i));
    float cos_h = 1.0f - one_minus_cos, sin_h = sqrt(fmax(0.0f, one_minus_cos * (2.0f - one_minus_cos)));
    cos_i = pmc_cos_sub_clamped(sin_i, cos_i, sin_h, cos_h);
  }
  cos_i += PMC_PICK_NORMAL_SLACK;
  return cos_i > 0.0f ? weight * fmin(cos_i, 1.0f) : 0.0f;
}

/* Weight of light at infinity l at normal n (pmc_distant_weight_at). */
PMC_FN float pmc_distant_weight(PMC_GLOBAL const PmcLight* l, float3 n) {
  return pmc_distant_weight_at(l->type, l->distant_weight, l->one_minus_cos, l->axis[0], l->axis[1],
                               l->axis[2], n.x, n.y, n.z);
}

/* The tree's weight at (p, n): the root's importance (0 without a tree). */
PMC_FN float pmc_tree_weight(const PmcLightSet* ls, float3 p, float3 n) {
  return ls->h.tree_nodes > 0 ? pmc_tree_importance(&ls->tree[0], p, n) : 0.0f;
}

/* The weights of the first PMC_DISTANT_KEPT lights at infinity, which the
 * pick keeps between its total and its choice, so that a sun's cosine bound
 * is computed once. */
#define PMC_DISTANT_KEPT 4

/* Sum of the strategies' weights at normal n, added in table order then the
 * tree's; the first PMC_DISTANT_KEPT weights into kept[] unless it is null.
 * The pick and its recomputation (pmc_light_pick_pmf) both add them here, so
 * their totals agree bit for bit. */
PMC_FN float pmc_strategy_sum(const PmcLightSet* ls, float3 n, float tree_weight, float* kept) {
  float total = 0.0f;
  for (int i = 0; i < ls->h.distant_end; ++i) {
    const float w = pmc_distant_weight(&ls->lights[i], n);
    if (kept && i < PMC_DISTANT_KEPT) kept[i] = w;
    total += w;
  }
  return total + tree_weight;
}

/* Keeps a rescaled random number below 1. */
PMC_FN float pmc_below_one(float u) { return fmin(fmax(u, 0.0f), 0x1.fffffep-1f); }

/* The pick among the lights at infinity and the tree (tree_weight, its
 * root's importance): a light at infinity's index (-1: none) with its
 * probability in *pmf, or PMC_PICK_TREE with the tree's share in *share and
 * the random number rescaled to the tree's part in *u. */
#define PMC_PICK_TREE (-2)
PMC_FN int pmc_pick_distant(const PmcLightSet* ls, float3 n, float tree_weight, float* u, float* share,
                            float* pmf) {
  float kept[PMC_DISTANT_KEPT];
  const float total = pmc_strategy_sum(ls, n, tree_weight, kept);
  if (!(total > 0.0f)) return -1;
  float x = *u * total, below = 0.0f;
  for (int i = 0; i < ls->h.distant_end; ++i) {
    const float w = i < PMC_DISTANT_KEPT ? kept[i] : pmc_distant_weight(&ls->lights[i], n);
    if (x < below + w) {
      *pmf = w / total;
      return i;
    }
    below += w;
  }
  if (!(tree_weight > 0.0f)) return -1; /* rounding ran past the last light at infinity */
  *share = tree_weight / total;
  *u = pmc_below_one((x - below) / tree_weight);
  return PMC_PICK_TREE;
}

/* One level of the tree walk from interior node a whose first child takes
 * the share `first`: the child u falls in, with u rescaled to it and its
 * share multiplied into *share. */
PMC_FN int pmc_tree_descend(const PmcLightSet* ls, int a, float first, float* u, float* share) {
  if (*u < first) {
    *share *= first;
    *u = pmc_below_one(*u / first);
    return a + 1;
  }
  *share *= 1.0f - first;
  *u = pmc_below_one((*u - first) / (1.0f - first));
  return (int)ls->tree[a].second;
}

/* Pick a light for the point p with normal n from one random number u;
 * returns its index (-1: none) and the probability in *pmf. */
PMC_FN int pmc_light_pick(const PmcLightSet* ls, float3 p, float3 n, float u, float* pmf) {
  *pmf = 0.0f;
  int count = ls->h.count;
  if (count <= 0) return -1;
  if (ls->h.sampler == PMC_LIGHT_SAMPLER_POWER) {
    /* Binary search on the running sums (stored in each light). */
    int lo = 0, hi = count - 1;
    while (lo < hi) {
      int mid = (lo + hi) >> 1;
      if (ls->lights[mid].cdf > u)
        hi = mid;
      else
        lo = mid + 1;
    }
    *pmf = ls->lights[lo].pmf;
    return lo;
  }
  float share = 1.0f; /* without lights at infinity the tree is the only strategy */
  if (ls->h.distant_end > 0) {
    const int picked = pmc_pick_distant(ls, n, pmc_tree_weight(ls, p, n), &u, &share, pmf);
    if (picked != PMC_PICK_TREE) return picked;
  }
  int a = 0;
  while (!(ls->tree[a].flags & PMC_TREE_LEAF))
    a = pmc_tree_descend(ls, a, pmc_tree_first_share(ls, a, p, n), &u, &share);
  *pmf = share;
  return (int)ls->tree[a].second;
}

/* The probability that pmc_light_pick(p, n) returns light k. */
PMC_FN float pmc_light_pick_pmf(const PmcLightSet* ls, float3 p, float3 n, int k) {
  if (k < 0) return 0.0f;
  if (ls->h.sampler == PMC_LIGHT_SAMPLER_POWER) return ls->lights[k].pmf;
  float share = 1.0f; /* as pmc_light_pick: the tree alone without lights at infinity */
  if (ls->h.distant_end > 0) {
    float tree_weight = pmc_tree_weight(ls, p, n);
    float total = pmc_strategy_sum(ls, n, tree_weight, 0);
    if (!(total > 0.0f)) return 0.0f;
    if (k < ls->h.distant_end) return pmc_distant_weight(&ls->lights[k], n) / total;
    if (!(tree_weight > 0.0f)) return 0.0f;
    share = tree_weight / total;
  }
  pmc_u32 trail_lo = ls->lights[k].tree_trail[0], trail_hi = ls->lights[k].tree_trail[1];
  int a = 0;
  for (int depth = 0; !(ls->tree[a].flags & PMC_TREE_LEAF); ++depth) {
    float first = pmc_tree_first_share(ls, a, p, n);
    int second = (int)(depth < 32 ? (trail_lo >> depth) & 1u : (trail_hi >> (depth - 32)) & 1u);
    if (second) {
      share *= 1.0f - first;
      a = (int)ls->tree[a].second;
    } else {
      share *= first;
      a = a + 1;
    }
  }
  return share;
}

/* The pdf with which the environment light samples direction d from point
 * p with (pick) normal n (pick probability included; 0 without environment). */
PMC_FN float pmc_env_light_pdf(const PmcLightSet* ls, float3 p, float3 n, float3 d) {
  if (ls->h.env == PMC_ENV_NONE) return 0.0f;
  float pmf = pmc_light_pick_pmf(ls, p, n, 0);
  if (ls->h.env == PMC_ENV_CONSTANT) return pmf * fmax(0.0f, dot(n, d)) * PMC_INV_PI;
  return pmf * pmc_env_map_pdf(ls, pmc_env_to_map(&ls->h, d));
}

/* An area light's sample from point p at point q of light l (picked with
 * probability pmf; omega: the spherical rectangle's solid angle where it is
 * sampled so, else 0). Returns 0 when it carries nothing. */
PMC_FN int pmc_area_light_sample_at(PMC_GLOBAL const PmcLight* l, float pmf, float omega, float3 p, float3 q,
                                    PmcLightSample* s) {
  float3 d = q - p;
  float dist = length(d);
  if (!(dist > 0.0f)) return 0;
  s->wi = d * (1.0f / dist);
  float cos_light = -dot(pmc_load3(l->normal), s->wi);
  if (l->type == PMC_LIGHT_QUAD && !(l->flags & PMC_LIGHT_TWO_SIDED) && cos_light <= 0.0f) return 0;
  s->pdf =
      omega >= PMC_SPH_RECT_MIN_SOLID_ANGLE ? pmf / omega : pmc_area_light_pdf(pmf, dist, l->area, cos_light);
  if (!(s->pdf > 0.0f)) return 0;
  s->dist = dist;
  s->weight = pmc_load3(l->rgb) * (1.0f / s->pdf);
  return pmc_max3(s->weight) > 0.0f && isfinite(pmc_max3(s->weight));
}

/* pmc_light_sample_begin's answer besides 0 (nothing) and 1 (done). */
#define PMC_LIGHT_SAMPLE_RECT 2 /* a spherical rectangle to sample: pmc_light_sample_rect_end */

/* Whether light l is a quad with perpendicular edges, which is sampled by
 * solid angle (its spherical rectangle) where that is large enough. */
PMC_FN int pmc_light_is_rectangle(PMC_GLOBAL const PmcLight* l) {
  return l->type == PMC_LIGHT_QUAD && (l->flags & PMC_LIGHT_RECTANGLE) != 0u;
}

/* Quad l's sample by area at (u1, u2), where its spherical rectangle (of
 * solid angle omega) is too small to sample. */
PMC_FN int pmc_quad_sample_by_area(PMC_GLOBAL const PmcLight* l, float pmf, float omega, float3 p, float u1,
                                   float u2, PmcLightSample* s) {
  const float3 q = pmc_load3(l->pos) + pmc_load3(l->axis) * u1 + pmc_load3(l->edge_v) * u2;
  return pmc_area_light_sample_at(l, pmf, omega, p, q, s);
}

/* Sample light `picked` (picked with probability pmf; -1: none) from point
 * p with (pick) normal n (u1, u2), except for one step: a quad sampled by
 * solid angle returns PMC_LIGHT_SAMPLE_RECT with its spherical rectangle in
 * *r, light index in *light and pick probability in *pmf, and its point is
 * at coordinates pmc_sph_rect_sample_xy(..., u1, u2), then
 * pmc_light_sample_rect_end. (On CPU devices the shade kernel samples the
 * rectangle quads of a batch's lanes together in float8 and calls this for
 * the other lights only.) */
PMC_FN int pmc_light_sample_picked(const PmcLightSet* ls, int picked, float pmf, float3 p, float3 n, float u1,
                                   float u2, PmcLightSample* s, PmcSphRect* r, int* light, float* pmf_out) {
  if (picked < 0 || !(pmf > 0.0f)) return 0;
  PMC_GLOBAL const PmcLight* l = &ls->lights[picked];
  pmc_u32 type = l->type;
  float3 rgb = pmc_load3(l->rgb);
  s->pdf = 0.0f;
  s->dist = INFINITY;
  if (type == PMC_LIGHT_TRIANGLE) {
    float2 bc = pmc_sample_triangle(u1, u2);
    float3 q = pmc_load3(l->pos) + pmc_load3(l->axis) * bc.y + pmc_load3(l->edge_v) * (1.0f - bc.x - bc.y);
    return pmc_area_light_sample_at(l, pmf, 0.0f, p, q, s);
  } else if (type == PMC_LIGHT_QUAD) {
    *light = picked;
    *pmf_out = pmf;
    const float omega = pmc_sph_rect_init(l, p, r);
    if (omega >= PMC_SPH_RECT_MIN_SOLID_ANGLE) return PMC_LIGHT_SAMPLE_RECT;
    return pmc_quad_sample_by_area(l, pmf, omega, p, u1, u2, s);
  } else if (type == PMC_LIGHT_POINT || type == PMC_LIGHT_SPOT) {
    float3 d = pmc_load3(l->pos) - p;
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return 0;
    s->dist = sqrt(dist2);
    s->wi = d * (1.0f / s->dist);
    float falloff = 1.0f;
    if (type == PMC_LIGHT_SPOT) falloff = pmc_spot_falloff(l, -dot(pmc_load3(l->axis), s->wi));
    if (!(falloff > 0.0f)) return 0;
    s->weight = rgb * (falloff / (dist2 * pmf));
  } else if (type == PMC_LIGHT_DIRECTIONAL) {
    s->wi = -pmc_load3(l->axis);
    s->weight = rgb * (1.0f / pmf);
  } else if (type == PMC_LIGHT_SUN) {
    /* Uniform in the cone's solid angle; 1 - cos and sin from it stay exact
     * for a 0.5 degree disk. */
    float omc = u1 * l->one_minus_cos;
    float cos_t = 1.0f - omc;
    float sin_t = sqrt(fmax(0.0f, omc * (2.0f - omc)));
    float sin_phi, cos_phi; /* of the angle 2 pi u2 */
    pmc_sincos_turns(u2, &sin_phi, &cos_phi);
    float3 axis = -pmc_load3(l->axis), t, b;
    pmc_basis(axis, &t, &b);
    s->wi = normalize(t * (sin_t * cos_phi) + b * (sin_t * sin_phi) + axis * cos_t);
    s->pdf = pmc_sun_pdf(l, pmf);
    s->weight = rgb * (1.0f / s->pdf);
  } else if (type == PMC_LIGHT_ENV) {
    if (ls->h.env == PMC_ENV_CONSTANT) {
      float3 t, b;
      pmc_basis(n, &t, &b);
      float3 dir_local = pmc_sample_cosine(u1, u2);
      if (!(dir_local.z > 0.0f)) return 0;
      s->wi = pmc_to_world(dir_local, t, b, n);
      s->pdf = pmf * dir_local.z * PMC_INV_PI;
      s->weight = rgb * (1.0f / s->pdf);
    } else {
      float3 le;
      float pdf = pmc_env_map_sample(ls, u1, u2, &s->wi, &le);
      s->pdf = pmf * pdf;
      if (!(s->pdf > 0.0f)) return 0;
      s->weight = le * (1.0f / s->pdf);
    }
  } else {
    return 0;
  }
  return pmc_max3(s->weight) > 0.0f && isfinite(pmc_max3(s->weight));
}

/* Pick a light (u_pick, pmc_light_pick), then pmc_light_sample_picked. */
PMC_FN int pmc_light_sample_begin(const PmcLightSet* ls, float3 p, float3 n, float u_pick, float u1, float u2,
                                  PmcLightSample* s, PmcSphRect* r, int* light, float* pmf_out) {
  float pmf;
  const int picked = pmc_light_pick(ls, p, n, u_pick, &pmf);
  return pmc_light_sample_picked(ls, picked, pmf, p, n, u1, u2, s, r, light, pmf_out);
}

/* The rest of a PMC_LIGHT_SAMPLE_RECT sample, at coordinates xy
 * (pmc_sph_rect_sample_xy) of the rectangle: pmc_area_light_sample_at's
 * answer for a quad sampled by solid angle, by PMC_RECT_SAMPLE_END. */
PMC_FN int pmc_light_sample_rect_end(const PmcLightSet* ls, int light, float pmf, const PmcSphRect* r,
                                     float2 xy, PmcLightSample* s) {
  PMC_GLOBAL const PmcLight* l = &ls->lights[light];
  PMC_RECT_SAMPLE_END(float, r->x.x, r->x.y, r->x.z, r->y.x, r->y.y, r->y.z, r->z.x, r->z.y, r->z.z, r->z0,
                      xy.x, xy.y, l->normal[0], l->normal[1], l->normal[2])
  if (!(dist > 0.0f)) return 0;
  s->wi = make_float3(wx, wy, wz);
  if (!(l->flags & PMC_LIGHT_TWO_SIDED) && cos_light <= 0.0f) return 0;
  s->pdf = pmf / r->solid_angle;
  if (!(s->pdf > 0.0f)) return 0;
  s->dist = dist;
  s->weight = pmc_load3(l->rgb) * (1.0f / s->pdf);
  return pmc_max3(s->weight) > 0.0f && isfinite(pmc_max3(s->weight));
}

/* Pick a light (u_pick, pmc_light_pick) and sample it from point p with
 * (pick) normal n (u1, u2). Returns 0 when the sample carries nothing. */
PMC_FN int pmc_light_sample(const PmcLightSet* ls, float3 p, float3 n, float u_pick, float u1, float u2,
                            PmcLightSample* s) {
  PmcSphRect r;
  int light = 0;
  float pmf = 0.0f;
  const int begun = pmc_light_sample_begin(ls, p, n, u_pick, u1, u2, s, &r, &light, &pmf);
  if (begun != PMC_LIGHT_SAMPLE_RECT) return begun;
  return pmc_light_sample_rect_end(
      ls, light, pmf, &r,
      pmc_sph_rect_sample_xy(r.solid_angle, r.k, r.b0, r.b1, r.z0, r.x0, r.x1, r.y0, r.y1, u1, u2), s);
}

/* Whether a traced ray (origin o, unit direction d, its hit at t_hit unless
 * it `escaped`) meets a quad light before its hit, with a relative tolerance
 * so that a light on a wall is seen: the quad faces the ray (or is two-sided),
 * its plane lies ahead at t (before the hit) and the point there lies inside
 * its edges. Writes t and the cosine term denom = n.d that the ray's MIS
 * weight needs. One source for the scalar form (pmc_quad_seen_at) and the
 * float8 one (the shade kernel's, eight rays of a batch at once against one
 * quad): F is float or float8, I its integer type, SEL its select; the quad's
 * fields are scalars. Straight-line, its products written out, so both forms
 * agree bit for bit. */
#define PMC_QUAD_SEEN(NAME, F, I, SEL)                                                                       \
  PMC_FN I NAME(PMC_GLOBAL const PmcLight* l, F ox, F oy, F oz, F dx, F dy, F dz, F t_hit, I escaped,        \
                F* t_out, F* denom_out) {                                                                    \
    const F zero = (F)(0.0f), one = (F)(1.0f);                                                               \
    const float nx = l->normal[0], ny = l->normal[1], nz = l->normal[2];                                     \
    const float cx = l->pos[0], cy = l->pos[1], cz = l->pos[2], inv_area = 1.0f / l->area;                   \
    const F denom = nx * dx + ny * dy + nz * dz;                                                             \
    const I two_sided = (I)((l->flags & PMC_LIGHT_TWO_SIDED) != 0u ? -1 : 0);                                \
    const I facing = !(denom == zero) & (two_sided | !(denom >= zero));                                      \
    const F t = (nx * (cx - ox) + ny * (cy - oy) + nz * (cz - oz)) / denom;                                  \
    const I ahead = (t > zero) & (escaped | (t <= t_hit * (F)(1.0001f)));                                    \
    const F rx = ox + dx * t - cx, ry = oy + dy * t - cy, rz = oz + dz * t - cz;                             \
    const float vx = l->edge_v[0], vy = l->edge_v[1], vz = l->edge_v[2];                                     \
    const float ux = l->axis[0], uy = l->axis[1], uz = l->axis[2];                                           \
    const F a = ((ry * vz - rz * vy) * nx + (rz * vx - rx * vz) * ny + (rx * vy - ry * vx) * nz) * inv_area; \
    const F b = ((uy * rz - uz * ry) * nx + (uz * rx - ux * rz) * ny + (ux * ry - uy * rx) * nz) * inv_area; \
    const I inside = (a >= zero) & (a <= one) & (b >= zero) & (b <= one);                                    \
    *t_out = t;                                                                                              \
    *denom_out = denom;                                                                                      \
    return facing & ahead & inside;                                                                          \
  }
PMC_QUAD_SEEN(pmc_quad_seen_at, float, int, PMC_SEL_SCALAR)

/* The radiance of quad light i that a ray from o meets at t (denom = n.d),
 * MIS-weighted against light sampling from o (`bsdf_pdf`, the pick normal n);
 * `full_weight` for camera rays, which light sampling cannot produce. */
PMC_FN float3 pmc_quad_seen_radiance(const PmcLightSet* ls, int i, float3 o, float t, float denom,
                                     float bsdf_pdf, float3 n, int full_weight) {
  PMC_GLOBAL const PmcLight* l = &ls->lights[i];
  const float w =
      full_weight
          ? 1.0f
          : pmc_mis_power(bsdf_pdf, pmc_quad_light_pdf(l, o, pmc_light_pick_pmf(ls, o, n, i), t, denom));
  return pmc_load3(l->rgb) * w;
}

/* What light at infinity i adds to an escaped ray from o along unit d,
 * MIS-weighted against light sampling from o (`bsdf_pdf`, the pick's normal
 * n; `full_weight` for camera rays), into *add; 0 when it adds nothing (a sun
 * the ray misses). For the environment map, m is d in map space and
 * `texel`, `row` its texel (pmc_env_texel_at): the caller finds them, so that
 * the shade kernel can find a batch's in one loop over its rays
 * (pmc_infinity_seen_lanes). */
PMC_FN int pmc_infinity_light_seen(const PmcLightSet* ls, int i, float3 o, float3 d, float bsdf_pdf, float3 n,
                                   int full_weight, float3 m, int texel, int row, float3* add) {
  PMC_GLOBAL const PmcLight* l = &ls->lights[i];
  float3 le;
  float light_pdf;
  if (l->type == PMC_LIGHT_ENV && ls->h.env == PMC_ENV_MAP) {
    /* pmc_env_light_pdf, with the texel found once */
    le = pmc_env_texel(ls, texel);
    light_pdf = full_weight ? 0.0f : pmc_light_pick_pmf(ls, o, n, 0) * pmc_env_map_pdf_in(ls, m, texel, row);
  } else if (l->type == PMC_LIGHT_ENV) {
    le = pmc_load3(l->rgb);
    light_pdf = full_weight ? 0.0f : pmc_env_light_pdf(ls, o, n, d);
  } else if (pmc_sun_contains(l, d)) {
    le = pmc_load3(l->rgb);
    light_pdf = full_weight ? 0.0f : pmc_sun_pdf(l, pmc_light_pick_pmf(ls, o, n, i));
  } else {
    return 0;
  }
  float w = full_weight ? 1.0f : pmc_mis_power(bsdf_pdf, light_pdf);
  *add = le * w;
  return 1;
}

/* Whether light at infinity i is the environment map (whose texel
 * pmc_infinity_light_seen needs). */
PMC_FN int pmc_infinity_is_map(const PmcLightSet* ls, int i) {
  return ls->lights[i].type == PMC_LIGHT_ENV && ls->h.env == PMC_ENV_MAP;
}

/* `sum` plus the radiance an escaped ray (origin o, unit direction d)
 * receives from the environment and the sun disks, MIS-weighted as
 * pmc_quad_seen_radiance. */
PMC_FN float3 pmc_infinity_seen(const PmcLightSet* ls, float3 o, float3 d, float bsdf_pdf, float3 n,
                                int full_weight, float3 sum) {
  for (int i = 0; i < ls->h.at_infinity; ++i) {
    float3 m = make_float3(0.0f, 0.0f, 0.0f), add;
    int texel = 0, row = 0;
    if (pmc_infinity_is_map(ls, i)) {
      m = pmc_env_to_map(&ls->h, d);
      texel = pmc_env_texel_at(&ls->h, m, &row);
    }
    if (pmc_infinity_light_seen(ls, i, o, d, bsdf_pdf, n, full_weight, m, texel, row, &add)) sum += add;
  }
  return sum;
}

/* Radiance that a traced ray (origin o, unit direction d) receives from the
 * lights it meets: quads closer than its hit at `t_hit` (pmc_quad_seen_at),
 * and if it `escaped`, the environment and sun disks. MIS-weighted against
 * light sampling from the previous vertex (`bsdf_pdf`; o with the normal `n`
 * it picked lights with); `full_weight` for camera rays. The shade kernel
 * takes the quads for a batch's rays together, eight at a time, in the same
 * order per ray. */
PMC_FN float3 pmc_lights_seen(const PmcLightSet* ls, float3 o, float3 d, float t_hit, int escaped,
                              float bsdf_pdf, float3 n, int full_weight) {
  float3 sum = make_float3(0.0f, 0.0f, 0.0f);
  for (int i = ls->h.distant_end; i < ls->h.quad_end; ++i) {
    float t, denom;
    if (pmc_quad_seen_at(&ls->lights[i], o.x, o.y, o.z, d.x, d.y, d.z, t_hit, escaped ? -1 : 0, &t, &denom))
      sum += pmc_quad_seen_radiance(ls, i, o, t, denom, bsdf_pdf, n, full_weight);
  }
  return escaped ? pmc_infinity_seen(ls, o, d, bsdf_pdf, n, full_weight, sum) : sum;
}

#endif /* PMC_LIGHTS_H */
