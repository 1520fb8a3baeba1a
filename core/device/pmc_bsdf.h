/* pmc_bsdf.h — the surface scattering model: a stack of energy-conserving
 * layers, prepared for one view direction, with its evaluation and sampling.
 *
 * A material evaluates to a PmcBsdf (pmc_surface.h fills it from the
 * parameter block): from the top, a clear coat, then a conductor (metalness)
 * beside a dielectric base that carries a sheen layer, a rough glass lobe
 * (transmission) and an opaque part of dielectric specular over Lambert.
 * Layering is albedo scaling, as Autodesk Standard Surface and OpenPBR
 * describe it: a layer whose lobe reflects E(mu_o) of the light lets
 * 1 - E(mu_o) through to what lies below, so no stack reflects more than it
 * receives. E comes from tables integrated from the lobes themselves
 * (pmc_bsdf_tables.h, by roughness and cos theta_o; Schlick's Fresnel is
 * linear in F0, so two GGX tables serve every F0). GGX reflection lobes get
 * multiple-scattering compensation in Turquin's (2019) form of Kulla and
 * Conty's idea: the single-scattering lobe scaled by 1 + F0 (1 / E1 - 1),
 * which makes a white rough conductor reflect exactly what it receives.
 *
 * pmc_bsdf_prepare() turns the stack into PmcLobes for one outgoing
 * direction wo (local shading frame, normal +z, wo.z > 0): each lobe's
 * weight and its probability of being sampled (proportional to its albedo).
 * Eval, pdf and sample then see only PmcLobes, so next-event estimation and
 * BSDF sampling agree on one mixture pdf (one-sample MIS).
 *
 * Glass (Walter et al. 2007): GGX reflection and refraction with exact
 * dielectric Fresnel, total internal reflection, radiance divided by eta^2
 * across the interface; eta is the relative IOR beyond the surface over the
 * side wo is on. Thin walls transmit without bending: a refracted direction
 * is the reflected one mirrored through the surface, with the Fresnel of a
 * slab (R + T^2 R / (1 - R^2)). Directions with wi.z < 0 are transmission.
 * Shared by kernels and host tests (furnace, pdf normalisation, chi-square).
 */
#ifndef PMC_BSDF_H
#define PMC_BSDF_H

#include "../abi/pmc_vec.h"
#include "pmc_bsdf_tables.h"
#include "pmc_microfacet.h"

/* The layer stack at a shading point (view-independent). */
typedef struct PmcBsdf {
  float3 diffuse;   /* Lambert albedo of the opaque base */
  float3 spec_f0;   /* dielectric specular: Schlick F0 (model 1: the closure graph's F0) */
  float3 spec_tint; /* its weight and tint (specular x specular_color); also tints glass reflection */
  float3 metal_f0;  /* conductor: Schlick F0 (the base colour) */
  float metal;      /* conductor weight (metalness) */
  float ax, ay;     /* GGX alphas of the base (tangent, bitangent) */
  float rotation;   /* of the tangent about the normal, in turns */
  float coat;       /* coat weight; its F0 and alpha: */
  float coat_f0, coat_alpha;
  float3 coat_color; /* tint of what lies under the coat */
  float sheen;       /* sheen weight, colour, roughness */
  float3 sheen_color;
  float sheen_r;
  float transmission;       /* fraction of the dielectric base that is glass */
  float3 transmission_tint; /* glass refraction tint per crossing (white with absorption) */
  float3 absorption;        /* Beer-Lambert coefficient inside, per scene unit (0: none) */
  float ior;                /* glass IOR (inside over outside) */
  int thin;                 /* thin-walled glass: no bending, no inside */
  int flat;                 /* model 1: diffuse and spec_f0 from a flattened closure graph */
  float3 emission;          /* emitted radiance */
} PmcBsdf;

/* The stack prepared for one view direction. */
typedef struct PmcLobes {
  float3 kd;               /* Lambert: f = kd / pi */
  float3 spec_p, spec_q;   /* base GGX reflection: F(c) = p + q (1 - c)^5, compensation folded in */
  float3 coat_p, coat_q;   /* coat GGX reflection, likewise */
  float3 sheen_w;          /* f = sheen_w * pmc_sheen_brdf */
  float3 glass_r, glass_t; /* glass reflection and refraction weights (tints included) */
  float ax, ay, coat_alpha, sheen_r;
  float eta; /* glass: relative IOR beyond the surface (thin walls: the IOR, for Fresnel) */
  int thin;
  /* sampling: cumulative probabilities of base GGX, coat, glass (the rest cosine) */
  float c_spec, c_coat, c_glass;
} PmcLobes;

