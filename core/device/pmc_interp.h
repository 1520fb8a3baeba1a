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
 * The material cache: a program's cache points form a group per key kind at
 * its start, its uv points' first, then its position points' (lookups, the
 * union of their sub-graphs, stores; materials/compiler.h). Each point looks
 * its values up; a group's sub-graphs then run only for the points that
 * missed one of its lookups, packed into the first lanes ("virtual lanes"
 * that read their shading inputs through lane_of[]), and each store inserts
 * and delivers those values back to the points they belong to. A batch in
 * which every point hit a group's lookups skips that group entirely. The
 * kinds miss apart (a point's uv points share its texel, its position points
 * its cell), so a point whose cell is new does not rerun its uv sub-graphs.
 *
 * A cache point is keyed on the shading point's uv texel or, when its
 * sub-graph reads the position only, on its position cell (pmc_cache.h); each
 * point of a lane computes either at most once. In cache_eval center the
 * group's sub-graphs read the texel's centre uv and the cell's centre
 * position, so a stored value depends on its key alone. With K sub-samples
 * (pmc_cache_supersample.h) the group's sub-graphs run K times, at K points
 * over the texel (cell), for the same packed lanes: each STORE adds its value
 * into the point's destination row (which no sub-graph reads: the group's
 * nodes live in their own slots), and the last pass's STORE stores the mean.
 * What one point does at a lookup and a store is pmc_cache_point.h's protocol.
 *
 * The file reads as its steps: pmc_interp_lanes() decodes an instruction and
 * runs the control instructions itself (OUTPUT, the cache group's LOOKUP and
 * STORE, END); every other opcode is computed by one of three groups,
 * pmc_interp_arith() (componentwise and vector math, colour), pmc_interp_data()
 * (compositing, rotations, flakes, pbrlib and hair data) and
 * pmc_interp_pattern() (geometry, images, noise, ramps, shapes, normal maps),
 * into R, which the loop then writes to the destination slots. An opcode reads
 * its operands by the slot names PMC_OPCODES (pmc_bytecode.h) gives them:
 * PMC_FETCH4(A, IMAGE, texcoord). All of it is inlined into the one kernel
 * function, so the split costs nothing at run time.
 */
#ifndef PMC_INTERP_H
#define PMC_INTERP_H

#include "../abi/pmc_bytecode.h"
#include "pmc_cache_point.h"
#include "pmc_cache_supersample.h"
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
#include "pmc_texture_lanes.h"

/* What a material may read at the shading point. */
typedef struct PmcShadingInputs {
  float2 uv;
  float3 position;
  float3 normal; /* shading normal, facing the viewer */
  float3 tangent;
  float3 bitangent;
  float footprint; /* uv-space width of the ray-cone footprint (isotropic texture LOD) */
  /* The footprint's ellipse (pmc_ray_cone_ellipse): major half-axis in uv
   * and minor width; an axis of 0 (no ellipse known) filters isotropically,
   * and a negative minor (PMC_FOOTPRINT_ONE_LEVEL) reads one mip level. */
  float2 footprint_axis;
  float footprint_minor;
} PmcShadingInputs;

/* The footprint of the ray cone's uv gradients g1, g2 (pmc_ray_cone_gradients):
 * its width and, if `ellipse` (pmc_texture_ellipse_needed), its ellipse; else
 * none and PMC_FOOTPRINT_ONE_LEVEL, so that image lookups are round at that
 * width and read one mip level.
 *
 * The ellipse's major axis is scaled by `major_scale`, never below its
 * minor width: pmc_footprint_major_scale of the hit's sample index i,
 * 1/sqrt(i + 1). A pixel's first i + 1 samples lie stratified (Sobol), about
 * sqrt(i + 1) of them along each axis of its footprint, so once they are
 * drawn a sample's filter needs to span only the step between them along the
 * major axis; the pixel filter averages the rest. The minor width, which sets
 * the mip level, stays. So a pixel's first sample filters over the whole
 * ellipse (this is the identity there) and its later ones take fewer taps
 * (pmc_texture_sample_ellipse takes about major / minor of them) and blur
 * less: from the 64th sample on, one trilinear tap at the minor width for
 * every ellipse up to the tap limit. An ellipse the scale makes round becomes
 * one isotropic lookup at its scaled width. */
PMC_FN void pmc_shading_footprint(PmcShadingInputs* in, float2 g1, float2 g2, int ellipse,
                                  float major_scale) {
  in->footprint = 2.0f * fmax(length(g1), length(g2));
  in->footprint_axis = make_float2(0.0f, 0.0f);
  in->footprint_minor = PMC_FOOTPRINT_ONE_LEVEL;
  if (!ellipse) return;
  pmc_ray_cone_ellipse(g1, g2, &in->footprint_axis, &in->footprint_minor);
  const float minor = in->footprint_minor;
  if (!(major_scale < 1.0f) || !(minor > 0.0f)) return;
  const float major = 2.0f * length(in->footprint_axis);
  const float scaled = fmax(major * major_scale, minor);
  if (scaled > minor * PMC_TEXTURE_ROUND) {
    in->footprint_axis = in->footprint_axis * (scaled / major);
  } else {
    in->footprint = scaled;
    in->footprint_axis = make_float2(0.0f, 0.0f);
    in->footprint_minor = 0.0f;
  }
}

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
 * (t, d, e) for every component c < width of every lane k < nn, into R. The
 * operands are the instruction's slots in order (PMC_A the first). */
#define PMC_CW(fetches, expr)          \
  fetches;                             \
  for (int c = 0; c < (int)width; ++c) \
    for (int k = 0; k < PMC_BATCH(nn); ++k) R[c][k] = (expr);
#define PMC_A pmc_fetch(code, stack, code[pc + 2u], (int)width, nn, A)
#define PMC_B pmc_fetch(code, stack, code[pc + 3u], (int)width, nn, B)
#define PMC_T pmc_fetch(code, stack, code[pc + 4u], (int)width, nn, T)
#define PMC_D pmc_fetch(code, stack, code[pc + 5u], (int)width, nn, D)
#define PMC_E pmc_fetch(code, stack, code[pc + 6u], (int)width, nn, E)
/* The operand word of `op`'s slot `slot` (PMC_OPCODES), and that operand
 * with all four components into V (for per-point bodies). */
#define PMC_OPERAND(op, slot) code[pc + 2u + (pmc_u32)PMC_ARG_##op##_##slot]
#define PMC_FETCH4(V, op, slot) pmc_fetch(code, stack, PMC_OPERAND(op, slot), 4, nn, V)

