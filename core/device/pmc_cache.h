/* pmc_cache.h — the progressive material cache: descriptors, hashes, value
 * encodings, lookup and insert. Shared by the kernels and host tests.
 *
 * A cacheable node's value at a shading point is stored as a texel of a
 * virtual mip-mapped texture (Fujieda and Harada 2022, sec. 3): the level
 * lambda = -log2(min(|g1|, |g2|)) + bias comes from the ray-cone uv gradients,
 * the texel is floor(uv * 2^lambda). The descriptor (material, node, lambda,
 * texel x, texel y) is hashed twice: h1 picks one of Nc cells, h2 is a 32-bit
 * fingerprint (never 0; 0 marks an empty entry). h1 is a hash of (material,
 * lambda, texel) plus the node's rank among its material's cache points, so
 * the points of one shading point sit in adjacent cells. A cell holds Ne 64-bit words
 * {fingerprint << 32 | encoded value}; an insert publishes one with a single
 * 64-bit compare-and-swap from 0, so readers never see a torn entry; on
 * collision the first value stays (the paper's Algorithm 1).
 *
 * Position keys (beyond the paper, which keys on uv only): a cache point whose
 * sub-graph reads the surface position and nothing else is keyed on a cell of
 * a 3D virtual grid instead: level lambda = -log2(r) + bias from the ray
 * cone's radius r at the hit in scene units (the footprint's minor half-axis,
 * as min(|g1|, |g2|) is in uv), cell floor(p * 2^lambda + 1/2) per axis
 * (cells centred on multiples of their width: see pmc_cache_cell_center). Its hash
 * has its own domain constant, so a uv texel and a position cell with equal
 * indices hash apart. Both kinds share the table, the fingerprints and the
 * policies; a material's group mixes them freely (the lookup's skip word
 * carries the kind in bit 31).
 *
 * Level floors (beyond the paper): a material whose patterns are finer than
 * the footprint raises the level to a floor from their bandwidth
 * (materials/bandwidth.h), or evaluates those points uncached when the floor
 * is too far above the footprint's level (pmc_cache_floored_level).
 *
 * Replacement policy (PmcCacheTable.policy, cache_policy):
 *  - keep-first (the paper's rule, the default): as above; a full cell drops
 *    the insert. The high word is the whole 32-bit fingerprint.
 *  - priority: the high word is {30 bits of fingerprint << 2 | depth tag},
 *    the tag min(depth, 3) of the inserting hit (0: a camera-ray hit, 1..3:
 *    that many surface hits before it, 3 or more). A camera insert that finds
 *    its cell full replaces the deepest non-camera entry (the first of equal
 *    tags) with one 64-bit CAS from the word it read; camera entries are never
 *    replaced, and deeper inserts never replace anything. The cost: the
 *    fingerprint loses its 2 low bits, so an absent key matches a given entry
 *    with probability 2^-30 instead of 2^-32: a lookup that misses in a full
 *    cell of 8 entries hits falsely with probability about 8 * 2^-30 = 7.5e-9
 *    (1.9e-9 with keep-first); tests/core/cache_policy_test.cpp measures the
 *    collision rate on real descriptors. Values keep all 32 bits.
 *
 * Encodings (32 bits): float as raw bits (exact); colour3/vector3 with
 * non-negative components as RGB9E5 (shared 5-bit exponent, 9-bit mantissas:
 * with M the largest channel, every channel's error is at most
 * max(M / 511.5, 2^-25): the largest channel is within 2^-9 M (0.2%) for
 * M >= 2^-16, the others within 2^-9 M * 1024/1023 (slightly more than
 * 2^-9 M when M rounds up to the next exponent); below 2^-16 the smallest
 * step 2^-24 bounds the error absolutely, and M < 2^-25 becomes black;
 * tests/core/cache_encoding_test.cpp derives this); vector2 as two IEEE
 * halves (relative error at most 2^-11 in the normal range, absolute
 * 2^-25 for subnormals). Values that cannot be encoded (negative colours,
 * NaN, Inf, beyond the format's range) are not inserted.
 */
#ifndef PMC_CACHE_H
#define PMC_CACHE_H

#include "../abi/pmc_vec.h"

#define PMC_LAMBDA_MIN (-16)
#define PMC_LAMBDA_MAX 40

/* Cache value encodings (the imm of CACHE_LOOKUP / CACHE_STORE, bits 8-9). */
#define PMC_ENC_FLOAT 0u
#define PMC_ENC_RGB9E5 1u
#define PMC_ENC_HALF2 2u

/* Statistics counters: the one list of them. X(NAME, key, meaning):
 * PMC_CSTAT_<NAME> indexes the counter buffer (the list's order is the
 * buffer's layout: append new counters at the end), `key` names the host's
 * CacheStats field (gpu/wavefront_renderer.h) and the key in the stats
 * JSON's "cache" object, `meaning` says what it counts. Every lookup is a
 * hit or a miss, and every miss ends in exactly one of inserts (into an
 * empty entry), replaced, already_present, dropped_full (cell full) or
 * not_encodable. Bypassed points are no lookups. */
