/* pmc_vec.h — the small vector vocabulary shared by host C++ and OpenCL C.
 *
 * Shading math (BSDFs, sampling, random numbers, ray cones: the device library
 * in core/device) is written once and compiled twice: by the C++ compiler for tests and
 * the CPU reference paths, and by the OpenCL compiler for the kernels. OpenCL C
 * has float2/float3 with arithmetic operators built in; on the host this file
 * provides look-alike types with the same operators and the handful of
 * built-in functions the shared code uses (dot, cross, normalize, length ...).
 *
 * Rule for shared structs: never put float3 in a struct that crosses the
 * host/device boundary (it is 16 bytes in OpenCL C). Use float[3] or scalars.
 */
#ifndef PMC_VEC_H
#define PMC_VEC_H

#ifdef __OPENCL_VERSION__
#define PMC_FN static inline
/* A function always inlined on the device: one that the shade kernel's loops
 * over a batch's lanes call (a call in a loop's body keeps the compiler from
 * vectorising the loop: gpu/kernels/shade_surface.cl, pmc_draw_hit_numbers), or
 * one returning a struct that a call would pass through memory, where the
 * caller then stalls reading it back (pmc_cache_texel_floored). */
#define PMC_FN_INLINE static inline __attribute__((always_inline))
#define PMC_GLOBAL __global
#define PMC_CONSTANT __constant
#define make_float2(x, y) ((float2)((x), (y)))
#define make_float3(x, y, z) ((float3)((x), (y), (z)))
#define make_float4(x, y, z, w) ((float4)((x), (y), (z), (w)))
typedef uint pmc_u32;
typedef int pmc_i32;
typedef ulong pmc_u64;
#else
#include <cmath>
#include <cstdint>
#include <cstring>
#define PMC_FN static inline
#define PMC_FN_INLINE static inline
#define PMC_GLOBAL
#define PMC_CONSTANT
typedef uint32_t pmc_u32;
typedef int32_t pmc_i32;
typedef uint64_t pmc_u64;
typedef uint32_t uint;

