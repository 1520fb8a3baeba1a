/* pmc_patterns.h — MaterialX 1.39 tiled shape and line pattern nodes:
 * tiledcircles, tiledcloverleafs, tiledhexagons, grid and crosshatch. Shared
 * by the OpenCL interpreter and the host reference (dialect: pmc_vec.h).
 *
 * MaterialX defines these nodes as node graphs in stdlib_ng.mtlx (NG_*_color3)
 * built from circle / cloverleaf / hexagon / line and modulo, ifgreater,
 * ifequal nodes; the functions below evaluate those graphs node for node:
 *
 *   st = texcoord * uvtiling - uvoffset
 *   regular:   shape(2 * mod(st, 1) - 1, radius = size)        (one per tile)
 *   staggered: rows of height h (h = 0.866025 for circles and hexagons,
 *              0.5 for cloverleafs), every other row shifted by 0.5:
 *                x = mod(st.x + (mod(st.y, 2h) > h ? 0.5 : 0), 1), y = mod(st.y, h)
 *              max of shape at (x, y), (1 - x, y), (x - 0.5, h - y),
 *              radius = size / 2
 *   grid:      s = 2 * mod((st.x [+ 0.5 on odd rows if staggered], st.y), 1) - 1,
 *              1 where |s.x| > 1 - thickness or |s.y| > 1 - thickness
 *   crosshatch: the same s; 1 within `thickness` of either diagonal segment
 *              (1,1)-(-1,-1) or (-1,1)-(1,-1)
 *
 * Node semantics used: modulo(a, b) = a - b * floor(a / b) (never negative
 * for b > 0; computed here with the exact fmod), ifgreater(v1, v2, in1, in2) =
 * v1 > v2 ? in1 : in2, min/max/clamp as GLSL. The hexagon graph is followed
 * as written, including its final test dot(p, (1, 1)) > 0 (IQ's SDF uses
 * length(p) * sign(p.y); the graph takes sqrt of the component sum, which is
 * > 0 exactly when the sum is > 0 and NaN, i.e. "inside", when it is < 0).
 *
 * Outputs are color3 (xyz, all equal, 0 or 1) with w = 1. Non-finite inputs,
 * or an overflowing texcoord * uvtiling, give 0.
 */
#ifndef PMC_PATTERNS_H
#define PMC_PATTERNS_H

#include "../abi/pmc_bytecode.h"
#include "../abi/pmc_vec.h"

#define PMC_PATTERN_FLT_MAX 3.40282347e38f

PMC_FN int pmc_pattern_finite(float x) { return fabs(x) <= PMC_PATTERN_FLT_MAX; }

/* MaterialX modulo for b > 0: in [0, b]. The remainder is fmod's, exact:
 * a - q b with the truncated quotient q, computed with one fma once q is
 * known to be right (a / b rounds q off by at most one, which the sign or
 * size of the remainder reveals). No library fmod: the compiler would
 * evaluate that call on every path. Beyond 2^23 periods a float has no
 * fraction left and the GLSL formula a - b floor(a / b) is used. Adding b to
 * a negative remainder rounds (to b itself for tiny remainders, as GLSL's
 * does). */
PMC_FN float pmc_pattern_mod(float a, float b) {
#ifdef __OPENCL_VERSION__
#define PMC_TRUNC trunc
#define PMC_FMA fma
#else
#define PMC_TRUNC std::trunc
#define PMC_FMA std::fma
#endif
  float q = PMC_TRUNC(a / b);
  float r;
  if (fabs(q) < 8388608.0f) {
    float s = a < 0.0f ? -1.0f : 1.0f;
    r = PMC_FMA(-q, b, a);
    if (r != 0.0f && (r < 0.0f) != (a < 0.0f))
      r = PMC_FMA(-(q - s), b, a); /* q one past the quotient */
    else if (fabs(r) >= b)
      r = PMC_FMA(-(q + s), b, a);              /* q one short */
    if (r == 0.0f) r = a < 0.0f ? -0.0f : 0.0f; /* fmod keeps the sign of a */
  } else {
    r = a - b * floor(a / b);
  }
#undef PMC_TRUNC
#undef PMC_FMA
  return r < 0.0f ? r + b : r;
}

/* circle node, center (0, 0): 1 inside or on the circle. */
PMC_FN float pmc_pattern_circle(float x, float y, float radius) {
  return (x * x + y * y > radius * radius) ? 0.0f : 1.0f;
}

/* cloverleaf node, center (0, 0): four circles of radius r evaluated at the
 * doubled coordinate shifted by +-r along each axis. */
PMC_FN float pmc_pattern_cloverleaf(float x, float y, float r) {
  float sx = x + x, sy = y + y;
  float ax = sx + r, ay = sy + r; /* sample_add */
  float bx = sx - r, by = sy - r; /* sample_subtract */
  float c1 = pmc_pattern_circle(ax, sy, r);
  float c2 = pmc_pattern_circle(bx, sy, r);
  float c3 = pmc_pattern_circle(sx, by, r);
  float c4 = pmc_pattern_circle(sx, ay, r);
  return fmax(fmax(c1, c2), fmax(c3, c4));
}

