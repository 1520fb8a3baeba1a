/* pmc_hair_data.h — MaterialX pbrlib's hair data nodes (their outputs are
 * data for chiang_hair_bsdf, which pmc does not render):
 * chiang_hair_roughness, deon_hair_absorption_from_melanin,
 * chiang_hair_absorption_from_color. One point's operands in, the result
 * out; shared by the OpenCL interpreter and the host reference (dialect:
 * pmc_vec.h). The math is MaterialX 1.39's
 * (libraries/pbrlib/genglsl/mx_chiang_hair_bsdf.glsl):
 *   chiang_hair_roughness   l = clamp(longitudinal, 0.001, 1),
 *                           a = clamp(azimuthal, 0.001, 1);
 *                           v = (0.726 l + 0.812 l^2 + 3.7 l^20)^2,
 *                           s = 0.265 a + 1.194 a^2 + 5.372 a^22 (Chiang et
 *                           al. 2016, eqs. 7-8); outputs roughness_R (v, s),
 *                           roughness_TT (v scale_TT^2, s),
 *                           roughness_TRT (v scale_TRT^2, s)
 *   deon_hair_absorption    m = -log(max(1 - concentration, 1e-4)),
 *     _from_melanin         eumelanin m (1 - redness), pheomelanin m redness;
 *                           max(eu * -log(eumelanin_color) + pheo *
 *                           -log(pheomelanin_color), 0) (d'Eon et al. 2011)
 *   chiang_hair_absorption  b = 5.969 - 0.215 beta + 2.532 beta^2 -
 *     _from_color           10.73 beta^3 + 5.574 beta^4 + 0.245 beta^5
 *                           (beta = azimuthal_roughness);
 *                           (log(clamp(color, 0.001, 1)) / b)^2 (Chiang et al.
 *                           2016, eq. 9)
 */
#ifndef PMC_HAIR_DATA_H
#define PMC_HAIR_DATA_H

#include "../abi/pmc_vec.h"

/* Outputs of chiang_hair_roughness, in its definition's order (the imm). */
#define PMC_HAIR_R 0u
#define PMC_HAIR_TT 1u
#define PMC_HAIR_TRT 2u

PMC_FN float4 pmc_chiang_hair_roughness(float longitudinal, float azimuthal, float scale_tt, float scale_trt,
                                        unsigned output) {
  float l = fmin(fmax(longitudinal, 0.001f), 1.0f);
  float a = fmin(fmax(azimuthal, 0.001f), 1.0f);
  float v = 0.726f * l + 0.812f * l * l + 3.7f * pow(l, 20.0f);
  v = v * v;
  float s = 0.265f * a + 1.194f * a * a + 5.372f * pow(a, 22.0f);
  float scale = output == PMC_HAIR_TT    ? scale_tt * scale_tt
                : output == PMC_HAIR_TRT ? scale_trt * scale_trt
                                         : 1.0f;
  return make_float4(v * scale, s, 0.0f, 0.0f);
}

PMC_FN float pmc_deon_hair_absorption1(float eumelanin, float pheomelanin, float eu_color, float pheo_color) {
  return fmax(eumelanin * -log(eu_color) + pheomelanin * -log(pheo_color), 0.0f);
}

PMC_FN float4 pmc_deon_hair_absorption(float concentration, float redness, float4 eu_color,
                                       float4 pheo_color) {
  float melanin = -log(fmax(1.0f - concentration, 0.0001f));
  float eu = melanin * (1.0f - redness), pheo = melanin * redness;
  return make_float4(pmc_deon_hair_absorption1(eu, pheo, eu_color.x, pheo_color.x),
                     pmc_deon_hair_absorption1(eu, pheo, eu_color.y, pheo_color.y),
                     pmc_deon_hair_absorption1(eu, pheo, eu_color.z, pheo_color.z), 0.0f);
}

PMC_FN float pmc_chiang_hair_absorption1(float c, float b_fac) {
  float sigma = log(fmin(fmax(c, 0.001f), 1.0f)) / b_fac;
  return sigma * sigma;
}

PMC_FN float4 pmc_chiang_hair_absorption(float4 color, float beta) {
  float b2 = beta * beta, b4 = b2 * b2;
  float b_fac = 5.969f - 0.215f * beta + 2.532f * b2 - 10.73f * b2 * beta + 5.574f * b4 + 0.245f * b4 * beta;
  return make_float4(pmc_chiang_hair_absorption1(color.x, b_fac), pmc_chiang_hair_absorption1(color.y, b_fac),
                     pmc_chiang_hair_absorption1(color.z, b_fac), 0.0f);
}

#endif /* PMC_HAIR_DATA_H */