/* The active lanes of a batch: n of them; virtual lane k is point lane_of[k]
 * (the identity but inside a cache group's sub-graphs, where the `live`
 * points that missed are packed to the front and padded to n with copies of
 * the first: pmc_lanes_pack_missed). uv / footprint are the uv and the texture
 * footprint the virtual lane's nodes read: the point's own, or in cache_eval
 * center the centre and width of its texel, so the stored value depends on
 * the texel alone (and the footprint is round there: no ellipse, axis 0);
 * pos likewise the position. An opcode that reads these or the shading
 * inputs must be listed in program_is_uniform (materials/compiler.cpp):
 * a program without such opcodes runs once for a whole batch. */
typedef struct PmcLanes {
  int n, live;
  int lane_of[PMC_LANES];
  float2 uv[PMC_LANES];
  float footprint[PMC_LANES];
  float2 axis[PMC_LANES]; /* the footprint's ellipse: major half-axis, */
  float minor[PMC_LANES]; /* minor width */
  float3 pos[PMC_LANES];
} PmcLanes;

/* Virtual lane k reads point p's own shading inputs. */
PMC_FN void pmc_lanes_set(PmcLanes* lanes, int k, int p, const PmcShadingInputs* in) {
  lanes->lane_of[k] = p;
  lanes->uv[k] = in[p].uv;
  lanes->footprint[k] = in[p].footprint;
  lanes->axis[k] = in[p].footprint_axis;
  lanes->minor[k] = in[p].footprint_minor;
  lanes->pos[k] = in[p].position;
}

/* Virtual lane k reads what virtual lane j reads (placed inputs included). */
PMC_FN void pmc_lanes_copy(PmcLanes* lanes, int k, int j) {
  lanes->lane_of[k] = lanes->lane_of[j];
  lanes->uv[k] = lanes->uv[j];
  lanes->footprint[k] = lanes->footprint[j];
  lanes->axis[k] = lanes->axis[j];
  lanes->minor[k] = lanes->minor[j];
  lanes->pos[k] = lanes->pos[j];
}

/* Every point of the batch, each in its own lane. */
PMC_FN void pmc_lanes_all(PmcLanes* lanes, const PmcShadingInputs* in, int n) {
  lanes->n = lanes->live = n;
  for (int k = 0; k < PMC_BATCH(n); ++k) pmc_lanes_set(lanes, k, k, in);
  (void)n; /* unused when PMC_LANES is 1 */
}

/* The cache groups of a program as the batch runs them: lookups and stores
 * so far (over all groups: the i-th store belongs to the i-th lookup, whose
 * rank in the material is i), the current group's first lookup, which
 * lookups are keyed on position, and per point which lookups missed (bit i:
 * the i-th lookup); every uv point of a point shares its texel, every
 * position point its cell. */
typedef struct PmcCacheGroup {
  pmc_u32 lookups, stores, first, by_position;
  pmc_u32 samples_uv, samples_position; /* sub-samples of its uv and position points */
  pmc_u32 pass, passes;                 /* the sub-sample the sub-graphs run at, and how many */
  pmc_u32 replay_pc;                    /* the group's first instruction after its lookups */
  pmc_u32 missed[PMC_LANES];
  PmcCacheTexel texel[PMC_LANES], cell[PMC_LANES];
} PmcCacheGroup;

PMC_FN void pmc_cache_group_begin(PmcCacheGroup* g, int n, const PmcCacheContext* cache) {
  (void)n; /* unused when PMC_LANES is 1 */
  g->lookups = g->stores = g->first = g->by_position = 0u;
  g->samples_uv = g->samples_position = 1u;
  g->pass = 0u;
  g->passes = 1u;
  g->replay_pc = 0u;
  for (int k = 0; k < PMC_BATCH(n); ++k) {
    g->missed[k] = 0u;
    g->texel[k].ready = g->texel[k].bypass = 0u;
    g->cell[k].ready = g->cell[k].bypass = 0u;
    if (cache) {
      g->texel[k] = cache[k].texel;
      g->cell[k] = cache[k].cell;
    }
  }
}

/* Virtual lane j (point k) reads its texel's and cell's centre in
 * cache_eval center, offset to the group's current sub-sample where its
 * kind has more than one (pmc_cache_subsample); else its own inputs. */
PMC_FN void pmc_lanes_place(PmcLanes* lanes, int j, int k, const PmcCacheGroup* g,
                            const PmcCacheContext* cache) {
  const PmcCacheTexel* texel = &g->texel[k];
  const PmcCacheTexel* cell = &g->cell[k];
  if (!cache || !cache[k].center) return;
  if (texel->ready && !texel->bypass) {
    float2 uv = make_float2(pmc_cache_texel_center(texel->tx, texel->lambda),
                            pmc_cache_texel_center(texel->ty, texel->lambda));
    if (g->samples_uv > 1u) {
      const float4 o = pmc_cache_subsample(texel, cache[k].material, g->pass & (g->samples_uv - 1u));
      uv = make_float2(pmc_cache_subsample_coord(uv.x, texel->tx, texel->lambda, o.x),
                       pmc_cache_subsample_coord(uv.y, texel->ty, texel->lambda, o.y));
    }
    lanes->uv[j] = uv;
    lanes->footprint[j] = pmc_cache_texel_footprint(texel->footprint_lambda, cache[k].bias);
    lanes->axis[j] = make_float2(0.0f, 0.0f); /* a texel's footprint is round */
    lanes->minor[j] = 0.0f;
  }
  if (cell->ready && !cell->bypass) {
    float3 p = make_float3(pmc_cache_cell_center(cell->tx, cell->lambda),
                           pmc_cache_cell_center(cell->ty, cell->lambda),
                           pmc_cache_cell_center(cell->tz, cell->lambda));
    if (g->samples_position > 1u) {
      const float4 o = pmc_cache_subsample(cell, cache[k].material, g->pass & (g->samples_position - 1u));
      p = make_float3(pmc_cache_subsample_coord(p.x, cell->tx, cell->lambda, o.x),
                      pmc_cache_subsample_coord(p.y, cell->ty, cell->lambda, o.y),
                      pmc_cache_subsample_coord(p.z, cell->tz, cell->lambda, o.z));
    }
    lanes->pos[j] = p;
  }
}

/* The group's lookups of point k that were bypassed (a key too fine to pay:
 * evaluated at the point's own inputs, never inserted): every uv point when
 * its texel is bypassed, every position point when its cell is. */
