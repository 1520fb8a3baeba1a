/* pmc_lights.h — sampling and evaluating every light, shared by the shade
 * kernel and host tests.
 *
 * The light table (PmcLight[], built by core/lights.cpp) holds emissive
 * triangles, the lights of a lights file and the environment, each with the
 * probability that next-event estimation picks it (proportional to power).
 * The shade kernel uses three entry points:
 *   pmc_light_sample  : at a hit, pick one light and sample a direction toward
 *                       it -> one shadow ray (delta lights: pdf 0, no MIS);
 *   pmc_env_light_pdf : when the BSDF samples the next direction, the pdf with
 *                       which the environment would have sampled it (stored in
 *                       the path: the constant environment samples around the
 *                       shading normal, which the escape no longer knows);
 *   pmc_lights_seen   : for every traced ray, the radiance of quads it passes
 *                       before its hit and, if it escapes, of the environment
 *                       and sun disks, MIS-weighted against light sampling.
 * Emissive triangles reached by a ray are shaded as surfaces (their material
 * emits); pmc_area_light_pdf gives their light-sampling pdf for the weight.
 *
 * Environment map (PMC_ENV_MAP): lat-long, +Y up, u = 0.5 + atan2(x, -z)/2pi,
 * v = acos(y)/pi, v = 0 the top row (the image centre is seen looking along
 * -Z, +X at u = 0.75), turned about +Y by the header's rotation. Texels are
 * constant over their solid angle (nearest lookup, so the sampled density
 * matches exactly). `env` holds, for a w x h map: w*h rgb texels (scale
 * applied), the marginal CDF of the h rows, then h conditional CDFs of w
 * columns (inclusive running sums, last entry 1), of luminance x sin(theta).
 */
#ifndef PMC_LIGHTS_H
#define PMC_LIGHTS_H

#include "../abi/pmc_types.h"
#include "pmc_bsdf.h"

typedef struct PmcLightSet {
  PMC_GLOBAL const PmcLight* lights;
  PMC_GLOBAL const float* env; /* the map's texels and CDFs (PMC_ENV_MAP only) */
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
  float u = 0.5f + atan2(d.x, -d.z) * (0.5f * PMC_INV_PI);
  float v = acos(clamp(d.y, -1.0f, 1.0f)) * PMC_INV_PI;
  return make_float2(u, v);
}

