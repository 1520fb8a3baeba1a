/* pmc_noise.h — MaterialX 1.39 procedural noise nodes: noise2d/3d, fractal2d/3d,
 * cellnoise2d/3d, worleynoise2d/3d. Shared by the OpenCL interpreter and the
 * host reference (see pmc_vec.h for the dialect rules).
 *
 * The algorithms and constants are those of MaterialX's own shader library
 * (libraries/stdlib/genglsl/lib/mx_noise.glsl and the per-node wrappers),
 * which in turn reproduces Open Shading Language's noise (oslnoise.h), so a
 * document renders with the same pattern here as in MaterialX viewers:
 *
 *  - Integer hash: Bob Jenkins' lookup3 "hashword" over the cell coordinates
 *    with initval 13 (a = b = c = 0xdeadbeef + 4*len + 13; add the words;
 *    mix every three words; final). Only the final mixing differs between
 *    lengths, see pmc_noise_hash2/3/4.
 *  - Perlin "improved" gradient noise with the quintic fade 6t^5-15t^4+10t^3.
 *    2D gradients are the eight (+-1,+-2)/(+-2,+-1) picked by the low 3 hash
 *    bits, 3D gradients the twelve cube edges (16 entries) by the low 4 bits;
 *    the results are scaled by 0.6616 (2D) and 0.9820 (3D) so that the range
 *    is about [-1, 1]. The three-channel variant takes one gradient per byte
 *    of the same hash, so its first channel equals the one-channel noise.
 *  - noise2d/3d vector4: xyz from the three-channel noise, w from the
 *    one-channel noise at p + (19, 73) (2D) or p + (19, 73, 29) (3D).
 *  - fractal: sum over octaves of amplitude * noise(p), amplitude *= diminish,
 *    p *= lacunarity. vector2 = (F(p), F(p + o)), vector4 = (F3(p), F(p + o))
 *    with o = (19, 193) in 2D and (19, 193, 17) in 3D.
 *  - cellnoise: hash of floor(p) mapped to [0, 1).
 *  - worley: one feature point per cell at cell + 0.5 + (h - 0.5) * jitter,
 *    h from the cell hash (lanes 0 and 1, or 0..2 in 3D); the 3x3 (3x3x3)
 *    neighbourhood is searched; Euclidean distances F1 <= F2 <= F3. Style 1
 *    ("Solid", MaterialX 1.39) returns the cell noise of the cell holding
 *    the nearest feature point instead of distances.
 *
 * Deviations from the GLSL, all for robustness and only visible outside the
 * range where the GLSL is well defined:
 *  - Cell indices are unsigned and wrap modulo 2^32, which equals the GLSL's
 *    int arithmetic whenever that does not overflow. For |p| >= 2^31 (where
 *    int(floor(p)) is undefined) the index is floor(p) mod 2^32, so the noise
 *    stays defined, finite and deterministic. Worley hashes its neighbour
 *    cells directly as integers (the GLSL round-trips them through float,
 *    which only matters beyond 2^24).
 *  - Hash-to-[0,1) never returns 1.0 (the GLSL's float(bits)/float(0xffffffff)
 *    rounds the top 128 hash values up to 1.0; here they give 1 - 2^-24).
 *  - Worley "Solid" finds the feature cell as cell + floor(offset) in integer
 *    arithmetic instead of floor(feature + p) in float.
 *  - Non-finite inputs (NaN, +-Inf) return 0 in every lane; fractal sums that
 *    overflow are clamped to +-FLT_MAX and stop adding octaves.
 */
#ifndef PMC_NOISE_H
#define PMC_NOISE_H

#include "../abi/pmc_vec.h"

#define PMC_NOISE_FLT_MAX 3.40282347e38f
#define PMC_NOISE_MAX_OCTAVES 16

/* ---- small helpers ------------------------------------------------------ */

/* True for finite x (false for NaN and +-Inf); plain comparisons, so it works
 * the same in both compilers without isfinite's return-type differences. */
PMC_FN int pmc_noise_finite(float x) { return fabs(x) <= PMC_NOISE_FLT_MAX; }

/* NaN -> 0, +-Inf -> +-FLT_MAX. */
PMC_FN float pmc_noise_sanitize(float x) {
  if (!(x == x)) return 0.0f;
  if (x > PMC_NOISE_FLT_MAX) return PMC_NOISE_FLT_MAX;
  if (x < -PMC_NOISE_FLT_MAX) return -PMC_NOISE_FLT_MAX;
  return x;
}

/* Cell index of an integer-valued finite float `fl` (a floor() result):
 * exactly (uint)(int)fl where that conversion is defined, else fl mod 2^32.
 * Branch-free, and without fmod (a library call the compiler would otherwise
 * speculate for every cell): beyond 2^31 every float is a multiple of 256,
 * so fl - 2^32 floor(fl / 2^32) and the shift into [-2^31, 2^31) are exact. */
PMC_FN pmc_u32 pmc_noise_cell(float fl) {
  float big = fl - 4294967296.0f * floor(fl * (1.0f / 4294967296.0f)); /* [0, 2^32) */
  big = big >= 2147483648.0f ? big - 4294967296.0f : big;              /* [-2^31, 2^31) */
  float v = fabs(fl) < 2147483648.0f ? fl : big;
  return (pmc_u32)(pmc_i32)v;
}

/* floor(x) as a cell index, returns the fraction x - floor(x) in [0, 1]. */
PMC_FN float pmc_noise_floorfrac(float x, pmc_u32* cell) {
  float fl = floor(x);
  *cell = pmc_noise_cell(fl);
  return x - fl;
}

/* ---- lookup3 hash ------------------------------------------------------- */

PMC_FN pmc_u32 pmc_noise_rotl(pmc_u32 x, int k) { return (x << k) | (x >> (32 - k)); }

/* lookup3 mix(): reversible mixing of three words. */
PMC_FN void pmc_noise_bjmix(pmc_u32* a, pmc_u32* b, pmc_u32* c) {
  *a -= *c;
  *a ^= pmc_noise_rotl(*c, 4);
  *c += *b;
  *b -= *a;
  *b ^= pmc_noise_rotl(*a, 6);
  *a += *c;
  *c -= *b;
  *c ^= pmc_noise_rotl(*b, 8);
  *b += *a;
  *a -= *c;
  *a ^= pmc_noise_rotl(*c, 16);
  *c += *b;
  *b -= *a;
  *b ^= pmc_noise_rotl(*a, 19);
  *a += *c;
  *c -= *b;
  *c ^= pmc_noise_rotl(*b, 4);
  *b += *a;
}