PMC_FN pmc_u32 pmc_group_bypassed(const PmcCacheGroup* g, int k) {
  return (g->texel[k].ready && g->texel[k].bypass ? ~g->by_position : 0u) |
         (g->cell[k].ready && g->cell[k].bypass ? g->by_position : 0u);
}

/* The current group's lookups: bits [first, lookups). */
PMC_FN pmc_u32 pmc_group_bits(const PmcCacheGroup* g) {
  const pmc_u32 upto = g->lookups >= 32u ? 0xffffffffu : (1u << g->lookups) - 1u;
  return upto & ~((1u << (g->first & 31u)) - 1u);
}

/* The packed lanes of a group run in multiples of this many (where the batch
 * has room): the vector width PoCL's loops take on x86 (eight floats). A
 * group usually runs for a few of a batch's points (about 14 of 64 on the
 * heavy scene), and its loops then spent as much time in their scalar
 * remainders as in their vector bodies; copies of a packed point fill the
 * spare lanes instead (docs/BENCHMARKS.md, "Heavy procedural scene"). */
#define PMC_LANE_PAD 8

/* Packs the points that need pass g->pass of the group into the first lanes,
 * reading their texel's and cell's centres (sub-samples) in cache_eval center:
 * on the last pass every point that missed a lookup, before it only those
 * with a miss that is not bypassed. A bypassed point keeps its last pass's
 * value, so with sub-samples it joins the last pass alone and its sub-graphs
 * run once, not once per sub-sample (at 256 spp, 4-8 times). Lanes past them
 * up to a multiple of PMC_LANE_PAD repeat the first (its inputs, so every
 * node reads valid ones; the stores skip them: lanes->live). Returns how
 * many points it packed. */
PMC_FN int pmc_lanes_pack_missed(PmcLanes* lanes, const PmcCacheGroup* g, const PmcShadingInputs* in, int n,
                                 const PmcCacheContext* cache) {
  const int last = g->pass + 1u >= g->passes;
  const pmc_u32 bits = pmc_group_bits(g);
  int nn = 0;
  (void)n; /* unused when PMC_LANES is 1 */
  for (int k = 0; k < PMC_BATCH(n); ++k)
    if ((last ? g->missed[k] & bits : g->missed[k] & bits & ~pmc_group_bypassed(g, k)) != 0u) {
      pmc_lanes_set(lanes, nn, k, in);
      pmc_lanes_place(lanes, nn, k, g, cache);
      ++nn;
    }
  lanes->live = nn;
#if PMC_LANES >= PMC_LANE_PAD
  if (nn > 0) {
    int padded = (nn + PMC_LANE_PAD - 1) / PMC_LANE_PAD * PMC_LANE_PAD;
    if (padded > PMC_LANES) padded = PMC_LANES;
    for (int j = nn; j < padded; ++j) pmc_lanes_copy(lanes, j, 0); /* placed once, copied */
    nn = padded;
  }
#endif
  lanes->n = nn;
  return lanes->live;
}

/* CACHE_LOOKUP for every point of the batch. imm: node id (bits 0-13) |
 * encoding << 14; the one "operand" word is the number of words to skip when
 * no point needs the group (0 but for the group's last lookup, whose skip
 * passes the group's sub-graphs and STOREs), with PMC_CACHE_KEY_POSITION set
 * for a position-keyed point. A hit delivers its value at once. Returns the
 * pc after the instruction, or past the group when every point hit. */
PMC_FN pmc_u32 pmc_interp_cache_lookup(PMC_GLOBAL const pmc_u32* code, pmc_u32 pc, const PmcShadingInputs* in,
                                       int n, float* stack, PmcCacheContext* cache, PmcCacheGroup* g,
                                       PmcLanes* lanes) {
  const pmc_u32 h = code[pc], imm = pmc_op_imm(h), width = pmc_op_width(h), dst = code[pc + 1u];
  const pmc_u32 bit = 1u << (g->lookups & 31u);
  const pmc_u32 word = PMC_OPERAND(CACHE_LOOKUP, skip);
  const int positional = (word & PMC_CACHE_KEY_POSITION) != 0u;
  const pmc_u32 rank = g->lookups;
  const pmc_u32 samples = pmc_cache_samples_of(word);
  if (g->stores == g->lookups) { /* no group open: this lookup begins one */
    g->first = g->lookups;
    g->samples_uv = g->samples_position = 1u;
    g->pass = 0u;
  }
  if (positional) {
    g->by_position |= bit;
    if (samples > g->samples_position) g->samples_position = samples;
  } else {
    if (samples > g->samples_uv) g->samples_uv = samples;
  }
  g->lookups += 1u;
  for (int k = 0; k < PMC_BATCH(n); ++k) {
    float4 v;
    int found = PMC_CACHE_POINT_MISS;
    if (cache) {
      const PmcCacheTexel* t =
          pmc_cache_point_key(&cache[k], in[k].uv, in[k].position, positional, &g->texel[k], &g->cell[k]);
      found = pmc_cache_point_lookup(&cache[k], t, positional, imm & 0x3fffu, rank, imm >> 14, &v);
    }
    if (found == PMC_CACHE_POINT_HIT) {
      float* row = stack + dst * PMC_LANES + k;
      row[0] = v.x;
      if (width > 1u) row[PMC_LANES] = v.y;
      if (width > 2u) row[2 * PMC_LANES] = v.z;
    } else {
      g->missed[k] |= bit;
    }
  }
  const pmc_u32 skip = word & ~(PMC_CACHE_KEY_POSITION | PMC_CACHE_SAMPLES_MASK);
  pc += 3u;
  if (skip != 0u) { /* the group's last lookup: pack the points that need it */
    g->replay_pc = pc;
    g->passes = 1u;
    if (cache && cache[0].center)
      g->passes = g->samples_uv > g->samples_position ? g->samples_uv : g->samples_position;
    /* only bypassed misses: straight to the last pass, the one they run in */
    if (pmc_lanes_pack_missed(lanes, g, in, n, cache) == 0 && g->passes > 1u) {
      g->pass = g->passes - 1u;
      pmc_lanes_pack_missed(lanes, g, in, n, cache);
    }
    if (lanes->n == 0) { /* every point hit: skip the sub-graphs and stores */
      pc += skip;
      g->stores = g->lookups; /* the group is closed */
      lanes->n = lanes->live = n;
      for (int k = 0; k < PMC_BATCH(n); ++k) lanes->lane_of[k] = k;
    }
  }
  return pc;
}

