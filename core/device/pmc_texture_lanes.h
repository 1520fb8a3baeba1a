/* pmc_texture_lanes.h — a batch's image lookups together, for CPU devices.
 *
 * pmc_texture_sample_lanes() gives each of n lookups exactly what
 * pmc_texture_sample_ellipse (pmc_texture.h) gives it, in three steps, each
 * eight lookups at a time in float8:
 *   1. the plans (pmc_texture_plans8): how many taps along the ellipse (one
 *      when round, or one level alone), their spacing, and the mip level
 *      with the trilinear weight (pmc_texture_lod's arithmetic);
 *   2. per tap round, every lookup's bilinear reads of one mip level
 *      ("jobs": the finer level's, and the coarser one's when any lookup
 *      blends):
 *      address modes and the filter as selects, texel and sRGB-table reads
 *      as eight-wide gathers at clamped indices, the fallback selected after
 *      (PoCL's loop vectoriser left the same loop written per job scalar);
 *   3. the same blends in the same order as the scalar code, so
 *      the results are equal bit for bit (the renders tried are identical;
 *      tests/gpu/interpreter_parity_test.cpp runs every address mode, filter
 *      and footprint kind through both).
 * One lookup at a time, the scalar form spent about a fifth of the spider
 * scene's samples (small textures that stay in the caches: arithmetic and
 * scalar loads, not memory); with the plans and blends still lane by lane,
 * the shade kernel took 1.11x this form's CPU per hit there. OpenCL only: the host and GPUs (PMC_LANES 1)
 * keep pmc_texture_sample_ellipse per point.
 *
 * The branch-free address arithmetic relies on the indices the lookups make:
 * after pmc_reduce_coord, a periodic axis reads indices in [-1, n], a
 * mirrored one in [-1, 2n], a clamped or constant one in [-n - 1, 2n], all
 * within one period of the wrap below.
 */
#ifndef PMC_TEXTURE_LANES_H
#define PMC_TEXTURE_LANES_H

#include "pmc_texture.h"

#if defined(__OPENCL_VERSION__) && defined(PMC_LANES) && PMC_LANES >= 8

/* pmc_reduce_coord, eight at a time. */
PMC_FN_INLINE float8 pmc_reduce_coord8(float8 u, uint8 mode) {
  const int8 mirror = convert_int8(mode == PMC_ADDR_MIRROR);
  const float8 h = select(u, 0.5f * u, mirror);
  float8 r = h - floor(h);
  r = select((float8)(0.0f), r, r < 1.0f);
  const float8 c = clamp(u, -1.0f, 2.0f);
  const float8 out = select(select(c, 2.0f * r, mirror), r, convert_int8(mode == PMC_ADDR_PERIODIC));
  return select((float8)(0.0f), out, isfinite(u));
}

/* pmc_address, eight at a time, for i within [-p, 2p) of the wrap's period
 * p (see the top). */
PMC_FN_INLINE int8 pmc_address8(int8 i, int8 n, uint8 mode) {
  const int8 mirror = convert_int8(mode == PMC_ADDR_MIRROR);
  const int8 p = select(n, 2 * n, mirror);
  int8 m = select(select(i, i - p, i >= p), i + p, i < 0);
  m = select(m, 2 * n - 1 - m, mirror & (m >= n));
  const int8 clamped = clamp(i, (int8)(0), n - 1);
  const int8 inside = select(i, (int8)(-1), (i < 0) | (i >= n));
  const int8 wraps = convert_int8(mode == PMC_ADDR_PERIODIC) | mirror;
  return select(select(inside, clamped, convert_int8(mode == PMC_ADDR_CLAMP)), m, wraps);
}

/* Eight words of the texel pool at indices i. */
PMC_FN_INLINE uint8 pmc_texels8(const PmcTextureSet* ts, uint8 i) {
  PMC_GLOBAL const pmc_u32* t = ts->texels;
  return (uint8)(t[i.s0], t[i.s1], t[i.s2], t[i.s3], t[i.s4], t[i.s5], t[i.s6], t[i.s7]);
}

/* Channel c (0 r, 1 g, 2 b, 3 alpha) of eight texel words, decoded as
 * pmc_texel_fetch does. */
