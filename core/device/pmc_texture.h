/* pmc_texture.h — filtered texture lookups, shared by kernels and host.
 *
 * Textures live in one pool of RGBA8 texels packed in 32-bit words (all mip
 * levels of all textures back to back, see PmcTexture). A lookup takes a uv,
 * MaterialX address modes (constant, clamp, periodic, mirror), a filter, and
 * a footprint in uv units from the ray cone; the footprint picks the mip
 * level (trilinear between the two nearest levels). With the footprint's
 * ellipse (pmc_texture_sample_ellipse) a few such lookups along its major
 * axis, each at the level of its minor axis, filter anisotropically. sRGB-encoded texels are
 * decoded through a 256-entry table. OBJ/MaterialX convention: v = 0 is the
 * bottom row of the image. The host runs the same code for the CPU reference
 * interpreter and the cut-out opacity filter.
 */
#ifndef PMC_TEXTURE_H
#define PMC_TEXTURE_H

#include "../abi/pmc_bytecode.h"
#include "../abi/pmc_types.h"

typedef struct PmcTextureSet {
  PMC_GLOBAL const PmcTexture* textures;
  PMC_GLOBAL const pmc_u32* texels; /* RGBA8, r in the low byte */
  PMC_CONSTANT const float* srgb_lut;
  pmc_u32 count;
} PmcTextureSet;

/* i mod n in [0, n). The lookups' indices lie within one period of the
 * range (pmc_reduce_coord), so they take the branches, not the division
 * (an integer division cost about a tenth of a bilinear lookup). */
PMC_FN int pmc_wrap_periodic(int i, int n) {
  if (i >= 0 && i < n) return i;
  if (i < 0 && i >= -n) return i + n;
  if (i >= n && i - n < n) return i - n;
  int m = i % n;
  return m < 0 ? m + n : m;
}

/* Texel index along one axis for an address mode; -1 means "outside" (constant). */
PMC_FN int pmc_address(int i, int n, pmc_u32 mode) {
  if (mode == PMC_ADDR_PERIODIC) return pmc_wrap_periodic(i, n);
  if (mode == PMC_ADDR_MIRROR) {
    int m = pmc_wrap_periodic(i, 2 * n);
    return m < n ? m : 2 * n - 1 - m;
  }
  if (mode == PMC_ADDR_CLAMP) return i < 0 ? 0 : (i >= n ? n - 1 : i);
  return (i < 0 || i >= n) ? -1 : i;
}

PMC_FN float4 pmc_texel_fetch(const PmcTextureSet* ts, pmc_u32 base, int w, int x, int y, int srgb) {
  pmc_u32 t = ts->texels[base + (pmc_u32)y * (pmc_u32)w + (pmc_u32)x];
  const pmc_u32 r = t & 255u, g = (t >> 8) & 255u, b = (t >> 16) & 255u;
  float a = (float)(t >> 24) * (1.0f / 255.0f);
  if (srgb) return make_float4(ts->srgb_lut[r], ts->srgb_lut[g], ts->srgb_lut[b], a);
  return make_float4((float)r * (1.0f / 255.0f), (float)g * (1.0f / 255.0f), (float)b * (1.0f / 255.0f), a);
}

/* Map a coordinate into a range where float texel math is exact enough for
 * the address mode: the periodic phase for periodic, phase of u/2 for mirror
 * (period 2), a clamp to [-1, 2] for clamp/constant. Huge (1e7) or NaN uvs
 * thus never poison the texel arithmetic. */
PMC_FN float pmc_reduce_coord(float u, pmc_u32 mode) {
  if (!isfinite(u)) return 0.0f;
  if (mode == PMC_ADDR_PERIODIC) {
    float r = u - floor(u);
    return r < 1.0f ? r : 0.0f;
  }
  if (mode == PMC_ADDR_MIRROR) {
    float h = 0.5f * u;
    float r = h - floor(h);
    return 2.0f * (r < 1.0f ? r : 0.0f);
  }
  return u < -1.0f ? -1.0f : (u > 2.0f ? 2.0f : u);
}

/* Where one mip level of a texture lies in the pool, and its size. */
typedef struct PmcTextureLevel {
  pmc_u32 base;
  int w, h;
} PmcTextureLevel;

/* Level `level`'s place: the levels before it, each half the one before
 * (at least 1 texel), lie back to back from level 0. When 2^level divides
 * both sides (a power-of-two texture's every level) the halvings are exact
 * and their sizes sum to (w h - w' h') 4/3 with w' h' the level's own size,
 * without the loop over the levels (perf: pmc_texture_lod 1.6% of the
 * default room's samples, most of it in that loop). */