/* A missed point's value over the group's passes: the sum of its sub-samples
 * so far in its destination row (`samples` of them; later passes add
 * nothing), and after the last pass their mean, with a one-float value
 * broadcast as an operand fetch gives it. */
PMC_FN float4 pmc_cache_accumulate(float* row, pmc_u32 width, pmc_u32 pass, pmc_u32 passes, pmc_u32 samples,
                                   float4 v) {
  if (pass < samples) {
    const float sum[4] = {v.x, v.y, v.z, v.w};
    for (pmc_u32 c = 0u; c < width; ++c)
      row[c * PMC_LANES] = pass == 0u ? sum[c] : row[c * PMC_LANES] + sum[c];
  }
  if (pass + 1u < passes) return v; /* not the last pass: the caller stores nothing */
  const float scale = 1.0f / (float)samples;
  const float x = row[0] * scale;
  if (width == 1u) return make_float4(x, x, x, x);
  return make_float4(x, row[PMC_LANES] * scale, width > 2u ? row[2 * PMC_LANES] * scale : 0.0f,
                     width > 3u ? row[3 * PMC_LANES] * scale : 0.0f);
}

/* CACHE_STORE: the group's k-th STORE belongs to its k-th LOOKUP (same imm).
 * A point that hit keeps its value; one that missed gets the computed operand
 * in `dst` and, with a cache, is inserted (pmc_cache_point_store). With
 * sub-samples (g->passes > 1) the stores of all but the last pass only add
 * their values up, and the last pass's store inserts the mean (a bypassed
 * key, evaluated at its own point in the last pass only, keeps that value). Returns
 * the next pc: past this STORE, or back to the group's sub-graphs after the
 * last STORE of a pass that is not the last. After the group's last store
 * every point runs again in its own lane. */
PMC_FN pmc_u32 pmc_interp_cache_store(PMC_GLOBAL const pmc_u32* code, pmc_u32 pc, const PmcShadingInputs* in,
                                      int n, float* stack, PmcCacheContext* cache, PmcCacheGroup* g,
                                      PmcLanes* lanes, float A[4][PMC_LANES]) {
  const pmc_u32 h = code[pc], imm = pmc_op_imm(h), width = pmc_op_width(h), dst = code[pc + 1u];
  const pmc_u32 bit = 1u << (g->stores & 31u);
  const pmc_u32 rank = g->stores;
  const int nn = lanes->n, live = lanes->live;
  const int last_pass = g->pass + 1u >= g->passes;
  (void)live; /* unused when PMC_LANES is 1 */
  const pmc_u32 samples = (g->by_position & bit) ? g->samples_position : g->samples_uv;
  g->stores += 1u;
  PMC_FETCH4(A, CACHE_STORE, value);
  for (int j = 0; j < PMC_BATCH(live); ++j) {
    int k = lanes->lane_of[j];
    if (!(g->missed[k] & bit)) continue;
    float4 v = pmc_lanes4(A, j);
    float* row = stack + dst * PMC_LANES + k;
    const PmcCacheTexel* t = (g->by_position & bit) ? &g->cell[k] : &g->texel[k];
    if (g->passes > 1u && !t->bypass) v = pmc_cache_accumulate(row, width, g->pass, g->passes, samples, v);
    if (!last_pass) continue;
    if (cache) v = pmc_cache_point_store(&cache[k], t, imm & 0x3fffu, rank, imm >> 14, v);
    row[0] = v.x;
    if (width > 1u) row[PMC_LANES] = v.y;
    if (width > 2u) row[2 * PMC_LANES] = v.z;
    if (width > 3u) row[3 * PMC_LANES] = v.w;
  }
  if (g->stores == g->lookups) {
    if (!last_pass) { /* the next sub-sample: the sub-graphs again */
      g->pass += 1u;
      g->stores = g->first;
      if (g->pass + 1u < g->passes) {
        for (int j = 0; j < PMC_BATCH(nn); ++j) pmc_lanes_place(lanes, j, lanes->lane_of[j], g, cache);
      } else {
        pmc_lanes_pack_missed(lanes, g, in, n, cache); /* the last: with the bypassed points */
      }
      return g->replay_pc;
    }
    pmc_lanes_all(lanes, in, n); /* the group is done: every point again */
  }
  return pc + 3u;
}

/* The parameters of the opcode groups: the instruction (op, width, imm at
 * pc), the stack, the active lanes, the shading inputs and textures, and the
 * operand and result arrays [component][lane]. Each returns 0 for an opcode
 * not its own.
 *
 * The three groups repeat their frame on purpose (the signature, `nn`,
 * PMC_OP_UNUSED, `switch (op)`, `default: return 0`, `return 1`: seven
 * lines each). OpenCL C has no function pointers, so one shared frame could
 * only be a pair of macros that open and close the function's switch; the
 * kernel would compile to the same code, but a reader (and clang-format,
 * and scripts/check-function-length's brace count) would no longer see
 * where each group's switch begins and ends, which is what makes a group
 * readable as a list of cases. */
#define PMC_OP_PARAMS                                                                                 \
  pmc_u32 op, PMC_GLOBAL const pmc_u32 *code, pmc_u32 pc, pmc_u32 width, pmc_u32 nargs, pmc_u32 imm,  \
      const float *stack, const PmcLanes *lanes, const PmcShadingInputs *in, const PmcTextureSet *ts, \
      float A[4][PMC_LANES], float B[4][PMC_LANES], float T[4][PMC_LANES], float D[4][PMC_LANES],     \
      float E[4][PMC_LANES], float F[4][PMC_LANES], float R[4][PMC_LANES]
#define PMC_OP_ARGS op, code, pc, width, nargs, imm, stack, lanes, in, ts, A, B, T, D, E, F, R
#define PMC_OP_UNUSED \
  (void)nargs;        \
  (void)in;           \
  (void)ts;           \
  (void)F

