/* pmc_interp.h — the material bytecode interpreter, one source for both sides.
 *
 * pmc_interp_run() executes one material program (see pmc_bytecode.h) for one
 * shading point: it reads operands from the float stack or inline constants,
 * computes on float4 lanes and writes `width` floats to the destination slot,
 * until END. OUTPUT instructions fill the surface parameter block that
 * pmc_surface_to_bsdf() turns into a BSDF. The OpenCL shade kernel and the
 * host's reference interpreter (materials/cpu_interpreter.cpp) both compile
 * this file, so tests can run every opcode on both and compare.
 */
#ifndef PMC_INTERP_H
#define PMC_INTERP_H

#include "../abi/pmc_bytecode.h"
#include "pmc_bsdf.h"
#include "pmc_cache.h"
#include "pmc_noise.h"
#include "pmc_patterns.h"
#include "pmc_texture.h"

/* What a material may read at the shading point. */
typedef struct PmcShadingInputs {
  float2 uv;
  float3 position;
  float3 normal; /* shading normal, facing the viewer */
  float3 tangent;
  float3 bitangent;
  float footprint; /* uv-space width of the ray-cone footprint (texture LOD) */
} PmcShadingInputs;

/* The material cache as one evaluation sees it. A null context (the host
 * reference, or --cache off, whose programs have no cache instructions)
 * makes every lookup a miss. */
typedef struct PmcCacheContext {
  PmcCacheTable table;
  float2 g1, g2; /* ray-cone uv gradients at the hit */
  float bias;    /* --mip-bias */
  float2 jitter; /* added to uv * 2^lambda before flooring, in [-0.5, 0.5):
                  * 0 is the nearest texel; uniform random offsets pick a
                  * neighbour with its bilinear weight (--cache-filter) */
  pmc_u32 material;
  pmc_u32 center;      /* --cache-eval center: evaluate misses at the texel centre */
  PmcCacheTexel texel; /* the shading point's texel, if the caller computed it
                        * (ready); else the first lookup computes it */
  pmc_u32 hits;        /* out: cache points found in this evaluation */
  /* out: PMC_CSTAT_* events, counted privately (no atomics per lookup); the
   * caller adds them up: the shade kernel once per work-group. */
  pmc_u32 counts[PMC_CSTAT_COUNT];
} PmcCacheContext;

PMC_FN float4 pmc_broadcast(float v) { return make_float4(v, v, v, v); }

PMC_FN float4 pmc_load_operand(PMC_GLOBAL const pmc_u32* code, const float* stack, pmc_u32 o) {
  pmc_u32 index = o & PMC_OPERAND_INDEX_MASK;
  pmc_u32 w = (o >> 28) & 3u; /* width - 1 */
  if (o & PMC_OPERAND_CONST) {
    PMC_GLOBAL const pmc_u32* c = code + index;
    float x = as_float((int)c[0]);
    if (w == 0u) return pmc_broadcast(x);
    float y = as_float((int)c[1]);
    if (w == 1u) return make_float4(x, y, 0.0f, 0.0f);
    float z = as_float((int)c[2]);
    return make_float4(x, y, z, w == 2u ? 0.0f : as_float((int)c[3]));
  }
  const float* p = stack + index;
  if (w == 0u) return pmc_broadcast(p[0]);
  if (w == 1u) return make_float4(p[0], p[1], 0.0f, 0.0f);
  return make_float4(p[0], p[1], p[2], w == 2u ? 0.0f : p[3]);
}

/* Float to int without undefined behaviour for NaN or huge values. */
PMC_FN int pmc_to_int(float x) {
  if (!(x > -1e6f)) return x > 0.0f ? 1000000 : -1000000; /* NaN and below */
  if (!(x < 1e6f)) return 1000000;
  return (int)x;
}

PMC_FN float pmc_lane(float4 v, int i) { return i == 0 ? v.x : (i == 1 ? v.y : (i == 2 ? v.z : v.w)); }

