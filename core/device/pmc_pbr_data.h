/* pmc_pbr_data.h — MaterialX pbrlib nodes whose outputs are data, not
 * closures: roughness_anisotropy, roughness_dual, artistic_ior, blackbody.
 * One point's operands in, the result out; the interpreter (pmc_interp.h)
 * calls these once per shading point. Shared by the OpenCL interpreter and the
 * host reference (dialect: pmc_vec.h). The math is MaterialX 1.39's
 * (libraries/pbrlib/genglsl/mx_*.glsl), with eps = FLT_EPSILON:
 *   roughness_anisotropy  a = clamp(r^2, eps, 1); anisotropy > 0:
 *                         s = sqrt(1 - clamp(anisotropy, 0, 0.98)),
 *                         (min(a / s, 1), a s); else (a, a)
 *   roughness_dual        y < 0 takes x; (clamp(x^2, eps, 1), clamp(y^2, eps, 1))
 *   artistic_ior          Gulbrandsen, "Artist Friendly Metallic Fresnel" (JCGT
 *                         2014), per channel with r = clamp(reflectivity, 0, 0.99),
 *                         g = edge_color: n = mix((1 + sqrt r) / (1 - sqrt r),
 *                         (1 - r) / (1 + r), g), k = sqrt(max(((n + 1)^2 r -
 *                         (n - 1)^2) / (1 - r), 0)); outputs ior n, extinction k
 *   blackbody             T clamped to [800, 25000] K; the Planckian locus in
 *                         CIE xy by Kang et al. (2002)'s cubic fits in 1000/T and
 *                         x (MaterialX's constants), Y = 1, XYZ -> linear Rec.709
 *                         (sRGB primaries, D65), negative channels clamped to 0
 */
#ifndef PMC_PBR_DATA_H
#define PMC_PBR_DATA_H

#include "../abi/pmc_vec.h"

#define PMC_FLT_EPSILON 1.1920928955078125e-7f

PMC_FN float2 pmc_roughness_anisotropy(float roughness, float anisotropy) {
  float a = fmin(fmax(roughness * roughness, PMC_FLT_EPSILON), 1.0f);
  if (!(anisotropy > 0.0f)) return make_float2(a, a);
  float s = sqrt(1.0f - fmin(fmax(anisotropy, 0.0f), 0.98f));
  return make_float2(fmin(a / s, 1.0f), a * s);
}

PMC_FN float2 pmc_roughness_dual(float2 r) {
  float y = r.y < 0.0f ? r.x : r.y;
  return make_float2(fmin(fmax(r.x * r.x, PMC_FLT_EPSILON), 1.0f), fmin(fmax(y * y, PMC_FLT_EPSILON), 1.0f));
}

/* One channel of artistic_ior: extinction != 0 returns k, else n. */
PMC_FN float pmc_artistic_ior1(float reflectivity, float edge_color, int extinction) {
  float r = fmin(fmax(reflectivity, 0.0f), 0.99f);
  float rs = sqrt(r);
  float n_min = (1.0f - r) / (1.0f + r);
  float n_max = (1.0f + rs) / (1.0f - rs);
  /* GLSL's mix(n_max, n_min, edge_color) as MaterialX defines it, x (1 - a) +
   * y a: at edge colours near 1, n_max + (n_min - n_max) a subtracts two
   * nearly equal products of n_max (up to 199 at r 0.99) and loses the
   * small n's digits to n_max's rounding */
  float n = n_max * (1.0f - edge_color) + n_min * edge_color;
  if (!extinction) return n;
  float np1 = n + 1.0f, nm1 = n - 1.0f;
  float k2 = (np1 * np1 * r - nm1 * nm1) / (1.0f - r);
  return sqrt(fmax(k2, 0.0f));
}

PMC_FN float4 pmc_artistic_ior(float4 reflectivity, float4 edge_color, int extinction) {
  return make_float4(pmc_artistic_ior1(reflectivity.x, edge_color.x, extinction),
                     pmc_artistic_ior1(reflectivity.y, edge_color.y, extinction),
                     pmc_artistic_ior1(reflectivity.z, edge_color.z, extinction), 0.0f);
}

PMC_FN float4 pmc_blackbody(float kelvin) {
  float T = fmin(fmax(kelvin, 800.0f), 25000.0f); /* NaN -> 800 K */
  float t = 1000.0f / T, t2 = t * t, t3 = t * t * t;
  float x = T < 4000.0f ? -0.2661239f * t3 - 0.2343580f * t2 + 0.8776956f * t + 0.179910f
                        : -3.0258469f * t3 + 2.1070379f * t2 + 0.2226347f * t + 0.240390f;
  float x2 = x * x, x3 = x * x * x;
  float y;
  if (T < 2222.0f)
    y = -1.1063814f * x3 - 1.34811020f * x2 + 2.18555832f * x - 0.20219683f;
  else if (T < 4000.0f)
    y = -0.9549476f * x3 - 1.37418593f * x2 + 2.09137015f * x - 0.16748867f;
  else
    y = 3.0817580f * x3 - 5.87338670f * x2 + 3.75112997f * x - 0.37001483f;
  if (y <= 0.0f) return make_float4(1.0f, 1.0f, 1.0f, 0.0f);
  float X = x / y, Z = (1.0f - x - y) / y; /* Y = 1 */
  float r = 3.2406f * X - 1.5372f - 0.4986f * Z;
  float g = -0.9689f * X + 1.8758f + 0.0415f * Z;
  float b = 0.0557f * X - 0.2040f + 1.0570f * Z;
  return make_float4(fmax(r, 0.0f), fmax(g, 0.0f), fmax(b, 0.0f), 0.0f);
}

#endif /* PMC_PBR_DATA_H */