// clang-format off
#define PMC_CACHE_COUNTERS(X)                                                                         \
  X(LOOKUPS, lookups, "cache lookups")                                                                \
  X(HITS, hits, "lookups that found their key")                                                       \
  X(INSERTS, inserts, "misses inserted into an empty entry")                                          \
  X(DROPPED_FULL, dropped_full, "misses not inserted: their cell was full")                           \
  X(NOT_ENCODABLE, not_encodable, "misses whose value the encoding cannot hold (not inserted)")       \
  X(MISSES, misses, "lookups that found nothing")                                                     \
  X(ALREADY_PRESENT, already_present, "inserts that found the key (another work-item won)")           \
  X(REPLACED, replaced, "priority policy: camera inserts that replaced a deeper entry")               \
  X(CAMERA_LOOKUPS, camera_lookups, "lookups at camera-ray hits (depth 0)")                           \
  X(CAMERA_HITS, camera_hits, "camera lookups that hit")                                              \
  X(POSITION_LOOKUPS, position_lookups, "lookups of position-keyed points (the rest are uv-keyed)")   \
  X(POSITION_HITS, position_hits, "position lookups that hit")                                        \
  X(BYPASSED, bypassed, "points evaluated without the cache: their level floor was more than the "    \
                        "refinement limit above the footprint's")
// clang-format on
#define PMC_CSTAT_ENUMERATOR_(NAME, key, meaning) PMC_CSTAT_##NAME,
enum { PMC_CACHE_COUNTERS(PMC_CSTAT_ENUMERATOR_) PMC_CSTAT_COUNT };
#undef PMC_CSTAT_ENUMERATOR_

/* Replacement policies (PmcCacheTable.policy). */
#define PMC_CACHE_KEEP_FIRST 0u
#define PMC_CACHE_PRIORITY 1u

/* ---- virtual mip level and texel indices --------------------------------- */

/* Whether a bias takes pmc_cache_level_integral (as (int)bias). */
PMC_FN_INLINE int pmc_cache_bias_integral(float bias) {
  float b = isfinite(bias) ? bias : 0.0f;
  return b == floor(b) && fabs(b) <= 64.0f;
}

/* pmc_cache_level for an integral bias: integer work and selects only, so
 * a loop of it over a batch's lanes vectorises (pmc_cache_texels_lanes). */
PMC_FN_INLINE int pmc_cache_level_integral(float m, int bias) {
  int bits = as_int(m);
  int biased_exponent = (bits >> 23) & 0xff; /* 0: subnormal, -log2(m) > 126 */
  int level = biased_exponent == 0 ? 127 : (127 - biased_exponent) - ((bits & 0x7fffff) != 0 ? 1 : 0);
  level = (m > 0.0f && isfinite(m) ? level : PMC_LAMBDA_MAX) + bias;
  return level < PMC_LAMBDA_MIN ? PMC_LAMBDA_MIN : (level > PMC_LAMBDA_MAX ? PMC_LAMBDA_MAX : level);
}

/* Integer virtual mip level floor(-log2(m) + bias) of a footprint of size m
 * (pmc_cache_lambda: m = min(|g1|, |g2|) from the uv gradients; position
 * keys: the cone radius in scene units); always finite and clamped. Degenerate footprints
 * (zero-area uv triangles, no cone, |g| overflowing or underflowing float)
 * use the finest level so distinct points never share a coarse texel by
 * accident. Lengths are sqrt(x^2 + y^2) on both sides (an overflow-safe
 * library length() on the device would disagree with the host at 1e30).
 * With an integral bias (the usual case) the level comes exactly from m's
 * exponent bits: floor(-log2(m)) = -E - (mantissa != 0) for m = 1.f * 2^E;
 * a library log2 cost about as much as the rest of a lookup on PoCL. */
PMC_FN_INLINE int pmc_cache_level(float m, float bias) {
  float b = isfinite(bias) ? bias : 0.0f;
  if (pmc_cache_bias_integral(b)) return pmc_cache_level_integral(m, (int)b);
  float lambda = (m > 0.0f && isfinite(m)) ? -log2(m) : (float)PMC_LAMBDA_MAX;
  lambda += b;
  if (!(lambda > (float)PMC_LAMBDA_MIN)) lambda = (float)PMC_LAMBDA_MIN; /* also NaN */
  if (lambda > (float)PMC_LAMBDA_MAX) lambda = (float)PMC_LAMBDA_MAX;
  return (int)floor(lambda);
}

/* The footprint size m of pmc_cache_lambda. */
PMC_FN_INLINE float pmc_cache_gradient_size(float2 g1, float2 g2) {
  float l1 = sqrt(g1.x * g1.x + g1.y * g1.y), l2 = sqrt(g2.x * g2.x + g2.y * g2.y);
  float m = fmin(l1, l2);
  return !(m > 0.0f) || !isfinite(m) ? fmax(l1, l2) : m;
}

PMC_FN int pmc_cache_lambda(float2 g1, float2 g2, float bias) {
  return pmc_cache_level(pmc_cache_gradient_size(g1, g2), bias);
}

/* 2^e for an integer e in [-126, 127], exactly, from the exponent bits (a
 * library exp2 costs tens of instructions and sits on every lookup's path). */
PMC_FN float pmc_exp2i(int e) { return as_float((e + 127) << 23); }