PMC_FN_INLINE float8 pmc_texel_channel8(const PmcTextureSet* ts, uint8 t, int c, int srgb) {
  const uint8 v = (t >> (uint8)(8 * c)) & 255u;
  if (srgb && c < 3) {
    PMC_CONSTANT const float* lut = ts->srgb_lut;
    return (float8)(lut[v.s0], lut[v.s1], lut[v.s2], lut[v.s3], lut[v.s4], lut[v.s5], lut[v.s6], lut[v.s7]);
  }
  return convert_float8(v) * (1.0f / 255.0f);
}

/* The bilinear (or nearest) reads of one mip level, jobs [0, count) (the
 * arrays padded to a multiple of eight with copies of job 0): uv in (x, y),
 * the level in (base, w, h), address modes and filter in bits (PMC_OP_IMAGE's
 * mode word), the fallback's channels in fb; the results in out.
 * pmc_texture_level's arithmetic, eight jobs at a time. */
#define PMC_TEXTURE_JOBS (2 * PMC_LANES)
typedef struct PmcTextureJobs {
  float x[PMC_TEXTURE_JOBS], y[PMC_TEXTURE_JOBS];
  pmc_u32 base[PMC_TEXTURE_JOBS];
  int w[PMC_TEXTURE_JOBS], h[PMC_TEXTURE_JOBS];
  pmc_u32 bits[PMC_TEXTURE_JOBS];
  float fb[4][PMC_TEXTURE_JOBS];
  float out[4][PMC_TEXTURE_JOBS];
} PmcTextureJobs;

PMC_FN_INLINE void pmc_texture_jobs_run(const PmcTextureSet* ts, PmcTextureJobs* J, int count,
                                        const int srgb) {
  for (int j = 0; j < count; j += 8) {
    const uint8 bits = vload8(0, J->bits + j), umode = bits & 3u, vmode = (bits >> 2) & 3u;
    const int8 closest = convert_int8(((bits >> 4) & 3u) == PMC_FILTER_CLOSEST);
    const int8 w = vload8(0, J->w + j), h = vload8(0, J->h + j);
    const float8 x = pmc_reduce_coord8(vload8(0, J->x + j), umode) * convert_float8(w);
    const float8 y = pmc_reduce_coord8(1.0f - vload8(0, J->y + j), vmode) * convert_float8(h);
    const float8 xs = select(x - 0.5f, x, closest), ys = select(y - 0.5f, y, closest);
    const float8 x0f = floor(xs), y0f = floor(ys);
    const float8 ax = xs - x0f, ay = ys - y0f;
    const int8 x0 = convert_int8(x0f), y0 = convert_int8(y0f);
    const int8 xa = pmc_address8(x0, w, umode), xb = pmc_address8(x0 + 1, w, umode);
    const int8 ya = pmc_address8(y0, h, vmode), yb = pmc_address8(y0 + 1, h, vmode);
    /* reads at clamped indices, the fallback selected after */
    const uint8 base = vload8(0, J->base + j), uw = as_uint8(w);
    const uint8 ra = base + as_uint8(max(ya, 0)) * uw, rb = base + as_uint8(max(yb, 0)) * uw;
    const uint8 ca = as_uint8(max(xa, 0)), cb = as_uint8(max(xb, 0));
    const uint8 t00 = pmc_texels8(ts, ra + ca), t10 = pmc_texels8(ts, ra + cb);
    const uint8 t01 = pmc_texels8(ts, rb + ca), t11 = pmc_texels8(ts, rb + cb);
    const int8 in00 = (xa >= 0) & (ya >= 0), in10 = (xb >= 0) & (ya >= 0);
    const int8 in01 = (xa >= 0) & (yb >= 0), in11 = (xb >= 0) & (yb >= 0);
    for (int c = 0; c < 4; ++c) {
      const float8 f = vload8(0, J->fb[c] + j);
      const float8 c00 = select(f, pmc_texel_channel8(ts, t00, c, srgb), in00);
      const float8 c10 = select(f, pmc_texel_channel8(ts, t10, c, srgb), in10);
      const float8 c01 = select(f, pmc_texel_channel8(ts, t01, c, srgb), in01);
      const float8 c11 = select(f, pmc_texel_channel8(ts, t11, c, srgb), in11);
      const float8 top = c00 + (c10 - c00) * ax;
      const float8 bottom = c01 + (c11 - c01) * ax;
      vstore8(select(top + (bottom - top) * ay, c00, closest), 0, J->out[c] + j);
    }
  }
}