PMC_FN PmcBsdf pmc_bsdf_zero(void) {
  PmcBsdf b;
  const float3 z = make_float3(0.0f, 0.0f, 0.0f);
  b.diffuse = b.spec_f0 = b.spec_tint = b.metal_f0 = b.coat_color = b.sheen_color = z;
  b.transmission_tint = b.absorption = b.emission = z;
  b.metal = b.coat = b.coat_f0 = b.sheen = b.transmission = b.rotation = 0.0f;
  b.ax = b.ay = b.coat_alpha = 0.25f;
  b.sheen_r = 0.3f;
  b.ior = 1.5f;
  b.thin = b.flat = 0;
  return b;
}

/* Schlick lobe of weight w and F0 f0 with compensation for alpha's E1: F = p + q m5. */
PMC_FN void pmc_schlick_lobe(float3 w, float3 f0, float e1, float3* p, float3* q) {
  const float3 one = make_float3(1.0f, 1.0f, 1.0f);
  const float3 comp = one + f0 * (1.0f / fmax(e1, 1e-3f) - 1.0f);
  *p = *p + w * comp * f0;
  *q = *q + w * comp * (one - f0);
}

PMC_FN float3 pmc_min3(float3 a, float3 b) {
  return make_float3(fmin(a.x, b.x), fmin(a.y, b.y), fmin(a.z, b.z));
}
PMC_FN float3 pmc_max0(float3 a) { return make_float3(fmax(a.x, 0.0f), fmax(a.y, 0.0f), fmax(a.z, 0.0f)); }

/* Perceptual roughness of a GGX alpha (the tables' axis). */
PMC_FN float pmc_table_rough(float alpha) { return sqrt(clamp(alpha, 0.0f, 1.0f)); }

/* The thin slab's reflectance from one interface's R (incoherent sum). */
PMC_FN float pmc_thin_fresnel(float r) { return r < 1.0f ? 2.0f * r / (1.0f + r) : 1.0f; }

/* Prepares the stack for wo (local, wo.z > 0). `entering`: wo is on the
 * outside of the glass (the side the surface's normals point to). */