/* hexagon node, center (0, 0), as the NG_hexagon_float graph computes it. */
PMC_FN float pmc_pattern_hexagon(float x, float y, float r) {
  const float kx = -0.866025f, ky = 0.5f, kz = 0.57735f;
  float px = fabs(y), py = fabs(x); /* p = (|d.y|, |d.x|) */
  float m1 = fmin(kx * px + ky * py, 0.0f);
  float p1x = px - (kx * m1) * 2.0f;
  float p1y = py - (ky * m1) * 2.0f;
  float m2 = fmin(-kx * p1x + ky * p1y, 0.0f);
  float p2x = p1x - (-kx * m2) * 2.0f;
  float p2y = p1y - (ky * m2) * 2.0f;
  float cx = fmin(fmax(p2x, -kz * r), kz * r); /* GLSL clamp = min(max()) */
  float p3x = p2x - cx;
  float p3y = p2y - r;
  return (p3x + p3y > 0.0f) ? 0.0f : 1.0f;
}

PMC_FN float pmc_pattern_shape(float x, float y, float radius, pmc_u32 shape) {
  if (shape == PMC_SHAPE_CIRCLES) return pmc_pattern_circle(x, y, radius);
  if (shape == PMC_SHAPE_CLOVERLEAFS) return pmc_pattern_cloverleaf(x, y, radius);
  if (shape == PMC_SHAPE_HEXAGONS) return pmc_pattern_hexagon(x, y, radius);
  return 0.0f;
}

/* line node, center (0, 0): 1 within `radius` of the segment a-b. */
PMC_FN float pmc_pattern_line(float x, float y, float radius, float ax, float ay, float bx, float by) {
  float pax = x - ax, pay = y - ay;
  float bax = bx - ax, bay = by - ay;
  float h = (pax * bax + pay * bay) / (bax * bax + bay * bay);
  h = fmin(fmax(h, 0.0f), 1.0f);
  float dx = pax - bax * h, dy = pay - bay * h;
  return (sqrt(dx * dx + dy * dy) > radius) ? 0.0f : 1.0f;
}

PMC_FN float4 pmc_pattern_color(float v) { return make_float4(v, v, v, 1.0f); }

/* tiledcircles / tiledcloverleafs / tiledhexagons (`shape` = PMC_SHAPE_*). */
PMC_FN float4 pmc_op_tiledshape(float2 uv, float2 tiling, float2 offset, float size, int staggered,
                                pmc_u32 shape) {
  float stx = uv.x * tiling.x - offset.x;
  float sty = uv.y * tiling.y - offset.y;
  if (!pmc_pattern_finite(stx) || !pmc_pattern_finite(sty) || !pmc_pattern_finite(size))
    return pmc_pattern_color(0.0f);
  float v;
  if (staggered) {
    /* Row height: sqrt(3)/2 for circles and hexagons, 1/2 for cloverleafs. */
    float h = shape == PMC_SHAPE_CLOVERLEAFS ? 0.5f : 0.866025f;
    float period = shape == PMC_SHAPE_CLOVERLEAFS ? 1.0f : 1.73205f;
    float shift = pmc_pattern_mod(sty, period) > h ? 0.5f : 0.0f;
    float x = pmc_pattern_mod(stx + shift, 1.0f);
    float y = pmc_pattern_mod(sty, h);
    float r = size / 2.0f;
    float a = pmc_pattern_shape(x, y, r, shape);
    float b = pmc_pattern_shape(1.0f - x, y, r, shape);
    float c = pmc_pattern_shape(x - 0.5f, h - y, r, shape);
    v = fmax(fmax(a, b), c);
  } else {
    float x = pmc_pattern_mod(stx, 1.0f) * 2.0f - 1.0f;
    float y = pmc_pattern_mod(sty, 1.0f) * 2.0f - 1.0f;
    v = pmc_pattern_shape(x, y, size, shape);
  }
  return pmc_pattern_color(v);
}

/* grid / crosshatch (`kind` = PMC_LINES_*). */
PMC_FN float4 pmc_op_linepattern(float2 uv, float2 tiling, float2 offset, float thickness, int staggered,
                                 pmc_u32 kind) {
  float stx = uv.x * tiling.x - offset.x;
  float sty = uv.y * tiling.y - offset.y;
  if (!pmc_pattern_finite(stx) || !pmc_pattern_finite(sty) || !pmc_pattern_finite(thickness))
    return pmc_pattern_color(0.0f);
  float shift = pmc_pattern_mod(sty, 2.0f) > 1.0f ? 0.5f : 0.0f;
  float x = pmc_pattern_mod(staggered ? stx + shift : stx, 1.0f) * 2.0f - 1.0f;
  float y = pmc_pattern_mod(sty, 1.0f) * 2.0f - 1.0f;
  float v = 0.0f;
  if (kind == PMC_LINES_GRID) {
    float edge = 1.0f - thickness;
    float xd = fabs(x) > edge ? 0.0f : 1.0f;
    float yd = fabs(y) > edge ? 0.0f : 1.0f;
    v = 1.0f - fmin(xd, yd);
  } else if (kind == PMC_LINES_CROSSHATCH) {
    float d1 = pmc_pattern_line(x, y, thickness, 1.0f, 1.0f, -1.0f, -1.0f);
    float d2 = pmc_pattern_line(x, y, thickness, -1.0f, 1.0f, 1.0f, -1.0f);
    v = fmax(d1, d2);
  }
  return pmc_pattern_color(v);
}

#endif /* PMC_PATTERNS_H */
