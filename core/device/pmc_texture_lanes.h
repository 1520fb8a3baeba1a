/* pmc_texture_lanes.h — a batch's image lookups together, for CPU devices.
 *
 * pmc_texture_sample_lanes() gives each of n lookups exactly what
 * pmc_texture_sample_ellipse (pmc_texture.h) gives it, in three steps:
 *   1. per lookup, its plan (scalar, cheap): how many taps along the
 *      ellipse (one when round, or one level alone), the taps' spacing, and
 *      the mip levels with the trilinear weight;
 *   2. per tap round, every lookup's bilinear reads of one mip level
 *      ("jobs", two per lookup for trilinear), eight at a time in float8:
 *      address modes and the filter as selects, texel and sRGB-table reads
 *      as eight-wide gathers at clamped indices, the fallback selected after
 *      (PoCL's loop vectoriser left the same loop written per job scalar);
 *   3. per lookup, the same blends in the same order as the scalar code, so
 *      the results are equal bit for bit (renders are identical;
 *      tests/gpu/interpreter_parity_test.cpp runs every address mode, filter
 *      and footprint kind through both).
 * One lookup at a time, the scalar form spent about a fifth of the spider
 * scene's samples (small textures that stay in the caches: arithmetic and
 * scalar loads, not memory). OpenCL only: the host and GPUs (PMC_LANES 1)
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

/* n lookups of texture `index`: lookup k at (u[k], v[k]) with
 * pmc_texture_sample_ellipse's footprint[k], axis (ax[k], ay[k]), minor[k],
 * mode word bits[k] and fallback fb[0..3][k]; the results in out[0..3][k]. */
PMC_FN void pmc_texture_sample_lanes(const PmcTextureSet* ts, pmc_u32 index, int n, const float* u,
                                     const float* v, const float* footprint, const float* ax, const float* ay,
                                     const float* minor, const pmc_u32* bits, float fb[4][PMC_LANES],
                                     float out[4][PMC_LANES]) {
  int taps[PMC_LANES];
  float s0[PMC_LANES], ds[PMC_LANES], t[PMC_LANES], axis_x[PMC_LANES], axis_y[PMC_LANES];
  PmcTextureLevel fine[PMC_LANES], coarse[PMC_LANES];
  int most = 0;
  int srgb = 0;
  if (index < ts->count) srgb = (ts->textures[index].flags & PMC_TEX_SRGB) != 0u;
  /* 1. the plans: pmc_texture_sample_ellipse's choices */
  for (int k = 0; k < n; ++k) {
    taps[k] = 0;
    s0[k] = ds[k] = 0.0f;
    axis_x[k] = axis_y[k] = 0.0f;
    if (index >= ts->count) continue;
    PMC_GLOBAL const PmcTexture* tex = &ts->textures[index];
    float width = footprint[k];
    int n_taps = 1;
    if (!(minor[k] < 0.0f)) {
      const float major = 2.0f * sqrt(ax[k] * ax[k] + ay[k] * ay[k]);
      const float m = minor[k] > 0.0f ? fmin(minor[k], major) : 0.0f; /* NaN: 0 */
      if (major > m * PMC_TEXTURE_ROUND && major < 1e30f) {
        const float ratio = major / fmax(m, 1e-30f);
        n_taps = ratio < (float)PMC_TEXTURE_MAX_TAPS ? (int)ceil(ratio) : PMC_TEXTURE_MAX_TAPS;
        width = fmax(major / (float)n_taps, m);
        s0[k] = width / major - 1.0f;
        ds[k] = -2.0f * s0[k] / (float)(n_taps - 1);
        axis_x[k] = ax[k];
        axis_y[k] = ay[k];
      }
    }
    const PmcTextureLod lod = pmc_texture_lod(tex, width);
    fine[k] = lod.fine;
    coarse[k] = lod.coarse;
    t[k] = lod.t;
    if (minor[k] < 0.0f) { /* PMC_FOOTPRINT_ONE_LEVEL: the nearer level alone */
      fine[k] = lod.t > 0.5f ? lod.coarse : lod.fine;
      t[k] = 0.0f;
    }
    taps[k] = n_taps;
    most = n_taps > most ? n_taps : most;
  }
  float sum[4][PMC_LANES];
  for (int k = 0; k < n; ++k) sum[0][k] = sum[1][k] = sum[2][k] = sum[3][k] = 0.0f;
  PmcTextureJobs J;
  int job_of[PMC_LANES];
  for (int i = 0; i < most; ++i) {
    /* 2. the round's jobs: each lookup's finer level, then the coarser ones */
    int count = 0;
    for (int k = 0; k < n; ++k) {
      job_of[k] = -1;
      if (i >= taps[k]) continue;
      const float s = s0[k] + (float)i * ds[k];
      J.x[count] = u[k] + axis_x[k] * s;
      J.y[count] = v[k] + axis_y[k] * s;
      J.base[count] = fine[k].base;
      J.w[count] = fine[k].w;
      J.h[count] = fine[k].h;
      J.bits[count] = bits[k];
      for (int c = 0; c < 4; ++c) J.fb[c][count] = fb[c][k];
      job_of[k] = count++;
    }
    const int fines = count;
    for (int k = 0; k < n; ++k) {
      if (job_of[k] < 0 || !(t[k] > 0.0f)) continue;
      const int f = job_of[k];
      J.x[count] = J.x[f];
      J.y[count] = J.y[f];
      J.base[count] = coarse[k].base;
      J.w[count] = coarse[k].w;
      J.h[count] = coarse[k].h;
      J.bits[count] = bits[k];
      for (int c = 0; c < 4; ++c) J.fb[c][count] = fb[c][k];
      ++count;
    }
    for (int p = count; p < ((count + 7) & ~7); ++p) { /* the last eight's spare jobs repeat the first */
      J.x[p] = J.x[0];
      J.y[p] = J.y[0];
      J.base[p] = J.base[0];
      J.w[p] = J.w[0];
      J.h[p] = J.h[0];
      J.bits[p] = J.bits[0];
      for (int c = 0; c < 4; ++c) J.fb[c][p] = J.fb[c][0];
    }
    if (srgb)
      pmc_texture_jobs_run(ts, &J, count, 1);
    else
      pmc_texture_jobs_run(ts, &J, count, 0);
    /* 3. pmc_texture_trilinear's blend and the taps' sum, in their order */
    int coarse_job = fines;
    for (int k = 0; k < n; ++k) {
      const int f = job_of[k];
      if (f < 0) continue;
      const int blend = t[k] > 0.0f;
      const int g = blend ? coarse_job++ : f;
      for (int c = 0; c < 4; ++c) {
        const float c0 = J.out[c][f];
        const float tri = blend ? c0 + (J.out[c][g] - c0) * t[k] : c0;
        sum[c][k] = sum[c][k] + tri;
      }
    }
  }
  for (int k = 0; k < n; ++k) {
    const float scale = 1.0f / (float)(taps[k] > 0 ? taps[k] : 1);
    for (int c = 0; c < 4; ++c) out[c][k] = taps[k] > 0 ? sum[c][k] * scale : fb[c][k];
  }
}

#endif /* OpenCL, PMC_LANES >= 8 */
#endif /* PMC_TEXTURE_LANES_H */