PMC_FN PmcLobes pmc_bsdf_prepare(const PmcBsdf* b, float3 wo, int entering) {
  PmcLobes l;
  const float3 one = make_float3(1.0f, 1.0f, 1.0f), zero = make_float3(0.0f, 0.0f, 0.0f);
  const float mu = clamp(wo.z, 0.0f, 1.0f);
  l.ax = fmax(b->ax, PMC_MIN_ALPHA);
  l.ay = fmax(b->ay, PMC_MIN_ALPHA);
  l.coat_alpha = fmax(b->coat_alpha, PMC_MIN_ALPHA);
  l.sheen_r = b->sheen_r;
  l.thin = b->thin;
  l.eta = (entering || b->thin) ? b->ior : 1.0f / b->ior; /* thin: for its Fresnel only */
  l.spec_p = l.spec_q = l.coat_p = l.coat_q = l.sheen_w = l.glass_r = l.glass_t = l.kd = zero;
  /* Anisotropic lobes take the larger of the isotropic albedos at their two
   * alphas (it bounds theirs from above, so the compensation never adds
   * energy; measured: at the projected or the mean alpha it does, by 2-5%). */
  /* Only the base's GGX lobes (conductor, dielectric specular) read them: a
   * stack without those (Lambert alone) skips the lookups, its zero lobe
   * weights making every product with them zero either way. */
  const int base_ggx =
      b->metal > 0.0f || (b->flat ? pmc_max3(b->spec_f0) > 0.0f : pmc_max3(b->spec_tint) > 0.0f);
  /* Lambert alone (MTL's Kd materials: no conductor, specular, coat, sheen or
   * glass): the general path below multiplies kd by ones and the lobe-choice
   * probabilities by zero lobes, so it gives kd and 0 (for an albedo whose
   * luminance is below 3e-39 it would give NaN probabilities): skip it. */
  if (!base_ggx && !(b->coat > 0.0f) && !(b->sheen > 0.0f) && !(b->transmission > 0.0f)) {
    l.kd = b->flat ? pmc_min3(b->diffuse * (1.0f / fmax(1e-4f, 1.0f - pmc_luminance(b->spec_f0))), one)
                   : b->diffuse;
    l.c_spec = l.c_coat = l.c_glass = 0.0f;
    return l;
  }
  float e1 = 0.0f, e5 = 0.0f;
  if (base_ggx) {
    e1 = pmc_table_lookup(pmc_ggx_e1_table, mu, pmc_table_rough(l.ax));
    e5 = pmc_table_lookup(pmc_ggx_e5_table, mu, pmc_table_rough(l.ax));
  }
  if (base_ggx && l.ay != l.ax) {
    const float e1y = pmc_table_lookup(pmc_ggx_e1_table, mu, pmc_table_rough(l.ay));
    if (e1y > e1) {
      e1 = e1y;
      e5 = pmc_table_lookup(pmc_ggx_e5_table, mu, pmc_table_rough(l.ay));
    }
  }

  /* Coat: what it reflects, and what it lets through (tinted). */
  float3 below = one;
  float c1 = 0.0f, c5 = 0.0f; /* the coat's table albedos */
  if (b->coat > 0.0f) {
    const float rc = pmc_table_rough(l.coat_alpha);
    c1 = pmc_table_lookup(pmc_ggx_e1_table, mu, rc);
    c5 = pmc_table_lookup(pmc_ggx_e5_table, mu, rc);
    const float f0 = b->coat_f0;
    pmc_schlick_lobe(make_float3(b->coat, b->coat, b->coat), make_float3(f0, f0, f0), c1, &l.coat_p,
                     &l.coat_q);
    const float3 ec = pmc_min3(l.coat_p * c1 + l.coat_q * c5, one);
    below = (one - ec) * (one + (b->coat_color - one) * b->coat);
  }
  /* Conductor beside the dielectric base. */
  if (b->metal > 0.0f) pmc_schlick_lobe(below * b->metal, b->metal_f0, e1, &l.spec_p, &l.spec_q);
  float3 w = below * (1.0f - b->metal);
  /* Sheen over the dielectric base, normalised where its albedo would pass 1. */
  if (b->sheen > 0.0f) {
    const float es = pmc_table_lookup(pmc_sheen_e_table, mu, b->sheen_r);
    l.sheen_w = w * b->sheen_color * (b->sheen / fmax(1.0f, es));
    w = w * (1.0f - b->sheen * fmin(1.0f, es));
  }
  /* Glass. */
  if (b->transmission > 0.0f) {
    l.glass_r = w * b->spec_tint * b->transmission;
    l.glass_t = w * b->transmission_tint * b->transmission;
    if (!b->flat) w = w * (1.0f - b->transmission); /* a flattened graph's lobes already are */
  }
  /* Opaque dielectric: specular over diffuse. */
  float3 p = zero, q = zero;
  if (b->flat) {
    if (pmc_max3(b->spec_f0) > 0.0f) pmc_schlick_lobe(one, b->spec_f0, e1, &p, &q);
  } else if (pmc_max3(b->spec_tint) > 0.0f) {
    pmc_schlick_lobe(b->spec_tint, b->spec_f0, e1, &p, &q);
  }
  const float3 ed = pmc_min3(p * e1 + q * e5, one);
  float3 kd = b->diffuse;
  if (b->flat) /* the graph's diffuse is under a constant (1 - F0): replace it by (1 - E) */
    kd = pmc_min3(kd * (1.0f / fmax(1e-4f, 1.0f - pmc_luminance(b->spec_f0))), one);
  l.kd = w * kd * (one - ed);
  l.spec_p = l.spec_p + w * p;
  l.spec_q = l.spec_q + w * q;

  /* Sampling probabilities, proportional to each lobe's albedo at wo. */
  const float a_spec = pmc_luminance(l.spec_p * e1 + l.spec_q * e5);
  const float a_coat = b->coat > 0.0f ? pmc_luminance(l.coat_p * c1 + l.coat_q * c5) : 0.0f;
  const float a_glass = 0.5f * (pmc_luminance(l.glass_r) + pmc_luminance(l.glass_t));
  const float a_cos = pmc_luminance(l.kd) + pmc_luminance(l.sheen_w) * 0.5f;
  const float sum = a_spec + a_coat + a_glass + a_cos;
  const float inv = sum > 0.0f ? 1.0f / sum : 0.0f;
  l.c_spec = a_spec * inv;
  l.c_coat = l.c_spec + a_coat * inv;
  l.c_glass = sum > 0.0f ? l.c_coat + a_glass * inv : 0.0f;
  if (!(sum > 0.0f)) l.c_spec = l.c_coat = 0.0f;
  return l;
}