/* Componentwise and vector math, comparisons, colour. */
PMC_FN int pmc_interp_arith(PMC_OP_PARAMS) {
  const int nn = lanes->n;
  PMC_OP_UNUSED;
  switch (op) {
    case PMC_OP_MOVE:
      PMC_CW(PMC_A, A[c][k])
      break;
    case PMC_OP_SWIZZLE: {
      PMC_FETCH4(A, SWIZZLE, in);
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
      PMC_FETCH4(A, DOT, in1);
      PMC_FETCH4(B, DOT, in2);
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
      PMC_FETCH4(A, NORMALIZE, in);
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
    case PMC_OP_MIX:
      PMC_CW(PMC_A; PMC_B; PMC_T, B[c][k] + (A[c][k] - B[c][k]) * T[c][k])
      break;
    case PMC_OP_REMAP:
      PMC_CW(PMC_A; PMC_B; PMC_T; PMC_D;
             PMC_E, D[c][k] + (A[c][k] - B[c][k]) * (E[c][k] - D[c][k]) / (T[c][k] - B[c][k]))
      break;
    case PMC_OP_IFGREATER:
      PMC_CW(PMC_A; PMC_B; PMC_T; PMC_D, A[c][k] > B[c][k] ? T[c][k] : D[c][k])
      break;
    case PMC_OP_IFGREATEREQ:
      PMC_CW(PMC_A; PMC_B; PMC_T; PMC_D, A[c][k] >= B[c][k] ? T[c][k] : D[c][k])
      break;
    case PMC_OP_LUMINANCE: {
      PMC_FETCH4(A, LUMINANCE, in);
      PMC_FETCH4(B, LUMINANCE, lumacoeffs);
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        float l = A[0][k] * B[0][k] + A[1][k] * B[1][k] + A[2][k] * B[2][k];
        pmc_set_lanes4(R, k, make_float4(l, l, l, A[3][k]));
      }
      break;
    }
    case PMC_OP_RGBTOHSV:
      PMC_FETCH4(A, RGBTOHSV, in);
      for (int k = 0; k < PMC_BATCH(nn); ++k) pmc_set_lanes4(R, k, pmc_rgb_to_hsv(pmc_lanes4(A, k)));
      break;
    case PMC_OP_HSVTORGB:
      PMC_FETCH4(A, HSVTORGB, in);
      for (int k = 0; k < PMC_BATCH(nn); ++k) pmc_set_lanes4(R, k, pmc_hsv_to_rgb(pmc_lanes4(A, k)));
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
      PMC_FETCH4(A, LENGTH, in);
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
      PMC_FETCH4(A, CROSS, in1);
      PMC_FETCH4(B, CROSS, in2);
      for (int k = 0; k < PMC_BATCH(nn); ++k)
        pmc_set_lanes4(
            R, k,
            make_float4(A[1][k] * B[2][k] - A[2][k] * B[1][k], A[2][k] * B[0][k] - A[0][k] * B[2][k],
                        A[0][k] * B[1][k] - A[1][k] * B[0][k], 0.0f));
      break;
    case PMC_OP_NOT:
      PMC_CW(PMC_A, A[c][k] == 0.0f ? 1.0f : 0.0f)
      break;
    case PMC_OP_IFEQUAL:
      pmc_fetch(code, stack, PMC_OPERAND(IFEQUAL, value1), 1, nn, A);
      pmc_fetch(code, stack, PMC_OPERAND(IFEQUAL, value2), 1, nn, B);
      PMC_CW(PMC_T; PMC_D, A[0][k] == B[0][k] ? T[c][k] : D[c][k])
      break;
    default:
      return 0;
  }
  return 1;
}

