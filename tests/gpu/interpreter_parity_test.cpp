// interpreter_parity_test.cpp — the material interpreter (core/device/pmc_interp.h)
// on the OpenCL device against the same source compiled for the host.
//
// The renderer shades on the device; constant folding, the CPU reference and
// the cut-out filter run the host build of the same interpreter. If the two
// drift apart (an opcode that reads its lanes differently, a host/OpenCL
// built-in that behaves differently, an int conversion that is UB on one
// side) images silently disagree with every host-side computation. This test
// runs every opcode, for every output width that makes sense, over random
// inputs drawn fresh each run (the seed is printed through SCOPED_TRACE; rerun
// with PMC_TEST_SEED=<seed> to reproduce), once with every operand in a stack
// slot and once with a mix of inline constants and broadcast scalars. Each
// program is <op> <OUTPUT> <END>, so END and OUTPUT are exercised by every
// case, once with a work-item per item and with 16 and 64 items per work-item
// (the lane-batched interpreter the shade kernel runs on CPU devices);
// CACHE_LOOKUP / CACHE_STORE run (as misses: no cache context) around a
// block in a chained program whose result must be the block's on both sides. Lanes beyond an instruction's
// width must stay untouched (a sentinel) on both sides. A table-completeness test fails when PMC_OPCODES
// gains an opcode without a case here.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <iomanip>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/device/pmc_interp.h"
#include "core/texture.h"
#include "gpu/program.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

constexpr int kPreload = 60;  // stack floats preloaded per work-item (15 operands x 4 lanes)
// uv(2) position(3) normal(3) tangent(3) bitangent(3) footprint(1) footprint_axis(2) footprint_minor(1)
// pad(2)
constexpr int kShading = 20;
constexpr int kData = kPreload + kShading;
constexpr uint32_t kDst = 64;  // result slot, outside the preloaded range
constexpr float kSentinel = -1234.5f;
constexpr int kItems = 128;                     // work-items per program
constexpr double kEps = 1.1920928955078125e-7;  // FLT_EPSILON = 1 ulp at 1.0

using Rng = std::mt19937;

float uniform(Rng& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }

// How an argument's values are drawn.
enum class Dist {
  Uniform,  // [lo, hi]
  Integer,  // integers in [lo, hi] (never perturbed: they select modes)
  Wide,     // random sign, log-uniform magnitude in [lo, hi] (noise coordinates up to 1e4)
  Signed,   // random sign, uniform magnitude in [lo, hi] (divisors away from zero)
};

struct ArgSpec {
  int width;  // 0: the case's width (a "T" input)
  float lo, hi;
  Dist dist = Dist::Uniform;
};

// How closely device and host must agree (see tolerance()).
enum class Tol {
  Exact,   // correctly rounded single operations / selections on identical inputs
  Div,     // x / y: OpenCL 1.2 allows 2.5 ulp
  Sqrt,    // 3 ulp
  Trig,    // sin, cos: 4 ulp
  Pow,     // 16 ulp
  Scaled,  // a few roundings (possibly fma-contracted) of intermediates up to the operand magnitude
  Noise,   // polynomial/noise evaluation of order-1 values, times amplitude
  Unit,    // results of order 1 (or their own size) whatever the operands' size
};

struct OpSpec {
  int op;
  std::vector<int> widths;  // output widths (DOT: operand widths)
  std::vector<ArgSpec> args;
  Tol tol;
  bool discontinuous = false;  // skip inputs within ~1e-4 of a jump (see near_discontinuity)
  std::function<uint32_t(int width, int index, Rng&)> imm;
  std::function<void(Rng&, std::array<float, 4>* vals)> fix;  // per-item adjustments
  int out_width = 0;                                          // 0: the case's width
  bool nargs_is_width = false;                                // COMBINE
};