/* lookup3 final(): returns the finished c. */
PMC_FN pmc_u32 pmc_noise_bjfinal(pmc_u32 a, pmc_u32 b, pmc_u32 c) {
  c ^= b;
  c -= pmc_noise_rotl(b, 14);
  a ^= c;
  a -= pmc_noise_rotl(c, 11);
  b ^= a;
  b -= pmc_noise_rotl(a, 25);
  c ^= b;
  c -= pmc_noise_rotl(b, 16);
  a ^= c;
  a -= pmc_noise_rotl(c, 4);
  b ^= a;
  b -= pmc_noise_rotl(a, 14);
  c ^= b;
  c -= pmc_noise_rotl(b, 24);
  return c;
}

/* Initial state of lookup3's hashword for `len` words and initval 13. */
PMC_FN pmc_u32 pmc_noise_seed(pmc_u32 len) { return 0xdeadbeefu + (len << 2) + 13u; }

PMC_FN pmc_u32 pmc_noise_hash2(pmc_u32 x, pmc_u32 y) {
  pmc_u32 s = pmc_noise_seed(2u);
  return pmc_noise_bjfinal(s + x, s + y, s);
}

PMC_FN pmc_u32 pmc_noise_hash3(pmc_u32 x, pmc_u32 y, pmc_u32 z) {
  pmc_u32 s = pmc_noise_seed(3u);
  return pmc_noise_bjfinal(s + x, s + y, s + z);
}

PMC_FN pmc_u32 pmc_noise_hash4(pmc_u32 x, pmc_u32 y, pmc_u32 z, pmc_u32 w) {
  pmc_u32 s = pmc_noise_seed(4u);
  pmc_u32 a = s + x, b = s + y, c = s + z;
  pmc_noise_bjmix(&a, &b, &c);
  return pmc_noise_bjfinal(a + w, b, c);
}

/* Hash bits to [0, 1): bits * 2^-32 (correctly rounded conversion), with the
 * few values that round up to 1.0 pulled back to the largest float below 1. */
PMC_FN float pmc_noise_to01(pmc_u32 bits) {
  float f = (float)bits * 2.3283064365386963e-10f;
  return f < 1.0f ? f : 0.99999994f;
}

/* ---- Perlin noise ------------------------------------------------------- */

PMC_FN float pmc_noise_fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

PMC_FN float pmc_noise_grad2(pmc_u32 hash, float x, float y) {
  pmc_u32 h = hash & 7u;
  float u = h < 4u ? x : y;
  float v = 2.0f * (h < 4u ? y : x);
  return ((h & 1u) ? -u : u) + ((h & 2u) ? -v : v);
}

PMC_FN float pmc_noise_grad3(pmc_u32 hash, float x, float y, float z) {
  pmc_u32 h = hash & 15u;
  float u = h < 8u ? x : y;
  float v = h < 4u ? y : ((h == 12u || h == 14u) ? x : z);
  return ((h & 1u) ? -u : u) + ((h & 2u) ? -v : v);
}

PMC_FN float pmc_noise_bilerp(float v0, float v1, float v2, float v3, float s, float t) {
  float s1 = 1.0f - s;
  return (1.0f - t) * (v0 * s1 + v1 * s) + t * (v2 * s1 + v3 * s);
}

PMC_FN float pmc_noise_trilerp(float v0, float v1, float v2, float v3, float v4, float v5, float v6, float v7,
                               float s, float t, float r) {
  float s1 = 1.0f - s, t1 = 1.0f - t, r1 = 1.0f - r;
  return (r1 * (t1 * (v0 * s1 + v1 * s) + t * (v2 * s1 + v3 * s)) +
          r * (t1 * (v4 * s1 + v5 * s) + t * (v6 * s1 + v7 * s)));
}

/* Signed 2D Perlin noise of finite (px, py). `lanes` 1: x only (the float
 * noise); 3: x, y, z from hash bytes 0, 1, 2. Unused lanes are 0. */
PMC_FN float4 pmc_noise_perlin2(float px, float py, int lanes) {
  pmc_u32 X, Y;
  float fx = pmc_noise_floorfrac(px, &X);
  float fy = pmc_noise_floorfrac(py, &Y);
  float u = pmc_noise_fade(fx), v = pmc_noise_fade(fy);
  pmc_u32 h00 = pmc_noise_hash2(X, Y), h10 = pmc_noise_hash2(X + 1u, Y);
  pmc_u32 h01 = pmc_noise_hash2(X, Y + 1u), h11 = pmc_noise_hash2(X + 1u, Y + 1u);
  float out[3] = {0.0f, 0.0f, 0.0f};
  for (int k = 0; k < lanes && k < 3; ++k) {
    int sh = 8 * k;
    out[k] = 0.6616f * pmc_noise_bilerp(pmc_noise_grad2(h00 >> sh, fx, fy),
                                        pmc_noise_grad2(h10 >> sh, fx - 1.0f, fy),
                                        pmc_noise_grad2(h01 >> sh, fx, fy - 1.0f),
                                        pmc_noise_grad2(h11 >> sh, fx - 1.0f, fy - 1.0f), u, v);
  }
  return make_float4(out[0], out[1], out[2], 0.0f);
}

/* Signed 3D Perlin noise of finite p, lanes as for pmc_noise_perlin2. */
PMC_FN float4 pmc_noise_perlin3(float px, float py, float pz, int lanes) {
  pmc_u32 X, Y, Z;
  float fx = pmc_noise_floorfrac(px, &X);
  float fy = pmc_noise_floorfrac(py, &Y);
  float fz = pmc_noise_floorfrac(pz, &Z);
  float u = pmc_noise_fade(fx), v = pmc_noise_fade(fy), w = pmc_noise_fade(fz);
  pmc_u32 h000 = pmc_noise_hash3(X, Y, Z), h100 = pmc_noise_hash3(X + 1u, Y, Z);
  pmc_u32 h010 = pmc_noise_hash3(X, Y + 1u, Z), h110 = pmc_noise_hash3(X + 1u, Y + 1u, Z);
  pmc_u32 h001 = pmc_noise_hash3(X, Y, Z + 1u), h101 = pmc_noise_hash3(X + 1u, Y, Z + 1u);
  pmc_u32 h011 = pmc_noise_hash3(X, Y + 1u, Z + 1u), h111 = pmc_noise_hash3(X + 1u, Y + 1u, Z + 1u);
  float gx = fx - 1.0f, gy = fy - 1.0f, gz = fz - 1.0f;
  float out[3] = {0.0f, 0.0f, 0.0f};
  for (int k = 0; k < lanes && k < 3; ++k) {
    int sh = 8 * k;
    out[k] = 0.9820f * pmc_noise_trilerp(
                           pmc_noise_grad3(h000 >> sh, fx, fy, fz), pmc_noise_grad3(h100 >> sh, gx, fy, fz),
                           pmc_noise_grad3(h010 >> sh, fx, gy, fz), pmc_noise_grad3(h110 >> sh, gx, gy, fz),
                           pmc_noise_grad3(h001 >> sh, fx, fy, gz), pmc_noise_grad3(h101 >> sh, gx, fy, gz),
                           pmc_noise_grad3(h011 >> sh, fx, gy, gz), pmc_noise_grad3(h111 >> sh, gx, gy, gz),
                           u, v, w);
  }
  return make_float4(out[0], out[1], out[2], 0.0f);
}