PMC_FN PmcTextureLevel pmc_texture_level_at(PMC_GLOBAL const PmcTexture* tex, int level) {
  PmcTextureLevel L;
  L.base = tex->offset;
  L.w = tex->width;
  L.h = tex->height;
  if (level > 0 && level < 16 && ((L.w | L.h) & ((1 << level) - 1)) == 0) {
    const int w = L.w >> level, h = L.h >> level;
    L.base += ((pmc_u32)L.w * (pmc_u32)L.h - (pmc_u32)w * (pmc_u32)h) / 3u * 4u;
    L.w = w;
    L.h = h;
    return L;
  }
  for (int l = 0; l < level; ++l) {
    L.base += (pmc_u32)L.w * (pmc_u32)L.h;
    L.w = L.w > 1 ? L.w >> 1 : 1;
    L.h = L.h > 1 ? L.h >> 1 : 1;
  }
  return L;
}

/* One mip level, bilinear or nearest. */
PMC_FN float4 pmc_texture_level(const PmcTextureSet* ts, PmcTextureLevel L, int srgb, float2 uv,
                                pmc_u32 umode, pmc_u32 vmode, pmc_u32 filter, float4 fallback) {
  const pmc_u32 base = L.base;
  const int w = L.w, h = L.h;
  /* Texel space: x to the right, y down from the top row. */
  float x = pmc_reduce_coord(uv.x, umode) * (float)w;
  float y = pmc_reduce_coord(1.0f - uv.y, vmode) * (float)h;
  if (filter == PMC_FILTER_CLOSEST) {
    int xi = pmc_address((int)floor(x), w, umode), yi = pmc_address((int)floor(y), h, vmode);
    if (xi < 0 || yi < 0) return fallback;
    return pmc_texel_fetch(ts, base, w, xi, yi, srgb);
  }
  x -= 0.5f;
  y -= 0.5f;
  float x0f = floor(x), y0f = floor(y);
  float ax = x - x0f, ay = y - y0f;
  int x0 = (int)x0f, y0 = (int)y0f;
  int xa = pmc_address(x0, w, umode), xb = pmc_address(x0 + 1, w, umode);
  int ya = pmc_address(y0, h, vmode), yb = pmc_address(y0 + 1, h, vmode);
  float4 c00 = (xa >= 0 && ya >= 0) ? pmc_texel_fetch(ts, base, w, xa, ya, srgb) : fallback;
  float4 c10 = (xb >= 0 && ya >= 0) ? pmc_texel_fetch(ts, base, w, xb, ya, srgb) : fallback;
  float4 c01 = (xa >= 0 && yb >= 0) ? pmc_texel_fetch(ts, base, w, xa, yb, srgb) : fallback;
  float4 c11 = (xb >= 0 && yb >= 0) ? pmc_texel_fetch(ts, base, w, xb, yb, srgb) : fallback;
  float4 top = c00 + (c10 - c00) * ax;
  float4 bottom = c01 + (c11 - c01) * ax;
  return top + (bottom - top) * ay;
}

/* A trilinear lookup's levels for a footprint: the finer level, and the
 * coarser one with its weight t (t 0: the finer alone). */
typedef struct PmcTextureLod {
  PmcTextureLevel fine, coarse;
  float t;
  int srgb;
} PmcTextureLod;

/* `footprint` is the uv-space width the lookup covers. */
PMC_FN PmcTextureLod pmc_texture_lod(PMC_GLOBAL const PmcTexture* tex, float footprint) {
  float size = (float)(tex->width > tex->height ? tex->width : tex->height);
  float lod = footprint > 0.0f && isfinite(footprint) ? log2(footprint * size) : 0.0f;
  float max_lod = (float)(tex->levels - 1);
  lod = lod > 0.0f ? (lod < max_lod ? lod : max_lod) : 0.0f;
  int l0 = (int)floor(lod);
  PmcTextureLod r;
  r.t = lod - (float)l0;
  if (l0 + 1 > (int)max_lod) r.t = 0.0f;
  r.srgb = (tex->flags & PMC_TEX_SRGB) != 0u;
  r.fine = pmc_texture_level_at(tex, l0);
  /* the next level from this one, as pmc_texture_level_at(l0 + 1) steps */
  r.coarse.base = r.fine.base + (pmc_u32)r.fine.w * (pmc_u32)r.fine.h;
  r.coarse.w = r.fine.w > 1 ? r.fine.w >> 1 : 1;
  r.coarse.h = r.fine.h > 1 ? r.fine.h >> 1 : 1;
  return r;
}

PMC_FN float4 pmc_texture_trilinear(const PmcTextureSet* ts, const PmcTextureLod* lod, float2 uv,
                                    pmc_u32 umode, pmc_u32 vmode, pmc_u32 filter, float4 fallback) {
  float4 c0 = pmc_texture_level(ts, lod->fine, lod->srgb, uv, umode, vmode, filter, fallback);
  if (lod->t <= 0.0f) return c0;
  float4 c1 = pmc_texture_level(ts, lod->coarse, lod->srgb, uv, umode, vmode, filter, fallback);
  return c0 + (c1 - c0) * lod->t;
}

