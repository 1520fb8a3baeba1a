/* pmc_microfacet.h — the microfacet pieces every lobe of pmc_bsdf.h is made of.
 *
 * Anisotropic GGX (Trowbridge-Reitz): its distribution D, Smith's Lambda and
 * G1, sampling of the visible normals (Heitz 2018); Fresnel for a dielectric
 * interface (exact, unpolarised) and Schlick's; refraction; the sheen lobe
 * (Estevez and Kulla 2017's "Charlie" distribution with Neubelt and
 * Pettineo's visibility term, as MaterialX's sheen_bsdf). Directions are in
 * the local shading frame (normal = +z, tangent = +x). No tables: the albedo
 * tables (pmc_bsdf_tables.h) are integrated from these functions by
 * scripts/bsdf_tables/make_bsdf_tables.cpp, so this file must not depend on them.
 */
#ifndef PMC_MICROFACET_H
#define PMC_MICROFACET_H

#include "../abi/pmc_vec.h"

#define PMC_MIN_ALPHA 0.00140328f /* (6/31)^4: on a column of the albedo tables */

/* GGX D(h) for a local half vector h and roughness alphas (ax along the
 * tangent, ay along the bitangent). */
PMC_FN float pmc_ggx_d2(float3 h, float ax, float ay) {
  if (h.z <= 0.0f) return 0.0f;
  const float x = h.x / ax, y = h.y / ay;
  const float d = x * x + y * y + h.z * h.z;
  return 1.0f / (PMC_PI * ax * ay * d * d);
}

/* Smith Lambda for anisotropic GGX; |w.z| is used, so it serves both sides. */
PMC_FN float pmc_ggx_lambda2(float3 w, float ax, float ay) {
  const float c2 = w.z * w.z;
  if (c2 <= 0.0f) return 1e30f;
  const float t2 = (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / c2;
  return 0.5f * (-1.0f + sqrt(1.0f + t2));
}

/* Isotropic forms (alpha = ax = ay). */
PMC_FN float pmc_ggx_d(float3 h, float alpha) { return pmc_ggx_d2(h, alpha, alpha); }
PMC_FN float pmc_ggx_lambda(float3 w, float alpha) { return pmc_ggx_lambda2(w, alpha, alpha); }
PMC_FN float pmc_ggx_g1(float3 w, float alpha) { return 1.0f / (1.0f + pmc_ggx_lambda(w, alpha)); }

/* A visible normal for wo (wo.z > 0) from two uniforms (Heitz 2018). */
PMC_FN float3 pmc_ggx_sample_vndf2(float3 wo, float ax, float ay, float u1, float u2) {
  float3 vh = normalize(make_float3(ax * wo.x, ay * wo.y, wo.z));
  float lensq = vh.x * vh.x + vh.y * vh.y;
  float3 t1 =
      lensq > 0.0f ? make_float3(-vh.y, vh.x, 0.0f) * (1.0f / sqrt(lensq)) : make_float3(1.0f, 0.0f, 0.0f);
  float3 t2 = cross(vh, t1);
  float r = sqrt(u1);
  float sin_phi, cos_phi;
  pmc_sincos_turns(u2, &sin_phi, &cos_phi);
  float p1 = r * cos_phi;
  float p2 = r * sin_phi;
  float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * sqrt(fmax(0.0f, 1.0f - p1 * p1)) + s * p2;
  float3 nh = t1 * p1 + t2 * p2 + vh * sqrt(fmax(0.0f, 1.0f - p1 * p1 - p2 * p2));
  return normalize(make_float3(ax * nh.x, ay * nh.y, fmax(1e-6f, nh.z)));
}

PMC_FN float3 pmc_ggx_sample_vndf(float3 wo, float alpha, float u1, float u2) {
  return pmc_ggx_sample_vndf2(wo, alpha, alpha, u1, u2);
}

/* Solid-angle pdf of wi when wi is the reflection of wo about a VNDF sample.
 * Defined over the whole sphere (directions below the horizon included), so
 * it integrates to one there. */
PMC_FN float pmc_ggx_reflect_pdf(float3 wo, float3 wi, float alpha) {
  float3 h = wo + wi;
  float hl = length(h);
  if (hl <= 0.0f || wo.z <= 0.0f) return 0.0f;
  h = h * (1.0f / hl);
  if (h.z <= 0.0f) return 0.0f;
  return pmc_ggx_g1(wo, alpha) * pmc_ggx_d(h, alpha) / (4.0f * wo.z);
}

/* Schlick's Fresnel from F0 to white: F0 + (1 - F0) (1 - c)^5. */
PMC_FN float pmc_schlick_m5(float cos_theta) {
  float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
  float m2 = m * m;
  return m2 * m2 * m;
}
PMC_FN float3 pmc_schlick(float3 f0, float cos_theta) {
  return f0 + (make_float3(1.0f, 1.0f, 1.0f) - f0) * pmc_schlick_m5(cos_theta);
}

/* Unpolarised Fresnel reflectance of a dielectric interface, for light
 * arriving at cos_i (> 0) on the side where the relative IOR (far side over
 * near side) is eta; 1 under total internal reflection. */
PMC_FN float pmc_fresnel_dielectric(float cos_i, float eta) {
  cos_i = clamp(cos_i, 0.0f, 1.0f);
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = sqrt(fmax(0.0f, 1.0f - sin2_t));
  const float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

/* wo refracted through a microfacet of normal m (dot(wo, m) > 0) into the
 * medium of relative IOR eta; 0 under total internal reflection. */
PMC_FN int pmc_refract(float3 wo, float3 m, float eta, float3* wt) {
  const float c = dot(wo, m);
  const float sin2_t = fmax(0.0f, 1.0f - c * c) / (eta * eta);
  if (sin2_t >= 1.0f) return 0;
  const float cos_t = sqrt(1.0f - sin2_t);
  *wt = wo * (-1.0f / eta) + m * (c / eta - cos_t);
  return 1;
}

/* The sheen lobe's distribution (Charlie: sin(theta_h)^(1/r)) and its BRDF
 * with Neubelt and Pettineo's visibility 1 / (4 (cos_i + cos_o - cos_i cos_o)),
 * for white sheen of roughness r (MaterialX's sheen_bsdf, mode conty_kulla). */
PMC_FN float pmc_sheen_d(float cos_h, float r) {
  const float inv_r = 1.0f / fmax(r, 0.005f);
  const float sin2 = fmax(0.0f, 1.0f - cos_h * cos_h);
  return (2.0f + inv_r) * pow(sin2, 0.5f * inv_r) * (0.5f * PMC_INV_PI);
}
PMC_FN float pmc_sheen_brdf(float3 wo, float3 wi, float r) {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  const float3 h = normalize(wo + wi);
  return pmc_sheen_d(h.z, r) / (4.0f * (wi.z + wo.z - wi.z * wo.z));
}

#endif /* PMC_MICROFACET_H */