PMC_FN float3 pmc_env_uv_to_dir(float u, float v) {
  float phi = (u - 0.5f) * (2.0f * PMC_PI);
  float theta = v * PMC_PI;
  float st = sin(theta);
  return make_float3(st * sin(phi), cos(theta), -st * cos(phi));
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

/* Column and row of the texel holding map direction m. */
PMC_FN int pmc_env_texel_index(const PmcLightHeader* h, float3 m) {
  float2 uv = pmc_env_dir_to_uv(m);
  int col = (int)(uv.x * (float)h->env_width);
  int row = (int)(uv.y * (float)h->env_height);
  col = col < 0 ? 0 : (col >= h->env_width ? h->env_width - 1 : col);
  row = row < 0 ? 0 : (row >= h->env_height ? h->env_height - 1 : row);
  return row * h->env_width + col;
}

PMC_FN float3 pmc_env_texel(const PmcLightSet* ls, int i) {
  return make_float3(ls->env[3 * i], ls->env[3 * i + 1], ls->env[3 * i + 2]);
}

/* Solid-angle density of the map's importance sampling at map direction m
 * (without the pick probability): p(texel) w h / (2 pi^2 sin(theta)). */
PMC_FN float pmc_env_map_pdf(const PmcLightSet* ls, float3 m) {
  const PmcLightHeader* h = &ls->h;
  if (h->env_uniform) return 0.25f * PMC_INV_PI;
  float sin_theta = sqrt(fmax(0.0f, 1.0f - m.y * m.y));
  if (!(sin_theta > 0.0f)) return 0.0f;
  int i = pmc_env_texel_index(h, m);
  int row = i / h->env_width;
  float row_sin = sin(((float)row + 0.5f) * PMC_PI / (float)h->env_height);
  float f = pmc_luminance(pmc_env_texel(ls, i)) * row_sin;
  float texels = (float)h->env_width * (float)h->env_height;
  return f * h->env_inv_integral * texels / (2.0f * PMC_PI * PMC_PI * sin_theta);
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

/* Where u falls inside bin i of an inclusive CDF, in [0, 1). */
PMC_FN float pmc_cdf_fraction(PMC_GLOBAL const float* cdf, int i, float u) {
  float lo = i > 0 ? cdf[i - 1] : 0.0f;
  float width = cdf[i] - lo;
  float f = width > 0.0f ? (u - lo) / width : 0.5f;
  return clamp(f, 0.0f, 0.99999994f);
}

/* Sample a map direction (world space) by luminance x sin(theta); returns
 * its density (without the pick probability), 0 on failure. */
PMC_FN float pmc_env_map_sample(const PmcLightSet* ls, float u1, float u2, float3* wi, float3* le) {
  const PmcLightHeader* h = &ls->h;
  int w = h->env_width, hh = h->env_height;
  float3 m;
  if (h->env_uniform) {
    float z = 1.0f - 2.0f * u1, r = sqrt(fmax(0.0f, 1.0f - z * z)), sin_phi, cos_phi;
    pmc_sincos_turns(u2, &sin_phi, &cos_phi);
    m = make_float3(r * cos_phi, z, r * sin_phi);
  } else {
    PMC_GLOBAL const float* marginal = ls->env + 3 * w * hh;
    int row = pmc_cdf_search(marginal, hh, u1);
    float fv = pmc_cdf_fraction(marginal, row, u1);
    PMC_GLOBAL const float* conditional = marginal + hh + row * w;
    int col = pmc_cdf_search(conditional, w, u2);
    float fu = pmc_cdf_fraction(conditional, col, u2);
    m = pmc_env_uv_to_dir(((float)col + fu) / (float)w, ((float)row + fv) / (float)hh);
  }
  float pdf = pmc_env_map_pdf(ls, m);
  *wi = pmc_env_to_world(h, m);
  *le = pmc_env_texel(ls, pmc_env_texel_index(h, m));
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

/* Solid-angle pdf of a sun disk's cone sampling (pick probability included). */
PMC_FN float pmc_sun_pdf(PMC_GLOBAL const PmcLight* l) { return l->pmf / (2.0f * PMC_PI * l->one_minus_cos); }

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

/* The pdf with which the environment light samples direction d from a point
 * with shading normal n (pick probability included; 0 without environment). */
PMC_FN float pmc_env_light_pdf(const PmcLightSet* ls, float3 n, float3 d) {
  if (ls->h.env == PMC_ENV_NONE) return 0.0f;
  float pmf = ls->lights[0].pmf;
  if (ls->h.env == PMC_ENV_CONSTANT) return pmf * fmax(0.0f, dot(n, d)) * PMC_INV_PI;
  return pmf * pmc_env_map_pdf(ls, pmc_env_to_map(&ls->h, d));
}

/* Pick a light by power (u_pick) and sample it from point p with shading
 * normal n (u1, u2). Returns 0 when the sample carries nothing. */
PMC_FN int pmc_light_sample(const PmcLightSet* ls, float3 p, float3 n, float u_pick, float u1, float u2,
                            PmcLightSample* s) {
  int count = ls->h.count;
  if (count <= 0) return 0;
  /* Binary search on the running sums (stored in each light). */
  int lo = 0, hi = count - 1;
  while (lo < hi) {
    int mid = (lo + hi) >> 1;
    if (ls->lights[mid].cdf > u_pick)
      hi = mid;
    else
      lo = mid + 1;
  }
  PMC_GLOBAL const PmcLight* l = &ls->lights[lo];
  float pmf = l->pmf;
  if (!(pmf > 0.0f)) return 0;
  pmc_u32 type = l->type;
  float3 rgb = pmc_load3(l->rgb);
  s->pdf = 0.0f;
  s->dist = INFINITY;
  if (type == PMC_LIGHT_TRIANGLE || type == PMC_LIGHT_QUAD) {
    float3 q = pmc_load3(l->pos);
    if (type == PMC_LIGHT_TRIANGLE) {
      float2 bc = pmc_sample_triangle(u1, u2);
      q = q + pmc_load3(l->axis) * bc.y + pmc_load3(l->edge_v) * (1.0f - bc.x - bc.y);
    } else {
      q = q + pmc_load3(l->axis) * u1 + pmc_load3(l->edge_v) * u2;
    }
    float3 d = q - p;
    float dist = length(d);
    if (!(dist > 0.0f)) return 0;
    s->wi = d * (1.0f / dist);
    float cos_light = -dot(pmc_load3(l->normal), s->wi);
    if (type == PMC_LIGHT_QUAD && !(l->flags & PMC_LIGHT_TWO_SIDED) && cos_light <= 0.0f) return 0;
    s->pdf = pmc_area_light_pdf(pmf, dist, l->area, cos_light);
    if (!(s->pdf > 0.0f)) return 0;
    s->dist = dist;
    s->weight = rgb * (1.0f / s->pdf);
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
    s->pdf = pmc_sun_pdf(l);
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

/* Radiance that a traced ray (origin o, unit direction d) receives from the
 * lights it meets: quads closer than its hit at `t_hit` (with a relative
 * tolerance, so a light on a wall is seen), and if it `escaped`, the
 * environment and sun disks. MIS-weighted against light sampling from the
 * previous vertex (`bsdf_pdf`, `env_pdf` from the path); `full_weight` for
 * camera rays, which light sampling cannot produce. */
PMC_FN float3 pmc_lights_seen(const PmcLightSet* ls, float3 o, float3 d, float t_hit, int escaped,
                              float bsdf_pdf, float env_pdf, int full_weight) {
  float3 sum = make_float3(0.0f, 0.0f, 0.0f);
  for (int i = ls->h.at_infinity; i < ls->h.quad_end; ++i) {
    PMC_GLOBAL const PmcLight* l = &ls->lights[i];
    float3 nrm = pmc_load3(l->normal);
    float denom = dot(nrm, d);
    if (denom == 0.0f || (!(l->flags & PMC_LIGHT_TWO_SIDED) && denom >= 0.0f)) continue;
    float3 corner = pmc_load3(l->pos);
    float t = dot(nrm, corner - o) / denom;
    if (!(t > 0.0f) || (!escaped && !(t <= t_hit * 1.0001f))) continue;
    float3 r = o + d * t - corner;
    float a = dot(cross(r, pmc_load3(l->edge_v)), nrm) / l->area;
    float b = dot(cross(pmc_load3(l->axis), r), nrm) / l->area;
    if (!(a >= 0.0f && a <= 1.0f && b >= 0.0f && b <= 1.0f)) continue;
    float w = full_weight ? 1.0f : pmc_mis_power(bsdf_pdf, pmc_area_light_pdf(l->pmf, t, l->area, denom));
    sum += pmc_load3(l->rgb) * w;
  }
  if (!escaped) return sum;
  for (int i = 0; i < ls->h.at_infinity; ++i) {
    PMC_GLOBAL const PmcLight* l = &ls->lights[i];
    float3 le;
    float light_pdf;
    if (l->type == PMC_LIGHT_ENV) {
      if (ls->h.env == PMC_ENV_MAP)
        le = pmc_env_texel(ls, pmc_env_texel_index(&ls->h, pmc_env_to_map(&ls->h, d)));
      else
        le = pmc_load3(l->rgb);
      light_pdf = env_pdf;
    } else if (pmc_sun_contains(l, d)) {
      le = pmc_load3(l->rgb);
      light_pdf = pmc_sun_pdf(l);
    } else {
      continue;
    }
    float w = full_weight ? 1.0f : pmc_mis_power(bsdf_pdf, light_pdf);
    sum += le * w;
  }
  return sum;
}

#endif /* PMC_LIGHTS_H */
