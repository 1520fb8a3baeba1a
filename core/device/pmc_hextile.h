/* pmc_hextile.h — MaterialX 1.39 hextiledimage and hextilednormalmap: an
 * image repeated over a hexagonal grid of tiles, each tile with its own random
 * rotation, scale and offset, blended so that no seams or repeats show
 * (Mikkelsen, "Practical Real-Time Hex-Tiling", JCGT 11(2), 2022). Shared by
 * the OpenCL interpreter and the host reference (dialect: pmc_vec.h).
 *
 * The grid: p = texcoord * tiling is scaled by 2 sqrt(3) and skewed into a
 * triangle lattice, (a, b) = (x - y / sqrt(3), 2 y / sqrt(3)). Every lattice
 * vertex is the centre of one hexagonal tile; a point lies in one triangle of
 * the lattice and its barycentric coordinates there weigh the three tiles
 * whose centres are the triangle's corners (1 at a centre, 0 on the far
 * edge). Tile i with centre c_i reads the image at
 *   q_i = c_i + R(angle_i) (p - c_i) / scale_i + offset_i
 * (R a counter-clockwise rotation in uv), where for two per-tile random
 * numbers (u, v) in [0, 1):
 *   angle_i  = radians(mix(rotationrange.x, rotationrange.y, u * rotation))
 *   scale_i  = mix(1, mix(scalerange.x, scalerange.y, v), scale)
 *   offset_i = mix(offsetrange.x, offsetrange.y, (u, v) * offset)
 * as MaterialX's implementations compute them. The random numbers come from
 * pmc's integer lattice hash of the tile's lattice index (pmc_noise.h), exact
 * on every device; MaterialX's GLSL hashes with float arithmetic, so the tile
 * pattern has the same statistics but is not the same pattern. q_i is written
 * as p + (R (p - c_i) / scale_i - (p - c_i)) + offset_i so that a tile without
 * randomness reads exactly p: the node then equals the plain tiled image.
 * Each read is filtered like `image`, its footprint divided by scale_i and
 * its ellipse's axis turned by angle_i (q_i's derivative is R(angle_i) /
 * scale_i).
 *
 * Blending: weight_i = luma_i * bary_i^7, normalised; a falloff other than
 * 0.5 then applies Schlick's gain (Graphics Gems IV) to each weight and
 * normalises again. For colours luma_i = mix(1, luminance(colour_i),
 * falloffcontrast) (brighter tiles win at the seams); alpha and normals blend
 * with luma_i = 1. Normals: each tile's tangent-space normal is decoded in
 * that tile's frame, the tangent and bitangent turned about the normal by
 * -angle_i (a tile that reads the image turned by +angle shows it turned by
 * -angle, so its slopes turn by -angle too), and the three normals are
 * blended as surface gradients (Mikkelsen, JCGT 9(3), 2020):
 *   g_i = (dot(N, N_i) N - N_i) / max(1e-6, |dot(N, N_i)|),
 *   out = normalize(N - sum w_i g_i).
 * MaterialX's GLSL and OSL turn the frame by +angle; -angle is the one that
 * agrees with hex-tiling the height field the normal map was baked from
 * (tests/materials/hextile_test.cpp checks it). As in pmc's normalmap, the
 * bitangent is cross(normal, tangent).
 */
#ifndef PMC_HEXTILE_H
#define PMC_HEXTILE_H

#include "../abi/pmc_vec.h"
#include "pmc_noise.h"
#include "pmc_texture.h"

/* The three tiles that cover one point. */
typedef struct PmcHexTiles {
  float2 coord[3]; /* where each tile reads the image */
  float bary[3];   /* barycentric weights of the tiles, summing to 1 */
  float angle[3];  /* each tile's rotation, radians */
  float scale[3];  /* each tile's scale (its footprint is divided by it) */
} PmcHexTiles;

/* Schlick's gain: x in [0, 1] pulled towards 0.5 (r > 0.5: softer seams) or
 * pushed towards 0 and 1 (r < 0.5: sharper ones); r = 0.5 is the identity. */
PMC_FN float pmc_hextile_gain(float x, float r) {
  float rr = clamp(r, 0.001f, 0.999f);
  float a = (1.0f / rr - 2.0f) * (1.0f - 2.0f * x);
  return x < 0.5f ? x / (a + 1.0f) : (a - x) / (a - 1.0f);
}

