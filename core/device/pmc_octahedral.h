/* pmc_octahedral.h — unit vectors in 32 bits (two 16-bit snorms of the
 * octahedral map, Cigolle et al. 2014), shared by host and kernels: the
 * triangle records carry their corners' tangents this way (3 words instead
 * of 9 floats; the error is below 1e-3 radians, 0.06 degrees). */
#ifndef PMC_OCTAHEDRAL_H
#define PMC_OCTAHEDRAL_H

#include "../abi/pmc_vec.h"

PMC_FN float pmc_sign_nz(float x) { return x >= 0.0f ? 1.0f : -1.0f; }

/* A unit vector as two 16-bit snorms (x in the low half). */
PMC_FN pmc_u32 pmc_oct_encode(float3 v) {
  const float l1 = fabs(v.x) + fabs(v.y) + fabs(v.z);
  float x = v.x / l1, y = v.y / l1;
  if (v.z < 0.0f) {
    const float ox = (1.0f - fabs(y)) * pmc_sign_nz(x), oy = (1.0f - fabs(x)) * pmc_sign_nz(y);
    x = ox;
    y = oy;
  }
  const int qx = (int)rint(clamp(x, -1.0f, 1.0f) * 32767.0f);
  const int qy = (int)rint(clamp(y, -1.0f, 1.0f) * 32767.0f);
  return ((pmc_u32)(qx & 0xffff)) | ((pmc_u32)(qy & 0xffff) << 16);
}

PMC_FN float pmc_snorm16(pmc_u32 bits) {
  const int v = (int)(bits & 0xffffu);
  return (float)(v >= 32768 ? v - 65536 : v) * (1.0f / 32767.0f);
}

/* The unit vector of pmc_oct_encode's word. Straight-line code (selects, and
 * normalize's arithmetic without its guards for tiny and huge vectors: the
 * unfolded vector's length is at least 1/sqrt(3)), so that a hit's three
 * corner tangents decode side by side; the same floats as normalize(). */
PMC_FN float3 pmc_oct_decode(pmc_u32 w) {
  const float x = pmc_snorm16(w), y = pmc_snorm16(w >> 16);
  const float z = 1.0f - fabs(x) - fabs(y);
  const float ox = (1.0f - fabs(y)) * pmc_sign_nz(x), oy = (1.0f - fabs(x)) * pmc_sign_nz(y);
  const float3 v = make_float3(z < 0.0f ? ox : x, z < 0.0f ? oy : y, z);
  return v * (1.0f / sqrt(dot(v, v)));
}

#endif /* PMC_OCTAHEDRAL_H */