/* floor(u * 2^lambda + offset) as a 64-bit integer without overflow or UB.
 * The offset is in [-0.5, 0.5): 0 gives the texel under u; a uniform random
 * offset gives stochastic bilinear selection (between the two texels whose
 * centres bracket u, the farther one is picked with probability equal to its
 * bilinear weight, so the mean over samples is the bilinear interpolation of
 * the texel values). Beyond
 * +-2^62 (uv ~1e7 at level 40 is 1e19) the float is already an integer and
 * the index is +-(2^62 + its bit pattern): still one key per distinct float
 * (and ordered), never an in-range index, at most 2^62 + 2^31 in magnitude.
 * NaN maps to 0. */
#define PMC_CACHE_BIG_INDEX ((long)4611686018427387904L) /* 2^62: indices from here on hold the float */

PMC_FN long pmc_cache_texel_jittered(float u, int lambda, float offset) {
  float s = u * pmc_exp2i(lambda) + offset;
  float f = floor(s);
  const float lim = 4.6116860184e18f; /* 2^62 */
  if (isnan(f)) return 0L;
  if (!(f > -lim && f < lim)) {
    long k = PMC_CACHE_BIG_INDEX + (long)(pmc_u32)as_int(fabs(f));
    return f < 0.0f ? -k : k;
  }
  return (long)f;
}

PMC_FN long pmc_cache_texel(float u, int lambda) { return pmc_cache_texel_jittered(u, lambda, 0.0f); }

/* Centre of a texel, in uv (for cache_eval center); always finite. Beyond
 * +-2^62 the index holds the float itself (see above): give back that uv
 * (the largest float for the texel of the infinite uvs). */
PMC_FN float pmc_cache_texel_center(long texel, int lambda) {
  const long big = PMC_CACHE_BIG_INDEX;
  if (texel >= big || texel <= -big) {
    float f = as_float((int)(pmc_u32)((texel < 0 ? -texel : texel) - big));
    float c = f * pmc_exp2i(-lambda);
    if (!isfinite(c)) c = 3.4028234664e38f;
    return texel < 0 ? -c : c;
  }
  return ((float)texel + 0.5f) * pmc_exp2i(-lambda);
}

/* Texture footprint (uv diameter) for a cache_eval center miss: what the
 * ray cone gives at this level without the mip bias, 2 * 2^-(lambda - bias)
 * (callers pass the footprint's level, not one raised to a level floor).
 * It depends on the level alone, so the stored value does not depend on the
 * inserting hit, and a positive bias refines the texel grid (position error)
 * without sharpening textures beyond what the cacheless render filters. */
PMC_FN float pmc_cache_texel_footprint(int lambda, float bias) {
  float b = isfinite(bias) ? bias : 0.0f;
  float f = 2.0f * exp2(-((float)lambda - b));
  return isfinite(f) ? f : 0.0f;
}

/* ---- hashing --------------------------------------------------------------- */

PMC_FN pmc_u64 pmc_mix64(pmc_u64 x) { /* splitmix64 finaliser */
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9UL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebUL;
  x ^= x >> 31;
  return x;
}

typedef struct PmcCacheKey {
  pmc_u64 h1; /* cell hash */
  pmc_u32 fingerprint;
} PmcCacheKey;

/* The part of the key that depends on the texel alone (level and indices).
 * Every cache point of one evaluation shares it, so the interpreter hashes
 * the texel once per shading point and each lookup adds only its material
 * and node (pmc_cache_key_at). */
PMC_FN pmc_u64 pmc_cache_texel_hash(int lambda, long tx, long ty) {
  pmc_u64 a = pmc_mix64(((pmc_u64)(pmc_u32)(lambda + 64) << 48) ^ 0x2545f4914f6cdd1dUL);
  pmc_u64 b = pmc_mix64(a ^ (pmc_u64)tx);
  return pmc_mix64(b ^ ((pmc_u64)ty * 0x9e3779b97f4a7c15UL));
}

/* The cell hash of a material's cache group at a texel: its k-th cache point
 * (the k-th lookup of the group, `rank`) lives in cell h1 = base + k (mod
 * Nc). Different texels get independent bases, so cells fill as evenly as
 * with one hash per point, but the points of one evaluation sit in adjacent
 * cells: the shade kernel can fetch them all before the interpreter needs
 * them (pmc_shade's prefetch pass), and they share memory pages. */
PMC_FN pmc_u64 pmc_cache_group_base(pmc_u64 texel_hash, pmc_u32 material) {
  return pmc_mix64(texel_hash ^ ((pmc_u64)material << 32) ^ 0x6a09e667f3bcc909UL);
}

/* The key of cache point `node` (rank `rank` in its material's group).
 * (material, node) is injective into the 64 bits XORed with the texel hash
 * (node ids are 14 bits), and pmc_mix64 is a bijection, so two descriptors
 * share the fingerprint's source word only if their texel hashes differ by
 * exactly the XOR of their (material, node) words: about 2^-64 for any pair. */
PMC_FN PmcCacheKey pmc_cache_key_at(pmc_u64 texel_hash, pmc_u64 group_base, pmc_u32 material, pmc_u32 node,
                                    pmc_u32 rank) {
  PmcCacheKey k;
  k.h1 = group_base + (pmc_u64)rank;
  pmc_u64 c = pmc_mix64(texel_hash ^ ((pmc_u64)material << 32) ^ (pmc_u64)node);
  pmc_u64 d = pmc_mix64(c ^ 0xd6e8feb86659fd93UL);
  pmc_u32 fp = (pmc_u32)(d >> 32);
  k.fingerprint = fp == 0u ? 1u : fp;
  return k;
}

