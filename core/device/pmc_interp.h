/* pmc_interp.h — the material bytecode interpreter, one source for both sides.
 *
 * pmc_interp_lanes() executes one material program (see pmc_bytecode.h) for
 * a batch of up to PMC_LANES shading points of that material at once, one
 * instruction for every point before the next: on a CPU device the decode and
 * dispatch of an instruction are paid once per batch instead of once per
 * point, and the arithmetic runs as short loops over the points that the
 * compiler vectorises. Values live in a lane-major stack, stack[slot *
 * PMC_LANES + lane]; an instruction reads its operands (stack slots or inline
 * constants; a one-float operand broadcasts over the components, which is how
 * MaterialX's "FA" variants work), computes component by component, or point
 * by point for the nodes that need a whole vector (noise, images, colour
 * spaces), and writes `width` floats per point. OUTPUT instructions fill each
 * point's surface parameter block, params[lane * PMC_P_COUNT + p], which
 * pmc_surface_to_bsdf() turns into a BSDF.
 *
 * PMC_LANES is 1 on the host (the reference interpreter,
 * materials/cpu_interpreter.cpp) and on GPUs (the SIMT hardware batches work
 * items itself); the shade kernel on CPU devices sets it higher. Both compile
 * this same file, so tests run every opcode through both and compare.
 *
 * The material cache: a program's cache points form one group at its start
 * (lookups, the union of their sub-graphs, stores; materials/compiler.h).
 * Each point looks its values up; the group's sub-graphs then run only for
 * the points that missed, packed into the first lanes ("virtual lanes" that
 * read their shading inputs through lane_of[]), and each store inserts and
 * delivers those values back to the points they belong to. A batch in which
 * every point hit skips the group entirely.
 *
 * A cache point is keyed on the shading point's uv texel or, when its
 * sub-graph reads the position only, on its position cell (pmc_cache.h); each
 * point of a lane computes either at most once. In cache_eval center the
 * group's sub-graphs read the texel's centre uv and the cell's centre
 * position, so a stored value depends on its key alone.
 */
#ifndef PMC_INTERP_H
#define PMC_INTERP_H

#include "../abi/pmc_bytecode.h"
#include "pmc_cache.h"
#include "pmc_compositing.h"
#include "pmc_flake.h"
#include "pmc_hair_data.h"
#include "pmc_hextile.h"
#include "pmc_noise.h"
#include "pmc_patterns.h"
#include "pmc_pbr_data.h"
#include "pmc_raycone.h"
#include "pmc_surface.h"
#include "pmc_texture.h"

/* What a material may read at the shading point. */
typedef struct PmcShadingInputs {
  float2 uv;
  float3 position;
  float3 normal; /* shading normal, facing the viewer */
  float3 tangent;
  float3 bitangent;
  float footprint; /* uv-space width of the ray-cone footprint (isotropic texture LOD) */
  /* The footprint's ellipse (pmc_ray_cone_ellipse): major half-axis in uv
   * and minor width; an axis of 0 (no ellipse known) filters isotropically. */
  float2 footprint_axis;
  float footprint_minor;
} PmcShadingInputs;

/* The footprint of the ray cone's uv gradients g1, g2 (pmc_ray_cone_gradients). */
PMC_FN void pmc_shading_footprint(PmcShadingInputs* in, float2 g1, float2 g2) {
  in->footprint = 2.0f * fmax(length(g1), length(g2));
  pmc_ray_cone_ellipse(g1, g2, &in->footprint_axis, &in->footprint_minor);
}

/* The material cache as one evaluation sees it. A null context (the host
 * reference, or the cache off, whose programs have no cache instructions)
 * makes every lookup a miss. */
typedef struct PmcCacheContext {
  PmcCacheTable table;
  float2 g1, g2;            /* ray-cone uv gradients at the hit */
  float bias;               /* mip_bias */
  float4 jitter;            /* added to uv * 2^lambda (x, y) and to the position *
                             * 2^lambda (x, y, z) before flooring, in [-0.5, 0.5): 0 is
                             * the nearest texel; uniform random offsets pick a neighbour
                             * with its bilinear (trilinear) weight (cache_filter) */
  float radius;             /* ray-cone radius at the hit, scene units (position keys) */
  pmc_u32 floors;           /* 0: no level floors (the three fields below are ignored) */
  int level_floor_uv;       /* the material's level floors (pmc_cache_floored_level; */
  int level_floor_position; /* PMC_LEVEL_NO_FLOOR: none) for uv and position points */
  int max_refine;           /* levels a floor may lie above the footprint's before bypass */
  pmc_u32 material;
  pmc_u32 center;      /* cache_eval center: evaluate misses at the texel centre */
  pmc_u32 depth;       /* surface hits before this one (0: a camera-ray hit); the
                        * priority policy tags entries with it, and camera
                        * lookups are counted apart */
  PmcCacheTexel texel; /* the shading point's texel, if the caller computed it
                        * (ready); else the first lookup computes it */
  PmcCacheTexel cell;  /* the same for its position cell */
  pmc_u32 hits;        /* out: cache points found in this evaluation */
#if PMC_CACHE_TRACE_RECORDS
  pmc_u32 trace_pixel, trace_sample; /* PMC_CACHE_TRACE: who looked up (gpu/cache_trace.h) */
#endif
  /* out: PMC_CSTAT_* events, counted privately (no atomics per lookup); the
   * caller adds them up: the shade kernel once per work-group. */
  pmc_u32 counts[PMC_CSTAT_COUNT];
} PmcCacheContext;

/* PMC_CACHE_TRACE (a diagnostic, gpu/cache_trace.h): the shade kernel
 * appends every lookup to a record region behind the cache table: a count
 * word, then two words per lookup (the key's 64-bit cell hash; the pixel, the
 * depth, the sample and whether the key is a position cell). Records past the
 * region's capacity are counted, not written. */
#ifndef PMC_CACHE_TRACE_RECORDS
#define PMC_CACHE_TRACE_RECORDS 0
#endif
#if PMC_CACHE_TRACE_RECORDS && defined(__OPENCL_VERSION__)
PMC_FN void pmc_cache_trace(const PmcCacheContext* cx, PmcCacheKey key, int positional) {
  __global volatile ulong* region = cx->table.entries + cx->table.cells * (ulong)cx->table.ways;
  const ulong slot = atom_inc(region);
  if (slot >= (ulong)PMC_CACHE_TRACE_RECORDS) return;
  region[1ul + 2ul * slot] = key.h1;
  region[2ul + 2ul * slot] = (ulong)cx->trace_pixel | ((ulong)min(cx->depth, 255u) << 32) |
                             ((ulong)(cx->trace_sample & 0xfffffu) << 40) | ((ulong)(positional != 0) << 60);
}
#define PMC_CACHE_TRACE(cx, key, positional) pmc_cache_trace(cx, key, positional)
#else
#define PMC_CACHE_TRACE(cx, key, positional) ((void)0)
#endif

