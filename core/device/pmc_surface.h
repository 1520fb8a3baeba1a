/* pmc_surface.h — a material's surface parameter block (PMC_P_*, written by
 * its bytecode; pmc_interp.h) as the layer stack of pmc_bsdf.h.
 *
 * Model 0 reads the block as standard_surface (the node table maps
 * open_pbr_surface, gltf_pbr, UsdPreviewSurface, disney_principled and MTL
 * onto the same inputs): base and base_color, metalness, specular weight and
 * colour with F0 from specular_IOR, roughness with MaterialX's anisotropy
 * mapping (roughness_anisotropy), coat (weight, colour, roughness, IOR),
 * sheen, transmission (colour as a tint per crossing, or with
 * transmission_depth > 0 as Beer-Lambert absorption of -ln(colour) / depth
 * per scene unit), thin_walled and emission. Model 1 is a flattened closure
 * graph: a diffuse albedo under a constant (1 - F0) and a Schlick F0, as
 * materials/closure_flatten.cpp writes them. Non-finite or out-of-range
 * values are clamped to the inputs' ranges.
 */
#ifndef PMC_SURFACE_H
#define PMC_SURFACE_H

#include "../abi/pmc_bytecode.h"
#include "pmc_bsdf.h"

PMC_FN float pmc_nonneg(float x) { return x > 0.0f && isfinite(x) ? x : 0.0f; }
PMC_FN float pmc_unit(float x, float fallback) { return isfinite(x) ? clamp(x, 0.0f, 1.0f) : fallback; }
PMC_FN float3 pmc_param3(const float* p, int i) {
  return make_float3(pmc_nonneg(p[i]), pmc_nonneg(p[i + 1]), pmc_nonneg(p[i + 2]));
}
PMC_FN float3 pmc_param3_unit(const float* p, int i) {
  return make_float3(pmc_unit(p[i], 0.0f), pmc_unit(p[i + 1], 0.0f), pmc_unit(p[i + 2], 0.0f));
}
/* Normal-incidence reflectance of a dielectric of this IOR (0.04 for nonsense). */
PMC_FN float pmc_f0_of_ior(float ior) {
  return isfinite(ior) && ior > 0.0f ? pmc_sqr((ior - 1.0f) / (ior + 1.0f)) : 0.04f;
}

PMC_FN PmcBsdf pmc_surface_to_bsdf(const float* p) {
  PmcBsdf b = pmc_bsdf_zero();
  const float3 one = make_float3(1.0f, 1.0f, 1.0f);
  const float rough = pmc_unit(p[PMC_P_SPECULAR_ROUGHNESS], 0.5f);
  const float a = fmin(fmax(rough * rough, 1.1920929e-7f), 1.0f);
  const float aniso = pmc_unit(p[PMC_P_SPECULAR_ANISOTROPY], 0.0f);
  if (aniso > 0.0f) { /* MaterialX's roughness_anisotropy */
    const float s = sqrt(1.0f - fmin(aniso, 0.98f));
    b.ax = fmin(a / s, 1.0f);
    b.ay = a * s;
    const float rot = p[PMC_P_SPECULAR_ROTATION];
    b.rotation = isfinite(rot) ? rot - floor(rot) : 0.0f;
  } else {
    b.ax = b.ay = a;
  }
  b.emission = pmc_param3(p, PMC_P_EMISSION_COLOR) * pmc_nonneg(p[PMC_P_EMISSION]);
  float ior = p[PMC_P_SPECULAR_IOR];
  b.ior = isfinite(ior) && ior > 0.0f ? clamp(ior, 1.0f / 8.0f, 8.0f) : 1.5f;
  b.thin = p[PMC_P_THIN_WALLED] > 0.5f;
  b.transmission = pmc_unit(p[PMC_P_TRANSMISSION], 0.0f);
  if (b.transmission > 0.0f) {
    const float3 tc = pmc_param3_unit(p, PMC_P_TRANSMISSION_COLOR);
    const float depth = pmc_nonneg(p[PMC_P_TRANSMISSION_DEPTH]);
    if (depth > 0.0f && !b.thin) {
      b.transmission_tint = one;
      b.absorption = make_float3(-log(fmax(tc.x, 1e-4f)), -log(fmax(tc.y, 1e-4f)), -log(fmax(tc.z, 1e-4f))) *
                     (1.0f / depth);
    } else {
      b.transmission_tint = tc;
    }
  }
  if (p[PMC_P_MODEL] > 0.5f) { /* a flattened closure graph */
    b.flat = 1;
    b.diffuse = pmc_param3(p, PMC_P_BASE_COLOR);
    b.spec_f0 = pmc_param3_unit(p, PMC_P_SPECULAR_COLOR);
    b.spec_tint = one;
    return b;
  }
  const float3 base_color = pmc_param3_unit(p, PMC_P_BASE_COLOR) * pmc_unit(p[PMC_P_BASE], 1.0f);
  b.diffuse = base_color;
  b.metal = pmc_unit(p[PMC_P_METALNESS], 0.0f);
  b.metal_f0 = base_color;
  const float f0 = pmc_f0_of_ior(b.ior);
  b.spec_f0 = make_float3(f0, f0, f0);
  b.spec_tint = pmc_param3_unit(p, PMC_P_SPECULAR_COLOR) * pmc_unit(p[PMC_P_SPECULAR], 1.0f);
  b.coat = pmc_unit(p[PMC_P_COAT], 0.0f);
  if (b.coat > 0.0f) {
    const float cr = pmc_unit(p[PMC_P_COAT_ROUGHNESS], 0.1f);
    b.coat_alpha = cr * cr;
    b.coat_f0 = pmc_f0_of_ior(p[PMC_P_COAT_IOR]);
    b.coat_color = pmc_param3_unit(p, PMC_P_COAT_COLOR);
  }
  b.sheen = pmc_unit(p[PMC_P_SHEEN], 0.0f);
  if (b.sheen > 0.0f) {
    b.sheen_color = pmc_param3_unit(p, PMC_P_SHEEN_COLOR);
    b.sheen_r = pmc_unit(p[PMC_P_SHEEN_ROUGHNESS], 0.3f);
  }
  return b;
}

#endif /* PMC_SURFACE_H */