PMC_FN PmcCacheKey pmc_cache_key(pmc_u32 material, pmc_u32 node, pmc_u32 rank, int lambda, long tx, long ty) {
  pmc_u64 th = pmc_cache_texel_hash(lambda, tx, ty);
  return pmc_cache_key_at(th, pmc_cache_group_base(th, material), material, node, rank);
}

/* Everything about one shading point's texel that its cache points share. */
typedef struct PmcCacheTexel {
  pmc_u64 hash;         /* pmc_cache_texel_hash */
  pmc_u64 base;         /* pmc_cache_group_base */
  long tx, ty;          /* texel indices */
  long tz;              /* position cells: the third index (0 for uv texels) */
  int lambda;           /* virtual mip level (the footprint's, raised to the level floor) */
  int footprint_lambda; /* the footprint's level alone (texture filtering in center mode) */
  pmc_u32 bypass;       /* the floor is too far above the footprint's level: evaluate uncached */
  pmc_u32 ready;        /* the fields above are filled */
} PmcCacheTexel;

/* Level floors (beyond the paper; materials/bandwidth.h computes them): a
 * cache point whose pattern has features of size w (in key units) needs
 * texels of at most w / 2, level >= ceil(log2(2 / w)), or its texel's one
 * value stands for a footprint the pattern changes inside, and the cached
 * image aliases where the cacheless one averages. The level is then
 * max(footprint level, floor). Raising it by d levels splits a footprint into
 * 4^d texels (8^d cells) and divides the hits accordingly; beyond
 * `max_refine` levels the point is evaluated without the cache (bypass).
 * PMC_LEVEL_NO_FLOOR: no floor. */
#define PMC_LEVEL_NO_FLOOR PMC_LAMBDA_MIN
PMC_FN int pmc_cache_floored_level(int lambda, int level_floor, int max_refine, pmc_u32* bypass) {
  *bypass = 0u;
  if (level_floor <= lambda) return lambda;
  if (level_floor - lambda > max_refine) *bypass = 1u;
  return level_floor > PMC_LAMBDA_MAX ? PMC_LAMBDA_MAX : level_floor;
}

/* The texel of a shading point: level from the ray-cone gradients and the
 * mip bias, indices of uv * 2^lambda + jitter (see pmc_cache_texel_jittered). */
PMC_FN_INLINE PmcCacheTexel pmc_cache_texel_floored(float2 uv, float2 g1, float2 g2, float bias,
                                                    float2 jitter, pmc_u32 material, int level_floor,
                                                    int max_refine) {
  PmcCacheTexel t;
  t.footprint_lambda = pmc_cache_lambda(g1, g2, bias);
  t.lambda = pmc_cache_floored_level(t.footprint_lambda, level_floor, max_refine, &t.bypass);
  t.tx = pmc_cache_texel_jittered(uv.x, t.lambda, jitter.x);
  t.ty = pmc_cache_texel_jittered(uv.y, t.lambda, jitter.y);
  t.tz = 0L;
  t.hash = pmc_cache_texel_hash(t.lambda, t.tx, t.ty);
  t.base = pmc_cache_group_base(t.hash, material);
  t.ready = 1u;
  return t;
}

PMC_FN PmcCacheTexel pmc_cache_texel_of(float2 uv, float2 g1, float2 g2, float bias, float2 jitter,
                                        pmc_u32 material) {
  return pmc_cache_texel_floored(uv, g1, g2, bias, jitter, material, PMC_LEVEL_NO_FLOOR, 0);
}

/* The hash of a position cell (level and three indices): a domain constant
 * of its own, so it never equals the texel hash of a uv texel by design. */
PMC_FN pmc_u64 pmc_cache_cell3_hash(int lambda, long tx, long ty, long tz) {
  pmc_u64 a = pmc_mix64(((pmc_u64)(pmc_u32)(lambda + 64) << 48) ^ 0x8c2d5f0e1b3a7d49UL);
  pmc_u64 b = pmc_mix64(a ^ (pmc_u64)tx);
  pmc_u64 c = pmc_mix64(b ^ ((pmc_u64)ty * 0x9e3779b97f4a7c15UL));
  return pmc_mix64(c ^ ((pmc_u64)tz * 0xc2b2ae3d27d4eb4fUL));
}

/* The position cell of a shading point: level from the ray cone's radius at
 * the hit (scene units) and the mip bias, indices of p * 2^lambda + 1/2 +
 * jitter per axis (uniform offsets in [-0.5, 0.5) give stochastic trilinear
 * selection, as they give bilinear selection for uv). The half cell centres
 * cell k on k * 2^-lambda: a plane at a grid-aligned coordinate (y = 0, x =
 * 2) lies mid-layer, so the rounding of its hit points (2 +- 1 ulp) keeps
 * one layer of cells, and centre evaluation reads the plane itself. */