/* Compositing, rotations, flakes, pbrlib and hair data nodes. */
PMC_FN int pmc_interp_data(PMC_OP_PARAMS) {
  const int nn = lanes->n;
  PMC_OP_UNUSED;
  switch (op) {
    case PMC_OP_BLEND:
      PMC_CW(PMC_A; PMC_B; PMC_T, pmc_blend1(A[c][k], B[c][k], T[c][k], imm))
      break;
    case PMC_OP_ROTATE2D: /* MaterialX mx_rotate_vector2: (ca x + sa y, -sa x + ca y) */
      PMC_FETCH4(A, ROTATE2D, in);
      pmc_fetch(code, stack, PMC_OPERAND(ROTATE2D, amount), 1, nn, B);
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        float a = B[0][k] * (PMC_PI / 180.0f);
        float sa = sin(a), ca = cos(a);
        pmc_set_lanes4(R, k,
                       make_float4(ca * A[0][k] + sa * A[1][k], -sa * A[0][k] + ca * A[1][k], 0.0f, 0.0f));
      }
      break;
    case PMC_OP_ROTATE3D: /* MaterialX mx_rotate_vector3 (Rodrigues, v' = v M):
                           * v c + cross(v, axis) s + axis dot(axis, v) (1 - c), axis normalised. */
      PMC_FETCH4(A, ROTATE3D, in);
      pmc_fetch(code, stack, PMC_OPERAND(ROTATE3D, amount), 1, nn, B);
      PMC_FETCH4(T, ROTATE3D, axis);
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
    case PMC_OP_COMPOSITE:
      PMC_FETCH4(A, COMPOSITE, fg);
      PMC_FETCH4(B, COMPOSITE, bg);
      pmc_fetch(code, stack, PMC_OPERAND(COMPOSITE, weight), 1, nn, T);
      for (int k = 0; k < PMC_BATCH(nn); ++k)
        pmc_set_lanes4(R, k, pmc_composite(pmc_lanes4(A, k), pmc_lanes4(B, k), T[0][k], imm));
      break;
    case PMC_OP_PREMULT:
      PMC_FETCH4(A, PREMULT, in);
      for (int k = 0; k < PMC_BATCH(nn); ++k) pmc_set_lanes4(R, k, pmc_premult(pmc_lanes4(A, k), imm));
      break;
    case PMC_OP_OUTSIDE:
      pmc_fetch(code, stack, PMC_OPERAND(OUTSIDE, mask), 1, nn, B);
      PMC_CW(PMC_A, A[c][k] * (1.0f - B[0][k]))
      break;
    case PMC_OP_FLAKE:
      pmc_fetch(code, stack, PMC_OPERAND(FLAKE, size), 1, nn, A);
      pmc_fetch(code, stack, PMC_OPERAND(FLAKE, roughness), 1, nn, B);
      pmc_fetch(code, stack, PMC_OPERAND(FLAKE, coverage), 1, nn, T);
      pmc_fetch(code, stack, PMC_OPERAND(FLAKE, position), 3, nn, D); /* a vector2 texcoord gets z = 0 */
      pmc_fetch(code, stack, PMC_OPERAND(FLAKE, normal), 3, nn, E);
      pmc_fetch(code, stack, PMC_OPERAND(FLAKE, tangent), 3, nn, F);
      pmc_fetch(code, stack, PMC_OPERAND(FLAKE, bitangent), 3, nn, R); /* read before R is written */
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        float3 bt = make_float3(R[0][k], R[1][k], R[2][k]);
        PmcFlake f =
            pmc_flake(A[0][k], B[0][k], T[0][k], make_float3(D[0][k], D[1][k], D[2][k]),
                      make_float3(E[0][k], E[1][k], E[2][k]), make_float3(F[0][k], F[1][k], F[2][k]), bt);
        pmc_set_lanes4(R, k, pmc_flake_output(f, imm));
      }
      break;
    case PMC_OP_ROUGHNESS_ANISO:
      pmc_fetch(code, stack, PMC_OPERAND(ROUGHNESS_ANISO, roughness), 1, nn, A);
      pmc_fetch(code, stack, PMC_OPERAND(ROUGHNESS_ANISO, anisotropy), 1, nn, B);
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        float2 r = pmc_roughness_anisotropy(A[0][k], B[0][k]);
        pmc_set_lanes4(R, k, make_float4(r.x, r.y, 0.0f, 0.0f));
      }
      break;
    case PMC_OP_ROUGHNESS_DUAL:
      pmc_fetch(code, stack, PMC_OPERAND(ROUGHNESS_DUAL, roughness), 2, nn, A);
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        float2 r = pmc_roughness_dual(make_float2(A[0][k], A[1][k]));
        pmc_set_lanes4(R, k, make_float4(r.x, r.y, 0.0f, 0.0f));
      }
      break;
    case PMC_OP_ARTISTIC_IOR:
      PMC_FETCH4(A, ARTISTIC_IOR, reflectivity);
      PMC_FETCH4(B, ARTISTIC_IOR, edge_color);
      for (int k = 0; k < PMC_BATCH(nn); ++k)
        pmc_set_lanes4(R, k, pmc_artistic_ior(pmc_lanes4(A, k), pmc_lanes4(B, k), imm != 0u));
      break;
    case PMC_OP_BLACKBODY:
      pmc_fetch(code, stack, PMC_OPERAND(BLACKBODY, temperature), 1, nn, A);
      for (int k = 0; k < PMC_BATCH(nn); ++k) pmc_set_lanes4(R, k, pmc_blackbody(A[0][k]));
      break;
    case PMC_OP_HAIR_ROUGHNESS:
      pmc_fetch(code, stack, PMC_OPERAND(HAIR_ROUGHNESS, longitudinal), 1, nn, A);
      pmc_fetch(code, stack, PMC_OPERAND(HAIR_ROUGHNESS, azimuthal), 1, nn, B);
      pmc_fetch(code, stack, PMC_OPERAND(HAIR_ROUGHNESS, scale_TT), 1, nn, T);
      pmc_fetch(code, stack, PMC_OPERAND(HAIR_ROUGHNESS, scale_TRT), 1, nn, D);
      for (int k = 0; k < PMC_BATCH(nn); ++k)
        pmc_set_lanes4(R, k, pmc_chiang_hair_roughness(A[0][k], B[0][k], T[0][k], D[0][k], imm));
      break;
    case PMC_OP_HAIR_MELANIN:
      pmc_fetch(code, stack, PMC_OPERAND(HAIR_MELANIN, melanin_concentration), 1, nn, A);
      pmc_fetch(code, stack, PMC_OPERAND(HAIR_MELANIN, melanin_redness), 1, nn, B);
      PMC_FETCH4(T, HAIR_MELANIN, eumelanin_color);
      PMC_FETCH4(D, HAIR_MELANIN, pheomelanin_color);
      for (int k = 0; k < PMC_BATCH(nn); ++k)
        pmc_set_lanes4(R, k, pmc_deon_hair_absorption(A[0][k], B[0][k], pmc_lanes4(T, k), pmc_lanes4(D, k)));
      break;
    case PMC_OP_HAIR_COLOR:
      PMC_FETCH4(A, HAIR_COLOR, color);
      pmc_fetch(code, stack, PMC_OPERAND(HAIR_COLOR, azimuthal_roughness), 1, nn, B);
      for (int k = 0; k < PMC_BATCH(nn); ++k)
        pmc_set_lanes4(R, k, pmc_chiang_hair_absorption(pmc_lanes4(A, k), B[0][k]));
      break;
    default:
      return 0;
  }
  return 1;
}