PMC_FN float4 pmc_noise_zero4(void) { return make_float4(0.0f, 0.0f, 0.0f, 0.0f); }

/* ---- noise2d / noise3d -------------------------------------------------- */

/* MaterialX noise2d before amplitude/pivot. width 1: the float noise in all
 * lanes; 2 and 3: the vector3 noise (lanes beyond the width are 0); 4: the
 * vector3 noise in xyz and w = float noise at p + (19, 73). */
PMC_FN float4 pmc_op_noise2d(float2 p, pmc_u32 width) {
  if (!pmc_noise_finite(p.x) || !pmc_noise_finite(p.y)) return pmc_noise_zero4();
  if (width <= 1u) {
    float n = pmc_noise_perlin2(p.x, p.y, 1).x;
    return make_float4(n, n, n, n);
  }
  float4 r = pmc_noise_perlin2(p.x, p.y, 3);
  if (width == 2u) r.z = 0.0f;
  if (width >= 4u) r.w = pmc_noise_perlin2(p.x + 19.0f, p.y + 73.0f, 1).x;
  return r;
}

/* MaterialX noise3d before amplitude/pivot; lanes as pmc_op_noise2d, the
 * vector4 w from the float noise at p + (19, 73, 29). */
PMC_FN float4 pmc_op_noise3d(float3 p, pmc_u32 width) {
  if (!pmc_noise_finite(p.x) || !pmc_noise_finite(p.y) || !pmc_noise_finite(p.z)) return pmc_noise_zero4();
  if (width <= 1u) {
    float n = pmc_noise_perlin3(p.x, p.y, p.z, 1).x;
    return make_float4(n, n, n, n);
  }
  float4 r = pmc_noise_perlin3(p.x, p.y, p.z, 3);
  if (width == 2u) r.z = 0.0f;
  if (width >= 4u) r.w = pmc_noise_perlin3(p.x + 19.0f, p.y + 73.0f, p.z + 29.0f, 1).x;
  return r;
}

/* ---- fractal2d / fractal3d ---------------------------------------------- */

PMC_FN int pmc_noise_octaves(int octaves) {
  return octaves < 0 ? 0 : (octaves > PMC_NOISE_MAX_OCTAVES ? PMC_NOISE_MAX_OCTAVES : octaves);
}

/* Octave sum of the 2D noise (lanes 1 or 3). Stops early once the position or
 * the amplitude is no longer finite; the sum is clamped to finite floats. */
PMC_FN float4 pmc_noise_fbm2(float px, float py, int octaves, float lacunarity, float diminish, int lanes) {
  float4 sum = pmc_noise_zero4();
  float amp = 1.0f;
  int n = pmc_noise_octaves(octaves);
  for (int i = 0; i < n; ++i) {
    if (!pmc_noise_finite(px) || !pmc_noise_finite(py) || !pmc_noise_finite(amp)) break;
    float4 v = pmc_noise_perlin2(px, py, lanes);
    sum.x += amp * v.x;
    sum.y += amp * v.y;
    sum.z += amp * v.z;
    amp *= diminish;
    px *= lacunarity;
    py *= lacunarity;
  }
  return make_float4(pmc_noise_sanitize(sum.x), pmc_noise_sanitize(sum.y), pmc_noise_sanitize(sum.z), 0.0f);
}

PMC_FN float4 pmc_noise_fbm3(float px, float py, float pz, int octaves, float lacunarity, float diminish,
                             int lanes) {
  float4 sum = pmc_noise_zero4();
  float amp = 1.0f;
  int n = pmc_noise_octaves(octaves);
  for (int i = 0; i < n; ++i) {
    if (!pmc_noise_finite(px) || !pmc_noise_finite(py) || !pmc_noise_finite(pz) || !pmc_noise_finite(amp))
      break;
    float4 v = pmc_noise_perlin3(px, py, pz, lanes);
    sum.x += amp * v.x;
    sum.y += amp * v.y;
    sum.z += amp * v.z;
    amp *= diminish;
    px *= lacunarity;
    py *= lacunarity;
    pz *= lacunarity;
  }
  return make_float4(pmc_noise_sanitize(sum.x), pmc_noise_sanitize(sum.y), pmc_noise_sanitize(sum.z), 0.0f);
}

/* MaterialX fractal2d before amplitude. width 1: float fractal in all lanes;
 * 2: (F(p), F(p + (19, 193))); 3: vector3 fractal; 4: vector3 fractal and
 * w = F(p + (19, 193)). Octaves are clamped to [0, 16]. */
PMC_FN float4 pmc_op_fractal2d(float2 p, int octaves, float lacunarity, float diminish, pmc_u32 width) {
  if (!pmc_noise_finite(p.x) || !pmc_noise_finite(p.y) || !pmc_noise_finite(lacunarity) ||
      !pmc_noise_finite(diminish))
    return pmc_noise_zero4();
  if (width <= 1u) {
    float n = pmc_noise_fbm2(p.x, p.y, octaves, lacunarity, diminish, 1).x;
    return make_float4(n, n, n, n);
  }
  if (width == 2u) {
    float a = pmc_noise_fbm2(p.x, p.y, octaves, lacunarity, diminish, 1).x;
    float b = pmc_noise_fbm2(p.x + 19.0f, p.y + 193.0f, octaves, lacunarity, diminish, 1).x;
    return make_float4(a, b, 0.0f, 0.0f);
  }
  float4 r = pmc_noise_fbm2(p.x, p.y, octaves, lacunarity, diminish, 3);
  if (width >= 4u) r.w = pmc_noise_fbm2(p.x + 19.0f, p.y + 193.0f, octaves, lacunarity, diminish, 1).x;
  return r;
}