PMC_FN_INLINE PmcCacheTexel pmc_cache_cell_floored(float3 p, float radius, float bias, float4 jitter,
                                                   pmc_u32 material, int level_floor, int max_refine) {
  PmcCacheTexel t;
  t.footprint_lambda = pmc_cache_level(radius, bias);
  t.lambda = pmc_cache_floored_level(t.footprint_lambda, level_floor, max_refine, &t.bypass);
  t.tx = pmc_cache_texel_jittered(p.x, t.lambda, jitter.x + 0.5f);
  t.ty = pmc_cache_texel_jittered(p.y, t.lambda, jitter.y + 0.5f);
  t.tz = pmc_cache_texel_jittered(p.z, t.lambda, jitter.z + 0.5f);
  t.hash = pmc_cache_cell3_hash(t.lambda, t.tx, t.ty, t.tz);
  t.base = pmc_cache_group_base(t.hash, material);
  t.ready = 1u;
  return t;
}

/* The selection offset (in cells) of a position point for stochastic
 * trilinear selection: (ju, jv) in [-0.5, 0.5)^2 along an orthonormal basis
 * of the tangent plane of the surface with normal n (Duff et al.'s branchless
 * basis), nothing along n. A 3D offset also chose cells in front of and
 * behind the surface, whose centres lie up to a cell off it: on
 * data/default/room.obj with solid_materials.mtlx (axis-aligned walls) the
 * in-plane offset took the hit rate at 640x360, 16 spp from 74.3 to 85.8%
 * and the bias at 320x180, 256 spp from 42.6 to 50.3 dB (worst 16x16 tile
 * 30.9 -> 40.9 dB); on the marble sphere hits 75.1 -> 81.4%, bias 48.5 ->
 * 48.2 dB (worst tile 37.5 -> 35.4 dB). A zero or non-finite n gives no offset.
 * A unit n (the kernel's geometric normals) skips the rescaling, whose two
 * divisions and square root cost the solid room 2-3% of its cached render. */
PMC_FN float4 pmc_cache_plane_jitter(float3 n, float ju, float jv) {
  const float len2 = dot(n, n);
  if (!(fabs(len2 - 1.0f) < 1e-5f)) { /* not already a unit vector (the kernel's normals are) */
    const float m = fmax(fabs(n.x), fmax(fabs(n.y), fabs(n.z))); /* scaled first: tiny and huge n */
    if (!(m > 0.0f) || !isfinite(m) || isnan(n.x + n.y + n.z)) return make_float4(0.0f, 0.0f, 0.0f, 0.0f);
    n = n * (1.0f / m);
    n = n * (1.0f / sqrt(dot(n, n)));
  }
  const float sg = n.z >= 0.0f ? 1.0f : -1.0f;
  const float a = -1.0f / (sg + n.z), b = n.x * n.y * a;
  const float3 t1 = make_float3(1.0f + sg * n.x * n.x * a, sg * b, -sg * n.x);
  const float3 t2 = make_float3(b, sg + n.y * n.y * a, -n.y);
  const float3 j = ju * t1 + jv * t2;
  return make_float4(j.x, j.y, j.z, 0.0f);
}

/* Centre of a position cell index (pmc_cache_cell_floored): k * 2^-lambda;
 * always finite (beyond +-2^62 as pmc_cache_texel_center). */
PMC_FN float pmc_cache_cell_center(long cell, int lambda) {
  if (cell >= PMC_CACHE_BIG_INDEX || cell <= -PMC_CACHE_BIG_INDEX)
    return pmc_cache_texel_center(cell, lambda);
  return (float)cell * pmc_exp2i(-lambda);
}

PMC_FN PmcCacheTexel pmc_cache_cell_of(float3 p, float radius, float bias, float4 jitter, pmc_u32 material) {
  return pmc_cache_cell_floored(p, radius, bias, jitter, material, PMC_LEVEL_NO_FLOOR, 0);
}

/* The CACHE_LOOKUP skip word: bit 31 marks a position-keyed point. */
#define PMC_CACHE_KEY_POSITION 0x80000000u

/* ---- encodings --------------------------------------------------------------- */

PMC_FN pmc_u32 pmc_float_bits(float f) { return (pmc_u32)as_int(f); }
PMC_FN float pmc_bits_float(pmc_u32 u) { return as_float((int)u); }

/* RGB9E5 (shared exponent, bias 15, 9-bit mantissas). Only non-negative
 * finite values up to 65408 = (511/512) * 2^16 can be encoded (NaN fails). */
PMC_FN int pmc_rgb9e5_encodable(float r, float g, float b) {
  return r >= 0.0f && g >= 0.0f && b >= 0.0f && fmax(r, fmax(g, b)) <= 65408.0f;
}
/* Returns 0xffffffff when the value cannot be encoded; that word is ALSO the
 * valid encoding of the brightest grey (all mantissas 511 at the top
 * exponent, e.g. 65365..65408 in every channel), so callers must test
 * pmc_rgb9e5_encodable(), not compare with PMC_RGB9E5_INVALID. */
