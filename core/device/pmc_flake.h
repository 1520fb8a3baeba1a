/* pmc_flake.h — MaterialX 1.39 flake2d / flake3d: a procedural pattern of
 * randomly oriented flakes (car paint, glitter). One point in, the node's four
 * outputs out; the interpreter (pmc_interp.h) calls pmc_flake() once per
 * shading point and keeps the output the instruction's imm selects
 * (PMC_FLAKE_*). Shared by the OpenCL interpreter and the host reference
 * (dialect: pmc_vec.h).
 *
 * The algorithm is MaterialX's (libraries/stdlib/genglsl/lib/mx_flake.glsl):
 *  - P = position / size (flake2d: (u, v, 0)); every integer cell c of the
 *    3x3x3 neighbourhood of floor(P) may hold one flake, a cube of half-width
 *    d = 1.5 / sqrt(3) centred at c + 0.5, randomly rotated;
 *  - the cell holds a flake if cellnoise(c) <= p(coverage), p a rational fit
 *    of the observed density (p(0) = 0, p(1) ~ 0.94);
 *  - its priority is cellnoise(c, 3); among the flakes whose rotated cube
 *    contains P the one with the highest priority wins;
 *  - rotation (Arvo, "Fast Random Rotation Matrices", Graphics Gems III) from
 *    the three-channel cellnoise of c;
 *  - outputs of the winning flake from the three-channel cellnoise of (c, 2)
 *    = (xi0, xi1, rand): rand, id = int(rand * (2^24 - 1)), presence = the
 *    priority, and the flake normal sampled from GGX with alpha = roughness^2:
 *    tan(theta) = alpha sqrt(xi1 / (1 - xi1)), phi = 2 pi xi0, in the frame
 *    (tangent, bitangent, normal), normalised;
 *  - no flake: id 0, rand 0, presence 0, flakenormal = the input normal.
 * The cellnoise hashes are pmc_noise.h's (MaterialX's lookup3 hashes of the
 * integer cell, with the same deviations: indices wrap modulo 2^32, hash
 * values never map to 1.0). A non-finite P (size 0, an infinite position)
 * has no flake.
 */
#ifndef PMC_FLAKE_H
#define PMC_FLAKE_H

#include "../abi/pmc_vec.h"
#include "pmc_noise.h"

/* Outputs of flake2d / flake3d, in the nodedef's order (imm of FLAKE). */
#define PMC_FLAKE_ID 0u
#define PMC_FLAKE_RAND 1u
#define PMC_FLAKE_PRESENCE 2u
#define PMC_FLAKE_NORMAL 3u

typedef struct PmcFlake {
  float id, rand, presence;
  float3 normal;
} PmcFlake;

/* lookup3 of five words (MaterialX mx_hash_int(x, y, z, xx, yy)). */
PMC_FN pmc_u32 pmc_flake_hash5(pmc_u32 x, pmc_u32 y, pmc_u32 z, pmc_u32 w, pmc_u32 v) {
  pmc_u32 s = pmc_noise_seed(5u);
  pmc_u32 a = s + x, b = s + y, c = s + z;
  pmc_noise_bjmix(&a, &b, &c);
  return pmc_noise_bjfinal(a + w, b + v, c);
}

/* Flake probability for a coverage x in [0, 1] (MaterialX's fitted curve). */
PMC_FN float pmc_flake_probability(float x) {
  float xx = x * x;
  return (-26.19771808f * xx + 26.39663835f * x) /
         (85.53857017f * xx * x - 102.35069432f * xx - 101.42634862f * x + 118.45082288f);
}

/* p rotated by the random rotation of the uniform numbers r (Arvo). */
PMC_FN float3 pmc_flake_rotate(float3 p, float3 r) {
  float theta = PMC_PI * 2.0f * r.x;
  float phi = PMC_PI * 2.0f * r.y;
  float z = r.z * 2.0f;
  float rr = sqrt(z);
  float vx = sin(phi) * rr, vy = cos(phi) * rr, vz = sqrt(2.0f - z);
  float st = sin(theta), ct = cos(theta);
  float sx = vx * ct - vy * st;
  float sy = vx * st + vy * ct;
  /* Rows of the matrix (MaterialX writes its columns). */
  return make_float3((vx * sx - ct) * p.x + (vy * sx + st) * p.y + (vz * sx) * p.z,
                     (vx * sy - st) * p.x + (vy * sy - ct) * p.y + (vz * sy) * p.z,
                     (vx * vz) * p.x + (vy * vz) * p.y + (1.0f - z) * p.z);
}