/* MaterialX fractal3d before amplitude; lanes as pmc_op_fractal2d with the
 * offset (19, 193, 17). */
PMC_FN float4 pmc_op_fractal3d(float3 p, int octaves, float lacunarity, float diminish, pmc_u32 width) {
  if (!pmc_noise_finite(p.x) || !pmc_noise_finite(p.y) || !pmc_noise_finite(p.z) ||
      !pmc_noise_finite(lacunarity) || !pmc_noise_finite(diminish))
    return pmc_noise_zero4();
  if (width <= 1u) {
    float n = pmc_noise_fbm3(p.x, p.y, p.z, octaves, lacunarity, diminish, 1).x;
    return make_float4(n, n, n, n);
  }
  if (width == 2u) {
    float a = pmc_noise_fbm3(p.x, p.y, p.z, octaves, lacunarity, diminish, 1).x;
    float b = pmc_noise_fbm3(p.x + 19.0f, p.y + 193.0f, p.z + 17.0f, octaves, lacunarity, diminish, 1).x;
    return make_float4(a, b, 0.0f, 0.0f);
  }
  float4 r = pmc_noise_fbm3(p.x, p.y, p.z, octaves, lacunarity, diminish, 3);
  if (width >= 4u)
    r.w = pmc_noise_fbm3(p.x + 19.0f, p.y + 193.0f, p.z + 17.0f, octaves, lacunarity, diminish, 1).x;
  return r;
}

/* ---- cellnoise ---------------------------------------------------------- */

PMC_FN float pmc_op_cellnoise2d(float2 p) {
  if (!pmc_noise_finite(p.x) || !pmc_noise_finite(p.y)) return 0.0f;
  return pmc_noise_to01(pmc_noise_hash2(pmc_noise_cell(floor(p.x)), pmc_noise_cell(floor(p.y))));
}

PMC_FN float pmc_op_cellnoise3d(float3 p) {
  if (!pmc_noise_finite(p.x) || !pmc_noise_finite(p.y) || !pmc_noise_finite(p.z)) return 0.0f;
  return pmc_noise_to01(
      pmc_noise_hash3(pmc_noise_cell(floor(p.x)), pmc_noise_cell(floor(p.y)), pmc_noise_cell(floor(p.z))));
}

/* ---- worley ------------------------------------------------------------- */

/* Keeps the three smallest squared distances in ascending order; returns 1
 * when d became the new nearest. Same update chain as MaterialX (strict <, so
 * the first of equal candidates in loop order wins). */
PMC_FN int pmc_noise_worley_insert(float d, float* d0, float* d1, float* d2) {
  if (d < *d0) {
    *d2 = *d1;
    *d1 = *d0;
    *d0 = d;
    return 1;
  }
  if (d < *d1) {
    *d2 = *d1;
    *d1 = d;
  } else if (d < *d2) {
    *d2 = d;
  }
  return 0;
}

/* Packs the worley result: distances (style 0) or the cell noise of the
 * nearest feature's cell (style 1; `c0..c2` are its three cell-noise lanes). */
PMC_FN float4 pmc_noise_worley_out(int style, pmc_u32 width, float d0, float d1, float d2, float c0, float c1,
                                   float c2) {
  float a, b, c;
  if (style == 1) {
    a = c0;
    b = c1;
    c = c2;
  } else {
    a = sqrt(d0);
    b = sqrt(d1);
    c = sqrt(d2);
  }
  if (width <= 1u) return make_float4(a, a, a, a);
  if (width == 2u) return make_float4(a, b, 0.0f, 0.0f);
  return make_float4(a, b, c, 0.0f);
}

/* MaterialX worleynoise2d (Euclidean). width 1: F1 in all lanes; 2: (F1, F2);
 * 3: (F1, F2, F3). style 1 (Solid): cell noise of the nearest feature's cell
 * (float in all lanes for width 1, else the vector cell noise). */
PMC_FN float4 pmc_op_worley2d(float2 p, float jitter, int style, pmc_u32 width) {
  if (!pmc_noise_finite(p.x) || !pmc_noise_finite(p.y) || !pmc_noise_finite(jitter)) return pmc_noise_zero4();
  pmc_u32 X, Y;
  float lx = pmc_noise_floorfrac(p.x, &X);
  float ly = pmc_noise_floorfrac(p.y, &Y);
  /* "Some big number" start value, as MaterialX: with jitter > 1 the
   * neighbourhood may hold no nearer point. */
  float d0 = 1e6f, d1 = 1e6f, d2 = 1e6f;
  pmc_u32 bx = X, by = Y;
  for (int i = -1; i <= 1; ++i) {
    for (int j = -1; j <= 1; ++j) {
      pmc_u32 cx = X + (pmc_u32)i, cy = Y + (pmc_u32)j;
      float ox = (pmc_noise_to01(pmc_noise_hash3(cx, cy, 0u)) - 0.5f) * jitter + 0.5f;
      float oy = (pmc_noise_to01(pmc_noise_hash3(cx, cy, 1u)) - 0.5f) * jitter + 0.5f;
      float dx = ((float)i + ox) - lx;
      float dy = ((float)j + oy) - ly;
      if (pmc_noise_worley_insert(dx * dx + dy * dy, &d0, &d1, &d2)) {
        bx = cx + pmc_noise_cell(floor(ox));
        by = cy + pmc_noise_cell(floor(oy));
      }
    }
  }
  float c0 = 0.0f, c1 = 0.0f, c2 = 0.0f;
  if (style == 1) {
    if (width <= 1u) {
      c0 = pmc_noise_to01(pmc_noise_hash2(bx, by));
    } else {
      c0 = pmc_noise_to01(pmc_noise_hash3(bx, by, 0u));
      c1 = pmc_noise_to01(pmc_noise_hash3(bx, by, 1u));
      c2 = pmc_noise_to01(pmc_noise_hash3(bx, by, 2u));
    }
  }
  return pmc_noise_worley_out(style, width, d0, d1, d2, c0, c1, c2);
}