#ifndef PMC_LANES
#define PMC_LANES 1
#endif
/* Loop bound over a batch's points: a constant 1 when batches are single
 * points, so those builds carry no loops. */
#if PMC_LANES == 1
#define PMC_BATCH(n) 1
#else
#define PMC_BATCH(n) (n)
#endif

PMC_FN float4 pmc_broadcast(float v) { return make_float4(v, v, v, v); }

/* Components [0, ncomp) of operand word `o` for lanes [0, n) into v[c][lane],
 * as a float4 would hold them: a one-float operand in every component, a
 * wider one in its own components and 0 beyond them. */
PMC_FN void pmc_fetch(PMC_GLOBAL const pmc_u32* code, const float* stack, pmc_u32 o, int ncomp, int n,
                      float v[4][PMC_LANES]) {
  pmc_u32 index = o & PMC_OPERAND_INDEX_MASK;
  int w = (int)((o >> 28) & 3u); /* width - 1 */
  (void)n;                       /* unused when PMC_LANES is 1 */
  for (int c = 0; c < ncomp; ++c) {
    int src = w == 0 ? 0 : c;
    if (w != 0 && c > w) {
      for (int k = 0; k < PMC_BATCH(n); ++k) v[c][k] = 0.0f;
    } else if (o & PMC_OPERAND_CONST) {
      float x = as_float((int)code[index + (pmc_u32)src]);
      for (int k = 0; k < PMC_BATCH(n); ++k) v[c][k] = x;
    } else {
      const float* row = stack + (index + (pmc_u32)src) * PMC_LANES;
      for (int k = 0; k < PMC_BATCH(n); ++k) v[c][k] = row[k];
    }
  }
}

PMC_FN float4 pmc_lanes4(float v[4][PMC_LANES], int k) {
  return make_float4(v[0][k], v[1][k], v[2][k], v[3][k]);
}

PMC_FN void pmc_set_lanes4(float v[4][PMC_LANES], int k, float4 r) {
  v[0][k] = r.x;
  v[1][k] = r.y;
  v[2][k] = r.z;
  v[3][k] = r.w;
}

/* Float to int without undefined behaviour for NaN or huge values. */
PMC_FN int pmc_to_int(float x) {
  if (!(x > -1e6f)) return x > 0.0f ? 1000000 : -1000000; /* NaN and below */
  if (!(x < 1e6f)) return 1000000;
  return (int)x;
}

PMC_FN float pmc_lane(float4 v, int i) { return i == 0 ? v.x : (i == 1 ? v.y : (i == 2 ? v.z : v.w)); }

PMC_FN float pmc_smoothstep1(float x, float lo, float hi) {
  if (x >= hi) return 1.0f;
  if (x <= lo) return 0.0f;
  float t = (x - lo) / (hi - lo);
  return t * t * (3.0f - 2.0f * t);
}

PMC_FN float4 pmc_rgb_to_hsv(float4 c) {
  float mx = fmax(c.x, fmax(c.y, c.z)), mn = fmin(c.x, fmin(c.y, c.z));
  float d = mx - mn;
  float h = 0.0f, s = mx > 0.0f ? d / mx : 0.0f;
  if (d > 0.0f) {
    if (mx == c.x)
      h = (c.y - c.z) / d;
    else if (mx == c.y)
      h = 2.0f + (c.z - c.x) / d;
    else
      h = 4.0f + (c.x - c.y) / d;
    h *= 1.0f / 6.0f;
    if (h < 0.0f) h += 1.0f;
  }
  return make_float4(h, s, mx, c.w);
}

PMC_FN float4 pmc_hsv_to_rgb(float4 c) {
  float h = c.x, s = c.y, v = c.z;
  if (s <= 0.0f) return make_float4(v, v, v, c.w);
  if (!isfinite(h)) h = 0.0f;
  h = 6.0f * (h - floor(h));
  if (h >= 6.0f) h = 0.0f;
  int i = (int)floor(h);
  float f = h - (float)i;
  float p = v * (1.0f - s), q = v * (1.0f - s * f), t = v * (1.0f - s * (1.0f - f));
  float r, g, b;
  if (i == 0)
    r = v, g = t, b = p;
  else if (i == 1)
    r = q, g = v, b = p;
  else if (i == 2)
    r = p, g = v, b = t;
  else if (i == 3)
    r = p, g = q, b = v;
  else if (i == 4)
    r = t, g = p, b = v;
  else
    r = v, g = p, b = q;
  return make_float4(r, g, b, c.w);
}

/* MaterialX place2d: SRT (order 0) or TRS (order 1) about a pivot. */
PMC_FN float4 pmc_place2d(float4 uv, float4 pivot, float4 scale, float rotate_degrees, float4 offset,
                          int order) {
  float a = -rotate_degrees * (PMC_PI / 180.0f);
  float ca = cos(a), sa = sin(a);
  float x = uv.x - pivot.x, y = uv.y - pivot.y;
  if (order == 0) {
    x = x / scale.x;
    y = y / scale.y;
    float rx = ca * x - sa * y, ry = sa * x + ca * y;
    x = rx - offset.x;
    y = ry - offset.y;
  } else {
    x -= offset.x;
    y -= offset.y;
    float rx = ca * x - sa * y, ry = sa * x + ca * y;
    x = rx / scale.x;
    y = ry / scale.y;
  }
  return make_float4(x + pivot.x, y + pivot.y, 0.0f, 0.0f);
}

/* Tangent-space normal map (0..1 encoded) to a world normal. */
PMC_FN float4 pmc_normalmap(float4 in, float scale, float3 n, float3 t) {
  float3 v = make_float3(in.x * 2.0f - 1.0f, in.y * 2.0f - 1.0f, in.z * 2.0f - 1.0f);
  v = make_float3(v.x * scale, v.y * scale, v.z);
  float3 b = cross(n, t);
  float3 r = t * v.x + b * v.y + n * v.z;
  float l = length(r);
  r = l > 0.0f && isfinite(l) ? r * (1.0f / l) : n;
  return make_float4(r.x, r.y, r.z, 0.0f);
}

/* MaterialX blend nodes, one lane (PMC_BLEND_*). M_FLOAT_EPS of the GLSL is 1e-6. */
PMC_FN float pmc_blend1(float fg, float bg, float mix, pmc_u32 mode) {
  float f;
  if (mode == PMC_BLEND_PLUS)
    f = fg + bg;
  else if (mode == PMC_BLEND_MINUS)
    f = bg - fg;
  else if (mode == PMC_BLEND_DIFFERENCE)
    f = fabs(bg - fg);
  else if (mode == PMC_BLEND_BURN) {
    if (fabs(fg) < 1e-6f) return 0.0f;
    f = 1.0f - (1.0f - bg) / fg;
  } else if (mode == PMC_BLEND_DODGE) {
    if (fabs(1.0f - fg) < 1e-6f) return 0.0f;
    f = bg / (1.0f - fg);
  } else
    f = 1.0f - (1.0f - fg) * (1.0f - bg);
  return mix * f + (1.0f - mix) * bg;
}

