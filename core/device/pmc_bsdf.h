/* pmc_bsdf.h — the surface scattering model and its sampling routines.
 *
 * A material evaluates to a PmcBsdf: a Lambert lobe plus an isotropic GGX
 * microfacet lobe with Schlick Fresnel, plus emission. Directions are in the
 * local shading frame (normal = +z). Sampling picks a lobe with probability
 * proportional to its albedo estimate, samples the cosine hemisphere or the
 * GGX distribution of visible normals (Heitz 2018), and returns the combined
 * one-sample-MIS pdf, so eval/pdf/sample stay consistent for light-sampling
 * MIS. Shared by kernels and host tests (pdf normalisation, chi-square).
 */
#ifndef PMC_BSDF_H
#define PMC_BSDF_H

#include "../abi/pmc_vec.h"

#define PMC_MIN_ALPHA 0.002f

typedef struct PmcBsdf {
  float3 diffuse;  /* Lambert albedo */
  float3 specular; /* F0 of the GGX lobe (Schlick) */
  float alpha;     /* GGX roughness alpha */
  float3 emission; /* emitted radiance */
} PmcBsdf;

/* GGX normal distribution D(h) for a local half vector h. */
PMC_FN float pmc_ggx_d(float3 h, float alpha) {
  float a2 = alpha * alpha;
  /* cos²(a²-1)+1 written as sin² + a² cos²: no cancellation near the peak. */
  float d = h.x * h.x + h.y * h.y + a2 * h.z * h.z;
  return h.z > 0.0f ? a2 / (PMC_PI * d * d) : 0.0f;
}

/* Smith Lambda for GGX. */
PMC_FN float pmc_ggx_lambda(float3 w, float alpha) {
  float c2 = w.z * w.z;
  float s2 = fmax(0.0f, 1.0f - c2);
  if (c2 <= 0.0f) return 1e30f;
  float t2 = s2 / c2;
  return 0.5f * (-1.0f + sqrt(1.0f + alpha * alpha * t2));
}

PMC_FN float pmc_ggx_g1(float3 w, float alpha) { return 1.0f / (1.0f + pmc_ggx_lambda(w, alpha)); }