// One entry per opcode: output widths, operand ranges, tolerance class.
// Ops with jumps whose deciding value is an input itself (floor, ceil,
// ifgreater, split, cellnoise's floor) need no skipping: both sides compare
// or floor the same float exactly. Ops that round before the jump (mod's
// division, the pattern ops' scaling, worley's solid style) are marked
// discontinuous and skip inputs within ~1e-4 of it.
std::vector<OpSpec> op_specs() {
  const std::vector<int> all = {1, 2, 3, 4};
  const ArgSpec T{0, -10, 10};
  const ArgSpec uv_in{2, -0.5f, 1.5f};
  std::vector<OpSpec> s;
  auto add = [&](OpSpec o) { s.push_back(std::move(o)); };

  add({PMC_OP_MOVE, all, {T}, Tol::Exact});
  add({PMC_OP_SWIZZLE, all, {{4, -10, 10}}, Tol::Exact, false, [](int, int, Rng& rng) {
         uint32_t imm = 0;
         for (int i = 0; i < 4; ++i)
           imm |= uint32_t(std::uniform_int_distribution<int>(0, 5)(rng)) << (3 * i);
         return imm;
       }});
  OpSpec combine{
      PMC_OP_COMBINE, {2, 3, 4}, {{1, -10, 10}, {1, -10, 10}, {1, -10, 10}, {1, -10, 10}}, Tol::Exact};
  combine.nargs_is_width = true;
  add(combine);
  add({PMC_OP_TEXCOORD, {2, 3}, {}, Tol::Exact});
  add({PMC_OP_POSITION, {3}, {}, Tol::Exact});
  add({PMC_OP_NORMAL, {3}, {}, Tol::Exact});
  add({PMC_OP_TANGENT, {3}, {}, Tol::Exact});
  add({PMC_OP_BITANGENT, {3}, {}, Tol::Exact});

  add({PMC_OP_ADD, all, {T, T}, Tol::Exact});
  add({PMC_OP_SUB, all, {T, T}, Tol::Exact});
  add({PMC_OP_MUL, all, {T, T}, Tol::Exact});
  add({PMC_OP_DIV, all, {{0, -100, 100}, {0, 0.1f, 10, Dist::Signed}}, Tol::Div});
  // a - b * floor(a / b): the division may round differently, so floor() can
  // jump by one near multiples of b; those inputs are skipped.
  add({PMC_OP_MOD, all, {{0, -100, 100}, {0, 0.5f, 10, Dist::Signed}}, Tol::Scaled, true});
  add({PMC_OP_POW, all, {{0, 0.01f, 10}, {0, -3, 3}}, Tol::Pow});  // positive base: no NaN
  add({PMC_OP_MIN, all, {T, T}, Tol::Exact});
  add({PMC_OP_MAX, all, {T, T}, Tol::Exact});
  OpSpec dot{PMC_OP_DOT, all, {T, T}, Tol::Scaled, false, [](int w, int, Rng&) { return uint32_t(w); }};
  dot.out_width = 1;
  add(dot);

  add({PMC_OP_ABS, all, {T}, Tol::Exact});
  add({PMC_OP_FLOOR, all, {{0, -100, 100}}, Tol::Exact});
  add({PMC_OP_CEIL, all, {{0, -100, 100}}, Tol::Exact});
  add({PMC_OP_SIN, all, {{0, -100, 100}}, Tol::Trig});
  add({PMC_OP_COS, all, {{0, -100, 100}}, Tol::Trig});
  add({PMC_OP_SQRT, all, {{0, 0, 1e4f}}, Tol::Sqrt});
  add({PMC_OP_NORMALIZE, all, {T}, Tol::Scaled});

  add({PMC_OP_CLAMP, all, {T, {0, -5, 0}, {0, 0, 5}}, Tol::Exact});
  add({PMC_OP_SMOOTHSTEP, all, {{0, -2, 3}, {0, -1, 0.4f}, {0, 0.6f, 2}}, Tol::Scaled});
  add({PMC_OP_MIX, all, {T, T, {0, -0.5f, 1.5f}}, Tol::Scaled});
  add({PMC_OP_REMAP, all, {T, {0, -2, -0.5f}, {0, 0.5f, 2}, T, T}, Tol::Scaled});
  auto equal_sometimes = [](Rng& rng, std::array<float, 4>* v) {
    if (uniform(rng, 0, 1) < 0.25f) v[1] = v[0];  // exercises the >= / > difference
  };
  add({PMC_OP_IFGREATER, all, {{1, -1, 1}, {1, -1, 1}, T, T}, Tol::Exact, false, nullptr, equal_sometimes});
  add({PMC_OP_IFGREATEREQ, all, {{1, -1, 1}, {1, -1, 1}, T, T}, Tol::Exact, false, nullptr, equal_sometimes});
  add({PMC_OP_LUMINANCE, {3, 4}, {{0, -0.5f, 2}, {3, 0, 1}}, Tol::Scaled});
  add({PMC_OP_RGBTOHSV, {3, 4}, {{0, -0.5f, 2}}, Tol::Scaled});
  add({PMC_OP_HSVTORGB,
       {3, 4},
       {{0, -2, 3}},
       Tol::Scaled,
       false,
       nullptr,
       [](Rng& rng, std::array<float, 4>* v) {
         v[0][1] = uniform(rng, -0.2f, 1.0f);  // saturation (<= 0: grey)
         v[0][2] = uniform(rng, 0.0f, 2.0f);   // value
       }});

  // IMAGE: uv, default, mode = (u mode | v mode << 2 | filter << 4 | PMC_IMAGE_ANISO half
  // the time, footprint scale).
  // imm cycles through texture 0 (sRGB 8x4), 1 (linear 5x3) and 2 (absent: default).
  add({PMC_OP_IMAGE,
       all,
       {{2, -2, 3}, {0, -1, 2}, {2, 0, 1}},
       Tol::Scaled,
       false,
       [](int, int index, Rng&) { return uint32_t(index % 3); },
       [](Rng& rng, std::array<float, 4>* v) {
         v[2][0] = float(std::uniform_int_distribution<int>(0, 31)(rng) |
                         (uniform(rng, 0, 1) < 0.5f ? PMC_IMAGE_ANISO : 0u));
         v[2][1] = uniform(rng, 0.5f, 4.0f);
       }});
  // Hex tiling: texcoord, tiling, rotation, rotationrange, scale, scalerange,
  // offset, offsetrange, falloff, default, mode (as IMAGE), then
  // falloffcontrast, lumacoeffs (HEXIMAGE) or strength, flip_g, normal,
  // tangent (HEXNORMALMAP). A tile's edge (the lattice triangle a point lies
  // in) is a jump in which tiles are read, but their weights vanish there
  // (bary^7). The per-tile angle (up to 360 degrees, an operand) rounds
  // differently through sin/cos on the two sides and moves each read point;
  // random texels make the image steep, and the normal map's gradient blend
  // divides by dot(N, N_i), small for texels whose normal lies near the
  // tangent plane (up to ~2e-5 seen). Both are held to Scaled, whose operand
  // magnitude is the rotation range's (~3e-3), still far below the O(1) error
  // of a wrong operand or lane.
  const std::vector<ArgSpec> hextile = {{2, -2, 3},      {2, 0.5f, 3}, {1, 0, 1}, {2, -180, 360},
                                        {1, 0, 1},       {2, 0.5f, 2}, {1, 0, 1}, {2, -1, 1},
                                        {1, 0.1f, 0.9f}, {0, -1, 2},   {2, 0, 1}};
  auto hextile_mode = [](Rng& rng, std::array<float, 4>* v) {
    v[10][0] = float(std::uniform_int_distribution<int>(0, 31)(rng) |
                     (uniform(rng, 0, 1) < 0.5f ? PMC_IMAGE_ANISO : 0u));
    v[10][1] = uniform(rng, 0.5f, 4.0f);
    if (uniform(rng, 0, 1) < 0.5f) v[1][1] = v[1][0];  // an even tiling: the ellipse's axis follows
  };
  std::vector<ArgSpec> heximage = hextile;
  heximage.insert(heximage.end(), {{1, 0, 1}, {3, 0, 1}});
  add({PMC_OP_HEXIMAGE,
       {3, 4},
       heximage,
       Tol::Scaled,
       true,
       [](int, int index, Rng&) { return uint32_t(index % 3); },
       hextile_mode});
  std::vector<ArgSpec> hexnormal = hextile;
  hexnormal.insert(hexnormal.end(), {{1, 0, 2}, {1, 0, 1, Dist::Integer}, {3, -1, 1}, {3, -1, 1}});
  add({PMC_OP_HEXNORMALMAP,
       {3},
       hexnormal,
       Tol::Scaled,
       true,
       [](int, int index, Rng&) { return uint32_t(index % 3); },
       [hextile_mode](Rng& rng, std::array<float, 4>* v) {
         hextile_mode(rng, v);
         v[13] = {0, 0, 1, 0};  // a unit normal and a unit tangent across it, as shading frames are
         float a = uniform(rng, 0, 6.2831853f);
         v[14] = {std::cos(a), std::sin(a), 0, 0};
       }});
  add({PMC_OP_PLACE2D,
       {2},
       {{2, -2, 3},
        {2, -1, 1},
        {2, 0.25f, 4, Dist::Signed},
        {1, -360, 360},
        {2, -1, 1},
        {1, 0, 1, Dist::Integer}},
       Tol::Scaled});
  const ArgSpec wide2{2, 1e-2f, 1e4f, Dist::Wide}, wide3{3, 1e-2f, 1e4f, Dist::Wide};
  add({PMC_OP_NOISE2D, all, {wide2, T, {1, -10, 10}}, Tol::Noise});
  add({PMC_OP_NOISE3D, all, {wide3, T, {1, -10, 10}}, Tol::Noise});
  const ArgSpec octaves{1, 0, 9, Dist::Integer}, lacunarity{1, 1.5f, 3}, diminish{1, 0.2f, 0.8f};
  add({PMC_OP_FRACTAL2D, all, {wide2, T, octaves, lacunarity, diminish}, Tol::Noise});
  add({PMC_OP_FRACTAL3D, all, {wide3, T, octaves, lacunarity, diminish}, Tol::Noise});
  add({PMC_OP_CELLNOISE2D, {1, 3}, {wide2}, Tol::Exact});
  add({PMC_OP_CELLNOISE3D, {1, 3}, {wide3}, Tol::Exact});
  // style 1 (solid cell value) jumps at cell borders; F1..F3 are continuous.
  add({PMC_OP_WORLEY2D, {1, 2, 3}, {wide2, {1, 0, 1.5f}, {1, 0, 1, Dist::Integer}}, Tol::Noise, true});
  add({PMC_OP_WORLEY3D, {1, 2, 3}, {wide3, {1, 0, 1.5f}, {1, 0, 1, Dist::Integer}}, Tol::Noise, true});
  add({PMC_OP_RAMPLR, all, {T, T, uv_in}, Tol::Scaled});
  add({PMC_OP_RAMPTB, all, {T, T, uv_in}, Tol::Scaled});
  add({PMC_OP_RAMP4, all, {T, T, T, T, uv_in}, Tol::Scaled});
  add({PMC_OP_SPLITLR, all, {T, T, {1, 0, 1}, uv_in}, Tol::Exact});
  add({PMC_OP_SPLITTB, all, {T, T, {1, 0, 1}, uv_in}, Tol::Exact});
  const std::vector<ArgSpec> shape_args = {
      {2, -3, 3}, {2, 0.5f, 4}, {2, -1, 1}, {1, 0.05f, 1}, {1, 0, 1, Dist::Integer}};
  add({PMC_OP_TILEDSHAPE, {1, 3}, shape_args, Tol::Exact, true, [](int, int index, Rng&) {
         return uint32_t(index % 3);
       }});
  std::vector<ArgSpec> line_args = shape_args;
  line_args[3] = {1, 0.01f, 0.5f};
  add({PMC_OP_LINEPATTERN, {1, 3}, line_args, Tol::Exact, true, [](int, int index, Rng&) {
         return uint32_t(index % 2);
       }});
  add({PMC_OP_NORMALMAP,
       {3},
       {{3, 0, 1}, {1, 0, 2}, {3, -1, 1}, {3, -1, 1}},
       Tol::Scaled,
       false,
       nullptr,
       [](Rng& rng, std::array<float, 4>* v) {
         // Keep the frame well conditioned: a normal not close to zero length.
         v[2][2] = uniform(rng, 0.5f, 1.0f);
       }});
  add({PMC_OP_TAN, all, {{0, -1.2f, 1.2f}}, Tol::Trig});
  add({PMC_OP_ASIN, all, {{0, -1, 1}}, Tol::Trig});
  add({PMC_OP_ACOS, all, {{0, -1, 1}}, Tol::Trig});
  add({PMC_OP_ATAN2, all, {T, {0, 0.1f, 10, Dist::Signed}}, Tol::Pow});
  add({PMC_OP_EXP, all, {{0, -5, 5}}, Tol::Trig});
  add({PMC_OP_LN, all, {{0, 0.01f, 100}}, Tol::Trig});
  add({PMC_OP_SIGN, all, {{0, -2, 2, Dist::Integer}}, Tol::Exact});
  add({PMC_OP_ROUND, all, {{0, -100, 100}}, Tol::Exact});
  add({PMC_OP_FRACT, all, {{0, -100, 100}}, Tol::Exact});
  OpSpec length{PMC_OP_LENGTH, {2, 3, 4}, {T},
                Tol::Scaled,   false,     [](int w, int, Rng&) { return uint32_t(w); }};
  length.out_width = 1;
  add(length);
  add({PMC_OP_CROSS, {3}, {{3, -10, 10}, {3, -10, 10}}, Tol::Scaled});
  add({PMC_OP_NOT, all, {{0, -1, 1, Dist::Integer}}, Tol::Exact});
  add({PMC_OP_IFEQUAL, all, {{1, 0, 2, Dist::Integer}, {1, 0, 2, Dist::Integer}, T, T}, Tol::Exact});
  // Burn and dodge jump to 0 within 1e-6 of their singularity; the random
  // inputs land there with probability ~1e-7.
  add({PMC_OP_BLEND, all, {T, T, {0, 0, 1}}, Tol::Scaled, false, [](int, int index, Rng&) {
         return uint32_t(index % 6);
       }});
  // disjointover's two branches: f + b above and below 1 both occur.
  add({PMC_OP_COMPOSITE,
       {4},
       {{4, 0, 1}, {4, 0, 1}, {1, 0, 1}},
       Tol::Scaled,
       false,
       [](int, int index, Rng&) { return uint32_t(index % 6); }});
  add({PMC_OP_PREMULT,
       {4},
       {{4, -2, 2}},
       Tol::Scaled,
       false,
       [](int, int index, Rng&) { return uint32_t(index % 2); },
       [](Rng& rng, std::array<float, 4>* v) {
         v[0][3] =
             uniform(rng, 0.0f, 1.0f) < 0.1f ? 0.0f : uniform(rng, 0.1f, 1.0f);  // alpha 0 passes through
       }});
  add({PMC_OP_OUTSIDE, all, {T, {1, 0, 1}}, Tol::Scaled});
  // Flakes: outputs id, rand, presence (width 1) and flakenormal (width 3).
  // A flake's edge is a jump (the rotation's sin/cos may round differently).
  add({PMC_OP_FLAKE,
       {1, 3},
       {{1, 0.05f, 0.5f}, {1, 0, 1}, {1, 0, 1}, {3, -2, 2}, {3, -1, 1}, {3, -1, 1}, {3, -1, 1}},
       Tol::Unit,
       true,
       [](int w, int, Rng& rng) {
         return w == 3 ? PMC_FLAKE_NORMAL : uint32_t(std::uniform_int_distribution<int>(0, 2)(rng));
       }});
  add({PMC_OP_ROUGHNESS_ANISO, {2}, {{1, -1.5f, 1.5f}, {1, -0.5f, 1.5f}}, Tol::Scaled});
  add({PMC_OP_ROUGHNESS_DUAL, {2}, {{2, -1.5f, 1.5f}}, Tol::Exact});
  // Edge colours near 0 put k near sqrt(0) of a cancellation (k = 0 exactly at
  // edge_color 0): rounding differences there are not errors.
  add({PMC_OP_ARTISTIC_IOR,
       {3},
       {{3, 0.05f, 0.9f}, {3, 0.3f, 1}},
       Tol::Unit,
       false,
       [](int, int index, Rng&) { return uint32_t(index % 2); }});
  add({PMC_OP_BLACKBODY, {3}, {{1, 500, 30000}}, Tol::Unit});
  // Hair data: roughness in and beyond its clamp [0.001, 1] (pow(x, 20) near 1),
  // the three outputs by imm.
  add({PMC_OP_HAIR_ROUGHNESS,
       {2},
       {{1, -0.2f, 1.2f}, {1, -0.2f, 1.2f}, {1, 0, 3}, {1, 0, 3}},
       Tol::Unit,
       false,
       [](int, int index, Rng&) { return uint32_t(index % 3); }});
  add({PMC_OP_HAIR_MELANIN, {3}, {{1, 0, 0.99f}, {1, 0, 1}, {3, 0.05f, 1}, {3, 0.05f, 1}}, Tol::Unit});
  add({PMC_OP_HAIR_COLOR, {3}, {{3, 0.0005f, 1.2f}, {1, 0, 1}}, Tol::Unit});
  add({PMC_OP_ROTATE2D, {2}, {{2, -10, 10}, {1, -360, 360}}, Tol::Scaled});
  add({PMC_OP_ROTATE3D,
       {3},
       {{3, -10, 10}, {1, -360, 360}, {3, -1, 1}},
       Tol::Scaled,
       false,
       nullptr,
       [](Rng& rng, std::array<float, 4>* v) {
         v[2][2] = uniform(rng, 0.5f, 1.0f);  // an axis well away from zero length
       }});
  return s;
}