PMC_FN float pmc_sign1(float x) { return x > 0.0f ? 1.0f : (x < 0.0f ? -1.0f : 0.0f); }
/* GLSL round(): halves away from zero (C's round). */
PMC_FN float pmc_round1(float x) { return x < 0.0f ? -floor(-x + 0.5f) : floor(x + 0.5f); }

/* Componentwise instruction bodies: `expr` of the operands' components a, b
 * (t, d, e) for every component c < width of every lane k < nn, into R. */
#define PMC_CW(fetches, expr)          \
  fetches;                             \
  for (int c = 0; c < (int)width; ++c) \
    for (int k = 0; k < PMC_BATCH(nn); ++k) R[c][k] = (expr);
#define PMC_A pmc_fetch(code, stack, code[pc + 2u], (int)width, nn, A)
#define PMC_B pmc_fetch(code, stack, code[pc + 3u], (int)width, nn, B)
#define PMC_T pmc_fetch(code, stack, code[pc + 4u], (int)width, nn, T)
#define PMC_D pmc_fetch(code, stack, code[pc + 5u], (int)width, nn, D)
#define PMC_E pmc_fetch(code, stack, code[pc + 6u], (int)width, nn, E)
/* The same operands with all four components (for per-point bodies). */
#define PMC_FETCH4(V, i) pmc_fetch(code, stack, code[pc + 2u + (i)], 4, nn, V)

/* Runs the program at `pc` until END for the `n` points `in[0..n)` (n <=
 * PMC_LANES). `stack` holds PMC_STACK_SIZE * PMC_LANES floats, `params` n
 * parameter blocks (filled by OUTPUT; the caller sets their defaults),
 * `cache` n contexts (one per point, all of the same material and table) or
 * null: then every lookup misses. */