/* Whether the prepared stack scatters at all. */
PMC_FN int pmc_lobes_any(const PmcLobes* l) {
  return pmc_max3(l->kd + l->spec_p + l->spec_q + l->coat_p + l->coat_q + l->sheen_w + l->glass_r +
                  l->glass_t) > 0.0f;
}

/* A GGX reflection lobe's f and its VNDF pdf (wo, wi above). */
PMC_FN float3 pmc_ggx_reflection(float3 p, float3 q, float3 wo, float3 wi, float3 h, float ax, float ay,
                                 float* pdf) {
  const float d = pmc_ggx_d2(h, ax, ay);
  const float lo = pmc_ggx_lambda2(wo, ax, ay);
  *pdf = d / ((1.0f + lo) * 4.0f * wo.z);
  const float g = 1.0f / (1.0f + lo + pmc_ggx_lambda2(wi, ax, ay));
  return (p + q * pmc_schlick_m5(dot(wi, h))) * (d * g / (4.0f * wo.z * wi.z));
}

/* The glass lobe: f and the pdf of sampling wi (VNDF, then reflect with
 * probability F). */
PMC_FN float3 pmc_glass_eval(const PmcLobes* l, float3 wo, float3 wi, float* pdf) {
  *pdf = 0.0f;
  const float3 zero = make_float3(0.0f, 0.0f, 0.0f);
  const int reflect = wi.z > 0.0f;
  float3 h;
  if (reflect || l->thin) {
    const float3 wr = make_float3(wi.x, wi.y, fabs(wi.z));
    h = wo + wr;
  } else {
    h = wo + wi * l->eta;
  }
  const float hl = length(h);
  if (!(hl > 0.0f)) return zero;
  h = h * (1.0f / hl);
  if (h.z < 0.0f) h = -h;
  const float wo_h = dot(wo, h);
  if (wo_h <= 0.0f) return zero;
  float f = pmc_fresnel_dielectric(wo_h, l->eta);
  if (l->thin) f = pmc_thin_fresnel(f);
  const float d = pmc_ggx_d2(h, l->ax, l->ay);
  const float lo = pmc_ggx_lambda2(wo, l->ax, l->ay);
  const float g = 1.0f / (1.0f + lo + pmc_ggx_lambda2(wi, l->ax, l->ay));
  const float dvis = d * wo_h / ((1.0f + lo) * wo.z); /* D_wo(h) */
  const float aw = fabs(wi.z);
  if (reflect) {
    *pdf = f * dvis / (4.0f * wo_h);
    return l->glass_r * (f * d * g / (4.0f * wo.z * aw));
  }
  if (l->thin) {
    *pdf = (1.0f - f) * dvis / (4.0f * wo_h);
    return l->glass_t * ((1.0f - f) * d * g / (4.0f * wo.z * aw));
  }
  const float wi_h = dot(wi, h);
  if (wi_h >= 0.0f) return zero; /* a microfacet facing away from wi */
  const float denom = pmc_sqr(wi_h + wo_h / l->eta);
  if (!(denom > 0.0f)) return zero;
  *pdf = (1.0f - f) * dvis * fabs(wi_h) / denom;
  const float ft = (1.0f - f) * d * g * fabs(wi_h * wo_h / (denom * aw * wo.z)) / (l->eta * l->eta);
  return l->glass_t * ft;
}

/* BSDF value f(wo, wi) (without the cosine) and, in *pdf, the solid-angle
 * pdf of sampling wi given wo. wo.z > 0; wi.z < 0 is transmission. */