/* MaterialX worleynoise3d; outputs as pmc_op_worley2d. */
PMC_FN float4 pmc_op_worley3d(float3 p, float jitter, int style, pmc_u32 width) {
  if (!pmc_noise_finite(p.x) || !pmc_noise_finite(p.y) || !pmc_noise_finite(p.z) || !pmc_noise_finite(jitter))
    return pmc_noise_zero4();
  pmc_u32 X, Y, Z;
  float lx = pmc_noise_floorfrac(p.x, &X);
  float ly = pmc_noise_floorfrac(p.y, &Y);
  float lz = pmc_noise_floorfrac(p.z, &Z);
  float d0 = 1e6f, d1 = 1e6f, d2 = 1e6f;
  pmc_u32 bx = X, by = Y, bz = Z;
  for (int i = -1; i <= 1; ++i) {
    for (int j = -1; j <= 1; ++j) {
      for (int k = -1; k <= 1; ++k) {
        pmc_u32 cx = X + (pmc_u32)i, cy = Y + (pmc_u32)j, cz = Z + (pmc_u32)k;
        float ox = (pmc_noise_to01(pmc_noise_hash4(cx, cy, cz, 0u)) - 0.5f) * jitter + 0.5f;
        float oy = (pmc_noise_to01(pmc_noise_hash4(cx, cy, cz, 1u)) - 0.5f) * jitter + 0.5f;
        float oz = (pmc_noise_to01(pmc_noise_hash4(cx, cy, cz, 2u)) - 0.5f) * jitter + 0.5f;
        float dx = ((float)i + ox) - lx;
        float dy = ((float)j + oy) - ly;
        float dz = ((float)k + oz) - lz;
        if (pmc_noise_worley_insert(dx * dx + dy * dy + dz * dz, &d0, &d1, &d2)) {
          bx = cx + pmc_noise_cell(floor(ox));
          by = cy + pmc_noise_cell(floor(oy));
          bz = cz + pmc_noise_cell(floor(oz));
        }
      }
    }
  }
  float c0 = 0.0f, c1 = 0.0f, c2 = 0.0f;
  if (style == 1) {
    if (width <= 1u) {
      c0 = pmc_noise_to01(pmc_noise_hash3(bx, by, bz));
    } else {
      c0 = pmc_noise_to01(pmc_noise_hash4(bx, by, bz, 0u));
      c1 = pmc_noise_to01(pmc_noise_hash4(bx, by, bz, 1u));
      c2 = pmc_noise_to01(pmc_noise_hash4(bx, by, bz, 2u));
    }
  }
  return pmc_noise_worley_out(style, width, d0, d1, d2, c0, c1, c2);
}

/* ---- the same noises for a batch of points ------------------------------ */
/* The interpreter evaluates a node for up to PMC_LANES points at once
 * (core/device/pmc_interp.h). These versions compute exactly what the
 * single-point functions above compute, point by point, but as straight-line
 * loops over the points that a compiler vectorises; positions and octave
 * counts may differ per point. Arrays are indexed by point, [0, n). */

#ifndef PMC_LANES
#define PMC_LANES 1
#endif

/* 2D Perlin of finite points: o0 (and with three, o1 and o2 from hash bytes
 * 1 and 2), before any scaling beyond the 0.6616 of pmc_noise_perlin2. */
PMC_FN void pmc_perlin2_lanes(const float* px, const float* py, int n, int three, float* o0, float* o1,
                              float* o2) {
  for (int k = 0; k < n; ++k) {
    float flx = floor(px[k]), fly = floor(py[k]);
    pmc_u32 X = pmc_noise_cell(flx), Y = pmc_noise_cell(fly);
    float fx = px[k] - flx, fy = py[k] - fly;
    float u = pmc_noise_fade(fx), v = pmc_noise_fade(fy);
    pmc_u32 h00 = pmc_noise_hash2(X, Y), h10 = pmc_noise_hash2(X + 1u, Y);
    pmc_u32 h01 = pmc_noise_hash2(X, Y + 1u), h11 = pmc_noise_hash2(X + 1u, Y + 1u);
    o0[k] = 0.6616f * pmc_noise_bilerp(pmc_noise_grad2(h00, fx, fy), pmc_noise_grad2(h10, fx - 1.0f, fy),
                                       pmc_noise_grad2(h01, fx, fy - 1.0f),
                                       pmc_noise_grad2(h11, fx - 1.0f, fy - 1.0f), u, v);
    if (three) {
      o1[k] = 0.6616f * pmc_noise_bilerp(pmc_noise_grad2(h00 >> 8, fx, fy),
                                         pmc_noise_grad2(h10 >> 8, fx - 1.0f, fy),
                                         pmc_noise_grad2(h01 >> 8, fx, fy - 1.0f),
                                         pmc_noise_grad2(h11 >> 8, fx - 1.0f, fy - 1.0f), u, v);
      o2[k] = 0.6616f * pmc_noise_bilerp(pmc_noise_grad2(h00 >> 16, fx, fy),
                                         pmc_noise_grad2(h10 >> 16, fx - 1.0f, fy),
                                         pmc_noise_grad2(h01 >> 16, fx, fy - 1.0f),
                                         pmc_noise_grad2(h11 >> 16, fx - 1.0f, fy - 1.0f), u, v);
    }
  }
}

/* 3D Perlin of finite points, as pmc_perlin2_lanes. The three channels are
 * written out one after another (no loop over them inside the loop over
 * points: the compiler vectorises only loops that hold none). */
#define PMC_PERLIN3_AT(sh)                                                                                 \
  (0.9820f *                                                                                               \
   pmc_noise_trilerp(pmc_noise_grad3(h000 >> (sh), fx, fy, fz), pmc_noise_grad3(h100 >> (sh), gx, fy, fz), \
                     pmc_noise_grad3(h010 >> (sh), fx, gy, fz), pmc_noise_grad3(h110 >> (sh), gx, gy, fz), \
                     pmc_noise_grad3(h001 >> (sh), fx, fy, gz), pmc_noise_grad3(h101 >> (sh), gx, fy, gz), \
                     pmc_noise_grad3(h011 >> (sh), fx, gy, gz), pmc_noise_grad3(h111 >> (sh), gx, gy, gz), \
                     u, v, w))
PMC_FN void pmc_perlin3_lanes(const float* px, const float* py, const float* pz, int n, int three, float* o0,
                              float* o1, float* o2) {
  for (int k = 0; k < n; ++k) {
    float flx = floor(px[k]), fly = floor(py[k]), flz = floor(pz[k]);
    pmc_u32 X = pmc_noise_cell(flx), Y = pmc_noise_cell(fly), Z = pmc_noise_cell(flz);
    float fx = px[k] - flx, fy = py[k] - fly, fz = pz[k] - flz;
    float u = pmc_noise_fade(fx), v = pmc_noise_fade(fy), w = pmc_noise_fade(fz);
    pmc_u32 h000 = pmc_noise_hash3(X, Y, Z), h100 = pmc_noise_hash3(X + 1u, Y, Z);
    pmc_u32 h010 = pmc_noise_hash3(X, Y + 1u, Z), h110 = pmc_noise_hash3(X + 1u, Y + 1u, Z);
    pmc_u32 h001 = pmc_noise_hash3(X, Y, Z + 1u), h101 = pmc_noise_hash3(X + 1u, Y, Z + 1u);
    pmc_u32 h011 = pmc_noise_hash3(X, Y + 1u, Z + 1u), h111 = pmc_noise_hash3(X + 1u, Y + 1u, Z + 1u);
    float gx = fx - 1.0f, gy = fy - 1.0f, gz = fz - 1.0f;
    o0[k] = PMC_PERLIN3_AT(0);
    if (three) {
      o1[k] = PMC_PERLIN3_AT(8);
      o2[k] = PMC_PERLIN3_AT(16);
    }
  }
}
#undef PMC_PERLIN3_AT