/* The tiles over p (texcoord * tiling already applied). */
PMC_FN PmcHexTiles pmc_hextile_tiles(float2 p, float rotation, float2 rotation_range, float scale,
                                     float2 scale_range, float offset, float2 offset_range) {
  const float sqrt3 = 1.7320508f;
  /* Coordinates too large for a lattice index (or NaN) read the tile at 0. */
  if (!(fabs(p.x) < 1e30f)) p.x = 0.0f;
  if (!(fabs(p.y) < 1e30f)) p.y = 0.0f;
  float x = p.x * (2.0f * sqrt3), y = p.y * (2.0f * sqrt3);
  float a = x - y * (1.0f / sqrt3), b = y * (2.0f / sqrt3);
  pmc_u32 ia, ib;
  float fa = pmc_noise_floorfrac(a, &ia), fb = pmc_noise_floorfrac(b, &ib);
  float rest = 1.0f - fa - fb;
  /* Lattice offsets of the three corners and their weights: the lower
   * triangle (0,0), (0,1), (1,0), or the upper one (1,1), (1,0), (0,1). */
  int upper = rest < 0.0f;
  pmc_u32 da[3], db[3];
  PmcHexTiles t;
  if (upper) {
    da[0] = 1u, db[0] = 1u, t.bary[0] = -rest;
    da[1] = 1u, db[1] = 0u, t.bary[1] = 1.0f - fb;
    da[2] = 0u, db[2] = 1u, t.bary[2] = 1.0f - fa;
  } else {
    da[0] = 0u, db[0] = 0u, t.bary[0] = rest;
    da[1] = 0u, db[1] = 1u, t.bary[1] = fb;
    da[2] = 1u, db[2] = 0u, t.bary[2] = fa;
  }
  float ca0 = floor(a), cb0 = floor(b); /* the triangle's lattice origin */
  for (int i = 0; i < 3; ++i) {
    /* The tile's centre back in uv: unskew, then undo the 2 sqrt(3) scale. */
    float ca = ca0 + (float)da[i], cb = cb0 + (float)db[i];
    float2 c = make_float2((ca + 0.5f * cb) * (1.0f / (2.0f * sqrt3)), cb * (sqrt3 * 0.5f) / (2.0f * sqrt3));
    pmc_u32 ka = ia + da[i], kb = ib + db[i];
    float u = pmc_noise_to01(pmc_noise_hash3(ka, kb, 0u));
    float v = pmc_noise_to01(pmc_noise_hash3(ka, kb, 1u));
    float deg = rotation_range.x + (rotation_range.y - rotation_range.x) * (u * rotation);
    float angle = deg * (3.14159265f / 180.0f);
    float s = 1.0f + (scale_range.x + (scale_range.y - scale_range.x) * v - 1.0f) * scale;
    float2 off = make_float2(offset_range.x + (offset_range.y - offset_range.x) * (u * offset),
                             offset_range.x + (offset_range.y - offset_range.x) * (v * offset));
    float sn = sin(angle), cs = cos(angle);
    float2 d = p - c;
    float2 r = make_float2(cs * d.x - sn * d.y, sn * d.x + cs * d.y) * (1.0f / s);
    t.coord[i] = p + (r - d) + off;
    t.angle[i] = angle;
    t.scale[i] = s;
  }
  return t;
}

/* Blend weights of the three tiles: luma_i * bary_i^7, normalised, then the
 * falloff gain (see the top of the file). Weights that do not sum to a
 * positive number (luma all 0 at a tile centre) fall back to luma 1. */
PMC_FN float3 pmc_hextile_weights(const PmcHexTiles* t, float3 luma, float falloff) {
  float b[3];
  for (int i = 0; i < 3; ++i) {
    float x = t->bary[i], x2 = x * x, x4 = x2 * x2;
    b[i] = x4 * x2 * x;
  }
  float3 w = make_float3(luma.x * b[0], luma.y * b[1], luma.z * b[2]);
  float sum = w.x + w.y + w.z;
  if (!(sum > 0.0f) || !isfinite(sum)) {
    w = make_float3(b[0], b[1], b[2]);
    sum = w.x + w.y + w.z;
  }
  w = w * (1.0f / sum);
  if (falloff != 0.5f) {
    w = make_float3(pmc_hextile_gain(w.x, falloff), pmc_hextile_gain(w.y, falloff),
                    pmc_hextile_gain(w.z, falloff));
    sum = w.x + w.y + w.z;
    if (sum != 0.0f) w = w * (1.0f / sum);
  }
  return w;
}