/* Lane-wise a > b ? x : y */
PMC_FN float4 pmc_where_greater(float4 a, float4 b, float4 x, float4 y, int or_equal) {
  float4 r;
  r.x = (or_equal ? a.x >= b.x : a.x > b.x) ? x.x : y.x;
  r.y = (or_equal ? a.y >= b.y : a.y > b.y) ? x.y : y.y;
  r.z = (or_equal ? a.z >= b.z : a.z > b.z) ? x.z : y.z;
  r.w = (or_equal ? a.w >= b.w : a.w > b.w) ? x.w : y.w;
  return r;
}

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

#define PMC_ARG(i) pmc_load_operand(code, stack, code[pc + 2u + (i)])

/* Runs the program at `pc` until END. `params` receives OUTPUT values. */
PMC_FN void pmc_interp_run(PMC_GLOBAL const pmc_u32* code, pmc_u32 pc, const PmcShadingInputs* in,
                           const PmcTextureSet* ts, float* stack, float* params, PmcCacheContext* cache) {
  /* While a --cache-eval center miss evaluates its block: the texel's centre
   * and width replace the hit's uv and ray-cone footprint, so the stored value
   * depends on the texel alone. */
  float2 uv_now = in->uv;
  float footprint_now = in->footprint;
  /* The cache group: lookups and stores so far, and which lookups missed. */
  pmc_u32 n_lookups = 0u, n_stores = 0u, missed = 0u;
  /* The cache descriptor's texel: the caller's, or computed at the first lookup. */
  PmcCacheTexel texel;
  texel.ready = 0u;
  if (cache) texel = cache->texel;
  for (int guard = 0; guard < 1 << 16; ++guard) {
    pmc_u32 h = code[pc];
    pmc_u32 op = pmc_op_code(h);
    pmc_u32 width = pmc_op_width(h);
    pmc_u32 nargs = pmc_op_nargs(h);
    pmc_u32 imm = pmc_op_imm(h);
    pmc_u32 dst = code[pc + 1u];
    float4 r = pmc_broadcast(0.0f);
    if (op == PMC_OP_END) return;
    switch (op) {
      case PMC_OP_OUTPUT: {
        float4 a = PMC_ARG(0);
        for (pmc_u32 i = 0; i < width && imm + i < PMC_P_COUNT; ++i) params[imm + i] = pmc_lane(a, (int)i);
        pc += 2u + nargs;
        continue;
      }
      case PMC_OP_MOVE:
        r = PMC_ARG(0);
        break;
      case PMC_OP_SWIZZLE: {
        float4 a = PMC_ARG(0);
        float v[4];
        for (int i = 0; i < 4; ++i) {
          pmc_u32 sel = (imm >> (3 * i)) & 7u;
          v[i] = sel < 4u ? pmc_lane(a, (int)sel) : (sel == 5u ? 1.0f : 0.0f);
        }
        r = make_float4(v[0], v[1], v[2], v[3]);
        break;
      }
      case PMC_OP_COMBINE: {
        float v[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        for (pmc_u32 i = 0; i < nargs && i < 4u; ++i) v[i] = PMC_ARG(i).x;
        r = make_float4(v[0], v[1], v[2], v[3]);
        break;
      }
      case PMC_OP_TEXCOORD:
        r = make_float4(uv_now.x, uv_now.y, 0.0f, 0.0f);
        break;
      case PMC_OP_CACHE_LOOKUP: {
        /* imm: node id (bits 0-13) | encoding << 14; the one "operand" word is
         * the number of words to skip on a hit when no earlier lookup of the
         * group missed (0 but for the group's last lookup, whose skip passes
         * the group's sub-graphs and STOREs). Without a cache context every
         * lookup misses. */
        pmc_u32 bit = 1u << (n_lookups & 31u);
        n_lookups += 1u;
        if (cache) {
          if (!texel.ready) /* once per evaluation: every cache point shares the texel */
            texel =
                pmc_cache_texel_of(in->uv, cache->g1, cache->g2, cache->bias, cache->jitter, cache->material);
          PmcCacheKey key =
              pmc_cache_key_at(texel.hash, texel.base, cache->material, imm & 0x3fffu, n_lookups - 1u);
          pmc_u32 bits;
          cache->counts[PMC_CSTAT_LOOKUPS] += 1u;
          if (pmc_cache_lookup(&cache->table, key, &bits)) {
            float4 v = pmc_cache_decode(bits, imm >> 14);
            stack[dst] = v.x;
            if (width > 1u) stack[dst + 1u] = v.y;
            if (width > 2u) stack[dst + 2u] = v.z;
            cache->hits += 1u;
            cache->counts[PMC_CSTAT_HITS] += 1u;
            pc += 3u + (missed == 0u ? code[pc + 2u] : 0u);
            continue;
          }
          cache->counts[PMC_CSTAT_MISSES] += 1u;
          if (cache->center) {
            uv_now = make_float2(pmc_cache_texel_center(texel.tx, texel.lambda),
                                 pmc_cache_texel_center(texel.ty, texel.lambda));
            footprint_now = pmc_cache_texel_footprint(texel.lambda, cache->bias);
          }
        }
        missed |= bit;
        pc += 3u;
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
        if (missed & bit) {
          float4 v = PMC_ARG(0);
          if (cache) {
            pmc_u32 bits;
            if (pmc_cache_encode(v, imm >> 14, &bits)) {
              if (cache->center) v = pmc_cache_decode(bits, imm >> 14);
              PmcCacheKey key =
                  pmc_cache_key_at(texel.hash, texel.base, cache->material, imm & 0x3fffu, n_stores - 1u);
              int result = pmc_cache_insert(&cache->table, key, bits);
              if (result > 0) cache->counts[PMC_CSTAT_INSERTS] += 1u;
              if (result == 0) cache->counts[PMC_CSTAT_ALREADY_PRESENT] += 1u;
              if (result < 0) cache->counts[PMC_CSTAT_DROPPED_FULL] += 1u;
            } else {
              cache->counts[PMC_CSTAT_NOT_ENCODABLE] += 1u;
            }
          }
          stack[dst] = v.x;
          if (width > 1u) stack[dst + 1u] = v.y;
          if (width > 2u) stack[dst + 2u] = v.z;
          if (width > 3u) stack[dst + 3u] = v.w;
        }
        uv_now = in->uv;
        footprint_now = in->footprint;
        pc += 2u + nargs;
        continue;
      }
      case PMC_OP_POSITION:
        r = make_float4(in->position.x, in->position.y, in->position.z, 0.0f);
        break;
      case PMC_OP_NORMAL:
        r = make_float4(in->normal.x, in->normal.y, in->normal.z, 0.0f);
        break;
      case PMC_OP_TANGENT:
        r = make_float4(in->tangent.x, in->tangent.y, in->tangent.z, 0.0f);
        break;
      case PMC_OP_BITANGENT:
        r = make_float4(in->bitangent.x, in->bitangent.y, in->bitangent.z, 0.0f);
        break;
      case PMC_OP_ADD:
        r = PMC_ARG(0) + PMC_ARG(1);
        break;
      case PMC_OP_SUB:
        r = PMC_ARG(0) - PMC_ARG(1);
        break;
      case PMC_OP_MUL:
        r = PMC_ARG(0) * PMC_ARG(1);
        break;
      case PMC_OP_DIV:
        r = PMC_ARG(0) / PMC_ARG(1);
        break;
      case PMC_OP_MOD: {
        float4 a = PMC_ARG(0), b = PMC_ARG(1);
        r = a - b * floor(a / b);
        break;
      }
      case PMC_OP_POW:
        r = pow(PMC_ARG(0), PMC_ARG(1));
        break;
      case PMC_OP_MIN:
        r = fmin(PMC_ARG(0), PMC_ARG(1));
        break;
      case PMC_OP_MAX:
        r = fmax(PMC_ARG(0), PMC_ARG(1));
        break;
      case PMC_OP_DOT: {
        float4 a = PMC_ARG(0), b = PMC_ARG(1);
        pmc_u32 n = imm == 0u ? 3u : imm; /* imm = operand width */
        float d = a.x * b.x;
        if (n > 1u) d += a.y * b.y;
        if (n > 2u) d += a.z * b.z;
        if (n > 3u) d += a.w * b.w;
        r = pmc_broadcast(d);
        break;
      }
      case PMC_OP_ABS:
        r = fabs(PMC_ARG(0));
        break;
      case PMC_OP_FLOOR:
        r = floor(PMC_ARG(0));
        break;
      case PMC_OP_CEIL:
        r = ceil(PMC_ARG(0));
        break;
      case PMC_OP_SIN:
        r = sin(PMC_ARG(0));
        break;
      case PMC_OP_COS:
        r = cos(PMC_ARG(0));
        break;
      case PMC_OP_SQRT:
        r = sqrt(PMC_ARG(0));
        break;
      case PMC_OP_NORMALIZE: {
        float4 a = PMC_ARG(0);
        float l2 = a.x * a.x + (width > 1u ? a.y * a.y : 0.0f) + (width > 2u ? a.z * a.z : 0.0f) +
                   (width > 3u ? a.w * a.w : 0.0f);
        r = l2 > 0.0f ? a * (1.0f / sqrt(l2)) : a;
        break;
      }
      case PMC_OP_CLAMP:
        r = fmin(fmax(PMC_ARG(0), PMC_ARG(1)), PMC_ARG(2));
        break;
      case PMC_OP_SMOOTHSTEP: {
        float4 a = PMC_ARG(0), lo = PMC_ARG(1), hi = PMC_ARG(2);
        r = make_float4(pmc_smoothstep1(a.x, lo.x, hi.x), pmc_smoothstep1(a.y, lo.y, hi.y),
                        pmc_smoothstep1(a.z, lo.z, hi.z), pmc_smoothstep1(a.w, lo.w, hi.w));
        break;
      }
      case PMC_OP_MIX: {
        float4 fg = PMC_ARG(0), bg = PMC_ARG(1), t = PMC_ARG(2);
        r = bg + (fg - bg) * t;
        break;
      }
      case PMC_OP_REMAP: {
        float4 a = PMC_ARG(0), il = PMC_ARG(1), ih = PMC_ARG(2), ol = PMC_ARG(3), oh = PMC_ARG(4);
        r = ol + (a - il) * (oh - ol) / (ih - il);
        break;
      }
      case PMC_OP_IFGREATER:
        r = pmc_where_greater(PMC_ARG(0), PMC_ARG(1), PMC_ARG(2), PMC_ARG(3), 0);
        break;
      case PMC_OP_IFGREATEREQ:
        r = pmc_where_greater(PMC_ARG(0), PMC_ARG(1), PMC_ARG(2), PMC_ARG(3), 1);
        break;
      case PMC_OP_LUMINANCE: {
        float4 c = PMC_ARG(0), k = PMC_ARG(1);
        float l = c.x * k.x + c.y * k.y + c.z * k.z;
        r = make_float4(l, l, l, c.w);
        break;
      }
      case PMC_OP_RGBTOHSV:
        r = pmc_rgb_to_hsv(PMC_ARG(0));
        break;
      case PMC_OP_HSVTORGB:
        r = pmc_hsv_to_rgb(PMC_ARG(0));
        break;
      case PMC_OP_IMAGE: {
        float4 uv = PMC_ARG(0), def = PMC_ARG(1), mode = PMC_ARG(2);
        pmc_u32 bits = (pmc_u32)pmc_to_int(mode.x);
        float4 c = pmc_texture_sample(ts, imm, make_float2(uv.x, uv.y), footprint_now * mode.y, bits & 3u,
                                      (bits >> 2) & 3u, (bits >> 4) & 3u, def);
        /* A float image reads the first channel. */
        r = width == 1u ? pmc_broadcast(c.x) : c;
        break;
      }
      case PMC_OP_PLACE2D:
        r = pmc_place2d(PMC_ARG(0), PMC_ARG(1), PMC_ARG(2), PMC_ARG(3).x, PMC_ARG(4),
                        pmc_to_int(PMC_ARG(5).x));
        break;
      case PMC_OP_NOISE2D: {
        float4 p = PMC_ARG(0);
        r = pmc_op_noise2d(make_float2(p.x, p.y), width) * PMC_ARG(1) + PMC_ARG(2);
        break;
      }
      case PMC_OP_NOISE3D: {
        float4 p = PMC_ARG(0);
        r = pmc_op_noise3d(make_float3(p.x, p.y, p.z), width) * PMC_ARG(1) + PMC_ARG(2);
        break;
      }
      case PMC_OP_FRACTAL2D: {
        float4 p = PMC_ARG(0);
        r = pmc_op_fractal2d(make_float2(p.x, p.y), pmc_to_int(PMC_ARG(2).x), PMC_ARG(3).x, PMC_ARG(4).x,
                             width) *
            PMC_ARG(1);
        break;
      }
      case PMC_OP_FRACTAL3D: {
        float4 p = PMC_ARG(0);
        r = pmc_op_fractal3d(make_float3(p.x, p.y, p.z), pmc_to_int(PMC_ARG(2).x), PMC_ARG(3).x, PMC_ARG(4).x,
                             width) *
            PMC_ARG(1);
        break;
      }
      case PMC_OP_CELLNOISE2D: {
        float4 p = PMC_ARG(0);
        r = pmc_broadcast(pmc_op_cellnoise2d(make_float2(p.x, p.y)));
        break;
      }
      case PMC_OP_CELLNOISE3D: {
        float4 p = PMC_ARG(0);
        r = pmc_broadcast(pmc_op_cellnoise3d(make_float3(p.x, p.y, p.z)));
        break;
      }
      case PMC_OP_WORLEY2D: {
        float4 p = PMC_ARG(0);
        r = pmc_op_worley2d(make_float2(p.x, p.y), PMC_ARG(1).x, pmc_to_int(PMC_ARG(2).x), width);
        break;
      }
      case PMC_OP_WORLEY3D: {
        float4 p = PMC_ARG(0);
        r = pmc_op_worley3d(make_float3(p.x, p.y, p.z), PMC_ARG(1).x, pmc_to_int(PMC_ARG(2).x), width);
        break;
      }
      case PMC_OP_RAMPLR: {
        float4 uv = PMC_ARG(2);
        r = PMC_ARG(0) + (PMC_ARG(1) - PMC_ARG(0)) * clamp(uv.x, 0.0f, 1.0f);
        break;
      }
      case PMC_OP_RAMPTB: {
        float4 uv = PMC_ARG(2);
        r = PMC_ARG(1) + (PMC_ARG(0) - PMC_ARG(1)) * clamp(uv.y, 0.0f, 1.0f);
        break;
      }
      case PMC_OP_RAMP4: {
        float4 uv = PMC_ARG(4);
        float s = clamp(uv.x, 0.0f, 1.0f), t = clamp(uv.y, 0.0f, 1.0f);
        float4 top = PMC_ARG(0) + (PMC_ARG(1) - PMC_ARG(0)) * s;
        float4 bottom = PMC_ARG(2) + (PMC_ARG(3) - PMC_ARG(2)) * s;
        r = bottom + (top - bottom) * t;
        break;
      }
      case PMC_OP_SPLITLR: {
        float4 uv = PMC_ARG(3);
        r = uv.x < PMC_ARG(2).x ? PMC_ARG(0) : PMC_ARG(1);
        break;
      }
      case PMC_OP_SPLITTB: {
        float4 uv = PMC_ARG(3);
        r = uv.y > PMC_ARG(2).x ? PMC_ARG(0) : PMC_ARG(1);
        break;
      }
      case PMC_OP_TILEDSHAPE: {
        float4 uv = PMC_ARG(0), tiling = PMC_ARG(1), offset = PMC_ARG(2);
        r = pmc_op_tiledshape(make_float2(uv.x, uv.y), make_float2(tiling.x, tiling.y),
                              make_float2(offset.x, offset.y), PMC_ARG(3).x, PMC_ARG(4).x != 0.0f, imm);
        break;
      }
      case PMC_OP_LINEPATTERN: {
        float4 uv = PMC_ARG(0), tiling = PMC_ARG(1), offset = PMC_ARG(2);
        r = pmc_op_linepattern(make_float2(uv.x, uv.y), make_float2(tiling.x, tiling.y),
                               make_float2(offset.x, offset.y), PMC_ARG(3).x, PMC_ARG(4).x != 0.0f, imm);
        break;
      }
      case PMC_OP_NORMALMAP: {
        float4 n = PMC_ARG(2), t = PMC_ARG(3);
        r = pmc_normalmap(PMC_ARG(0), PMC_ARG(1).x, make_float3(n.x, n.y, n.z), make_float3(t.x, t.y, t.z));
        break;
      }
      case PMC_OP_TAN:
        r = tan(PMC_ARG(0));
        break;
      case PMC_OP_ASIN:
        r = asin(PMC_ARG(0));
        break;
      case PMC_OP_ACOS:
        r = acos(PMC_ARG(0));
        break;
      case PMC_OP_ATAN2:
        r = atan2(PMC_ARG(0), PMC_ARG(1));
        break;
      case PMC_OP_EXP:
        r = exp(PMC_ARG(0));
        break;
      case PMC_OP_LN:
        r = log(PMC_ARG(0));
        break;
      case PMC_OP_SIGN: {
        float4 a = PMC_ARG(0);
        r = make_float4(pmc_sign1(a.x), pmc_sign1(a.y), pmc_sign1(a.z), pmc_sign1(a.w));
        break;
      }
      case PMC_OP_ROUND: {
        float4 a = PMC_ARG(0);
        r = make_float4(pmc_round1(a.x), pmc_round1(a.y), pmc_round1(a.z), pmc_round1(a.w));
        break;
      }
      case PMC_OP_FRACT: {
        float4 a = PMC_ARG(0);
        r = a - floor(a);
        break;
      }
      case PMC_OP_LENGTH: {
        float4 a = PMC_ARG(0);
        pmc_u32 n = imm == 0u ? 3u : imm; /* imm = operand width */
        float d = a.x * a.x;
        if (n > 1u) d += a.y * a.y;
        if (n > 2u) d += a.z * a.z;
        if (n > 3u) d += a.w * a.w;
        r = pmc_broadcast(sqrt(d));
        break;
      }
      case PMC_OP_CROSS: {
        float4 a = PMC_ARG(0), b = PMC_ARG(1);
        r = make_float4(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x, 0.0f);
        break;
      }
      case PMC_OP_NOT: {
        float4 a = PMC_ARG(0);
        r = make_float4(a.x == 0.0f ? 1.0f : 0.0f, a.y == 0.0f ? 1.0f : 0.0f, a.z == 0.0f ? 1.0f : 0.0f,
                        a.w == 0.0f ? 1.0f : 0.0f);
        break;
      }
      case PMC_OP_IFEQUAL:
        r = PMC_ARG(0).x == PMC_ARG(1).x ? PMC_ARG(2) : PMC_ARG(3);
        break;
      case PMC_OP_BLEND: {
        float4 fg = PMC_ARG(0), bg = PMC_ARG(1), m = PMC_ARG(2);
        r = make_float4(pmc_blend1(fg.x, bg.x, m.x, imm), pmc_blend1(fg.y, bg.y, m.y, imm),
                        pmc_blend1(fg.z, bg.z, m.z, imm), pmc_blend1(fg.w, bg.w, m.w, imm));
        break;
      }
      case PMC_OP_ROTATE2D: {
        /* MaterialX mx_rotate_vector2: (ca x + sa y, -sa x + ca y) */
        float4 v = PMC_ARG(0);
        float a = PMC_ARG(1).x * (PMC_PI / 180.0f);
        float sa = sin(a), ca = cos(a);
        r = make_float4(ca * v.x + sa * v.y, -sa * v.x + ca * v.y, 0.0f, 0.0f);
        break;
      }
      case PMC_OP_ROTATE3D: {
        /* MaterialX mx_rotate_vector3 (Rodrigues, v' = v M):
         * v c + cross(v, axis) s + axis dot(axis, v) (1 - c), axis normalised. */
        float4 v4 = PMC_ARG(0), ax4 = PMC_ARG(2);
        float3 v = make_float3(v4.x, v4.y, v4.z), ax = make_float3(ax4.x, ax4.y, ax4.z);
        float l = length(ax);
        ax = l > 0.0f ? ax * (1.0f / l) : ax;
        float a = PMC_ARG(1).x * (PMC_PI / 180.0f);
        float sn = sin(a), c = cos(a);
        float3 res = v * c + cross(v, ax) * sn + ax * (dot(ax, v) * (1.0f - c));
        r = make_float4(res.x, res.y, res.z, 0.0f);
        break;
      }
      default:
        return; /* unknown opcode: the compiler never emits one; stop safely */
    }
    stack[dst] = r.x;
    if (width > 1u) stack[dst + 1u] = r.y;
    if (width > 2u) stack[dst + 2u] = r.z;
    if (width > 3u) stack[dst + 3u] = r.w;
    pc += 2u + nargs;
  }
}

#undef PMC_ARG

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

PMC_FN float pmc_nonneg(float x) { return x > 0.0f && isfinite(x) ? x : 0.0f; }
PMC_FN float3 pmc_param3(const float* p, int i) {
  return make_float3(pmc_nonneg(p[i]), pmc_nonneg(p[i + 1]), pmc_nonneg(p[i + 2]));
}

/* The surface parameter block as a BSDF (Lambert + GGX + emission). For
 * standard_surface: dielectric F0 from specular_IOR, metals tint F0 by the
 * base colour; the coat (if any) is folded into the specular lobe as an
 * approximation. For MTL: Kd and Ks lobes as given. */
PMC_FN PmcBsdf pmc_surface_to_bsdf(const float* p) {
  PmcBsdf b;
  float3 base_color = pmc_param3(p, PMC_P_BASE_COLOR) * pmc_nonneg(p[PMC_P_BASE]);
  float rough = clamp(p[PMC_P_SPECULAR_ROUGHNESS], 0.0f, 1.0f);
  if (!isfinite(rough)) rough = 0.5f;
  b.emission = pmc_param3(p, PMC_P_EMISSION_COLOR) * pmc_nonneg(p[PMC_P_EMISSION]);
  if (p[PMC_P_MODEL] > 0.5f) {
    b.diffuse = base_color;
    b.specular = pmc_param3(p, PMC_P_SPECULAR_COLOR) * pmc_nonneg(p[PMC_P_SPECULAR]);
    b.alpha = rough * rough;
    return b;
  }
  float metal = clamp(p[PMC_P_METALNESS], 0.0f, 1.0f);
  if (!isfinite(metal)) metal = 0.0f;
  float ior = p[PMC_P_SPECULAR_IOR];
  float f0 = isfinite(ior) && ior > 0.0f ? pmc_sqr((ior - 1.0f) / (ior + 1.0f)) : 0.04f;
  float3 dielectric = pmc_param3(p, PMC_P_SPECULAR_COLOR) * (f0 * pmc_nonneg(p[PMC_P_SPECULAR]));
  b.specular = dielectric * (1.0f - metal) + base_color * metal;
  b.diffuse = base_color * ((1.0f - metal) * (1.0f - f0 * fmin(1.0f, pmc_nonneg(p[PMC_P_SPECULAR]))));
  b.alpha = rough * rough;
  float coat = clamp(p[PMC_P_COAT], 0.0f, 1.0f);
  if (coat > 0.0f && isfinite(coat)) {
    b.specular = b.specular + pmc_param3(p, PMC_P_COAT_COLOR) * (0.04f * coat);
  }
  return b;
}

#endif /* PMC_INTERP_H */