/* Octave sums (pmc_noise_fbm2/3) for a batch: a point stops at its own
 * octave count or once its position or amplitude is no longer finite. `dims`
 * is 2 or 3 (pz unused for 2). */
PMC_FN void pmc_fbm_lanes(int dims, const float* px, const float* py, const float* pz, const int* octaves,
                          const float* lacunarity, const float* diminish, int n, int three, float* s0,
                          float* s1, float* s2) {
  float x[PMC_LANES], y[PMC_LANES], z[PMC_LANES], amp[PMC_LANES], v0[PMC_LANES], v1[PMC_LANES], v2[PMC_LANES];
  int alive[PMC_LANES], oct[PMC_LANES];
  int most = 0;
  for (int k = 0; k < n; ++k) {
    x[k] = px[k];
    y[k] = py[k];
    z[k] = dims == 3 ? pz[k] : 0.0f;
    amp[k] = 1.0f;
    alive[k] = 1;
    oct[k] = pmc_noise_octaves(octaves[k]);
    most = oct[k] > most ? oct[k] : most;
    s0[k] = s1[k] = s2[k] = 0.0f;
  }
  for (int i = 0; i < most; ++i) {
    float qx[PMC_LANES], qy[PMC_LANES], qz[PMC_LANES];
    for (int k = 0; k < n; ++k) {
      alive[k] = alive[k] && i < oct[k] && pmc_noise_finite(x[k]) && pmc_noise_finite(y[k]) &&
                 pmc_noise_finite(z[k]) && pmc_noise_finite(amp[k]);
      qx[k] = alive[k] ? x[k] : 0.0f; /* finite inputs for the lanes that stopped */
      qy[k] = alive[k] ? y[k] : 0.0f;
      qz[k] = alive[k] ? z[k] : 0.0f;
    }
    if (dims == 3)
      pmc_perlin3_lanes(qx, qy, qz, n, three, v0, v1, v2);
    else
      pmc_perlin2_lanes(qx, qy, n, three, v0, v1, v2);
    for (int k = 0; k < n; ++k) {
      if (alive[k]) {
        s0[k] += amp[k] * v0[k];
        if (three) {
          s1[k] += amp[k] * v1[k];
          s2[k] += amp[k] * v2[k];
        }
      }
      amp[k] *= diminish[k];
      x[k] *= lacunarity[k];
      y[k] *= lacunarity[k];
      z[k] *= lacunarity[k];
    }
  }
  for (int k = 0; k < n; ++k) {
    s0[k] = pmc_noise_sanitize(s0[k]);
    s1[k] = pmc_noise_sanitize(s1[k]);
    s2[k] = pmc_noise_sanitize(s2[k]);
  }
}

/* pmc_op_noise2d / pmc_op_noise3d for a batch (dims 2 or 3): out[c][k] is
 * component c of point k's result (4 components). */
PMC_FN void pmc_noise_lanes(int dims, const float* px, const float* py, const float* pz, pmc_u32 width, int n,
                            float out[4][PMC_LANES]) {
  float qx[PMC_LANES], qy[PMC_LANES], qz[PMC_LANES], w0[PMC_LANES], w1[PMC_LANES], w2[PMC_LANES];
  int bad[PMC_LANES];
  for (int k = 0; k < n; ++k) {
    bad[k] = !pmc_noise_finite(px[k]) || !pmc_noise_finite(py[k]) || (dims == 3 && !pmc_noise_finite(pz[k]));
    qx[k] = bad[k] ? 0.0f : px[k];
    qy[k] = bad[k] ? 0.0f : py[k];
    qz[k] = bad[k] || dims != 3 ? 0.0f : pz[k];
  }
  const int three = width > 1u;
  if (dims == 3)
    pmc_perlin3_lanes(qx, qy, qz, n, three, out[0], out[1], out[2]);
  else
    pmc_perlin2_lanes(qx, qy, n, three, out[0], out[1], out[2]);
  for (int k = 0; k < n; ++k) {
    if (!three) out[1][k] = out[2][k] = out[3][k] = out[0][k];
    if (width == 2u) out[2][k] = 0.0f;
    if (three) out[3][k] = 0.0f;
  }
  if (width >= 4u) { /* w: the float noise at an offset position */
    for (int k = 0; k < n; ++k) {
      qx[k] = bad[k] ? 0.0f : px[k] + 19.0f;
      qy[k] = bad[k] ? 0.0f : py[k] + 73.0f;
      qz[k] = bad[k] || dims != 3 ? 0.0f : pz[k] + 29.0f;
    }
    if (dims == 3)
      pmc_perlin3_lanes(qx, qy, qz, n, 0, w0, w1, w2);
    else
      pmc_perlin2_lanes(qx, qy, n, 0, w0, w1, w2);
    for (int k = 0; k < n; ++k) out[3][k] = w0[k];
  }
  for (int k = 0; k < n; ++k)
    if (bad[k]) out[0][k] = out[1][k] = out[2][k] = out[3][k] = 0.0f;
}