PMC_FN float3 pmc_bsdf_eval_pdf(const PmcLobes* l, float3 wo, float3 wi, float* pdf) {
  *pdf = 0.0f;
  float3 f = make_float3(0.0f, 0.0f, 0.0f);
  if (wo.z <= 0.0f || wi.z == 0.0f) return f;
  float p = 0.0f;
  if (l->c_glass > l->c_coat) {
    float pg;
    f = pmc_glass_eval(l, wo, wi, &pg);
    p = (l->c_glass - l->c_coat) * pg;
  }
  if (wi.z < 0.0f) {
    *pdf = p;
    return f;
  }
  const float p_cos = 1.0f - l->c_glass;
  f += l->kd * PMC_INV_PI;
  if (pmc_max3(l->sheen_w) > 0.0f) f += l->sheen_w * pmc_sheen_brdf(wo, wi, l->sheen_r);
  p += p_cos * wi.z * PMC_INV_PI;
  const int spec = l->c_spec > 0.0f || pmc_max3(l->spec_p + l->spec_q) > 0.0f;
  const int coat = l->c_coat > l->c_spec || pmc_max3(l->coat_p + l->coat_q) > 0.0f;
  const float3 h = spec || coat ? normalize(wo + wi) : wi; /* Lambert alone needs no half vector */
  if ((spec || coat) && h.z > 0.0f) {
    float ps;
    if (spec) {
      f += pmc_ggx_reflection(l->spec_p, l->spec_q, wo, wi, h, l->ax, l->ay, &ps);
      p += l->c_spec * ps;
    }
    if (coat) {
      f += pmc_ggx_reflection(l->coat_p, l->coat_q, wo, wi, h, l->coat_alpha, l->coat_alpha, &ps);
      p += (l->c_coat - l->c_spec) * ps;
    }
  }
  *pdf = p;
  return f;
}

/* BSDF value f(wo, wi) (without the cosine). */
PMC_FN float3 pmc_bsdf_eval(const PmcLobes* l, float3 wo, float3 wi) {
  float pdf;
  return pmc_bsdf_eval_pdf(l, wo, wi, &pdf);
}

/* Solid-angle pdf of sampling wi given wo. */
PMC_FN float pmc_bsdf_pdf(const PmcLobes* l, float3 wo, float3 wi) {
  float pdf;
  pmc_bsdf_eval_pdf(l, wo, wi, &pdf);
  return pdf;
}

/* Cosine-weighted hemisphere direction (concentric mapping). The shade
 * kernel's pmc_sample_cosine8 (gpu/kernels/samplers8.cl) is its float8
 * twin, the same operations in the same order: keep the two alike. */
PMC_FN float3 pmc_sample_cosine(float u1, float u2) {
  float a = 2.0f * u1 - 1.0f;
  float c = 2.0f * u2 - 1.0f;
  if (a == 0.0f && c == 0.0f) return make_float3(0.0f, 0.0f, 1.0f);
  /* both octants' values, then a select: the comparison is a coin toss per
   * sample, which as a branch cost more than the second division */
  const int wide = fabs(a) > fabs(c);
  const float r = wide ? a : c;
  const float turns = wide ? 0.125f * (c / a) : 0.25f - 0.125f * (a / c); /* the angle, in turns */
  float sin_phi, cos_phi;
  pmc_sincos_turns(turns, &sin_phi, &cos_phi);
  float x = r * cos_phi, y = r * sin_phi;
  return make_float3(x, y, sqrt(fmax(0.0f, 1.0f - x * x - y * y)));
}

/* Sample wi; returns 0 (and leaves *wi undefined) when the sample is invalid.
 * On success *pdf is the mixture pdf and *weight = f |cos| / pdf. The
 * diffuse lobe's direction is pmc_sample_cosine(u1, u2), or *cosine_wi where
 * the caller computed it already (the shade kernel, for a batch's lanes
 * together; null: here). */