/* Reads tile i's texel: `fp` is the point's uv footprint times the tiling
 * (its axis 0: isotropic); `fallback` is the value where there is no texture. */
PMC_FN float4 pmc_hextile_sample(const PmcTextureSet* ts, pmc_u32 index, const PmcHexTiles* t, int i,
                                 PmcFootprint fp, pmc_u32 mode, float4 fallback) {
  float s = fabs(t->scale[i]);
  float k = s > 0.0f ? 1.0f / s : 1.0f;
  float2 axis = fp.axis;
  if (axis.x != 0.0f || axis.y != 0.0f) {
    float sn = sin(t->angle[i]), cs = cos(t->angle[i]);
    axis = make_float2(cs * fp.axis.x - sn * fp.axis.y, sn * fp.axis.x + cs * fp.axis.y) * k;
  }
  return pmc_texture_sample_ellipse(ts, index, t->coord[i], s > 0.0f ? fp.width / s : fp.width, axis,
                                    fp.minor * k, mode & 3u, (mode >> 2) & 3u, (mode >> 4) & 3u, fallback);
}

/* hextiledimage: the colour of the three tiles, blended by luminance. */
PMC_FN float4 pmc_hextile_image(const PmcTextureSet* ts, pmc_u32 index, const PmcHexTiles* t, PmcFootprint fp,
                                pmc_u32 mode, float4 fallback, float falloff, float contrast,
                                float3 lumacoeffs) {
  float4 c[3];
  float l[3];
  for (int i = 0; i < 3; ++i) {
    c[i] = pmc_hextile_sample(ts, index, t, i, fp, mode, fallback);
    float y = c[i].x * lumacoeffs.x + c[i].y * lumacoeffs.y + c[i].z * lumacoeffs.z;
    l[i] = 1.0f + (y - 1.0f) * contrast;
  }
  float3 w = pmc_hextile_weights(t, make_float3(l[0], l[1], l[2]), falloff);
  float3 aw = pmc_hextile_weights(t, make_float3(1.0f, 1.0f, 1.0f), falloff);
  float4 r = c[0] * w.x + c[1] * w.y + c[2] * w.z;
  r.w = c[0].w * aw.x + c[1].w * aw.y + c[2].w * aw.z;
  return r;
}

/* v turned by `angle` about the unit axis n (Rodrigues). */
PMC_FN float3 pmc_hextile_turn(float3 v, float3 n, float angle) {
  float sn = sin(angle), cs = cos(angle);
  return v * cs + cross(n, v) * sn + n * (dot(n, v) * (1.0f - cs));
}

/* hextilednormalmap: a world normal from the three tiles' normals. */
PMC_FN float4 pmc_hextile_normalmap(const PmcTextureSet* ts, pmc_u32 index, const PmcHexTiles* t,
                                    PmcFootprint fp, pmc_u32 mode, float4 fallback, float falloff,
                                    float strength, int flip_g, float3 n, float3 tangent) {
  float3 w = pmc_hextile_weights(t, make_float3(1.0f, 1.0f, 1.0f), falloff);
  float wi[3] = {clamp(w.x, 0.0f, 1.0f), clamp(w.y, 0.0f, 1.0f), clamp(w.z, 0.0f, 1.0f)};
  float3 g = make_float3(0.0f, 0.0f, 0.0f);
  for (int i = 0; i < 3; ++i) {
    float4 c = pmc_hextile_sample(ts, index, t, i, fp, mode, fallback);
    if (flip_g) c.y = 1.0f - c.y;
    float3 v = make_float3(c.x * 2.0f - 1.0f, c.y * 2.0f - 1.0f, c.z * 2.0f - 1.0f);
    float3 ti = pmc_hextile_turn(tangent, n, -t->angle[i]);
    float3 bi = cross(n, ti);
    float3 ni = ti * (v.x * strength) + bi * (v.y * strength) + n * v.z;
    float len = length(ni);
    ni = len > 0.0f && isfinite(len) ? ni * (1.0f / len) : n;
    float d = dot(n, ni);
    g = g + (n * d - ni) * (wi[i] / fmax(1e-6f, fabs(d)));
  }
  float3 r = n - g;
  float len = length(r);
  r = len > 0.0f && isfinite(len) ? r * (1.0f / len) : n;
  return make_float4(r.x, r.y, r.z, 0.0f);
}

#endif /* PMC_HEXTILE_H */