// Tolerance of one lane. `h` is the host value, `m` the largest operand
// magnitude of the work-item. OpenCL 1.2 (full profile) bounds: +, -, *,
// min/max/fabs/floor/ceil and comparisons are exact (0 ulp), x/y 2.5 ulp,
// sqrt 3 ulp, sin/cos 4 ulp, pow 16 ulp; the host (glibc) is within 1 ulp.
// Results are compared with one more ulp than the sum, relative to |h| with
// an absolute floor of a few ulp of 1 for results near zero. Composite
// operations (mix, remap, normalize, colour conversions, place2d, image
// filtering, ...) round a few intermediates whose magnitude is bounded by the
// operands, and OpenCL may contract a*b+c into one fma: each such step moves
// the result by up to an ulp of the intermediate, so they get 64 ulp of
// max(|h|, m). Noise ops evaluate hash-selected gradients and quintic fades
// on values of order 1 (the cell fraction x - floor(x) is exact on both
// sides even at 1e4) over up to 8 octaves, then scale by amplitude: 1e-5 of
// max(1, |h|, m) is ~100x the expected few-ulp differences and still ~1e4
// times smaller than the O(1) error of a wrong hash, lane or octave. Unit
// drops m where an operand's scale does not reach the result (blackbody's
// 1000 / T, flake positions divided by the size, artistic_ior's ratios of
// order-1 values): 1e-5 of max(1, |h|).
double tolerance(Tol t, double h, double m) {
  const double a = std::fabs(h);
  switch (t) {
    case Tol::Exact:
      return 0.0;
    case Tol::Div:
      return 4 * kEps * a;
    case Tol::Sqrt:
      return 5 * kEps * a;
    case Tol::Trig:
      return 6 * kEps * a + 4 * kEps;
    case Tol::Pow:
      return 18 * kEps * a + 4 * kEps;
    case Tol::Scaled:
      return 64 * kEps * std::max({a, m, 1e-3});
    case Tol::Noise:
      return 1e-5 * std::max({1.0, a, m});
    case Tol::Unit:
      return 1e-5 * std::max(1.0, a);
  }
  return 0.0;
}