#define PMC_RGB9E5_INVALID 0xffffffffu
PMC_FN pmc_u32 pmc_encode_rgb9e5(float r, float g, float b) {
  if (!pmc_rgb9e5_encodable(r, g, b)) return PMC_RGB9E5_INVALID;
  float m = fmax(r, fmax(g, b));
  if (m < 1.52587890625e-05f * (1.0f / 512.0f)) return 0u; /* below the smallest step: zero */
  /* e = floor(log2(m)), exactly, from the exponent bits: m in [2^e, 2^(e+1)).
   * (A library log2 may round just below a power of two up to it, and
   * differs between the host and OpenCL devices.) */
  int e = ((as_int(m) >> 23) & 0xff) - 127;
  if (e < -16) e = -16;   /* also subnormal m */
  int exp_shared = e + 1; /* mantissas < 512 */
  float scale = pmc_exp2i(9 - exp_shared);
  int mm = (int)floor(m * scale + 0.5f);
  if (mm == 512) {
    exp_shared += 1;
    scale *= 0.5f;
  }
  pmc_u32 rm = (pmc_u32)floor(r * scale + 0.5f), gm = (pmc_u32)floor(g * scale + 0.5f),
          bm = (pmc_u32)floor(b * scale + 0.5f);
  rm = rm > 511u ? 511u : rm;
  gm = gm > 511u ? 511u : gm;
  bm = bm > 511u ? 511u : bm;
  return rm | (gm << 9) | (bm << 18) | ((pmc_u32)(exp_shared + 15) << 27);
}

PMC_FN float4 pmc_decode_rgb9e5(pmc_u32 v) {
  int e = (int)(v >> 27) - 15;
  float scale = pmc_exp2i(e - 9);
  return make_float4((float)(v & 511u) * scale, (float)((v >> 9) & 511u) * scale,
                     (float)((v >> 18) & 511u) * scale, 0.0f);
}

/* IEEE half from float (round to nearest even), and back; no NaN/Inf inputs. */
PMC_FN pmc_u32 pmc_float_to_half(float f) {
  pmc_u32 x = pmc_float_bits(f);
  pmc_u32 sign = (x >> 16) & 0x8000u;
  pmc_u32 mag = x & 0x7fffffffu;
  if (mag >= 0x477ff000u) return sign | 0x7bffu; /* clamp to the largest half */
  if (mag < 0x33000000u) return sign;            /* underflow to signed zero */
  if (mag < 0x38800000u) {                       /* subnormal half */
    pmc_u32 shift = 113u - (mag >> 23);
    pmc_u32 m = (mag & 0x7fffffu) | 0x800000u;
    pmc_u32 h = m >> (shift + 13u);
    pmc_u32 rem = m & ((1u << (shift + 13u)) - 1u);
    pmc_u32 half_bit = 1u << (shift + 12u);
    if (rem > half_bit || (rem == half_bit && (h & 1u))) h += 1u;
    return sign | h;
  }
  pmc_u32 h = ((mag - 0x38000000u) >> 13);
  pmc_u32 rem = mag & 0x1fffu;
  if (rem > 0x1000u || (rem == 0x1000u && (h & 1u))) h += 1u;
  return sign | h;
}

PMC_FN float pmc_half_to_float(pmc_u32 h) {
  pmc_u32 sign = (h & 0x8000u) << 16;
  pmc_u32 e = (h >> 10) & 31u, m = h & 1023u;
  if (e == 0u) {
    float f = (float)m * 5.9604644775390625e-8f; /* 2^-24 */
    return sign ? -f : f;
  }
  return pmc_bits_float(sign | ((e + 112u) << 23) | (m << 13));
}

/* Encode `v` for `enc`; returns 0 and leaves *out untouched when it cannot. */
PMC_FN int pmc_cache_encode(float4 v, pmc_u32 enc, pmc_u32* out) {
  if (enc == PMC_ENC_FLOAT) {
    if (!isfinite(v.x)) return 0;
    *out = pmc_float_bits(v.x);
    return 1;
  }
  if (enc == PMC_ENC_RGB9E5) {
    if (!pmc_rgb9e5_encodable(v.x, v.y, v.z)) return 0;
    *out = pmc_encode_rgb9e5(v.x, v.y, v.z);
    return 1;
  }
  if (!(isfinite(v.x) && isfinite(v.y)) || fabs(v.x) > 65504.0f || fabs(v.y) > 65504.0f) return 0;
  *out = pmc_float_to_half(v.x) | (pmc_float_to_half(v.y) << 16);
  return 1;
}

PMC_FN float4 pmc_cache_decode(pmc_u32 bits, pmc_u32 enc) {
  if (enc == PMC_ENC_FLOAT) {
    float f = pmc_bits_float(bits);
    return make_float4(f, f, f, f);
  }
  if (enc == PMC_ENC_RGB9E5) return pmc_decode_rgb9e5(bits);
  return make_float4(pmc_half_to_float(bits & 0xffffu), pmc_half_to_float(bits >> 16), 0.0f, 0.0f);
}

/* ---- the table ---------------------------------------------------------------- */

#ifdef __OPENCL_VERSION__
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#define PMC_CACHE_PTR __global volatile ulong*
PMC_FN pmc_u64 pmc_cas64(PMC_CACHE_PTR p, pmc_u64 expected, pmc_u64 desired) {
  return atom_cmpxchg(p, expected, desired);
}
PMC_FN pmc_u64 pmc_load64(PMC_CACHE_PTR p) { return *p; }
#else
#define PMC_CACHE_PTR pmc_u64*
PMC_FN pmc_u64 pmc_cas64(pmc_u64* p, pmc_u64 expected, pmc_u64 desired) {
  __atomic_compare_exchange_n(p, &expected, desired, false, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE);
  return expected; /* the previous value, as OpenCL's atom_cmpxchg returns */
}
/* Host-side counter bump (the kernels count privately and sum per work-group). */
PMC_FN void pmc_stat_add(pmc_u64* stats, int which) {
  if (stats) __atomic_fetch_add(&stats[which], 1ull, __ATOMIC_RELAXED);
}
/* Entries are read while other threads may CAS them: an atomic load on the
 * host (a plain read racing with the CAS is a data race in C++). */