/* pmc_op_fractal2d / pmc_op_fractal3d for a batch (dims 2 or 3). */
PMC_FN void pmc_fractal_lanes(int dims, const float* px, const float* py, const float* pz, const int* octaves,
                              const float* lacunarity, const float* diminish, pmc_u32 width, int n,
                              float out[4][PMC_LANES]) {
  float qx[PMC_LANES], qy[PMC_LANES], qz[PMC_LANES], w0[PMC_LANES], w1[PMC_LANES], w2[PMC_LANES];
  int bad[PMC_LANES];
  for (int k = 0; k < n; ++k) {
    bad[k] = !pmc_noise_finite(px[k]) || !pmc_noise_finite(py[k]) ||
             (dims == 3 && !pmc_noise_finite(pz[k])) || !pmc_noise_finite(lacunarity[k]) ||
             !pmc_noise_finite(diminish[k]);
    qx[k] = bad[k] ? 0.0f : px[k];
    qy[k] = bad[k] ? 0.0f : py[k];
    qz[k] = bad[k] || dims != 3 ? 0.0f : pz[k];
  }
  const int three = width > 2u;
  pmc_fbm_lanes(dims, qx, qy, qz, octaves, lacunarity, diminish, n, three, out[0], out[1], out[2]);
  if (width <= 1u) {
    for (int k = 0; k < n; ++k) out[1][k] = out[2][k] = out[3][k] = out[0][k];
  } else {
    if (width == 2u || width >= 4u) { /* the second value: the float fractal at an offset position */
      for (int k = 0; k < n; ++k) {
        qx[k] = bad[k] ? 0.0f : px[k] + 19.0f;
        qy[k] = bad[k] ? 0.0f : py[k] + 193.0f;
        qz[k] = bad[k] || dims != 3 ? 0.0f : pz[k] + 17.0f;
      }
      pmc_fbm_lanes(dims, qx, qy, qz, octaves, lacunarity, diminish, n, 0, w0, w1, w2);
    }
    for (int k = 0; k < n; ++k) {
      if (width == 2u) {
        out[1][k] = w0[k];
        out[2][k] = 0.0f;
        out[3][k] = 0.0f;
      } else {
        out[3][k] = width >= 4u ? w0[k] : 0.0f;
      }
    }
  }
  for (int k = 0; k < n; ++k)
    if (bad[k]) out[0][k] = out[1][k] = out[2][k] = out[3][k] = 0.0f;
}

/* One candidate feature point at squared distance d of the point whose
 * three nearest so far are e0 <= e1 <= e2 (pmc_noise_worley_insert's chain as
 * selects, so that the loops over points vectorise); `nearest` says whether
 * it became the nearest. */
#define PMC_WORLEY_TAKE(d, e0, e1, e2, nearest) \
  {                                             \
    nearest = (d) < e0;                         \
    e2 = (d) < e1 ? e1 : ((d) < e2 ? (d) : e2); \
    e1 = nearest ? e0 : ((d) < e1 ? (d) : e1);  \
    e0 = nearest ? (d) : e0;                    \
  }

/* The worley cells' search of pmc_op_worley2d for a batch of finite points:
 * the three nearest squared distances and, with `cells` (some point has
 * style 1), the nearest feature's cell. The loop over points is the innermost
 * one, each cell offset an outer loop in the single-point form's order, so
 * that the compiler vectorises it (it does not vectorise a loop that holds
 * another). The nearest feature's cell is cx + pmc_noise_cell(floor(ox)) of
 * the nearest candidate's cell and offset, which the search keeps and
 * converts once at the end. */
PMC_FN void pmc_worley2_search_lanes(const float* px, const float* py, const float* jitter, int n, int cells,
                                     float* d0, float* d1, float* d2, pmc_u32* bx, pmc_u32* by) {
  pmc_u32 X[PMC_LANES], Y[PMC_LANES];
  float lx[PMC_LANES], ly[PMC_LANES], box[PMC_LANES], boy[PMC_LANES];
  for (int k = 0; k < n; ++k) {
    lx[k] = pmc_noise_floorfrac(px[k], &X[k]), ly[k] = pmc_noise_floorfrac(py[k], &Y[k]);
    d0[k] = d1[k] = d2[k] = 1e6f;
    bx[k] = X[k], by[k] = Y[k];
    box[k] = boy[k] = 0.0f;
  }
#define PMC_WORLEY2_CELL(TRACK)                                                               \
  for (int k = 0; k < n; ++k) {                                                               \
    const pmc_u32 cx = X[k] + (pmc_u32)i, cy = Y[k] + (pmc_u32)j;                             \
    const float ox = (pmc_noise_to01(pmc_noise_hash3(cx, cy, 0u)) - 0.5f) * jitter[k] + 0.5f; \
    const float oy = (pmc_noise_to01(pmc_noise_hash3(cx, cy, 1u)) - 0.5f) * jitter[k] + 0.5f; \
    const float dx = ((float)i + ox) - lx[k], dy = ((float)j + oy) - ly[k];                   \
    float e0 = d0[k], e1 = d1[k], e2 = d2[k];                                                 \
    int nearest;                                                                              \
    PMC_WORLEY_TAKE(dx* dx + dy * dy, e0, e1, e2, nearest)                                    \
    d0[k] = e0, d1[k] = e1, d2[k] = e2;                                                       \
    if (TRACK) {                                                                              \
      bx[k] = nearest ? cx : bx[k], by[k] = nearest ? cy : by[k];                             \
      box[k] = nearest ? ox : box[k], boy[k] = nearest ? oy : boy[k];                         \
    }                                                                                         \
  }
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j) {
      if (cells) {
        PMC_WORLEY2_CELL(1)
      } else {
        PMC_WORLEY2_CELL(0)
      }
    }
#undef PMC_WORLEY2_CELL
  if (cells) /* the own cell, offset 0, where no candidate was nearer than 1e6 */
    for (int k = 0; k < n; ++k) {
      bx[k] += pmc_noise_cell(floor(box[k]));
      by[k] += pmc_noise_cell(floor(boy[k]));
    }
}