const char* op_name(int op) {
  static const char* names[] = {
#define PMC_TEST_OP_NAME(name, lo, hi, slots) #name,
      PMC_OPCODES(PMC_TEST_OP_NAME)
#undef PMC_TEST_OP_NAME
  };
  return op >= 0 && op < PMC_OP_COUNT ? names[op] : "?";
}

// ---- programs ---------------------------------------------------------------

struct Operand {
  bool is_const = false;
  bool raw = false;  // a plain word (CACHE_LOOKUP's skip count), not a value
  uint32_t word = 0;
  int width = 1;
  uint32_t slot = 0;             // stack slot when not constant
  std::array<float, 4> value{};  // the constant
};

struct Instr {
  int op;
  int width;
  uint32_t imm;
  uint32_t dst;
  std::vector<Operand> args;
};

// Appends instructions + END + their inline constants to `code`; returns the entry.
uint32_t assemble(std::vector<uint32_t>& code, const std::vector<Instr>& prog) {
  const uint32_t entry = uint32_t(code.size());
  uint32_t words = 2;  // END
  for (const Instr& in : prog) words += 2 + uint32_t(in.args.size());
  uint32_t const_at = entry + words;
  std::vector<uint32_t> consts;
  for (const Instr& in : prog) {
    code.push_back(pmc_op_header(uint32_t(in.op), uint32_t(in.width), uint32_t(in.args.size()), in.imm));
    code.push_back(in.dst);
    for (const Operand& a : in.args) {
      if (a.raw) {
        code.push_back(a.word);
      } else if (a.is_const) {
        code.push_back(pmc_operand(1, const_at + uint32_t(consts.size()), uint32_t(a.width)));
        for (int l = 0; l < a.width; ++l) {
          uint32_t bits;
          std::memcpy(&bits, &a.value[size_t(l)], 4);
          consts.push_back(bits);
        }
      } else {
        code.push_back(pmc_operand(0, a.slot, uint32_t(a.width)));
      }
    }
  }
  code.push_back(pmc_op_header(PMC_OP_END, 1, 0, 0));
  code.push_back(0);
  code.insert(code.end(), consts.begin(), consts.end());
  return entry;
}