PMC_FN void pmc_interp_lanes(PMC_GLOBAL const pmc_u32* code, pmc_u32 pc, const PmcShadingInputs* in, int n,
                             const PmcTextureSet* ts, float* stack, float* params, PmcCacheContext* cache) {
  /* Operands and result, [component][lane]. */
  float A[4][PMC_LANES], B[4][PMC_LANES], T[4][PMC_LANES], D[4][PMC_LANES], E[4][PMC_LANES], F[4][PMC_LANES],
      R[4][PMC_LANES];
  /* Active lanes: nn of them; virtual lane k is point lane_of[k] (the
   * identity but inside a cache group's sub-graphs, where the points that
   * missed are packed to the front). uv_now / footprint_now are the uv and
   * the texture footprint the virtual lane's nodes read: the point's own, or
   * in cache_eval center the centre and width of its texel, so the stored
   * value depends on the texel alone (and the footprint is round there: no
   * ellipse, axis_now 0). */
  int nn = n;
  int lane_of[PMC_LANES];
  float2 uv_now[PMC_LANES];
  float footprint_now[PMC_LANES];
  float2 axis_now[PMC_LANES]; /* the footprint's ellipse: major half-axis, */
  float minor_now[PMC_LANES]; /* minor width */
  float3 pos_now[PMC_LANES];  /* likewise the position */
  /* The cache group: lookups and stores so far, which of them are keyed on
   * position, and per point which lookups missed; every uv point of a point
   * shares its texel, every position point its cell. */
  pmc_u32 n_lookups = 0u, n_stores = 0u, by_position = 0u;
  pmc_u32 missed[PMC_LANES];
  PmcCacheTexel texel[PMC_LANES], cell[PMC_LANES];
  for (int k = 0; k < PMC_BATCH(n); ++k) {
    lane_of[k] = k;
    uv_now[k] = in[k].uv;
    footprint_now[k] = in[k].footprint;
    axis_now[k] = in[k].footprint_axis;
    minor_now[k] = in[k].footprint_minor;
    pos_now[k] = in[k].position;
    missed[k] = 0u;
    texel[k].ready = 0u;
    cell[k].ready = 0u;
    if (cache) {
      texel[k] = cache[k].texel;
      cell[k] = cache[k].cell;
    }
  }
  for (int guard = 0; guard < 1 << 16; ++guard) {
    pmc_u32 h = code[pc];
    pmc_u32 op = pmc_op_code(h);
    pmc_u32 width = pmc_op_width(h);
    pmc_u32 nargs = pmc_op_nargs(h);
    pmc_u32 imm = pmc_op_imm(h);
    pmc_u32 dst = code[pc + 1u];
    if (op == PMC_OP_END) return;
    switch (op) {
      case PMC_OP_OUTPUT: {
        PMC_FETCH4(A, 0);
        for (pmc_u32 i = 0; i < width && imm + i < PMC_P_COUNT; ++i)
          for (int k = 0; k < PMC_BATCH(nn); ++k) params[k * PMC_P_COUNT + (int)(imm + i)] = A[i][k];
        pc += 2u + nargs;
        continue;
      }
      case PMC_OP_MOVE:
        PMC_CW(PMC_A, A[c][k])
        break;
      case PMC_OP_SWIZZLE: {
        PMC_FETCH4(A, 0);
        for (int c = 0; c < (int)width; ++c) {
          pmc_u32 sel = (imm >> (3 * c)) & 7u;
          for (int k = 0; k < PMC_BATCH(nn); ++k) R[c][k] = sel < 4u ? A[sel][k] : (sel == 5u ? 1.0f : 0.0f);
        }
        break;
      }
      case PMC_OP_COMBINE:
        for (int c = 0; c < (int)width; ++c) {
          if ((pmc_u32)c < nargs && c < 4) pmc_fetch(code, stack, code[pc + 2u + (pmc_u32)c], 1, nn, A);
          for (int k = 0; k < PMC_BATCH(nn); ++k) R[c][k] = (pmc_u32)c < nargs ? A[0][k] : 0.0f;
        }
        break;
      case PMC_OP_TEXCOORD:
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          pmc_set_lanes4(R, k, make_float4(uv_now[k].x, uv_now[k].y, 0.0f, 0.0f));
        break;
      case PMC_OP_POSITION:
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float3 v = pos_now[k];
          pmc_set_lanes4(R, k, make_float4(v.x, v.y, v.z, 0.0f));
        }
        break;
      case PMC_OP_NORMAL:
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float3 v = in[lane_of[k]].normal;
          pmc_set_lanes4(R, k, make_float4(v.x, v.y, v.z, 0.0f));
        }
        break;
      case PMC_OP_TANGENT:
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float3 v = in[lane_of[k]].tangent;
          pmc_set_lanes4(R, k, make_float4(v.x, v.y, v.z, 0.0f));
        }
        break;
      case PMC_OP_BITANGENT:
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float3 v = in[lane_of[k]].bitangent;
          pmc_set_lanes4(R, k, make_float4(v.x, v.y, v.z, 0.0f));
        }
        break;
      case PMC_OP_CACHE_LOOKUP: {
        /* imm: node id (bits 0-13) | encoding << 14; the one "operand" word is
         * the number of words to skip when no point needs the group (0 but
         * for the group's last lookup, whose skip passes the group's
         * sub-graphs and STOREs), with PMC_CACHE_KEY_POSITION set for a
         * position-keyed point. A hit delivers its value at once. */
        pmc_u32 bit = 1u << (n_lookups & 31u);
        const pmc_u32 word = code[pc + 2u];
        const int positional = (word & PMC_CACHE_KEY_POSITION) != 0u;
        if (positional) by_position |= bit;
        n_lookups += 1u;
        for (int k = 0; k < PMC_BATCH(n); ++k) {
          int hit = 0;
          if (cache) {
            PmcCacheContext* cx = &cache[k];
            /* once per point: every cache point of a kind shares its texel or cell */
            if (positional && !cell[k].ready)
              cell[k] = pmc_cache_cell_floored(in[k].position, cx->radius, cx->bias, cx->jitter, cx->material,
                                               cx->floors ? cx->level_floor_position : PMC_LEVEL_NO_FLOOR,
                                               cx->max_refine);
            if (!positional && !texel[k].ready)
              texel[k] = pmc_cache_texel_floored(
                  in[k].uv, cx->g1, cx->g2, cx->bias, make_float2(cx->jitter.x, cx->jitter.y), cx->material,
                  cx->floors ? cx->level_floor_uv : PMC_LEVEL_NO_FLOOR, cx->max_refine);
            const PmcCacheTexel* t = positional ? &cell[k] : &texel[k];
            if (t->bypass) { /* too fine a texel to pay: evaluate, never insert */
              cx->counts[PMC_CSTAT_BYPASSED] += 1u;
              missed[k] |= bit;
              continue;
            }
            PmcCacheKey key = pmc_cache_key_at(t->hash, t->base, cx->material, imm & 0x3fffu, n_lookups - 1u);
            PMC_CACHE_TRACE(cx, key, positional);
            pmc_u32 bits;
            const pmc_u32 camera = cx->depth == 0u ? 1u : 0u;
            cx->counts[PMC_CSTAT_LOOKUPS] += 1u;
            cx->counts[PMC_CSTAT_CAMERA_LOOKUPS] += camera;
            cx->counts[PMC_CSTAT_POSITION_LOOKUPS] += (pmc_u32)positional;
            if (pmc_cache_lookup(&cx->table, key, &bits)) {
              float4 v = pmc_cache_decode(bits, imm >> 14);
              float* row = stack + dst * PMC_LANES + k;
              row[0] = v.x;
              if (width > 1u) row[PMC_LANES] = v.y;
              if (width > 2u) row[2 * PMC_LANES] = v.z;
              cx->hits += 1u;
              cx->counts[PMC_CSTAT_HITS] += 1u;
              cx->counts[PMC_CSTAT_CAMERA_HITS] += camera;
              cx->counts[PMC_CSTAT_POSITION_HITS] += (pmc_u32)positional;
              hit = 1;
            } else {
              cx->counts[PMC_CSTAT_MISSES] += 1u;
            }
          }
          if (!hit) missed[k] |= bit;
        }
        pmc_u32 skip = word & ~PMC_CACHE_KEY_POSITION;
        pc += 3u;
        if (skip != 0u) { /* the group's last lookup: pack the points that need it */
          nn = 0;
          for (int k = 0; k < PMC_BATCH(n); ++k)
            if (missed[k] != 0u) {
              lane_of[nn] = k;
              uv_now[nn] = in[k].uv;
              footprint_now[nn] = in[k].footprint;
              axis_now[nn] = in[k].footprint_axis;
              minor_now[nn] = in[k].footprint_minor;
              pos_now[nn] = in[k].position;
              if (cache && cache[k].center && texel[k].ready && !texel[k].bypass) {
                uv_now[nn] = make_float2(pmc_cache_texel_center(texel[k].tx, texel[k].lambda),
                                         pmc_cache_texel_center(texel[k].ty, texel[k].lambda));
                footprint_now[nn] = pmc_cache_texel_footprint(texel[k].footprint_lambda, cache[k].bias);
                axis_now[nn] = make_float2(0.0f, 0.0f); /* a texel's footprint is round */
                minor_now[nn] = 0.0f;
              }
              if (cache && cache[k].center && cell[k].ready && !cell[k].bypass)
                pos_now[nn] = make_float3(pmc_cache_cell_center(cell[k].tx, cell[k].lambda),
                                          pmc_cache_cell_center(cell[k].ty, cell[k].lambda),
                                          pmc_cache_cell_center(cell[k].tz, cell[k].lambda));
              ++nn;
            }
          if (nn == 0) { /* every point hit: skip the sub-graphs and stores */
            pc += skip;
            nn = n;
            for (int k = 0; k < PMC_BATCH(n); ++k) lane_of[k] = k;
          }
        }
        continue;
      }
      case PMC_OP_CACHE_STORE: {
        /* The group's k-th STORE belongs to its k-th LOOKUP (same imm). A
         * point that hit keeps its value; one that missed gets the computed
         * operand in `dst` and, with a cache, is inserted (in center mode the
         * stored, quantised value is delivered: a texel's value is then the
         * same whether this sample missed or a later one hits, which makes
         * center-mode renders independent of who inserts). */
        pmc_u32 bit = 1u << (n_stores & 31u);
        n_stores += 1u;
        PMC_FETCH4(A, 0);
        for (int j = 0; j < PMC_BATCH(nn); ++j) {
          int k = lane_of[j];
          if (!(missed[k] & bit)) continue;
          float4 v = pmc_lanes4(A, j);
          if (cache) {
            PmcCacheContext* cx = &cache[k];
            pmc_u32 bits;
            const PmcCacheTexel* t = (by_position & bit) ? &cell[k] : &texel[k];
            if (t->bypass) {
              /* evaluated without the cache: nothing to insert */
            } else if (pmc_cache_encode(v, imm >> 14, &bits)) {
              if (cx->center) v = pmc_cache_decode(bits, imm >> 14);
              PmcCacheKey key =
                  pmc_cache_key_at(t->hash, t->base, cx->material, imm & 0x3fffu, n_stores - 1u);
              int result = pmc_cache_insert(&cx->table, key, bits, cx->depth);
              if (result == 1) cx->counts[PMC_CSTAT_INSERTS] += 1u;
              if (result == 2) cx->counts[PMC_CSTAT_REPLACED] += 1u;
              if (result == 0) cx->counts[PMC_CSTAT_ALREADY_PRESENT] += 1u;
              if (result < 0) cx->counts[PMC_CSTAT_DROPPED_FULL] += 1u;
            } else {
              cx->counts[PMC_CSTAT_NOT_ENCODABLE] += 1u;
            }
          }
          float* row = stack + dst * PMC_LANES + k;
          row[0] = v.x;
          if (width > 1u) row[PMC_LANES] = v.y;
          if (width > 2u) row[2 * PMC_LANES] = v.z;
          if (width > 3u) row[3 * PMC_LANES] = v.w;
        }
        if (n_stores == n_lookups) { /* the group is done: every point again */
          nn = n;
          for (int k = 0; k < PMC_BATCH(n); ++k) {
            lane_of[k] = k;
            uv_now[k] = in[k].uv;
            footprint_now[k] = in[k].footprint;
            axis_now[k] = in[k].footprint_axis;
            minor_now[k] = in[k].footprint_minor;
            pos_now[k] = in[k].position;
          }
        }
        pc += 2u + nargs;
        continue;
      }
      case PMC_OP_ADD:
        PMC_CW(PMC_A; PMC_B, A[c][k] + B[c][k])
        break;
      case PMC_OP_SUB:
        PMC_CW(PMC_A; PMC_B, A[c][k] - B[c][k])
        break;
      case PMC_OP_MUL:
        PMC_CW(PMC_A; PMC_B, A[c][k] * B[c][k])
        break;
      case PMC_OP_DIV:
        PMC_CW(PMC_A; PMC_B, A[c][k] / B[c][k])
        break;
      case PMC_OP_MOD:
        PMC_CW(PMC_A; PMC_B, A[c][k] - B[c][k] * floor(A[c][k] / B[c][k]))
        break;
      case PMC_OP_POW:
        PMC_CW(PMC_A; PMC_B, pow(A[c][k], B[c][k]))
        break;
      case PMC_OP_MIN:
        PMC_CW(PMC_A; PMC_B, fmin(A[c][k], B[c][k]))
        break;
      case PMC_OP_MAX:
        PMC_CW(PMC_A; PMC_B, fmax(A[c][k], B[c][k]))
        break;
      case PMC_OP_DOT: {
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        pmc_u32 m = imm == 0u ? 3u : imm; /* imm = operand width */
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float d = A[0][k] * B[0][k];
          if (m > 1u) d += A[1][k] * B[1][k];
          if (m > 2u) d += A[2][k] * B[2][k];
          if (m > 3u) d += A[3][k] * B[3][k];
          pmc_set_lanes4(R, k, pmc_broadcast(d));
        }
        break;
      }
      case PMC_OP_ABS:
        PMC_CW(PMC_A, fabs(A[c][k]))
        break;
      case PMC_OP_FLOOR:
        PMC_CW(PMC_A, floor(A[c][k]))
        break;
      case PMC_OP_CEIL:
        PMC_CW(PMC_A, ceil(A[c][k]))
        break;
      case PMC_OP_SIN:
        PMC_CW(PMC_A, sin(A[c][k]))
        break;
      case PMC_OP_COS:
        PMC_CW(PMC_A, cos(A[c][k]))
        break;
      case PMC_OP_SQRT:
        PMC_CW(PMC_A, sqrt(A[c][k]))
        break;
      case PMC_OP_NORMALIZE: {
        PMC_FETCH4(A, 0);
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float4 a = pmc_lanes4(A, k);
          float l2 = a.x * a.x + (width > 1u ? a.y * a.y : 0.0f) + (width > 2u ? a.z * a.z : 0.0f) +
                     (width > 3u ? a.w * a.w : 0.0f);
          pmc_set_lanes4(R, k, l2 > 0.0f ? a * (1.0f / sqrt(l2)) : a);
        }
        break;
      }
      case PMC_OP_CLAMP:
        PMC_CW(PMC_A; PMC_B; PMC_T, fmin(fmax(A[c][k], B[c][k]), T[c][k]))
        break;
      case PMC_OP_SMOOTHSTEP:
        PMC_CW(PMC_A; PMC_B; PMC_T, pmc_smoothstep1(A[c][k], B[c][k], T[c][k]))
        break;
      case PMC_OP_MIX: /* fg, bg, mix: bg + (fg - bg) * mix */
        PMC_CW(PMC_A; PMC_B; PMC_T, B[c][k] + (A[c][k] - B[c][k]) * T[c][k])
        break;
      case PMC_OP_REMAP: /* in, inlow, inhigh, outlow, outhigh */
        PMC_CW(PMC_A; PMC_B; PMC_T; PMC_D;
               PMC_E, D[c][k] + (A[c][k] - B[c][k]) * (E[c][k] - D[c][k]) / (T[c][k] - B[c][k]))
        break;
      case PMC_OP_IFGREATER: /* value1, value2, in1, in2 */
        PMC_CW(PMC_A; PMC_B; PMC_T; PMC_D, A[c][k] > B[c][k] ? T[c][k] : D[c][k])
        break;
      case PMC_OP_IFGREATEREQ:
        PMC_CW(PMC_A; PMC_B; PMC_T; PMC_D, A[c][k] >= B[c][k] ? T[c][k] : D[c][k])
        break;
      case PMC_OP_LUMINANCE: {
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float l = A[0][k] * B[0][k] + A[1][k] * B[1][k] + A[2][k] * B[2][k];
          pmc_set_lanes4(R, k, make_float4(l, l, l, A[3][k]));
        }
        break;
      }
      case PMC_OP_RGBTOHSV:
        PMC_FETCH4(A, 0);
        for (int k = 0; k < PMC_BATCH(nn); ++k) pmc_set_lanes4(R, k, pmc_rgb_to_hsv(pmc_lanes4(A, k)));
        break;
      case PMC_OP_HSVTORGB:
        PMC_FETCH4(A, 0);
        for (int k = 0; k < PMC_BATCH(nn); ++k) pmc_set_lanes4(R, k, pmc_hsv_to_rgb(pmc_lanes4(A, k)));
        break;
      case PMC_OP_IMAGE: { /* uv, default, mode; imm = texture index */
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        PMC_FETCH4(T, 2);
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          /* T[1]: the uv chain's footprint scale; the ellipse only where the
           * chain keeps its direction (PMC_IMAGE_ANISO) */
          pmc_u32 bits = (pmc_u32)pmc_to_int(T[0][k]);
          const float s = T[1][k];
          const float2 axis = (bits & PMC_IMAGE_ANISO) ? axis_now[k] * s : make_float2(0.0f, 0.0f);
          float4 c = pmc_texture_sample_ellipse(ts, imm, make_float2(A[0][k], A[1][k]), footprint_now[k] * s,
                                                axis, minor_now[k] * s, bits & 3u, (bits >> 2) & 3u,
                                                (bits >> 4) & 3u, pmc_lanes4(B, k));
          /* A float image reads the first channel. */
          pmc_set_lanes4(R, k, width == 1u ? pmc_broadcast(c.x) : c);
        }
        break;
      }
      case PMC_OP_HEXIMAGE:       /* see PMC_OPCODES for the operands; imm = texture index */
      case PMC_OP_HEXNORMALMAP: { /* more operands than arrays: the tiles first, then the rest */
        PmcHexTiles tiles[PMC_LANES];
        float gain[PMC_LANES];  /* the tiling's footprint gain */
        float2 axis[PMC_LANES]; /* the ellipse's major half-axis, tiled */
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          A[0][k] *= B[0][k];
          A[1][k] *= B[1][k];
          gain[k] = fmax(fabs(B[0][k]), fabs(B[1][k]));
          /* An even tiling (|x| = |y|: a uniform scale, perhaps mirrored)
           * maps the ellipse's axes onto the tiled ellipse's; an uneven one
           * would not: isotropic there. */
          axis[k] = fabs(B[0][k]) == fabs(B[1][k])
                        ? make_float2(axis_now[k].x * B[0][k], axis_now[k].y * B[1][k])
                        : make_float2(0.0f, 0.0f);
        }
        PMC_FETCH4(B, 2);
        PMC_FETCH4(T, 3);
        PMC_FETCH4(D, 4);
        PMC_FETCH4(E, 5);
        PMC_FETCH4(F, 6);
        PMC_FETCH4(R, 7);
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          tiles[k] = pmc_hextile_tiles(make_float2(A[0][k], A[1][k]), B[0][k], make_float2(T[0][k], T[1][k]),
                                       D[0][k], make_float2(E[0][k], E[1][k]), F[0][k],
                                       make_float2(R[0][k], R[1][k]));
        PMC_FETCH4(A, 8);  /* falloff */
        PMC_FETCH4(B, 9);  /* default */
        PMC_FETCH4(T, 10); /* mode */
        PMC_FETCH4(D, 11); /* falloffcontrast | strength */
        PMC_FETCH4(E, 12); /* lumacoeffs | flip_g */
        if (op == PMC_OP_HEXNORMALMAP) {
          PMC_FETCH4(F, 13); /* normal */
          PMC_FETCH4(R, 14); /* tangent, read before R is written */
        }
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          pmc_u32 bits = (pmc_u32)pmc_to_int(T[0][k]);
          PmcFootprint fp;
          fp.width = footprint_now[k] * T[1][k] * gain[k];
          fp.axis = (bits & PMC_IMAGE_ANISO) ? axis[k] * T[1][k] : make_float2(0.0f, 0.0f);
          fp.minor = minor_now[k] * T[1][k] * gain[k];
          float4 r =
              op == PMC_OP_HEXIMAGE
                  ? pmc_hextile_image(ts, imm, &tiles[k], fp, bits, pmc_lanes4(B, k), A[0][k], D[0][k],
                                      make_float3(E[0][k], E[1][k], E[2][k]))
                  : pmc_hextile_normalmap(ts, imm, &tiles[k], fp, bits, pmc_lanes4(B, k), A[0][k], D[0][k],
                                          E[0][k] != 0.0f, make_float3(F[0][k], F[1][k], F[2][k]),
                                          make_float3(R[0][k], R[1][k], R[2][k]));
          pmc_set_lanes4(R, k, r);
        }
        break;
      }
      case PMC_OP_PLACE2D:
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        PMC_FETCH4(T, 2);
        PMC_FETCH4(D, 3);
        PMC_FETCH4(E, 4);
        PMC_FETCH4(F, 5);
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          pmc_set_lanes4(R, k,
                         pmc_place2d(pmc_lanes4(A, k), pmc_lanes4(B, k), pmc_lanes4(T, k), D[0][k],
                                     pmc_lanes4(E, k), pmc_to_int(F[0][k])));
        break;
      case PMC_OP_NOISE2D:   /* texcoord, amplitude, pivot */
      case PMC_OP_NOISE3D: { /* position, amplitude, pivot */
        const int dims = op == PMC_OP_NOISE3D ? 3 : 2;
        pmc_fetch(code, stack, code[pc + 2u], dims, nn, A);
        PMC_FETCH4(B, 1);
        PMC_FETCH4(T, 2);
        pmc_noise_lanes(dims, A[0], A[1], A[2], width, nn, R);
        for (int c = 0; c < 4; ++c)
          for (int k = 0; k < PMC_BATCH(nn); ++k) R[c][k] = R[c][k] * B[c][k] + T[c][k];
        break;
      }
      case PMC_OP_FRACTAL2D:   /* texcoord, amplitude, octaves, lacunarity, diminish */
      case PMC_OP_FRACTAL3D: { /* position, ... */
        const int dims = op == PMC_OP_FRACTAL3D ? 3 : 2;
        pmc_fetch(code, stack, code[pc + 2u], dims, nn, A);
        PMC_FETCH4(B, 1);
        pmc_fetch(code, stack, code[pc + 4u], 1, nn, T);
        pmc_fetch(code, stack, code[pc + 5u], 1, nn, D);
        pmc_fetch(code, stack, code[pc + 6u], 1, nn, E);
        int octaves[PMC_LANES];
        for (int k = 0; k < PMC_BATCH(nn); ++k) octaves[k] = pmc_to_int(T[0][k]);
        pmc_fractal_lanes(dims, A[0], A[1], A[2], octaves, D[0], E[0], width, nn, R);
        for (int c = 0; c < 4; ++c)
          for (int k = 0; k < PMC_BATCH(nn); ++k) R[c][k] = R[c][k] * B[c][k];
        break;
      }
      case PMC_OP_CELLNOISE2D:
      case PMC_OP_CELLNOISE3D: {
        const int dims = op == PMC_OP_CELLNOISE3D ? 3 : 2;
        pmc_fetch(code, stack, code[pc + 2u], dims, nn, A);
        pmc_cellnoise_lanes(dims, A[0], A[1], A[2], nn, R[0]);
        for (int k = 0; k < PMC_BATCH(nn); ++k) R[1][k] = R[2][k] = R[3][k] = R[0][k];
        break;
      }
      case PMC_OP_WORLEY2D: /* texcoord, jitter, style */
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        PMC_FETCH4(T, 2);
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          pmc_set_lanes4(R, k,
                         pmc_op_worley2d(make_float2(A[0][k], A[1][k]), B[0][k], pmc_to_int(T[0][k]), width));
        break;
      case PMC_OP_WORLEY3D:
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        PMC_FETCH4(T, 2);
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          pmc_set_lanes4(
              R, k,
              pmc_op_worley3d(make_float3(A[0][k], A[1][k], A[2][k]), B[0][k], pmc_to_int(T[0][k]), width));
        break;
      case PMC_OP_RAMPLR: /* valuel, valuer, texcoord */
        pmc_fetch(code, stack, code[pc + 4u], 2, nn, T);
        PMC_CW(PMC_A; PMC_B, A[c][k] + (B[c][k] - A[c][k]) * clamp(T[0][k], 0.0f, 1.0f))
        break;
      case PMC_OP_RAMPTB: /* valuet, valueb, texcoord */
        pmc_fetch(code, stack, code[pc + 4u], 2, nn, T);
        PMC_CW(PMC_A; PMC_B, B[c][k] + (A[c][k] - B[c][k]) * clamp(T[1][k], 0.0f, 1.0f))
        break;
      case PMC_OP_RAMP4: { /* tl, tr, bl, br, texcoord */
        pmc_fetch(code, stack, code[pc + 6u], 2, nn, E);
        PMC_A;
        PMC_B;
        PMC_T;
        PMC_D;
        for (int c = 0; c < (int)width; ++c)
          for (int k = 0; k < PMC_BATCH(nn); ++k) {
            float s = clamp(E[0][k], 0.0f, 1.0f), t = clamp(E[1][k], 0.0f, 1.0f);
            float top = A[c][k] + (B[c][k] - A[c][k]) * s;
            float bottom = T[c][k] + (D[c][k] - T[c][k]) * s;
            R[c][k] = bottom + (top - bottom) * t;
          }
        break;
      }
      case PMC_OP_SPLITLR: /* valuel, valuer, center, texcoord */
        pmc_fetch(code, stack, code[pc + 4u], 1, nn, T);
        pmc_fetch(code, stack, code[pc + 5u], 2, nn, D);
        PMC_CW(PMC_A; PMC_B, D[0][k] < T[0][k] ? A[c][k] : B[c][k])
        break;
      case PMC_OP_SPLITTB: /* valuet, valueb, center, texcoord */
        pmc_fetch(code, stack, code[pc + 4u], 1, nn, T);
        pmc_fetch(code, stack, code[pc + 5u], 2, nn, D);
        PMC_CW(PMC_A; PMC_B, D[1][k] > T[0][k] ? A[c][k] : B[c][k])
        break;
      case PMC_OP_TILEDSHAPE:  /* texcoord, uvtiling, uvoffset, size, staggered; imm = shape */
      case PMC_OP_LINEPATTERN: /* texcoord, uvtiling, uvoffset, thickness, staggered; imm = kind */
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        PMC_FETCH4(T, 2);
        PMC_FETCH4(D, 3);
        PMC_FETCH4(E, 4);
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float2 uv = make_float2(A[0][k], A[1][k]), tiling = make_float2(B[0][k], B[1][k]);
          float2 offset = make_float2(T[0][k], T[1][k]);
          pmc_set_lanes4(R, k,
                         op == PMC_OP_TILEDSHAPE
                             ? pmc_op_tiledshape(uv, tiling, offset, D[0][k], E[0][k] != 0.0f, imm)
                             : pmc_op_linepattern(uv, tiling, offset, D[0][k], E[0][k] != 0.0f, imm));
        }
        break;
      case PMC_OP_NORMALMAP: /* in, scale, normal, tangent */
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        PMC_FETCH4(T, 2);
        PMC_FETCH4(D, 3);
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          pmc_set_lanes4(R, k,
                         pmc_normalmap(pmc_lanes4(A, k), B[0][k], make_float3(T[0][k], T[1][k], T[2][k]),
                                       make_float3(D[0][k], D[1][k], D[2][k])));
        break;
      case PMC_OP_TAN:
        PMC_CW(PMC_A, tan(A[c][k]))
        break;
      case PMC_OP_ASIN:
        PMC_CW(PMC_A, asin(A[c][k]))
        break;
      case PMC_OP_ACOS:
        PMC_CW(PMC_A, acos(A[c][k]))
        break;
      case PMC_OP_ATAN2:
        PMC_CW(PMC_A; PMC_B, atan2(A[c][k], B[c][k]))
        break;
      case PMC_OP_EXP:
        PMC_CW(PMC_A, exp(A[c][k]))
        break;
      case PMC_OP_LN:
        PMC_CW(PMC_A, log(A[c][k]))
        break;
      case PMC_OP_SIGN:
        PMC_CW(PMC_A, pmc_sign1(A[c][k]))
        break;
      case PMC_OP_ROUND:
        PMC_CW(PMC_A, pmc_round1(A[c][k]))
        break;
      case PMC_OP_FRACT:
        PMC_CW(PMC_A, A[c][k] - floor(A[c][k]))
        break;
      case PMC_OP_LENGTH: {
        PMC_FETCH4(A, 0);
        pmc_u32 m = imm == 0u ? 3u : imm; /* imm = operand width */
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float d = A[0][k] * A[0][k];
          if (m > 1u) d += A[1][k] * A[1][k];
          if (m > 2u) d += A[2][k] * A[2][k];
          if (m > 3u) d += A[3][k] * A[3][k];
          pmc_set_lanes4(R, k, pmc_broadcast(sqrt(d)));
        }
        break;
      }
      case PMC_OP_CROSS:
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          pmc_set_lanes4(
              R, k,
              make_float4(A[1][k] * B[2][k] - A[2][k] * B[1][k], A[2][k] * B[0][k] - A[0][k] * B[2][k],
                          A[0][k] * B[1][k] - A[1][k] * B[0][k], 0.0f));
        break;
      case PMC_OP_NOT:
        PMC_CW(PMC_A, A[c][k] == 0.0f ? 1.0f : 0.0f)
        break;
      case PMC_OP_IFEQUAL: /* value1, value2, in1, in2 (values compared on their first component) */
        pmc_fetch(code, stack, code[pc + 2u], 1, nn, A);
        pmc_fetch(code, stack, code[pc + 3u], 1, nn, B);
        PMC_CW(PMC_T; PMC_D, A[0][k] == B[0][k] ? T[c][k] : D[c][k])
        break;
      case PMC_OP_BLEND: /* fg, bg, mix; imm = mode */
        PMC_CW(PMC_A; PMC_B; PMC_T, pmc_blend1(A[c][k], B[c][k], T[c][k], imm))
        break;
      case PMC_OP_ROTATE2D: /* MaterialX mx_rotate_vector2: (ca x + sa y, -sa x + ca y) */
        PMC_FETCH4(A, 0);
        pmc_fetch(code, stack, code[pc + 3u], 1, nn, B);
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float a = B[0][k] * (PMC_PI / 180.0f);
          float sa = sin(a), ca = cos(a);
          pmc_set_lanes4(R, k,
                         make_float4(ca * A[0][k] + sa * A[1][k], -sa * A[0][k] + ca * A[1][k], 0.0f, 0.0f));
        }
        break;
      case PMC_OP_ROTATE3D: /* MaterialX mx_rotate_vector3 (Rodrigues, v' = v M):
                             * v c + cross(v, axis) s + axis dot(axis, v) (1 - c), axis normalised. */
        PMC_FETCH4(A, 0);
        pmc_fetch(code, stack, code[pc + 3u], 1, nn, B);
        PMC_FETCH4(T, 2);
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float3 v = make_float3(A[0][k], A[1][k], A[2][k]), ax = make_float3(T[0][k], T[1][k], T[2][k]);
          float l = length(ax);
          ax = l > 0.0f ? ax * (1.0f / l) : ax;
          float a = B[0][k] * (PMC_PI / 180.0f);
          float sn = sin(a), cs = cos(a);
          float3 res = v * cs + cross(v, ax) * sn + ax * (dot(ax, v) * (1.0f - cs));
          pmc_set_lanes4(R, k, make_float4(res.x, res.y, res.z, 0.0f));
        }
        break;
      case PMC_OP_COMPOSITE: /* fg, bg, mix; imm = PMC_COMP_* */
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        pmc_fetch(code, stack, code[pc + 4u], 1, nn, T);
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          pmc_set_lanes4(R, k, pmc_composite(pmc_lanes4(A, k), pmc_lanes4(B, k), T[0][k], imm));
        break;
      case PMC_OP_PREMULT: /* imm 0: premult, 1: unpremult */
        PMC_FETCH4(A, 0);
        for (int k = 0; k < PMC_BATCH(nn); ++k) pmc_set_lanes4(R, k, pmc_premult(pmc_lanes4(A, k), imm));
        break;
      case PMC_OP_OUTSIDE: /* in, mask (one float) */
        pmc_fetch(code, stack, code[pc + 3u], 1, nn, B);
        PMC_CW(PMC_A, A[c][k] * (1.0f - B[0][k]))
        break;
      case PMC_OP_FLAKE: /* size, roughness, coverage, position, normal, tangent, bitangent */
        pmc_fetch(code, stack, code[pc + 2u], 1, nn, A);
        pmc_fetch(code, stack, code[pc + 3u], 1, nn, B);
        pmc_fetch(code, stack, code[pc + 4u], 1, nn, T);
        pmc_fetch(code, stack, code[pc + 5u], 3, nn, D); /* a vector2 texcoord gets z = 0 */
        pmc_fetch(code, stack, code[pc + 6u], 3, nn, E);
        pmc_fetch(code, stack, code[pc + 7u], 3, nn, F);
        pmc_fetch(code, stack, code[pc + 8u], 3, nn, R); /* the bitangent, read before R is written */
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float3 bt = make_float3(R[0][k], R[1][k], R[2][k]);
          PmcFlake f =
              pmc_flake(A[0][k], B[0][k], T[0][k], make_float3(D[0][k], D[1][k], D[2][k]),
                        make_float3(E[0][k], E[1][k], E[2][k]), make_float3(F[0][k], F[1][k], F[2][k]), bt);
          pmc_set_lanes4(R, k, pmc_flake_output(f, imm));
        }
        break;
      case PMC_OP_ROUGHNESS_ANISO: /* roughness, anisotropy */
        pmc_fetch(code, stack, code[pc + 2u], 1, nn, A);
        pmc_fetch(code, stack, code[pc + 3u], 1, nn, B);
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float2 r = pmc_roughness_anisotropy(A[0][k], B[0][k]);
          pmc_set_lanes4(R, k, make_float4(r.x, r.y, 0.0f, 0.0f));
        }
        break;
      case PMC_OP_ROUGHNESS_DUAL: /* roughness (vector2) */
        pmc_fetch(code, stack, code[pc + 2u], 2, nn, A);
        for (int k = 0; k < PMC_BATCH(nn); ++k) {
          float2 r = pmc_roughness_dual(make_float2(A[0][k], A[1][k]));
          pmc_set_lanes4(R, k, make_float4(r.x, r.y, 0.0f, 0.0f));
        }
        break;
      case PMC_OP_ARTISTIC_IOR: /* reflectivity, edge_color; imm 1: extinction */
        PMC_FETCH4(A, 0);
        PMC_FETCH4(B, 1);
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          pmc_set_lanes4(R, k, pmc_artistic_ior(pmc_lanes4(A, k), pmc_lanes4(B, k), imm != 0u));
        break;
      case PMC_OP_BLACKBODY: /* temperature */
        pmc_fetch(code, stack, code[pc + 2u], 1, nn, A);
        for (int k = 0; k < PMC_BATCH(nn); ++k) pmc_set_lanes4(R, k, pmc_blackbody(A[0][k]));
        break;
      case PMC_OP_HAIR_ROUGHNESS: /* longitudinal, azimuthal, scale_TT, scale_TRT */
        pmc_fetch(code, stack, code[pc + 2u], 1, nn, A);
        pmc_fetch(code, stack, code[pc + 3u], 1, nn, B);
        pmc_fetch(code, stack, code[pc + 4u], 1, nn, T);
        pmc_fetch(code, stack, code[pc + 5u], 1, nn, D);
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          pmc_set_lanes4(R, k, pmc_chiang_hair_roughness(A[0][k], B[0][k], T[0][k], D[0][k], imm));
        break;
      case PMC_OP_HAIR_MELANIN: /* concentration, redness, eumelanin_color, pheomelanin_color */
        pmc_fetch(code, stack, code[pc + 2u], 1, nn, A);
        pmc_fetch(code, stack, code[pc + 3u], 1, nn, B);
        PMC_FETCH4(T, 2);
        PMC_FETCH4(D, 3);
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          pmc_set_lanes4(R, k,
                         pmc_deon_hair_absorption(A[0][k], B[0][k], pmc_lanes4(T, k), pmc_lanes4(D, k)));
        break;
      case PMC_OP_HAIR_COLOR: /* color, azimuthal_roughness */
        PMC_FETCH4(A, 0);
        pmc_fetch(code, stack, code[pc + 3u], 1, nn, B);
        for (int k = 0; k < PMC_BATCH(nn); ++k)
          pmc_set_lanes4(R, k, pmc_chiang_hair_absorption(pmc_lanes4(A, k), B[0][k]));
        break;
      default:
        return; /* unknown opcode: the compiler never emits one; stop safely */
    }
    for (int c = 0; c < (int)width; ++c) {
      float* row = stack + (dst + (pmc_u32)c) * PMC_LANES;
      for (int k = 0; k < PMC_BATCH(nn); ++k) row[k] = R[c][k];
    }
    pc += 2u + nargs;
  }
}