PMC_FN pmc_u64 pmc_load64(pmc_u64* p) { return __atomic_load_n(p, __ATOMIC_ACQUIRE); }
#endif

typedef struct PmcCacheTable {
  PMC_CACHE_PTR entries; /* cells * ways words */
  pmc_u64 cells;
  pmc_u32 ways;
  pmc_u32 policy; /* PMC_CACHE_KEEP_FIRST or PMC_CACHE_PRIORITY */
} PmcCacheTable;

/* Cell index: h1 % Nc (a mask when Nc is a power of two, as auto-sizing picks). */
PMC_FN pmc_u64 pmc_cache_cell(const PmcCacheTable* t, pmc_u64 h1) {
  return (t->cells & (t->cells - 1ul)) == 0ul ? (h1 & (t->cells - 1ul)) : (h1 % t->cells);
}

/* Priority entries: the fingerprint's top 30 bits (never 0, so no entry is
 * the empty word) above the 2-bit depth tag. */
PMC_FN pmc_u32 pmc_cache_fp30(pmc_u32 fingerprint) {
  pmc_u32 f = fingerprint >> 2;
  return f == 0u ? 1u : f;
}
PMC_FN pmc_u32 pmc_cache_depth_tag(pmc_u32 depth) { return depth < 3u ? depth : 3u; }

/* The high word an entry of key `k` has (priority: with any tag, so the
 * comparison masks the tag off): entry e holds k iff ((e >> 32) & mask) == want. */
PMC_FN pmc_u32 pmc_cache_match_mask(const PmcCacheTable* t) {
  return t->policy == PMC_CACHE_PRIORITY ? 0xfffffffcu : 0xffffffffu;
}
PMC_FN pmc_u32 pmc_cache_match_word(const PmcCacheTable* t, PmcCacheKey k) {
  return t->policy == PMC_CACHE_PRIORITY ? pmc_cache_fp30(k.fingerprint) << 2 : k.fingerprint;
}

/* A cell is read PMC_CELL_CHUNK words at a time, every load of a chunk issued
 * before any is looked at. Scanning word by word with an early exit costs one
 * memory round trip per word: on a GPU each is hundreds of cycles at a random
 * address, and a lookup that hits in the fourth word waited four times (on an
 * H200, 8 words at a time cut the default scene's shade stage at 1080p from
 * 1.60 to 0.36 s). On a CPU the words share a cache line and the early exit
 * wins (8 at a time: shade +4% on PoCL), so the host build sets 1 there
 * (gpu/wave_kernels.cpp), and with it PMC_CELL_VECTOR: a cell of 8
 * entries compared in one vector operation (pmc_cache_lookup). The device
 * reads plain (not volatile) words: a stale word reads as an older state of
 * the cell, which is empty or the same entry, so at worst a lookup misses
 * (and evaluates) or an insert's CAS fails and it goes on from the value the
 * CAS returns. */
#ifndef PMC_CELL_CHUNK
#define PMC_CELL_CHUNK 8
#endif
#ifdef __OPENCL_VERSION__
#define PMC_CELL_WORD(t, i) (((__global const ulong*)(t)->entries)[i])
#else
#define PMC_CELL_WORD(t, i) pmc_load64(&(t)->entries[i])
#endif

/* Words [i0, i0 + PMC_CELL_CHUNK) of the cell at `base` (0 past its end). */
PMC_FN void pmc_cache_read_chunk(const PmcCacheTable* t, pmc_u64 base, pmc_u32 i0,
                                 pmc_u64 w[PMC_CELL_CHUNK]) {
  for (pmc_u32 j = 0; j < PMC_CELL_CHUNK; ++j)
    w[j] = i0 + j < t->ways ? PMC_CELL_WORD(t, base + i0 + j) : 0ul;
}

/* Lookup: 1 and the encoded value on a hit. Entries fill from the front and
 * are never emptied (priority replaces one non-empty word by another), so the
 * first empty entry ends the scan. */