float draw(Rng& rng, const ArgSpec& a) {
  switch (a.dist) {
    case Dist::Integer:
      return float(std::uniform_int_distribution<int>(int(a.lo), int(a.hi))(rng));
    case Dist::Wide: {
      float mag = std::exp(uniform(rng, std::log(a.lo), std::log(a.hi)));
      return uniform(rng, 0, 1) < 0.5f ? -mag : mag;
    }
    case Dist::Signed:
      return (uniform(rng, 0, 1) < 0.5f ? -1.0f : 1.0f) * uniform(rng, a.lo, a.hi);
    case Dist::Uniform:
      break;
  }
  return uniform(rng, a.lo, a.hi);
}

// One program under test and the work-items that run it.
struct Case {
  std::string label;
  const OpSpec* spec = nullptr;  // null for the chained CACHE_* program
  int out_width = 4;
  Tol tol = Tol::Exact;
  bool discontinuous = false;
  uint32_t entry = 0;
  std::vector<int> arg_width;                    // per argument (as encoded)
  std::vector<bool> arg_const;                   // per argument
  std::vector<std::array<float, 4>> const_vals;  // per argument, when constant
  std::vector<bool> perturb;                     // per preloaded float: may be nudged to find discontinuities
  size_t first_item = 0;
};

// Random shading inputs for one work-item (data[kPreload ..]).
void draw_shading(Rng& rng, float* d) {
  d[0] = uniform(rng, -2, 3);  // uv
  d[1] = uniform(rng, -2, 3);
  for (int k = 2; k < 5; ++k) d[k] = uniform(rng, -100, 100);  // position
  for (int k = 5; k < 14; ++k) d[k] = uniform(rng, -1, 1);     // normal, tangent, bitangent
  // The footprint and its ellipse from random ray-cone gradients, often
  // long and thin (one of them short), sometimes none; a fifth of the points
  // without their ellipse, reading one mip level (a hit after a rough bounce);
  // the ellipses' major axes scaled as a pixel's samples 0 to 1023 scale them.
  const float g = uniform(rng, 0, 1) < 0.1f ? 0.0f : uniform(rng, 0, 0.15f);
  const float ga = uniform(rng, 0, 6.2831853f), gb = ga + uniform(rng, 0.5f, 2.6f);
  const float g2 = g * (uniform(rng, 0, 1) < 0.5f ? uniform(rng, 0, 0.2f) : uniform(rng, 0.2f, 1.0f));
  const pmc_u32 sample = (1u << int(uniform(rng, 0, 10.99f))) - 1u;
  PmcShadingInputs in{};
  pmc_shading_footprint(&in, make_float2(g * std::cos(ga), g * std::sin(ga)),
                        make_float2(g2 * std::cos(gb), g2 * std::sin(gb)), uniform(rng, 0, 1) < 0.8f,
                        pmc_footprint_major_scale(sample));
  d[14] = in.footprint;
  d[15] = in.footprint_axis.x;
  d[16] = in.footprint_axis.y;
  d[17] = in.footprint_minor;
  d[18] = d[19] = 0;
}

PmcShadingInputs unpack_shading(const float* d) {
  PmcShadingInputs in{};
  in.uv = make_float2(d[0], d[1]);
  in.position = make_float3(d[2], d[3], d[4]);
  in.normal = make_float3(d[5], d[6], d[7]);
  in.tangent = make_float3(d[8], d[9], d[10]);
  in.bitangent = make_float3(d[11], d[12], d[13]);
  in.footprint = d[14];
  in.footprint_axis = make_float2(d[15], d[16]);
  in.footprint_minor = d[17];
  return in;
}

// Runs one work-item on the host exactly as the kernel below does.
void host_run(const std::vector<uint32_t>& code, uint32_t entry, const float* d, const PmcTextureSet& ts,
              float out[8]) {
  float stack[PMC_STACK_SIZE];
  float params[PMC_P_COUNT];
  for (int k = 0; k < PMC_STACK_SIZE; ++k) stack[k] = k < kPreload ? d[k] : 0.0f;
  for (uint32_t k = 0; k < 4; ++k) stack[kDst + k] = kSentinel;
  for (int k = 0; k < PMC_P_COUNT; ++k) params[k] = kSentinel;
  PmcShadingInputs in = unpack_shading(d + kPreload);
  pmc_interp_run(code.data(), entry, &in, &ts, stack, params, nullptr);
  for (int k = 0; k < 4; ++k) {
    out[k] = stack[kDst + uint32_t(k)];
    out[4 + k] = params[k];
  }
}