/* One shading point (PMC_LANES must be 1: the host reference and tests). */
PMC_FN void pmc_interp_run(PMC_GLOBAL const pmc_u32* code, pmc_u32 pc, const PmcShadingInputs* in,
                           const PmcTextureSet* ts, float* stack, float* params, PmcCacheContext* cache) {
  pmc_interp_lanes(code, pc, in, 1, ts, stack, params, cache);
}

#undef PMC_CW
#undef PMC_A
#undef PMC_B
#undef PMC_T
#undef PMC_D
#undef PMC_E
#undef PMC_FETCH4

/* Parameter defaults of standard_surface (PMC_STANDARD_SURFACE); the normal
 * defaults to the shading normal. */
PMC_FN void pmc_surface_defaults(float* p, float3 shading_normal) {
  for (int i = 0; i < PMC_P_COUNT; ++i) p[i] = 0.0f;
#define PMC_SURFACE_DEFAULT(input, param, width, x, y, z) \
  p[param] = x;                                           \
  if (width > 1) {                                        \
    p[param + 1] = y;                                     \
    p[param + 2] = z;                                     \
  }
  PMC_STANDARD_SURFACE(PMC_SURFACE_DEFAULT)
#undef PMC_SURFACE_DEFAULT
  p[PMC_P_NORMAL] = shading_normal.x;
  p[PMC_P_NORMAL + 1] = shading_normal.y;
  p[PMC_P_NORMAL + 2] = shading_normal.z;
}

#endif /* PMC_INTERP_H */