/* Sample a visible normal for wo (wo.z > 0) from two uniforms (Heitz 2018). */
PMC_FN float3 pmc_ggx_sample_vndf(float3 wo, float alpha, float u1, float u2) {
  float3 vh = normalize(make_float3(alpha * wo.x, alpha * wo.y, wo.z));
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
  return normalize(make_float3(alpha * nh.x, alpha * nh.y, fmax(1e-6f, nh.z)));
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

PMC_FN float3 pmc_schlick(float3 f0, float cos_theta) {
  float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
  float m5 = m * m * m * m * m;
  return f0 + (make_float3(1.0f, 1.0f, 1.0f) - f0) * m5;
}

/* Probability of choosing the specular lobe. */
PMC_FN float pmc_bsdf_spec_prob(const PmcBsdf* b) {
  float ld = pmc_luminance(b->diffuse);
  float ls = pmc_luminance(b->specular);
  float sum = ld + ls;
  return sum > 0.0f ? ls / sum : 0.0f;
}

/* BSDF value f(wo, wi) (without the cosine) and, in *pdf, the solid-angle
 * pdf of sampling wi given wo, sharing the half vector, D and Smith's
 * Lambda(wo) between the two (next-event estimation and sampling need
 * both). For wo, wi in the upper hemisphere wo + wi has a positive z, so
 * the half vector always exists there. */
PMC_FN float3 pmc_bsdf_eval_pdf(const PmcBsdf* b, float3 wo, float3 wi, float* pdf) {
  *pdf = 0.0f;
  if (wo.z <= 0.0f || wi.z <= 0.0f) return make_float3(0.0f, 0.0f, 0.0f);
  const float ps = pmc_bsdf_spec_prob(b);
  float3 f = b->diffuse * PMC_INV_PI;
  float p = (1.0f - ps) * wi.z * PMC_INV_PI;
  const int specular = pmc_max3(b->specular) > 0.0f;
  if (specular || ps > 0.0f) {
    const float3 h = normalize(wo + wi);
    const float alpha = fmax(b->alpha, PMC_MIN_ALPHA);
    const float d = pmc_ggx_d(h, alpha);
    const float lambda_o = pmc_ggx_lambda(wo, alpha);
    if (specular) {
      const float g = 1.0f / (1.0f + lambda_o + pmc_ggx_lambda(wi, alpha));
      f += pmc_schlick(b->specular, dot(wi, h)) * (d * g / (4.0f * wo.z * wi.z));
    }
    if (ps > 0.0f) p += ps * (d / ((1.0f + lambda_o) * 4.0f * wo.z)); /* pmc_ggx_reflect_pdf */
  }
  *pdf = p;
  return f;
}

/* BSDF value f(wo, wi) (without the cosine). */
PMC_FN float3 pmc_bsdf_eval(const PmcBsdf* b, float3 wo, float3 wi) {
  float pdf;
  return pmc_bsdf_eval_pdf(b, wo, wi, &pdf);
}

/* Solid-angle pdf of sampling wi given wo. */
PMC_FN float pmc_bsdf_pdf(const PmcBsdf* b, float3 wo, float3 wi) {
  float pdf;
  pmc_bsdf_eval_pdf(b, wo, wi, &pdf);
  return pdf;
}

/* Cosine-weighted hemisphere direction (concentric mapping). */
PMC_FN float3 pmc_sample_cosine(float u1, float u2) {
  float a = 2.0f * u1 - 1.0f;
  float c = 2.0f * u2 - 1.0f;
  float r, turns; /* the angle, in turns */
  if (a == 0.0f && c == 0.0f) return make_float3(0.0f, 0.0f, 1.0f);
  if (fabs(a) > fabs(c)) {
    r = a;
    turns = 0.125f * (c / a);
  } else {
    r = c;
    turns = 0.25f - 0.125f * (a / c);
  }
  float sin_phi, cos_phi;
  pmc_sincos_turns(turns, &sin_phi, &cos_phi);
  float x = r * cos_phi, y = r * sin_phi;
  return make_float3(x, y, sqrt(fmax(0.0f, 1.0f - x * x - y * y)));
}

/* Sample wi; returns 0 (and leaves *wi undefined) when the sample is invalid.
 * On success *pdf is the combined pdf and *weight = f * cos / pdf. */
PMC_FN int pmc_bsdf_sample(const PmcBsdf* b, float3 wo, float ulobe, float u1, float u2, float3* wi,
                           float* pdf, float3* weight) {
  if (wo.z <= 0.0f) return 0;
  float ps = pmc_bsdf_spec_prob(b);
  if (ulobe < ps) {
    float3 h = pmc_ggx_sample_vndf(wo, fmax(b->alpha, PMC_MIN_ALPHA), u1, u2);
    *wi = h * (2.0f * dot(wo, h)) - wo;
  } else {
    *wi = pmc_sample_cosine(u1, u2);
  }
  if ((*wi).z <= 0.0f) return 0;
  const float3 f = pmc_bsdf_eval_pdf(b, wo, *wi, pdf);
  if (!(*pdf > 0.0f)) return 0;
  *weight = f * ((*wi).z / *pdf);
  return 1;
}

/* Power heuristic (beta = 2) for two strategies. */
PMC_FN float pmc_mis_power(float pa, float pb) {
  float a = pa * pa, b = pb * pb;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

/* Uniform point on a triangle from two uniforms (returns barycentrics b1, b2). */
PMC_FN float2 pmc_sample_triangle(float u1, float u2) {
  float s = sqrt(u1);
  return make_float2(1.0f - s, u2 * s);
}

#endif /* PMC_BSDF_H */