/* The plans of lookups [k, k + 8) (step 1): pmc_texture_sample_ellipse's
 * choices and pmc_texture_lod's arithmetic in float8. Each lookup's taps
 * (1 when round or one level alone), their spacing (s0, ds; 0 when round),
 * its ellipse's axis (0 when round), its finer level and the trilinear
 * weight (0: that level alone). */
typedef struct PmcTexturePlans {
  int taps[PMC_LANES], level[PMC_LANES];
  float s0[PMC_LANES], ds[PMC_LANES], t[PMC_LANES], axis_x[PMC_LANES], axis_y[PMC_LANES];
} PmcTexturePlans;

PMC_FN_INLINE void pmc_texture_plans8(PMC_GLOBAL const PmcTexture* tex, int k, const float* footprint,
                                      const float* ax, const float* ay, const float* minor,
                                      PmcTexturePlans* P) {
  const float8 mn = vload8(0, minor + k), fx = vload8(0, ax + k), fy = vload8(0, ay + k);
  const int8 one_level = mn < 0.0f; /* PMC_FOOTPRINT_ONE_LEVEL */
  const float8 major = 2.0f * sqrt(fx * fx + fy * fy);
  const float8 m = select((float8)(0.0f), fmin(mn, major), mn > 0.0f); /* NaN: 0 */
  const int8 ellipse = !one_level & (major > m * PMC_TEXTURE_ROUND) & (major < 1e30f);
  const float8 ratio = major / fmax(m, 1e-30f);
  const int8 taps = select(
      (int8)(1),
      convert_int8(select((float8)(PMC_TEXTURE_MAX_TAPS), ceil(ratio), ratio < (float)PMC_TEXTURE_MAX_TAPS)),
      ellipse);
  const float8 w = fmax(major / convert_float8(taps), m);
  const float8 s0 = select((float8)(0.0f), w / major - 1.0f, ellipse);
  vstore8(s0, 0, P->s0 + k);
  vstore8(select((float8)(0.0f), -2.0f * s0 / convert_float8(taps - 1), ellipse), 0, P->ds + k);
  vstore8(select((float8)(0.0f), fx, ellipse), 0, P->axis_x + k);
  vstore8(select((float8)(0.0f), fy, ellipse), 0, P->axis_y + k);
  vstore8(taps, 0, P->taps + k);
  /* pmc_texture_lod at the taps' width (the footprint when round) */
  const float8 width = select(vload8(0, footprint + k), w, ellipse);
  const float size = (float)(tex->width > tex->height ? tex->width : tex->height);
  const float max_lod = (float)(tex->levels - 1);
  float8 lod = select((float8)(0.0f), log2(width * size), (width > 0.0f) & isfinite(width));
  lod = select((float8)(0.0f), select((float8)(max_lod), lod, lod < max_lod), lod > 0.0f);
  const float8 l0f = floor(lod);
  const int8 l0 = convert_int8(l0f);
  float8 t = select(lod - l0f, (float8)(0.0f), l0 + 1 > (int)max_lod);
  /* one level alone: the nearer one */
  vstore8(select(l0, l0 + 1, one_level & (t > 0.5f)), 0, P->level + k);
  vstore8(select(t, (float8)(0.0f), one_level), 0, P->t + k);
}

/* n lookups of texture `index`: lookup k at (u[k], v[k]) with
 * pmc_texture_sample_ellipse's footprint[k], axis (ax[k], ay[k]), minor[k],
 * mode word bits[k] and fallback fb[0..3][k]; the results in out[0..3][k].
 * The arrays hold PMC_LANES entries; those past n (up to the next multiple
 * of eight) are computed on whatever they hold and ignored: every read
 * stays inside the texture's levels whatever the inputs. Jobs are the
 * lookups' own lanes: the finer level's at [0, m), the coarser one's at
 * [m, 2m), run only when some lookup blends. */