PMC_FN int pmc_bsdf_sample_from(const PmcLobes* l, float3 wo, float ulobe, float u1, float u2,
                                const float3* cosine_wi, float3* wi, float* pdf, float3* weight) {
  if (wo.z <= 0.0f) return 0;
  if (ulobe < l->c_spec) {
    const float3 h = pmc_ggx_sample_vndf2(wo, l->ax, l->ay, u1, u2);
    *wi = h * (2.0f * dot(wo, h)) - wo;
  } else if (ulobe < l->c_coat) {
    const float3 h = pmc_ggx_sample_vndf(wo, l->coat_alpha, u1, u2);
    *wi = h * (2.0f * dot(wo, h)) - wo;
  } else if (ulobe < l->c_glass) {
    /* the lobe choice's leftover uniform picks reflection or refraction */
    const float usel = (ulobe - l->c_coat) / (l->c_glass - l->c_coat);
    const float3 h = pmc_ggx_sample_vndf2(wo, l->ax, l->ay, u1, u2);
    const float wo_h = dot(wo, h);
    float f = pmc_fresnel_dielectric(wo_h, l->eta);
    if (l->thin) f = pmc_thin_fresnel(f);
    *wi = h * (2.0f * wo_h) - wo;
    if (usel >= f) {
      if (l->thin) {
        (*wi).z = -(*wi).z;
      } else if (!pmc_refract(wo, h, l->eta, wi)) {
        return 0;
      }
      if ((*wi).z >= 0.0f) return 0;
    } else if ((*wi).z <= 0.0f) {
      return 0;
    }
  } else {
    *wi = cosine_wi ? *cosine_wi : pmc_sample_cosine(u1, u2);
  }
  if ((*wi).z == 0.0f || (ulobe < l->c_coat && (*wi).z < 0.0f)) return 0;
  const float3 f = pmc_bsdf_eval_pdf(l, wo, *wi, pdf);
  if (!(*pdf > 0.0f)) return 0;
  *weight = f * (fabs((*wi).z) / *pdf);
  return 1;
}
PMC_FN int pmc_bsdf_sample(const PmcLobes* l, float3 wo, float ulobe, float u1, float u2, float3* wi,
                           float* pdf, float3* weight) {
  return pmc_bsdf_sample_from(l, wo, ulobe, u1, u2, 0, wi, pdf, weight);
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

/* Render passes (core/device/pmc_passes.h). Lobes whose GGX alpha is at most
 * this are near-delta: a mirror or clear glass, which the albedo pass looks
 * through (alpha 0.01 is roughness 0.1). */
#define PMC_SPECULAR_ALPHA 0.01f

/* The prepared stack's directional albedo at wo (local, wo.z > 0): each
 * lobe's weight times its table albedo at mu_o (glass: reflection and
 * refraction weighted by the dielectric Fresnel at wo), summed
 * and clamped to [0, 1] per channel. An estimate for the albedo pass, not
 * the BSDF's exact integral. */
PMC_FN float3 pmc_lobes_albedo(const PmcLobes* l, float3 wo) {
  const float mu = clamp(wo.z, 0.0f, 1.0f);
  const float rs = pmc_table_rough(fmax(l->ax, l->ay)), rc = pmc_table_rough(l->coat_alpha);
  float3 a = l->kd;
  a += l->spec_p * pmc_table_lookup(pmc_ggx_e1_table, mu, rs) +
       l->spec_q * pmc_table_lookup(pmc_ggx_e5_table, mu, rs);
  a += l->coat_p * pmc_table_lookup(pmc_ggx_e1_table, mu, rc) +
       l->coat_q * pmc_table_lookup(pmc_ggx_e5_table, mu, rc);
  a += l->sheen_w * pmc_table_lookup(pmc_sheen_e_table, mu, l->sheen_r);
  float f = pmc_fresnel_dielectric(fmax(mu, 1e-4f), l->eta);
  if (l->thin) f = pmc_thin_fresnel(f);
  a += l->glass_r * f + l->glass_t * (1.0f - f);
  return make_float3(clamp(a.x, 0.0f, 1.0f), clamp(a.y, 0.0f, 1.0f), clamp(a.z, 0.0f, 1.0f));
}

/* Whether every lobe of the prepared stack that scatters is near-delta
 * (PMC_SPECULAR_ALPHA): no Lambert or sheen, and only smooth GGX lobes. */
PMC_FN int pmc_lobes_specular_only(const PmcLobes* l) {
  if (pmc_max3(l->kd + l->sheen_w) > 0.0f || !pmc_lobes_any(l)) return 0;
  const int smooth = fmax(l->ax, l->ay) <= PMC_SPECULAR_ALPHA;
  const int base = pmc_max3(l->spec_p + l->spec_q + l->glass_r + l->glass_t) > 0.0f;
  const int coat = pmc_max3(l->coat_p + l->coat_q) > 0.0f;
  return (!base || smooth) && (!coat || l->coat_alpha <= PMC_SPECULAR_ALPHA);
}

#endif /* PMC_BSDF_H */