PMC_FN PmcFlake pmc_flake(float size, float roughness, float coverage, float3 position, float3 normal,
                          float3 tangent, float3 bitangent) {
  PmcFlake out;
  out.id = 0.0f;
  out.rand = 0.0f;
  out.presence = 0.0f;
  out.normal = normal;
  float probability = pmc_flake_probability(fmin(fmax(coverage, 0.0f), 1.0f));
  const float d = 1.5f / sqrt(3.0f);
  float3 P = make_float3(position.x / size, position.y / size, position.z / size);
  if (!pmc_noise_finite(P.x) || !pmc_noise_finite(P.y) || !pmc_noise_finite(P.z)) return out;
  float3 base = make_float3(floor(P.x), floor(P.y), floor(P.z));
  pmc_u32 bx = pmc_noise_cell(base.x), by = pmc_noise_cell(base.y), bz = pmc_noise_cell(base.z);
  float best = 0.0f;
  pmc_u32 fx = 0u, fy = 0u, fz = 0u;
  for (int i = -1; i < 2; ++i) {
    for (int j = -1; j < 2; ++j) {
      for (int k = -1; k < 2; ++k) {
        float3 pp = make_float3(P.x - (base.x + (float)i) - 0.5f, P.y - (base.y + (float)j) - 0.5f,
                                P.z - (base.z + (float)k) - 0.5f);
        if (pp.x * pp.x + pp.y * pp.y + pp.z * pp.z >= d * d * 3.0f) continue;
        pmc_u32 cx = bx + (pmc_u32)i, cy = by + (pmc_u32)j, cz = bz + (pmc_u32)k;
        if (pmc_noise_to01(pmc_noise_hash3(cx, cy, cz)) > probability) continue;
        float priority = pmc_noise_to01(pmc_noise_hash4(cx, cy, cz, 3u));
        if (priority < best) continue;
        float3 rot = make_float3(pmc_noise_to01(pmc_noise_hash4(cx, cy, cz, 0u)),
                                 pmc_noise_to01(pmc_noise_hash4(cx, cy, cz, 1u)),
                                 pmc_noise_to01(pmc_noise_hash4(cx, cy, cz, 2u)));
        pp = pmc_flake_rotate(pp, rot);
        if (fabs(pp.x) <= d && fabs(pp.y) <= d && fabs(pp.z) <= d) {
          best = priority;
          fx = cx;
          fy = cy;
          fz = cz;
        }
      }
    }
  }
  if (best <= 0.0f) return out;
  float xi0 = pmc_noise_to01(pmc_flake_hash5(fx, fy, fz, 2u, 0u));
  float xi1 = pmc_noise_to01(pmc_flake_hash5(fx, fy, fz, 2u, 1u));
  out.rand = pmc_noise_to01(pmc_flake_hash5(fx, fy, fz, 2u, 2u));
  out.id = (float)(int)(out.rand * 16777215.0f);
  out.presence = best;
  float phi = PMC_PI * 2.0f * xi0;
  float tan_theta = roughness * roughness * sqrt(xi1) / sqrt(1.0f - xi1);
  float sin_theta = tan_theta / sqrt(1.0f + tan_theta * tan_theta);
  float cos_theta = sqrt(1.0f - sin_theta * sin_theta);
  float a = cos(phi) * sin_theta, b = sin(phi) * sin_theta;
  float3 m = make_float3(tangent.x * a + bitangent.x * b + normal.x * cos_theta,
                         tangent.y * a + bitangent.y * b + normal.y * cos_theta,
                         tangent.z * a + bitangent.z * b + normal.z * cos_theta);
  float l2 = m.x * m.x + m.y * m.y + m.z * m.z;
  out.normal = l2 > 0.0f ? m * (1.0f / sqrt(l2)) : m;
  return out;
}

/* The output `which` (PMC_FLAKE_*) as an instruction result. */
PMC_FN float4 pmc_flake_output(PmcFlake f, pmc_u32 which) {
  if (which == PMC_FLAKE_ID) return make_float4(f.id, 0.0f, 0.0f, 0.0f);
  if (which == PMC_FLAKE_RAND) return make_float4(f.rand, 0.0f, 0.0f, 0.0f);
  if (which == PMC_FLAKE_PRESENCE) return make_float4(f.presence, 0.0f, 0.0f, 0.0f);
  return make_float4(f.normal.x, f.normal.y, f.normal.z, 0.0f);
}

#endif /* PMC_FLAKE_H */