PMC_FN void pmc_texture_sample_lanes(const PmcTextureSet* ts, pmc_u32 index, int n, const float* u,
                                     const float* v, const float* footprint, const float* ax, const float* ay,
                                     const float* minor, const pmc_u32* bits, float fb[4][PMC_LANES],
                                     float out[4][PMC_LANES]) {
  if (index >= ts->count) {
    for (int k = 0; k < n; ++k)
      for (int c = 0; c < 4; ++c) out[c][k] = fb[c][k];
    return;
  }
  PMC_GLOBAL const PmcTexture* tex = &ts->textures[index];
  const int srgb = (tex->flags & PMC_TEX_SRGB) != 0u;
  const int m = (n + 7) & ~7;
  PmcTexturePlans P;
  for (int k = 0; k < m; k += 8) pmc_texture_plans8(tex, k, footprint, ax, ay, minor, &P);
  int most = 1, blends = 0;
  PmcTextureJobs J;
  for (int k = 0; k < m; ++k) { /* the levels' places, and the jobs' fixed parts */
    if (k < n) {
      most = P.taps[k] > most ? P.taps[k] : most;
      blends |= P.t[k] > 0.0f;
    }
    const PmcTextureLevel L = pmc_texture_level_at(tex, P.level[k]);
    J.base[k] = L.base;
    J.w[k] = L.w;
    J.h[k] = L.h;
    /* the next level from this one, as pmc_texture_lod steps */
    J.base[m + k] = L.base + (pmc_u32)L.w * (pmc_u32)L.h;
    J.w[m + k] = L.w > 1 ? L.w >> 1 : 1;
    J.h[m + k] = L.h > 1 ? L.h >> 1 : 1;
    J.bits[k] = J.bits[m + k] = bits[k];
    for (int c = 0; c < 4; ++c) J.fb[c][k] = J.fb[c][m + k] = fb[c][k];
  }
  float8 sum[4][PMC_LANES / 8];
  for (int q = 0; q < m / 8; ++q) sum[0][q] = sum[1][q] = sum[2][q] = sum[3][q] = (float8)(0.0f);
  for (int i = 0; i < most; ++i) {
    /* 2. the round's jobs: every lookup's tap i (lookups with fewer taps
     * compute one they drop) */
    for (int k = 0; k < m; k += 8) {
      const float8 s = vload8(0, P.s0 + k) + (float)i * vload8(0, P.ds + k);
      const float8 x = vload8(0, u + k) + vload8(0, P.axis_x + k) * s;
      const float8 y = vload8(0, v + k) + vload8(0, P.axis_y + k) * s;
      vstore8(x, 0, J.x + k);
      vstore8(y, 0, J.y + k);
      if (blends) { /* the coarser level's jobs read the same points */
        vstore8(x, 0, J.x + m + k);
        vstore8(y, 0, J.y + m + k);
      }
    }
    if (srgb)
      pmc_texture_jobs_run(ts, &J, blends ? 2 * m : m, 1);
    else
      pmc_texture_jobs_run(ts, &J, blends ? 2 * m : m, 0);
    /* 3. pmc_texture_trilinear's blend and the taps' sum, in their order */
    for (int k = 0; k < m; k += 8) {
      const float8 t = vload8(0, P.t + k);
      const int8 blend = t > 0.0f, active = (int8)(i) < vload8(0, P.taps + k);
      for (int c = 0; c < 4; ++c) {
        const float8 c0 = vload8(0, J.out[c] + k);
        const float8 c1 = blends ? vload8(0, J.out[c] + m + k) : c0;
        const float8 tri = select(c0, c0 + (c1 - c0) * t, blend);
        sum[c][k / 8] = select(sum[c][k / 8], sum[c][k / 8] + tri, active);
      }
    }
  }
  for (int k = 0; k < m; k += 8) {
    const float8 scale = 1.0f / convert_float8(vload8(0, P.taps + k));
    for (int c = 0; c < 4; ++c) vstore8(sum[c][k / 8] * scale, 0, out[c] + k);
  }
}

#endif /* OpenCL, PMC_LANES >= 8 */
#endif /* PMC_TEXTURE_LANES_H */