struct float2 {
  float x, y;
};
struct float3 {
  float x, y, z;
};
struct float4 {
  float x, y, z, w;
};
PMC_FN float4 make_float4(float x, float y, float z, float w) { return float4{x, y, z, w}; }
/* OpenCL's bit casts. */
PMC_FN float as_float(int i) {
  float f;
  std::memcpy(&f, &i, 4);
  return f;
}
PMC_FN int as_int(float f) {
  int i;
  std::memcpy(&i, &f, 4);
  return i;
}
PMC_FN float2 make_float2(float x, float y) { return float2{x, y}; }
PMC_FN float3 make_float3(float x, float y, float z) { return float3{x, y, z}; }
PMC_FN float3 operator+(float3 a, float3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
PMC_FN float3 operator-(float3 a, float3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
PMC_FN float3 operator-(float3 a) { return {-a.x, -a.y, -a.z}; }
PMC_FN float3 operator*(float3 a, float3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
PMC_FN float3 operator*(float3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
PMC_FN float3 operator*(float s, float3 a) { return {a.x * s, a.y * s, a.z * s}; }
PMC_FN float3 operator/(float3 a, float s) { return {a.x / s, a.y / s, a.z / s}; }
PMC_FN float3 operator/(float3 a, float3 b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
PMC_FN float3& operator+=(float3& a, float3 b) { return a = a + b; }
PMC_FN float3& operator*=(float3& a, float3 b) { return a = a * b; }
PMC_FN float3& operator*=(float3& a, float s) { return a = a * s; }
PMC_FN float2 operator+(float2 a, float2 b) { return {a.x + b.x, a.y + b.y}; }
PMC_FN float2 operator-(float2 a, float2 b) { return {a.x - b.x, a.y - b.y}; }
PMC_FN float2 operator*(float2 a, float s) { return {a.x * s, a.y * s}; }
PMC_FN float2 operator*(float s, float2 a) { return {a.x * s, a.y * s}; }
#define PMC_F4_BINOP(OP)                                                                                     \
  PMC_FN float4 operator OP(float4 a, float4 b) { return {a.x OP b.x, a.y OP b.y, a.z OP b.z, a.w OP b.w}; } \
  PMC_FN float4 operator OP(float4 a, float s) { return {a.x OP s, a.y OP s, a.z OP s, a.w OP s}; }          \
  PMC_FN float4 operator OP(float s, float4 a) { return {s OP a.x, s OP a.y, s OP a.z, s OP a.w}; }
PMC_F4_BINOP(+)
PMC_F4_BINOP(-)
PMC_F4_BINOP(*)
PMC_F4_BINOP(/)
#undef PMC_F4_BINOP
PMC_FN float4 operator-(float4 a) { return {-a.x, -a.y, -a.z, -a.w}; }
#define PMC_F4_UNARY(FN) \
  PMC_FN float4 FN(float4 a) { return {std::FN(a.x), std::FN(a.y), std::FN(a.z), std::FN(a.w)}; }
PMC_F4_UNARY(fabs)
PMC_F4_UNARY(floor)
PMC_F4_UNARY(ceil)
PMC_F4_UNARY(sin)
PMC_F4_UNARY(cos)
PMC_F4_UNARY(sqrt)
PMC_F4_UNARY(tan)
PMC_F4_UNARY(asin)
PMC_F4_UNARY(acos)
PMC_F4_UNARY(exp)
PMC_F4_UNARY(log)
#undef PMC_F4_UNARY
#define PMC_F4_BINARY(FN)                                                                \
  PMC_FN float4 FN(float4 a, float4 b) {                                                 \
    return {std::FN(a.x, b.x), std::FN(a.y, b.y), std::FN(a.z, b.z), std::FN(a.w, b.w)}; \
  }
PMC_F4_BINARY(fmin)
PMC_F4_BINARY(fmax)
PMC_F4_BINARY(pow)
PMC_F4_BINARY(atan2)
#undef PMC_F4_BINARY
PMC_FN float dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
PMC_FN float dot(float2 a, float2 b) { return a.x * b.x + a.y * b.y; }
PMC_FN float3 cross(float3 a, float3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
PMC_FN float length(float3 a) { return std::sqrt(dot(a, a)); }
PMC_FN float length(float2 a) { return std::sqrt(dot(a, a)); }
PMC_FN float3 normalize(float3 a) { return a * (1.0f / length(a)); }
PMC_FN float3 fabs(float3 a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
PMC_FN float3 fmin(float3 a, float3 b) {
  return {std::fmin(a.x, b.x), std::fmin(a.y, b.y), std::fmin(a.z, b.z)};
}
PMC_FN float3 fmax(float3 a, float3 b) {
  return {std::fmax(a.x, b.x), std::fmax(a.y, b.y), std::fmax(a.z, b.z)};
}
PMC_FN float clamp(float x, float lo, float hi) { return std::fmin(std::fmax(x, lo), hi); }
PMC_FN float mix(float a, float b, float t) { return a + (b - a) * t; }
PMC_FN float3 mix(float3 a, float3 b, float t) { return a + (b - a) * t; }
using std::acos;
using std::atan2;
using std::ceil;
using std::cos;
using std::exp;
using std::fabs;
using std::floor;
using std::fmax;
using std::fmin;
using std::isfinite;
using std::isnan;
using std::log2;
using std::pow;
using std::sin;
using std::sqrt;
#endif

#define PMC_PI 3.14159265358979323846f
#define PMC_INV_PI 0.31830988618379067154f

/* sin and cos of t turns (the angle 2 pi t) for moderate |t|: reduced exactly
 * to within an eighth of a turn of a quarter, then Cephes' single-precision
 * minimax polynomials on [-pi/4, pi/4] (error about 1e-7). Samplers draw
 * angles as fractions of a turn; PoCL's sin and cos spend most of their time
 * in a general argument reduction (`__pocl_argReductionS` in profiles of the
 * shade kernel). */
PMC_FN void pmc_sincos_turns(float t, float* s, float* c) {
  float q = floor(t * 4.0f + 0.5f);
  float x = (t - q * 0.25f) * (2.0f * 3.14159265358979323846f);
  float z = x * x;
  float sn = ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * x + x;
  float cs = ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) * z * z -
             0.5f * z + 1.0f;
  int k = (int)q & 3;
  *s = k == 0 ? sn : (k == 1 ? cs : (k == 2 ? -sn : -cs));
  *c = k == 0 ? cs : (k == 1 ? -sn : (k == 2 ? -cs : sn));
}

/* atan2(y, x) in [-pi, pi] from atan on [0, 1]: t = min / max of |x| and |y|,
 * atan(t) = t P(t^2) with P of degree 8 fitted here to atan(t) / t (Lawson's
 * reweighted least squares; largest error 1.2e-7 rad on [0, 1] evaluated in
 * float, about 2 ulp), then the octant's reflections. A zero y counts as +0
 * (atan2(0, 0) is 0, atan2(0, x < 0) is +pi); a NaN argument gives NaN, two
 * infinite ones NaN too. The lat-long environment map finds each escaped
 * ray's texel with it: PoCL's atan2 took 15% of the shade kernel on a scene
 * seen mostly against its sky. */
PMC_FN float pmc_atan2(float y, float x) {
  if (isnan(x) || isnan(y)) return x + y;
  const float ax = fabs(x), ay = fabs(y);
  const float hi = fmax(ax, ay), lo = fmin(ax, ay);
  const float t = hi > 0.0f ? lo / hi : 0.0f;
  const float s = t * t;
  float p = 2.9035538900643587e-3f;
  p = p * s - 1.628301665186882e-2f;
  p = p * s + 4.3039385229349136e-2f;
  p = p * s - 7.533677667379379e-2f;
  p = p * s + 1.065467894077301e-1f;
  p = p * s - 1.4207133650779724e-1f;
  p = p * s + 1.9993054866790771e-1f;
  p = p * s - 3.333309292793274e-1f;
  p = p * s + 1.0f;
  float r = t * p;
  if (ay > ax) r = 0.5f * PMC_PI - r;
  if (x < 0.0f) r = PMC_PI - r;
  return y < 0.0f ? -r : r;
}

/* acos(c) for c in [-1, 1] (clamped) as atan2(sqrt((1 - c)(1 + c)), c). */
PMC_FN float pmc_acos(float c) {
  c = fmin(fmax(c, -1.0f), 1.0f);
  return pmc_atan2(sqrt((1.0f - c) * (1.0f + c)), c);
}

/* Three floats from any address space (a macro, since OpenCL pointers carry one). */
#define pmc_load3(p) make_float3((p)[0], (p)[1], (p)[2])
PMC_FN float pmc_max3(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }
PMC_FN float pmc_luminance(float3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
PMC_FN float pmc_sqr(float x) { return x * x; }

/* An orthonormal basis around n (Duff et al. 2017, "Building an orthonormal
 * basis, revisited"): branch-free apart from the sign, no singularity. */
PMC_FN void pmc_basis(float3 n, float3* t, float3* b) {
  float sign = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (sign + n.z);
  float bb = n.x * n.y * a;
  *t = make_float3(1.0f + sign * n.x * n.x * a, sign * bb, -sign * n.x);
  *b = make_float3(bb, sign + n.y * n.y * a, -n.y);
}

/* c ? a : b, the scalar twin of OpenCL's select(b, a, c) for arithmetic
 * written once for float and float8 (PMC_TREE_IMPORTANCE,
 * PMC_RAY_CONE_GRADIENTS: their SEL). */
#define PMC_SEL_SCALAR(c, a, b) ((c) ? (a) : (b))

PMC_FN float3 pmc_to_local(float3 v, float3 t, float3 b, float3 n) {
  return make_float3(dot(v, t), dot(v, b), dot(v, n));
}
PMC_FN float3 pmc_to_world(float3 v, float3 t, float3 b, float3 n) { return t * v.x + b * v.y + n * v.z; }

#endif /* PMC_VEC_H */