/* The same for pmc_op_worley3d. */
PMC_FN void pmc_worley3_search_lanes(const float* px, const float* py, const float* pz, const float* jitter,
                                     int n, int cells, float* d0, float* d1, float* d2, pmc_u32* bx,
                                     pmc_u32* by, pmc_u32* bz) {
  pmc_u32 X[PMC_LANES], Y[PMC_LANES], Z[PMC_LANES];
  float lx[PMC_LANES], ly[PMC_LANES], lz[PMC_LANES], box[PMC_LANES], boy[PMC_LANES], boz[PMC_LANES];
  for (int k = 0; k < n; ++k) {
    lx[k] = pmc_noise_floorfrac(px[k], &X[k]), ly[k] = pmc_noise_floorfrac(py[k], &Y[k]);
    lz[k] = pmc_noise_floorfrac(pz[k], &Z[k]);
    d0[k] = d1[k] = d2[k] = 1e6f;
    bx[k] = X[k], by[k] = Y[k], bz[k] = Z[k];
    box[k] = boy[k] = boz[k] = 0.0f;
  }
#define PMC_WORLEY3_CELL(TRACK)                                                                           \
  for (int k = 0; k < n; ++k) {                                                                           \
    const pmc_u32 cx = X[k] + (pmc_u32)i, cy = Y[k] + (pmc_u32)j, cz = Z[k] + (pmc_u32)l;                 \
    const float ox = (pmc_noise_to01(pmc_noise_hash4(cx, cy, cz, 0u)) - 0.5f) * jitter[k] + 0.5f;         \
    const float oy = (pmc_noise_to01(pmc_noise_hash4(cx, cy, cz, 1u)) - 0.5f) * jitter[k] + 0.5f;         \
    const float oz = (pmc_noise_to01(pmc_noise_hash4(cx, cy, cz, 2u)) - 0.5f) * jitter[k] + 0.5f;         \
    const float dx = ((float)i + ox) - lx[k], dy = ((float)j + oy) - ly[k], dz = ((float)l + oz) - lz[k]; \
    float e0 = d0[k], e1 = d1[k], e2 = d2[k];                                                             \
    int nearest;                                                                                          \
    PMC_WORLEY_TAKE(dx* dx + dy * dy + dz * dz, e0, e1, e2, nearest)                                      \
    d0[k] = e0, d1[k] = e1, d2[k] = e2;                                                                   \
    if (TRACK) {                                                                                          \
      bx[k] = nearest ? cx : bx[k], by[k] = nearest ? cy : by[k], bz[k] = nearest ? cz : bz[k];           \
      box[k] = nearest ? ox : box[k], boy[k] = nearest ? oy : boy[k], boz[k] = nearest ? oz : boz[k];     \
    }                                                                                                     \
  }
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int l = -1; l <= 1; ++l) {
        if (cells) {
          PMC_WORLEY3_CELL(1)
        } else {
          PMC_WORLEY3_CELL(0)
        }
      }
#undef PMC_WORLEY3_CELL
  if (cells)
    for (int k = 0; k < n; ++k) {
      bx[k] += pmc_noise_cell(floor(box[k]));
      by[k] += pmc_noise_cell(floor(boy[k]));
      bz[k] += pmc_noise_cell(floor(boz[k]));
    }
}
#undef PMC_WORLEY_TAKE

/* pmc_op_worley2d / pmc_op_worley3d for a batch (dims 2 or 3; pz unused for
 * 2): out[c][k] is component c of point k's result, the single-point form's
 * value. Each point's jitter and style are its own. Scalar, one point's 9
 * (27) cells with 2 (3) hashes each made worley the costliest noise per
 * point by far (bench.node_costs); these loops run eight or sixteen points
 * per instruction. */
PMC_FN void pmc_worley_lanes(int dims, const float* px, const float* py, const float* pz, const float* jitter,
                             const int* style, pmc_u32 width, int n, float out[4][PMC_LANES]) {
  float qx[PMC_LANES], qy[PMC_LANES], qz[PMC_LANES], jit[PMC_LANES], d0[PMC_LANES], d1[PMC_LANES],
      d2[PMC_LANES];
  pmc_u32 bx[PMC_LANES], by[PMC_LANES], bz[PMC_LANES];
  int bad[PMC_LANES];
  for (int k = 0; k < n; ++k) {
    bad[k] = !pmc_noise_finite(px[k]) || !pmc_noise_finite(py[k]) ||
             (dims == 3 && !pmc_noise_finite(pz[k])) || !pmc_noise_finite(jitter[k]);
    qx[k] = bad[k] ? 0.0f : px[k];
    qy[k] = bad[k] ? 0.0f : py[k];
    qz[k] = bad[k] || dims != 3 ? 0.0f : pz[k];
    jit[k] = bad[k] ? 0.0f : jitter[k];
  }
  int cells = 0; /* some point wants the nearest feature's cell noise (style 1) */
  for (int k = 0; k < n; ++k) cells |= style[k] == 1;
  if (dims == 3) {
    pmc_worley3_search_lanes(qx, qy, qz, jit, n, cells, d0, d1, d2, bx, by, bz);
  } else {
    pmc_worley2_search_lanes(qx, qy, jit, n, cells, d0, d1, d2, bx, by);
    for (int k = 0; k < n; ++k) bz[k] = 0u;
  }
  for (int k = 0; k < n; ++k) {
    /* style 1: the cell noise of the nearest feature's cell (pmc_noise_worley_out) */
    float c0 = 0.0f, c1 = 0.0f, c2 = 0.0f;
    if (cells && dims == 3) {
      c0 = pmc_noise_to01(width <= 1u ? pmc_noise_hash3(bx[k], by[k], bz[k])
                                      : pmc_noise_hash4(bx[k], by[k], bz[k], 0u));
      c1 = pmc_noise_to01(pmc_noise_hash4(bx[k], by[k], bz[k], 1u));
      c2 = pmc_noise_to01(pmc_noise_hash4(bx[k], by[k], bz[k], 2u));
    } else if (cells) {
      c0 = pmc_noise_to01(width <= 1u ? pmc_noise_hash2(bx[k], by[k]) : pmc_noise_hash3(bx[k], by[k], 0u));
      c1 = pmc_noise_to01(pmc_noise_hash3(bx[k], by[k], 1u));
      c2 = pmc_noise_to01(pmc_noise_hash3(bx[k], by[k], 2u));
    }
    const float4 r = pmc_noise_worley_out(style[k], width, d0[k], d1[k], d2[k], c0, c1, c2);
    out[0][k] = bad[k] ? 0.0f : r.x;
    out[1][k] = bad[k] ? 0.0f : r.y;
    out[2][k] = bad[k] ? 0.0f : r.z;
    out[3][k] = bad[k] ? 0.0f : r.w;
  }
}

/* pmc_op_cellnoise2d / 3d for a batch. */
PMC_FN void pmc_cellnoise_lanes(int dims, const float* px, const float* py, const float* pz, int n,
                                float* out) {
  for (int k = 0; k < n; ++k) {
    int bad = !pmc_noise_finite(px[k]) || !pmc_noise_finite(py[k]) || (dims == 3 && !pmc_noise_finite(pz[k]));
    float x = bad ? 0.0f : px[k], y = bad ? 0.0f : py[k], z = bad || dims != 3 ? 0.0f : pz[k];
    pmc_u32 X = pmc_noise_cell(floor(x)), Y = pmc_noise_cell(floor(y)), Z = pmc_noise_cell(floor(z));
    pmc_u32 h = dims == 3 ? pmc_noise_hash3(X, Y, Z) : pmc_noise_hash2(X, Y);
    out[k] = bad ? 0.0f : pmc_noise_to01(h);
  }
}

#endif /* PMC_NOISE_H */