PMC_FN int pmc_cache_lookup(const PmcCacheTable* t, PmcCacheKey k, pmc_u32* value) {
  pmc_u64 base = pmc_cache_cell(t, k.h1) * (pmc_u64)t->ways;
  pmc_u32 mask = pmc_cache_match_mask(t), want = pmc_cache_match_word(t, k);
#if defined(__OPENCL_VERSION__) && defined(PMC_CELL_VECTOR) && PMC_CELL_VECTOR
  /* CPU devices (PMC_CELL_VECTOR=1, set by the host): a cell of 8 entries
   * is one cache line, compared in one vector operation. The word-by-word
   * scan's exit lands on a different entry from lookup to lookup, a branch
   * the core mispredicts; here the only branch is hit or miss. Empty words
   * never match (no fingerprint is 0) and a key sits in a cell once; the
   * first match is taken all the same, as the scan would. */
  if (t->ways == 8u) {
    const ulong8 w = vload8(0, ((__global const ulong*)t->entries) + base);
    const int8 match = (convert_uint8(w >> (ulong8)32) & (uint8)mask) == (uint8)want;
    if (!any(match)) return 0;
    const int8 at = select((int8)8, (int8)(0, 1, 2, 3, 4, 5, 6, 7), match);
    const int4 at4 = min(at.lo, at.hi);
    const int2 at2 = min(at4.lo, at4.hi);
    uint words[8];
    vstore8(convert_uint8(w), 0, words); /* each entry's low word: its value */
    *value = words[min(at2.x, at2.y)];
    return 1;
  }
#endif
  for (pmc_u32 i0 = 0; i0 < t->ways; i0 += PMC_CELL_CHUNK) {
    pmc_u64 w[PMC_CELL_CHUNK];
    pmc_cache_read_chunk(t, base, i0, w);
    for (pmc_u32 j = 0; j < PMC_CELL_CHUNK; ++j) {
      if (w[j] == 0ul) return 0;
      if (((pmc_u32)(w[j] >> 32) & mask) == want) {
        *value = (pmc_u32)w[j];
        return 1;
      }
    }
  }
  return 0;
}

/* Insert (Algorithm 1): publish {fingerprint, value} in the first empty entry
 * with one 64-bit CAS; if the fingerprint is already there the first value
 * stays. Returns 1 inserted, 0 already present, -1 cell full (dropped). */
PMC_FN int pmc_cache_insert_keep_first(const PmcCacheTable* t, PmcCacheKey k, pmc_u32 value) {
  pmc_u64 base = pmc_cache_cell(t, k.h1) * (pmc_u64)t->ways;
  pmc_u64 word = ((pmc_u64)k.fingerprint << 32) | (pmc_u64)value;
  for (pmc_u32 i0 = 0; i0 < t->ways; i0 += PMC_CELL_CHUNK) {
    pmc_u64 w[PMC_CELL_CHUNK];
    pmc_cache_read_chunk(t, base, i0, w);
    for (pmc_u32 j = 0; j < PMC_CELL_CHUNK && i0 + j < t->ways; ++j) {
      pmc_u64 e = w[j];
      if (e == 0ul) {
        pmc_u64 prev = pmc_cas64(&t->entries[base + i0 + j], 0ul, word);
        if (prev == 0ul) return 1;
        e = prev; /* somebody else won this entry: look at what they wrote */
      }
      if ((pmc_u32)(e >> 32) == k.fingerprint) return 0;
    }
  }
  return -1;
}

/* Insert with the priority policy, from a hit after `depth` surface hits.
 * Each pass scans the cell: the key found ends it (0); the first empty entry
 * gets the word by a CAS from 0 (1); in a full cell a camera insert CASes the
 * deepest non-camera entry from the word the pass read (2), anything else is
 * dropped (-1). A lost CAS means the cell changed since the pass read it:
 * the next pass sees the change (the winner may have been this very key).
 * A word changes at most twice (empty -> entry, non-camera -> camera entry),
 * so at most 2 * ways CASes of a cell can fail: the loop ends. Two inserts of
 * one key cannot both succeed: each pass reads every word it does not CAS,
 * and words only move forward, so the later CAS finds its word changed. */
PMC_FN int pmc_cache_insert_priority(const PmcCacheTable* t, PmcCacheKey k, pmc_u32 value, pmc_u32 depth) {
  pmc_u64 base = pmc_cache_cell(t, k.h1) * (pmc_u64)t->ways;
  pmc_u32 fp = pmc_cache_fp30(k.fingerprint), tag = pmc_cache_depth_tag(depth);
  pmc_u64 word = ((pmc_u64)((fp << 2) | tag) << 32) | (pmc_u64)value;
  for (pmc_u32 pass = 0; pass <= 2u * t->ways; ++pass) {
    pmc_u32 victim = t->ways, victim_tag = 0u;
    pmc_u64 victim_word = 0ul;
    int lost = 0;
    for (pmc_u32 i = 0; i < t->ways; ++i) {
      pmc_u64 e = pmc_load64(&t->entries[base + i]);
      if (e == 0ul) {
        if (pmc_cas64(&t->entries[base + i], 0ul, word) == 0ul) return 1;
        lost = 1;
        break;
      }
      pmc_u32 high = (pmc_u32)(e >> 32);
      if ((high >> 2) == fp) return 0;
      if ((high & 3u) > victim_tag) {
        victim = i;
        victim_tag = high & 3u;
        victim_word = e;
      }
    }
    if (lost) continue;
    if (tag != 0u || victim == t->ways) return -1;
    if (pmc_cas64(&t->entries[base + victim], victim_word, word) == victim_word) return 2;
  }
  return -1; /* not reached (see above) */
}

/* Insert under the table's policy from a hit after `depth` surface hits (0:
 * the camera ray's; keep-first ignores it). Returns 1 inserted into an empty
 * entry, 2 replaced a deeper entry (priority), 0 already present, -1 dropped. */
PMC_FN int pmc_cache_insert(const PmcCacheTable* t, PmcCacheKey k, pmc_u32 value, pmc_u32 depth) {
  if (t->policy == PMC_CACHE_PRIORITY) return pmc_cache_insert_priority(t, k, value, depth);
  return pmc_cache_insert_keep_first(t, k, value);
}

#endif /* PMC_CACHE_H */