const char* kKernel = R"CL(
#include "pmc_interp.h"
__kernel void interp_parity(__global const uint* code, __global const uint* entries,
                            __global const float* data, __global const PmcTexture* textures,
                            __global const uint* texels, __constant float* srgb_lut,
                            uint texture_count, __global float* out, uint n) {
  uint i = get_global_id(0);
  if (i >= n) return;
  __global const float* d = data + (size_t)i * KDATA;
  float stack[PMC_STACK_SIZE];
  float params[PMC_P_COUNT];
  for (int k = 0; k < PMC_STACK_SIZE; ++k) stack[k] = k < KPRELOAD ? d[k] : 0.0f;
  for (int k = 0; k < 4; ++k) stack[KDST + k] = KSENTINEL;
  for (int k = 0; k < PMC_P_COUNT; ++k) params[k] = KSENTINEL;
  __global const float* s = d + KPRELOAD;
  PmcShadingInputs in;
  in.uv = make_float2(s[0], s[1]);
  in.position = make_float3(s[2], s[3], s[4]);
  in.normal = make_float3(s[5], s[6], s[7]);
  in.tangent = make_float3(s[8], s[9], s[10]);
  in.bitangent = make_float3(s[11], s[12], s[13]);
  in.footprint = s[14];
  in.footprint_axis = make_float2(s[15], s[16]);
  in.footprint_minor = s[17];
  PmcTextureSet ts;
  ts.textures = textures;
  ts.texels = texels;
  ts.srgb_lut = srgb_lut;
  ts.count = texture_count;
  pmc_interp_run(code, entries[i], &in, &ts, stack, params, 0); /* no cache: every lookup misses */
  for (int k = 0; k < 4; ++k) {
    out[8 * i + k] = stack[KDST + k];
    out[8 * i + 4 + k] = params[k];
  }
}

/* The same items in batches of PMC_LANES (consecutive items share a program),
 * as the shade kernel runs materials on CPU devices. */
__kernel void interp_parity_lanes(__global const uint* code, __global const uint* entries,
                                  __global const float* data, __global const PmcTexture* textures,
                                  __global const uint* texels, __constant float* srgb_lut,
                                  uint texture_count, __global float* out, uint n) {
  uint first = get_global_id(0) * PMC_LANES;
  if (first >= n) return;
  int m = (int)min((uint)PMC_LANES, n - first);
  float stack[PMC_STACK_SIZE * PMC_LANES];
  float params[PMC_P_COUNT * PMC_LANES];
  PmcShadingInputs in[PMC_LANES];
  for (int l = 0; l < m; ++l) {
    __global const float* d = data + (size_t)(first + l) * KDATA;
    for (int k = 0; k < PMC_STACK_SIZE; ++k) stack[k * PMC_LANES + l] = k < KPRELOAD ? d[k] : 0.0f;
    for (int k = 0; k < 4; ++k) stack[(KDST + k) * PMC_LANES + l] = KSENTINEL;
    for (int k = 0; k < PMC_P_COUNT; ++k) params[l * PMC_P_COUNT + k] = KSENTINEL;
    __global const float* s = d + KPRELOAD;
    in[l].uv = make_float2(s[0], s[1]);
    in[l].position = make_float3(s[2], s[3], s[4]);
    in[l].normal = make_float3(s[5], s[6], s[7]);
    in[l].tangent = make_float3(s[8], s[9], s[10]);
    in[l].bitangent = make_float3(s[11], s[12], s[13]);
    in[l].footprint = s[14];
    in[l].footprint_axis = make_float2(s[15], s[16]);
    in[l].footprint_minor = s[17];
  }
  PmcTextureSet ts;
  ts.textures = textures;
  ts.texels = texels;
  ts.srgb_lut = srgb_lut;
  ts.count = texture_count;
  pmc_interp_lanes(code, entries[first], in, m, &ts, stack, params, 0);
  for (int l = 0; l < m; ++l)
    for (int k = 0; k < 4; ++k) {
      out[8 * (first + l) + k] = stack[(KDST + k) * PMC_LANES + l];
      out[8 * (first + l) + 4 + k] = params[l * PMC_P_COUNT + k];
    }
}
)CL";

// A tiny texture set: an 8x4 sRGB and a 5x3 linear RGBA8 texture with random
// texels and full mip chains (TexturePool builds them), packed as the kernels
// read them.
struct TinyTextures {
  TexturePool pool;
  std::vector<uint32_t> words;
  std::vector<float> lut = srgb_decode_table();

  explicit TinyTextures(Rng& rng) {
    auto random_rgba = [&](int w, int h) {
      std::vector<uint8_t> px(size_t(w) * size_t(h) * 4);
      for (uint8_t& b : px) b = uint8_t(std::uniform_int_distribution<int>(0, 255)(rng));
      return px;
    };
    pool.add("tiny_srgb", 8, 4, random_rgba(8, 4), true);
    pool.add("tiny_linear", 5, 3, random_rgba(5, 3), false);
    const TexelBytes b = pool.texels();
    for (size_t i = 0; i + 3 < b.size(); i += 4)
      words.push_back(uint32_t(b[i]) | uint32_t(b[i + 1]) << 8 | uint32_t(b[i + 2]) << 16 |
                      uint32_t(b[i + 3]) << 24);
  }
  PmcTextureSet host() const {
    PmcTextureSet ts{};
    ts.textures = pool.textures().data();
    ts.texels = words.data();
    ts.srgb_lut = lut.data();
    ts.count = uint32_t(pool.size());
    return ts;
  }
};

uint32_t test_seed() {
  if (const char* s = std::getenv("PMC_TEST_SEED")) return uint32_t(std::strtoul(s, nullptr, 10));
  return std::random_device{}();
}

TEST(Interpreter, EveryOpcodeHasAParityCase) {
  std::set<int> covered;
  for (const OpSpec& s : op_specs()) covered.insert(s.op);
  // Exercised indirectly: END and OUTPUT close every program; the reserved
  // cache opcodes run (as misses) in the chained program of DeviceMatchesHostForEveryOpcode.
  const std::set<int> indirect = {PMC_OP_END, PMC_OP_OUTPUT, PMC_OP_CACHE_LOOKUP, PMC_OP_CACHE_STORE};
  for (int op = 0; op < PMC_OP_COUNT; ++op)
    EXPECT_TRUE(covered.count(op) || indirect.count(op))
        << "opcode " << op_name(op) << " has no case in op_specs(): add one with its operand ranges";
  EXPECT_EQ(covered.size() + indirect.size(), size_t(PMC_OP_COUNT));
}