/* Geometry, images, hex tiling, placement, noise, ramps, splits, shapes, normal maps. */
PMC_FN int pmc_interp_pattern(PMC_OP_PARAMS) {
  const int nn = lanes->n;
  PMC_OP_UNUSED;
  switch (op) {
    case PMC_OP_TEXCOORD:
      for (int k = 0; k < PMC_BATCH(nn); ++k)
        pmc_set_lanes4(R, k, make_float4(lanes->uv[k].x, lanes->uv[k].y, 0.0f, 0.0f));
      break;
    case PMC_OP_POSITION:
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        float3 v = lanes->pos[k];
        pmc_set_lanes4(R, k, make_float4(v.x, v.y, v.z, 0.0f));
      }
      break;
    case PMC_OP_NORMAL:
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        float3 v = in[lanes->lane_of[k]].normal;
        pmc_set_lanes4(R, k, make_float4(v.x, v.y, v.z, 0.0f));
      }
      break;
    case PMC_OP_TANGENT:
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        float3 v = in[lanes->lane_of[k]].tangent;
        pmc_set_lanes4(R, k, make_float4(v.x, v.y, v.z, 0.0f));
      }
      break;
    case PMC_OP_BITANGENT:
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        float3 v = in[lanes->lane_of[k]].bitangent;
        pmc_set_lanes4(R, k, make_float4(v.x, v.y, v.z, 0.0f));
      }
      break;
    case PMC_OP_IMAGE: {
      PMC_FETCH4(A, IMAGE, texcoord);
      PMC_FETCH4(B, IMAGE, default);
      PMC_FETCH4(T, IMAGE, mode);
#if defined(__OPENCL_VERSION__) && PMC_LANES >= 8
      { /* the batch's lookups together (pmc_texture_lanes.h); the same values as below */
        float fp[PMC_LANES], ax[PMC_LANES], ay[PMC_LANES], minor[PMC_LANES];
        pmc_u32 bits[PMC_LANES];
        for (int k = 0; k < nn; ++k) {
          bits[k] = (pmc_u32)pmc_to_int(T[0][k]);
          const float s = T[1][k];
          const float2 axis = (bits[k] & PMC_IMAGE_ANISO) ? lanes->axis[k] * s : make_float2(0.0f, 0.0f);
          fp[k] = lanes->footprint[k] * s;
          ax[k] = axis.x;
          ay[k] = axis.y;
          minor[k] = lanes->minor[k] * s;
        }
        pmc_texture_sample_lanes(ts, imm, nn, A[0], A[1], fp, ax, ay, minor, bits, B, R);
        if (width == 1u)
          for (int k = 0; k < nn; ++k) R[1][k] = R[2][k] = R[3][k] = R[0][k];
        break;
      }
#endif
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        /* T[1]: the uv chain's footprint scale; the ellipse only where the
         * chain keeps its direction (PMC_IMAGE_ANISO) */
        pmc_u32 bits = (pmc_u32)pmc_to_int(T[0][k]);
        const float s = T[1][k];
        const float2 axis = (bits & PMC_IMAGE_ANISO) ? lanes->axis[k] * s : make_float2(0.0f, 0.0f);
        float4 c = pmc_texture_sample_ellipse(ts, imm, make_float2(A[0][k], A[1][k]), lanes->footprint[k] * s,
                                              axis, lanes->minor[k] * s, bits & 3u, (bits >> 2) & 3u,
                                              (bits >> 4) & 3u, pmc_lanes4(B, k));
        /* A float image reads the first channel. */
        pmc_set_lanes4(R, k, width == 1u ? pmc_broadcast(c.x) : c);
      }
      break;
    }
    case PMC_OP_HEXIMAGE:       /* imm = texture index; the two share their first 11 slots, and */
    case PMC_OP_HEXNORMALMAP: { /* slots 11, 12 are HEXNORMALMAP's strength, flip_g */
      /* more operands than arrays: the tiles first, then the rest */
      PmcHexTiles tiles[PMC_LANES];
      float gain[PMC_LANES];  /* the tiling's footprint gain */
      float2 axis[PMC_LANES]; /* the ellipse's major half-axis, tiled */
      PMC_FETCH4(A, HEXIMAGE, texcoord);
      PMC_FETCH4(B, HEXIMAGE, tiling);
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        A[0][k] *= B[0][k];
        A[1][k] *= B[1][k];
        gain[k] = fmax(fabs(B[0][k]), fabs(B[1][k]));
        /* An even tiling (|x| = |y|: a uniform scale, perhaps mirrored)
         * maps the ellipse's axes onto the tiled ellipse's; an uneven one
         * would not: isotropic there. */
        axis[k] = fabs(B[0][k]) == fabs(B[1][k])
                      ? make_float2(lanes->axis[k].x * B[0][k], lanes->axis[k].y * B[1][k])
                      : make_float2(0.0f, 0.0f);
      }
      PMC_FETCH4(B, HEXIMAGE, rotation);
      PMC_FETCH4(T, HEXIMAGE, rotationrange);
      PMC_FETCH4(D, HEXIMAGE, scale);
      PMC_FETCH4(E, HEXIMAGE, scalerange);
      PMC_FETCH4(F, HEXIMAGE, offset);
      PMC_FETCH4(R, HEXIMAGE, offsetrange);
      for (int k = 0; k < PMC_BATCH(nn); ++k)
        tiles[k] =
            pmc_hextile_tiles(make_float2(A[0][k], A[1][k]), B[0][k], make_float2(T[0][k], T[1][k]), D[0][k],
                              make_float2(E[0][k], E[1][k]), F[0][k], make_float2(R[0][k], R[1][k]));
      PMC_FETCH4(A, HEXIMAGE, falloff);
      PMC_FETCH4(B, HEXIMAGE, default);
      PMC_FETCH4(T, HEXIMAGE, mode);
      PMC_FETCH4(D, HEXIMAGE, falloffcontrast); /* HEXNORMALMAP: strength */
      PMC_FETCH4(E, HEXIMAGE, lumacoeffs);      /* HEXNORMALMAP: flip_g */
      if (op == PMC_OP_HEXNORMALMAP) {
        PMC_FETCH4(F, HEXNORMALMAP, normal);
        PMC_FETCH4(R, HEXNORMALMAP, tangent); /* read before R is written */
      }
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        pmc_u32 bits = (pmc_u32)pmc_to_int(T[0][k]);
        PmcFootprint fp;
        fp.width = lanes->footprint[k] * T[1][k] * gain[k];
        fp.axis = (bits & PMC_IMAGE_ANISO) ? axis[k] * T[1][k] : make_float2(0.0f, 0.0f);
        fp.minor = lanes->minor[k] * T[1][k] * gain[k];
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
      PMC_FETCH4(A, PLACE2D, texcoord);
      PMC_FETCH4(B, PLACE2D, pivot);
      PMC_FETCH4(T, PLACE2D, scale);
      PMC_FETCH4(D, PLACE2D, degrees);
      PMC_FETCH4(E, PLACE2D, offset);
      PMC_FETCH4(F, PLACE2D, operationorder);
      for (int k = 0; k < PMC_BATCH(nn); ++k)
        pmc_set_lanes4(R, k,
                       pmc_place2d(pmc_lanes4(A, k), pmc_lanes4(B, k), pmc_lanes4(T, k), D[0][k],
                                   pmc_lanes4(E, k), pmc_to_int(F[0][k])));
      break;
    case PMC_OP_NOISE2D:
    case PMC_OP_NOISE3D: {
      const int dims = op == PMC_OP_NOISE3D ? 3 : 2;
      pmc_fetch(code, stack, PMC_OPERAND(NOISE2D, texcoord), dims, nn, A);
      PMC_FETCH4(B, NOISE2D, amplitude);
      PMC_FETCH4(T, NOISE2D, pivot);
      pmc_noise_lanes(dims, A[0], A[1], A[2], width, nn, R);
      for (int c = 0; c < 4; ++c)
        for (int k = 0; k < PMC_BATCH(nn); ++k) R[c][k] = R[c][k] * B[c][k] + T[c][k];
      break;
    }
    case PMC_OP_FRACTAL2D:
    case PMC_OP_FRACTAL3D: {
      const int dims = op == PMC_OP_FRACTAL3D ? 3 : 2;
      pmc_fetch(code, stack, PMC_OPERAND(FRACTAL2D, texcoord), dims, nn, A);
      PMC_FETCH4(B, FRACTAL2D, amplitude);
      pmc_fetch(code, stack, PMC_OPERAND(FRACTAL2D, octaves), 1, nn, T);
      pmc_fetch(code, stack, PMC_OPERAND(FRACTAL2D, lacunarity), 1, nn, D);
      pmc_fetch(code, stack, PMC_OPERAND(FRACTAL2D, diminish), 1, nn, E);
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
      pmc_fetch(code, stack, PMC_OPERAND(CELLNOISE2D, texcoord), dims, nn, A);
      pmc_cellnoise_lanes(dims, A[0], A[1], A[2], nn, R[0]);
      for (int k = 0; k < PMC_BATCH(nn); ++k) R[1][k] = R[2][k] = R[3][k] = R[0][k];
      break;
    }
    case PMC_OP_WORLEY2D:
    case PMC_OP_WORLEY3D: {
      const int dims = op == PMC_OP_WORLEY3D ? 3 : 2;
      pmc_fetch(code, stack, PMC_OPERAND(WORLEY2D, texcoord), dims, nn, A);
      pmc_fetch(code, stack, PMC_OPERAND(WORLEY2D, jitter), 1, nn, B);
      pmc_fetch(code, stack, PMC_OPERAND(WORLEY2D, style), 1, nn, T);
      int style[PMC_LANES];
      for (int k = 0; k < PMC_BATCH(nn); ++k) style[k] = pmc_to_int(T[0][k]);
      pmc_worley_lanes(dims, A[0], A[1], A[2], B[0], style, width, nn, R);
      break;
    }
    case PMC_OP_RAMPLR:
      pmc_fetch(code, stack, PMC_OPERAND(RAMPLR, texcoord), 2, nn, T);
      PMC_CW(PMC_A; PMC_B, A[c][k] + (B[c][k] - A[c][k]) * clamp(T[0][k], 0.0f, 1.0f))
      break;
    case PMC_OP_RAMPTB:
      pmc_fetch(code, stack, PMC_OPERAND(RAMPTB, texcoord), 2, nn, T);
      PMC_CW(PMC_A; PMC_B, B[c][k] + (A[c][k] - B[c][k]) * clamp(T[1][k], 0.0f, 1.0f))
      break;
    case PMC_OP_RAMP4: {
      pmc_fetch(code, stack, PMC_OPERAND(RAMP4, texcoord), 2, nn, E);
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
    case PMC_OP_SPLITLR:
      pmc_fetch(code, stack, PMC_OPERAND(SPLITLR, center), 1, nn, T);
      pmc_fetch(code, stack, PMC_OPERAND(SPLITLR, texcoord), 2, nn, D);
      PMC_CW(PMC_A; PMC_B, D[0][k] < T[0][k] ? A[c][k] : B[c][k])
      break;
    case PMC_OP_SPLITTB:
      pmc_fetch(code, stack, PMC_OPERAND(SPLITTB, center), 1, nn, T);
      pmc_fetch(code, stack, PMC_OPERAND(SPLITTB, texcoord), 2, nn, D);
      PMC_CW(PMC_A; PMC_B, D[1][k] > T[0][k] ? A[c][k] : B[c][k])
      break;
    case PMC_OP_TILEDSHAPE:
    case PMC_OP_LINEPATTERN:
      PMC_FETCH4(A, TILEDSHAPE, texcoord);
      PMC_FETCH4(B, TILEDSHAPE, uvtiling);
      PMC_FETCH4(T, TILEDSHAPE, uvoffset);
      PMC_FETCH4(D, TILEDSHAPE, size);
      PMC_FETCH4(E, TILEDSHAPE, staggered);
      for (int k = 0; k < PMC_BATCH(nn); ++k) {
        float2 uv = make_float2(A[0][k], A[1][k]), tiling = make_float2(B[0][k], B[1][k]);
        float2 offset = make_float2(T[0][k], T[1][k]);
        pmc_set_lanes4(R, k,
                       op == PMC_OP_TILEDSHAPE
                           ? pmc_op_tiledshape(uv, tiling, offset, D[0][k], E[0][k] != 0.0f, imm)
                           : pmc_op_linepattern(uv, tiling, offset, D[0][k], E[0][k] != 0.0f, imm));
      }
      break;
    case PMC_OP_NORMALMAP:
      PMC_FETCH4(A, NORMALMAP, in);
      PMC_FETCH4(B, NORMALMAP, scale);
      PMC_FETCH4(T, NORMALMAP, normal);
      PMC_FETCH4(D, NORMALMAP, tangent);
      for (int k = 0; k < PMC_BATCH(nn); ++k)
        pmc_set_lanes4(R, k,
                       pmc_normalmap(pmc_lanes4(A, k), B[0][k], make_float3(T[0][k], T[1][k], T[2][k]),
                                     make_float3(D[0][k], D[1][k], D[2][k])));
      break;
    default:
      return 0;
  }
  return 1;
}

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
  PmcLanes lanes_now;
  PmcLanes* lanes = &lanes_now;
  PmcCacheGroup group;
  pmc_lanes_all(lanes, in, n);
  pmc_cache_group_begin(&group, n, cache);
  for (int guard = 0; guard < 1 << 16; ++guard) {
    const pmc_u32 h = code[pc];
    const pmc_u32 op = pmc_op_code(h), width = pmc_op_width(h), nargs = pmc_op_nargs(h), imm = pmc_op_imm(h);
    const pmc_u32 dst = code[pc + 1u];
    const int nn = lanes->n;
    if (op == PMC_OP_END) return;
    if (op == PMC_OP_OUTPUT) {
      PMC_FETCH4(A, OUTPUT, in);
      for (pmc_u32 i = 0; i < width && imm + i < PMC_P_COUNT; ++i)
        for (int k = 0; k < PMC_BATCH(nn); ++k) params[k * PMC_P_COUNT + (int)(imm + i)] = A[i][k];
    } else if (op == PMC_OP_CACHE_LOOKUP) {
      pc = pmc_interp_cache_lookup(code, pc, in, n, stack, cache, &group, lanes);
      continue;
    } else if (op == PMC_OP_CACHE_STORE) {
      pc = pmc_interp_cache_store(code, pc, in, n, stack, cache, &group, lanes, A);
      continue;
    } else if (pmc_interp_arith(PMC_OP_ARGS) || pmc_interp_data(PMC_OP_ARGS) ||
               pmc_interp_pattern(PMC_OP_ARGS)) {
      for (int c = 0; c < (int)width; ++c) {
        float* row = stack + (dst + (pmc_u32)c) * PMC_LANES;
        for (int k = 0; k < PMC_BATCH(nn); ++k) row[k] = R[c][k];
      }
    } else {
      return; /* unknown opcode: the compiler never emits one; stop safely */
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
#undef PMC_OPERAND
#undef PMC_OP_PARAMS
#undef PMC_OP_ARGS
#undef PMC_OP_UNUSED

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