/* Trilinear lookup: `footprint` is the uv-space width the lookup covers. */
PMC_FN float4 pmc_texture_sample(const PmcTextureSet* ts, pmc_u32 index, float2 uv, float footprint,
                                 pmc_u32 umode, pmc_u32 vmode, pmc_u32 filter, float4 fallback) {
  if (index >= ts->count) return fallback;
  const PmcTextureLod lod = pmc_texture_lod(&ts->textures[index], footprint);
  return pmc_texture_trilinear(ts, &lod, uv, umode, vmode, filter, fallback);
}

/* A lookup's footprint: the isotropic width and the ellipse (see below). */
typedef struct PmcFootprint {
  float width;
  float2 axis;
  float minor;
} PmcFootprint;

/* Anisotropic filtering over the footprint's ellipse, as GPUs do it: a few
 * trilinear taps spaced along the major axis, each at the level of the
 * ellipse's width across it. `axis` is the major half-axis in uv (its length
 * half the major width P), `minor` the width across it (clamped to P),
 * `footprint` the isotropic width (what pmc_texture_sample takes).
 *
 * n = ceil(P / minor) taps, at most PMC_TEXTURE_MAX_TAPS, each of width
 * w = max(P / n, minor) (the cap widens them: the taps then still cover the
 * major axis, blurrier across it), their centres spread evenly so that
 * together they span P: the outer ones at +-(P - w) / 2. An ellipse rounder
 * than PMC_TEXTURE_ROUND (axis 0 among them: no ellipse known) is one tap at
 * `footprint`, the isotropic lookup bit for bit; as P / minor tends to 1 the
 * taps merge into that one anyway (w -> P, spread -> 0). A negative minor
 * (PMC_FOOTPRINT_ONE_LEVEL) is one bilinear tap at `footprint`'s nearest
 * level. */
#define PMC_TEXTURE_MAX_TAPS 8
#define PMC_TEXTURE_ROUND 1.0625f
/* A `minor` below 0: no ellipse, and the lookup reads the footprint's nearest
 * mip level alone (bilinear; no blend with the next level), half a trilinear
 * lookup's work. The shade kernel passes it for hits whose textures the lobe
 * that sampled their ray averages (pmc_texture_ellipse_needed): a level's
 * half step of blur there is inside that average. */
#define PMC_FOOTPRINT_ONE_LEVEL (-1.0f)
PMC_FN float4 pmc_texture_sample_ellipse(const PmcTextureSet* ts, pmc_u32 index, float2 uv, float footprint,
                                         float2 axis, float minor, pmc_u32 umode, pmc_u32 vmode,
                                         pmc_u32 filter, float4 fallback) {
  if (minor < 0.0f) { /* PMC_FOOTPRINT_ONE_LEVEL */
    if (index >= ts->count) return fallback;
    const PmcTextureLod lod = pmc_texture_lod(&ts->textures[index], footprint);
    return pmc_texture_level(ts, lod.t > 0.5f ? lod.coarse : lod.fine, lod.srgb, uv, umode, vmode, filter,
                             fallback);
  }
  const float major = 2.0f * sqrt(axis.x * axis.x + axis.y * axis.y);
  const float m = minor > 0.0f ? fmin(minor, major) : 0.0f; /* NaN: 0 */
  if (!(major > m * PMC_TEXTURE_ROUND) || !(major < 1e30f))
    return pmc_texture_sample(ts, index, uv, footprint, umode, vmode, filter, fallback);
  const float ratio = major / fmax(m, 1e-30f);
  const int n = ratio < (float)PMC_TEXTURE_MAX_TAPS ? (int)ceil(ratio) : PMC_TEXTURE_MAX_TAPS;
  const float w = fmax(major / (float)n, m);
  /* tap i at uv + axis * (s0 + i * ds): s from -(1 - w / P) to +(1 - w / P) */
  const float s0 = w / major - 1.0f;
  const float ds = -2.0f * s0 / (float)(n - 1);
  if (index >= ts->count) return fallback;
  const PmcTextureLod lod = pmc_texture_lod(&ts->textures[index], w); /* every tap's */
  float4 sum = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
  for (int i = 0; i < PMC_TEXTURE_MAX_TAPS; ++i) {
    if (i >= n) break;
    const float s = s0 + (float)i * ds;
    sum = sum + pmc_texture_trilinear(ts, &lod, uv + axis * s, umode, vmode, filter, fallback);
  }
  return sum * (1.0f / (float)n);
}

#endif /* PMC_TEXTURE_H */