TEST(Interpreter, DeviceMatchesHostForEveryOpcode) {
  const uint32_t seed = test_seed();
  SCOPED_TRACE("seed " + std::to_string(seed) + " (reproduce with PMC_TEST_SEED=" + std::to_string(seed) +
               ")");
  Rng rng(seed);
  const std::vector<OpSpec> specs = op_specs();
  TinyTextures tex(rng);
  const PmcTextureSet host_ts = tex.host();

  std::vector<uint32_t> code;
  std::vector<Case> cases;
  std::vector<float> data;  // kData floats per work-item
  std::vector<uint32_t> entries;

  for (const OpSpec& spec : specs) {
    int index = 0;
    for (int width : spec.widths) {
      for (int variant = 0; variant < 2; ++variant, ++index) {
        Case c;
        c.spec = &spec;
        c.tol = spec.tol;
        c.discontinuous = spec.discontinuous;
        c.out_width = spec.out_width ? spec.out_width : width;
        const size_t nargs = spec.nargs_is_width ? size_t(width) : spec.args.size();
        Instr ins{spec.op, c.out_width, spec.imm ? spec.imm(width, index, rng) : 0u, kDst, {}};
        // Variant 0: every operand in a slot at full width. Variant 1: odd
        // arguments become inline constants, "T" arguments at even positions
        // become width-1 slots that broadcast.
        std::vector<std::array<float, 4>> const_vals(nargs);
        {
          std::vector<std::array<float, 4>> v(std::max<size_t>(nargs, 1));
          for (size_t k = 0; k < nargs; ++k)
            for (auto& f : v[k]) f = draw(rng, spec.args[k]);
          if (spec.fix) spec.fix(rng, v.data());
          for (size_t k = 0; k < nargs; ++k) const_vals[k] = v[k];
        }
        for (size_t k = 0; k < nargs; ++k) {
          const ArgSpec& a = spec.args[k];
          Operand o;
          o.width = a.width ? a.width : width;
          o.slot = uint32_t(4 * k);
          if (variant == 1) {
            if (k % 2 == 1) {
              o.is_const = true;
              o.value = const_vals[k];
            } else if (a.width == 0) {
              o.width = 1;
            }
          }
          ins.args.push_back(o);
          c.arg_width.push_back(o.width);
          c.arg_const.push_back(o.is_const);
          c.const_vals.push_back(o.value);
        }
        Instr out{PMC_OP_OUTPUT, c.out_width, 0, 0, {Operand{false, false, 0, c.out_width, kDst, {}}}};
        c.entry = assemble(code, {ins, out});
        std::ostringstream label;
        label << op_name(spec.op) << "." << width << (variant ? " (constants, broadcast)" : " (slots)")
              << " imm " << ins.imm;
        c.label = label.str();
        c.perturb.assign(kData, false);
        for (size_t k = 0; k < nargs; ++k)
          if (!c.arg_const[k] && spec.args[k].dist != Dist::Integer)
            for (int l = 0; l < 4; ++l) c.perturb[4 * k + size_t(l)] = true;
        for (int k = 0; k < 5; ++k) c.perturb[size_t(kPreload + k)] = true;  // uv, position

        c.first_item = entries.size();
        for (int item = 0; item < kItems; ++item) {
          std::vector<std::array<float, 4>> v(std::max<size_t>(nargs, 1));
          for (size_t k = 0; k < nargs; ++k)
            for (auto& f : v[k]) f = draw(rng, spec.args[k]);
          if (spec.fix) spec.fix(rng, v.data());
          std::vector<float> d(kData, 0.0f);
          for (size_t k = 0; k < nargs; ++k)
            for (int l = 0; l < 4; ++l) d[4 * k + size_t(l)] = v[k][size_t(l)];
          draw_shading(rng, &d[kPreload]);
          data.insert(data.end(), d.begin(), d.end());
          entries.push_back(c.entry);
        }
        cases.push_back(std::move(c));
      }
    }
  }
  {
    // Chained program around a cache block, as the compiler emits it:
    //   MOVE s68 <- s0; CACHE_LOOKUP s72 [skip]; ADD s76 <- s68, s4;
    //   CACHE_STORE s72 <- s76; MUL kDst <- s72, s68; OUTPUT
    // Without a cache context (host reference, cache off) every lookup is a
    // miss: the block runs into its own slot, the STORE delivers it to the
    // point's slot, and the result is (a + b) * a on both sides.
    Case c;
    c.label = "MOVE; CACHE_LOOKUP; ADD; CACHE_STORE; MUL (chained, cache miss)";
    c.out_width = 4;
    c.tol = Tol::Exact;
    const uint32_t block_words = (2 + 2) + (2 + 1);  // ADD + CACHE_STORE
    Operand skip;
    skip.raw = true;
    skip.word = block_words;
    std::vector<Instr> prog = {
        {PMC_OP_MOVE, 4, 0, 68, {Operand{false, false, 0, 4, 0, {}}}},
        {PMC_OP_CACHE_LOOKUP, 4, 0, 72, {skip}},
        {PMC_OP_ADD, 4, 0, 76, {Operand{false, false, 0, 4, 68, {}}, Operand{false, false, 0, 4, 4, {}}}},
        {PMC_OP_CACHE_STORE, 4, 0, 72, {Operand{false, false, 0, 4, 76, {}}}},
        {PMC_OP_MUL, 4, 0, kDst, {Operand{false, false, 0, 4, 72, {}}, Operand{false, false, 0, 4, 68, {}}}},
        {PMC_OP_OUTPUT, 4, 0, 0, {Operand{false, false, 0, 4, kDst, {}}}},
    };
    c.entry = assemble(code, prog);
    c.first_item = entries.size();
    for (int item = 0; item < kItems; ++item) {
      std::vector<float> d(kData, 0.0f);
      for (int k = 0; k < 8; ++k) d[size_t(k)] = uniform(rng, -10, 10);
      draw_shading(rng, &d[kPreload]);
      data.insert(data.end(), d.begin(), d.end());
      entries.push_back(c.entry);
    }
    cases.push_back(std::move(c));
  }

  // Device runs: one item per work-item, and batches of 16 and 64 items per
  // work-item (the lane-batched interpreter of CPU devices).
  const ClContext& cl = test::cl();
  const size_t n = entries.size();
  ASSERT_EQ(kItems % 64, 0) << "a batch must not straddle two programs";
  auto run_device = [&](int lanes) {
    std::ostringstream opts;
    opts << "-DKDATA=" << kData << " -DKPRELOAD=" << kPreload << " -DKDST=" << kDst
         << " -DKSENTINEL=" << kSentinel << "f -DPMC_LANES=" << lanes;
    ClProgram program = ClProgram::from_text(cl, "interpreter_parity_test.cl", kKernel, opts.str());
    ClBuffer code_buf = cl.buffer_of(code);
    ClBuffer entry_buf = cl.buffer_of(entries);
    ClBuffer data_buf = cl.buffer_of(data);
    ClBuffer tex_buf = cl.buffer_of(tex.pool.textures());
    ClBuffer texel_buf = cl.buffer_of(tex.words);
    ClBuffer lut_buf = cl.buffer_of(tex.lut);
    ClBuffer out_buf = cl.buffer(n * 8 * sizeof(float));
    cl_kernel k = program.kernel(lanes == 1 ? "interp_parity" : "interp_parity_lanes");
    set_kernel_args(k, code_buf, entry_buf, data_buf, tex_buf, texel_buf, lut_buf, cl_uint(tex.pool.size()),
                    out_buf, cl_uint(n));
    enqueue_1d(cl.queue(), k, (n + size_t(lanes) - 1) / size_t(lanes));
    std::vector<float> out(n * 8);
    cl.read(out_buf, 0, out.size() * sizeof(float), out.data());
    return out;
  };

  // Compare each device run with the host.
  std::map<std::string, double> worst;  // op -> max |d - h| / tolerance unit, for the record
  for (int lanes : {1, 16, 64}) {
    SCOPED_TRACE("device: " + std::to_string(lanes) + " item(s) per work-item");
    const std::vector<float> dev = run_device(lanes);
    for (const Case& c : cases) {
      int skipped = 0, failures = 0;
      for (int item = 0; item < kItems; ++item) {
        const size_t i = c.first_item + size_t(item);
        const float* d = &data[i * kData];
        float host[8];
        host_run(code, c.entry, d, host_ts, host);
        const float* gpu = &dev[i * 8];
        // Operand values as the program sees them (slots or inline constants).
        auto arg = [&](size_t k2, int l) {
          return c.arg_const[k2] ? c.const_vals[k2][size_t(l)] : d[4 * k2 + size_t(l)];
        };
        double m = 0;
        for (size_t k2 = 0; k2 < c.arg_width.size(); ++k2)
          for (int l = 0; l < c.arg_width[k2]; ++l) m = std::max(m, double(std::fabs(arg(k2, l))));
        if (c.spec && c.spec->args.empty()) m = 100;  // geometric inputs

        // Lanes beyond the width stay untouched; OUTPUT copies the result exactly.
        for (int l = c.out_width; l < 4; ++l) {
          EXPECT_EQ(host[l], kSentinel) << c.label << ": host wrote lane " << l;
          EXPECT_EQ(gpu[l], kSentinel) << c.label << ": device wrote lane " << l;
          EXPECT_EQ(host[4 + l], kSentinel) << c.label << ": host OUTPUT wrote param " << l;
          EXPECT_EQ(gpu[4 + l], kSentinel) << c.label << ": device OUTPUT wrote param " << l;
        }
        if (!c.spec)  // the chained program: a miss runs the block, (a + b) * a
          for (int l = 0; l < 4; ++l)
            EXPECT_EQ(host[l], (d[l] + d[4 + l]) * d[l]) << c.label << " lane " << l;
        bool ok = true;
        std::ostringstream why;
        why << std::setprecision(9);
        for (int l = 0; l < c.out_width; ++l) {
          if (c.spec) {  // OUTPUT is exact on each side
            EXPECT_EQ(std::memcmp(&host[l], &host[4 + l], 4), 0) << c.label << ": host OUTPUT lane " << l;
            EXPECT_EQ(std::memcmp(&gpu[l], &gpu[4 + l], 4), 0) << c.label << ": device OUTPUT lane " << l;
          }
          const double tol = tolerance(c.tol, host[l], m);
          const double err = std::fabs(double(gpu[l]) - double(host[l]));
          const bool finite = std::isfinite(host[l]) && std::isfinite(gpu[l]);
          if (!finite && !(c.spec == nullptr && std::memcmp(&host[l], &gpu[l], 4) == 0)) ok = false;
          if (finite && err > tol) ok = false;
          if (finite && c.spec) {
            const double unit = tol > 0 ? tol : kEps;
            double& w = worst[op_name(c.spec->op)];
            w = std::max(w, err / unit);
          }
          why << (l ? ", " : "") << "lane " << l << ": device " << gpu[l] << " host " << host[l]
              << " (|diff| " << err << ", tolerance " << tol << ")";
        }
        if (ok) continue;
        if (c.discontinuous) {
          // Is the item within ~1e-4 of a jump? Nudge the continuous inputs and
          // see whether the host result itself changes by more than the tolerance.
          bool near = false;
          for (int trial = 0; trial < 8 && !near; ++trial) {
            std::vector<float> p(d, d + kData);
            for (size_t q = 0; q < p.size(); ++q)
              if (c.perturb[q]) p[q] += uniform(rng, -1e-4f, 1e-4f) * std::max(1.0f, std::fabs(p[q]));
            float h2[8];
            host_run(code, c.entry, p.data(), host_ts, h2);
            for (int l = 0; l < c.out_width; ++l)
              near = near || !(std::fabs(double(h2[l]) - double(host[l])) <= tolerance(c.tol, host[l], m));
          }
          if (near) {
            ++skipped;
            continue;
          }
        }
        if (++failures <= 3) {
          std::ostringstream inputs;
          inputs << std::setprecision(9);
          for (size_t k2 = 0; k2 < c.arg_width.size(); ++k2) {
            inputs << " arg" << k2 << (c.arg_const[k2] ? "(const)" : "") << "=(";
            for (int l = 0; l < c.arg_width[k2]; ++l) inputs << (l ? " " : "") << arg(k2, l);
            inputs << ")";
          }
          ADD_FAILURE() << c.label << ", item " << item << ":" << inputs.str() << " uv=(" << d[kPreload]
                        << " " << d[kPreload + 1] << ") footprint " << d[kPreload + 14] << "\n  "
                        << why.str();
        }
      }
      EXPECT_EQ(failures, 0) << c.label;
      // The skip must stay rare, or the comparison says nothing.
      EXPECT_LE(skipped, kItems / 20) << c.label << ": too many inputs near a discontinuity";
    }
  }
  std::ostringstream summary;
  for (const auto& [name, w] : worst) summary << name << "=" << w << " ";
  RecordProperty("device", cl.description());
  RecordProperty("worst_error_in_tolerance_units", summary.str());
  if (std::getenv("PMC_TEST_VERBOSE")) std::printf("worst |diff| / tolerance: %s\n", summary.str().c_str());
}

}  // namespace
}  // namespace pmc
