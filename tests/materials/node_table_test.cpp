// node_table_test.cpp — the node table (materials/node_table.h) against the interpreter.
//
// The table lists each node's inputs in the order its opcode reads them; the
// interpreter (core/device/pmc_interp.h) reads operands by the slot names
// PMC_OPCODES gives them. The names tie the two together only where a node's
// inputs carry its opcode's slot names (checked at the end), so here every
// node the table emits is compiled through the table with a distinct value
// in every input lane, run on the host interpreter, and compared with an
// answer computed from the inputs *by name*: an analytic formula, or a
// direct call of the device function the opcode wraps with the named
// arguments in their documented places. Swapping any two inputs of
// different roles changes the answer. A node without an expected answer
// here fails the completeness test, so a new node cannot be added to the
// table without one.
#include "materials/node_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/device/pmc_interp.h"
#include "materials/emit.h"

namespace pmc {
namespace {

using Named = std::map<std::string, float4>;
struct Shading {
  float2 uv = make_float2(0.3125f, 0.6875f);
  float3 p = make_float3(1.25f, -0.75f, 2.5f);
  float3 n = make_float3(0.0f, 0.6f, 0.8f);
  float3 t = make_float3(1.0f, 0.0f, 0.0f);
  float3 b = make_float3(0.0f, 0.8f, -0.6f);
};
using Expected = std::function<float4(const Named& in, const Shading& s, int width)>;

float4 f4(float x, float y, float z, float w) { return make_float4(x, y, z, w); }
float4 bc(float x) { return make_float4(x, x, x, x); }
float lane(float4 v, int i) { return i == 0 ? v.x : i == 1 ? v.y : i == 2 ? v.z : v.w; }
float4 map4(float4 a, float4 b, float (*fn)(float, float)) {
  return f4(fn(a.x, b.x), fn(a.y, b.y), fn(a.z, b.z), fn(a.w, b.w));
}
float4 map1(float4 a, float (*fn)(float)) { return f4(fn(a.x), fn(a.y), fn(a.z), fn(a.w)); }
float2 xy(float4 v) { return make_float2(v.x, v.y); }
float3 xyz(float4 v) { return make_float3(v.x, v.y, v.z); }
float smooth1(float x, float lo, float hi) {
  if (x >= hi) return 1.0f;
  if (x <= lo) return 0.0f;
  float t = (x - lo) / (hi - lo);
  return t * t * (3.0f - 2.0f * t);
}

// The answer for each node, from its inputs by name.
std::map<std::string, Expected> expectations() {
  std::map<std::string, Expected> e;
  e["constant"] = [](const Named& in, const Shading&, int) { return in.at("value"); };
  e["dot"] = [](const Named& in, const Shading&, int) { return in.at("in"); };
  e["texcoord"] = [](const Named&, const Shading& s, int) { return f4(s.uv.x, s.uv.y, 0, 0); };
  e["position"] = [](const Named&, const Shading& s, int) { return f4(s.p.x, s.p.y, s.p.z, 0); };
  e["normal"] = [](const Named&, const Shading& s, int) { return f4(s.n.x, s.n.y, s.n.z, 0); };
  e["tangent"] = [](const Named&, const Shading& s, int) { return f4(s.t.x, s.t.y, s.t.z, 0); };
  e["bitangent"] = [](const Named&, const Shading& s, int) { return f4(s.b.x, s.b.y, s.b.z, 0); };
  e["place2d"] = [](const Named& in, const Shading&, int) {
    return pmc_place2d(in.at("texcoord"), in.at("pivot"), in.at("scale"), in.at("rotate").x, in.at("offset"),
                       int(in.at("operationorder").x));
  };
  e["noise2d"] = [](const Named& in, const Shading&, int w) {
    return pmc_op_noise2d(xy(in.at("texcoord")), pmc_u32(w)) * in.at("amplitude") + bc(in.at("pivot").x);
  };
  e["noise3d"] = [](const Named& in, const Shading&, int w) {
    return pmc_op_noise3d(xyz(in.at("position")), pmc_u32(w)) * in.at("amplitude") + bc(in.at("pivot").x);
  };
  e["fractal2d"] = [](const Named& in, const Shading&, int w) {
    return pmc_op_fractal2d(xy(in.at("texcoord")), int(in.at("octaves").x), in.at("lacunarity").x,
                            in.at("diminish").x, pmc_u32(w)) *
           in.at("amplitude");
  };
  e["fractal3d"] = [](const Named& in, const Shading&, int w) {
    return pmc_op_fractal3d(xyz(in.at("position")), int(in.at("octaves").x), in.at("lacunarity").x,
                            in.at("diminish").x, pmc_u32(w)) *
           in.at("amplitude");
  };
  e["cellnoise2d"] = [](const Named& in, const Shading&, int) {
    return bc(pmc_op_cellnoise2d(xy(in.at("texcoord"))));
  };
  e["cellnoise3d"] = [](const Named& in, const Shading&, int) {
    return bc(pmc_op_cellnoise3d(xyz(in.at("position"))));
  };
  e["worleynoise2d"] = [](const Named& in, const Shading&, int w) {
    return pmc_op_worley2d(xy(in.at("texcoord")), in.at("jitter").x, int(in.at("style").x), pmc_u32(w));
  };
  e["worleynoise3d"] = [](const Named& in, const Shading&, int w) {
    return pmc_op_worley3d(xyz(in.at("position")), in.at("jitter").x, int(in.at("style").x), pmc_u32(w));
  };
  e["add"] = [](const Named& in, const Shading&, int) { return in.at("in1") + in.at("in2"); };
  e["subtract"] = [](const Named& in, const Shading&, int) { return in.at("in1") - in.at("in2"); };
  e["multiply"] = [](const Named& in, const Shading&, int) { return in.at("in1") * in.at("in2"); };
  e["divide"] = [](const Named& in, const Shading&, int) { return in.at("in1") / in.at("in2"); };
  e["modulo"] = [](const Named& in, const Shading&, int) {
    return map4(in.at("in1"), in.at("in2"), [](float a, float b) { return a - b * std::floor(a / b); });
  };
  e["power"] = [](const Named& in, const Shading&, int) {
    return map4(in.at("in1"), in.at("in2"), [](float a, float b) { return std::pow(a, b); });
  };
  e["min"] = [](const Named& in, const Shading&, int) {
    return map4(in.at("in1"), in.at("in2"), [](float a, float b) { return std::fmin(a, b); });
  };
  e["max"] = [](const Named& in, const Shading&, int) {
    return map4(in.at("in1"), in.at("in2"), [](float a, float b) { return std::fmax(a, b); });
  };
  e["absval"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::fabs); };
  e["floor"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::floor); };
  e["ceil"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::ceil); };
  e["sin"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::sin); };
  e["cos"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::cos); };
  e["sqrt"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::sqrt); };
  e["normalize"] = [](const Named& in, const Shading&, int w) {
    float4 a = in.at("in");
    float l2 = 0;
    for (int i = 0; i < w; ++i) l2 += lane(a, i) * lane(a, i);
    return a * (1.0f / std::sqrt(l2));
  };
  e["clamp"] = [](const Named& in, const Shading&, int) {
    float4 r = map4(in.at("in"), in.at("low"), [](float a, float b) { return std::fmax(a, b); });
    return map4(r, in.at("high"), [](float a, float b) { return std::fmin(a, b); });
  };
  e["smoothstep"] = [](const Named& in, const Shading&, int) {
    float4 x = in.at("in"), lo = in.at("low"), hi = in.at("high");
    return f4(smooth1(x.x, lo.x, hi.x), smooth1(x.y, lo.y, hi.y), smooth1(x.z, lo.z, hi.z),
              smooth1(x.w, lo.w, hi.w));
  };
  e["remap"] = [](const Named& in, const Shading&, int) {
    return in.at("outlow") + (in.at("in") - in.at("inlow")) * (in.at("outhigh") - in.at("outlow")) /
                                 (in.at("inhigh") - in.at("inlow"));
  };
  e["mix"] = [](const Named& in, const Shading&, int) {
    return in.at("bg") + (in.at("fg") - in.at("bg")) * in.at("mix");
  };
  e["ifgreater"] = [](const Named& in, const Shading&, int) {
    return in.at("value1").x > in.at("value2").x ? in.at("in1") : in.at("in2");
  };
  e["ifgreatereq"] = [](const Named& in, const Shading&, int) {
    return in.at("value1").x >= in.at("value2").x ? in.at("in1") : in.at("in2");
  };
  auto clamp01 = [](float x) { return std::fmin(std::fmax(x, 0.0f), 1.0f); };
  e["ramplr"] = [=](const Named& in, const Shading&, int) {
    return in.at("valuel") + (in.at("valuer") - in.at("valuel")) * clamp01(in.at("texcoord").x);
  };
  e["ramptb"] = [=](const Named& in, const Shading&, int) {
    return in.at("valueb") + (in.at("valuet") - in.at("valueb")) * clamp01(in.at("texcoord").y);
  };
  e["ramp4"] = [=](const Named& in, const Shading&, int) {
    float s = clamp01(in.at("texcoord").x), t = clamp01(in.at("texcoord").y);
    float4 top = in.at("valuetl") + (in.at("valuetr") - in.at("valuetl")) * s;
    float4 bottom = in.at("valuebl") + (in.at("valuebr") - in.at("valuebl")) * s;
    return bottom + (top - bottom) * t;
  };
  e["splitlr"] = [](const Named& in, const Shading&, int) {
    return in.at("texcoord").x < in.at("center").x ? in.at("valuel") : in.at("valuer");
  };
  e["splittb"] = [](const Named& in, const Shading&, int) {
    return in.at("texcoord").y > in.at("center").x ? in.at("valuet") : in.at("valueb");
  };
  e["rgbtohsv"] = [](const Named& in, const Shading&, int) { return pmc_rgb_to_hsv(in.at("in")); };
  e["hsvtorgb"] = [](const Named& in, const Shading&, int) { return pmc_hsv_to_rgb(in.at("in")); };
  e["luminance"] = [](const Named& in, const Shading&, int) {
    float4 c = in.at("in"), k = in.at("lumacoeffs");
    float l = c.x * k.x + c.y * k.y + c.z * k.z;
    return f4(l, l, l, c.w);
  };
  e["combine3"] = [](const Named& in, const Shading&, int) {
    return f4(in.at("in1").x, in.at("in2").x, in.at("in3").x, 0);
  };
  e["combine4"] = [](const Named& in, const Shading&, int) {
    return f4(in.at("in1").x, in.at("in2").x, in.at("in3").x, in.at("in4").x);
  };
  e["normalmap"] = [](const Named& in, const Shading&, int) {
    return pmc_normalmap(in.at("in"), in.at("scale").x, xyz(in.at("normal")), xyz(in.at("tangent")));
  };
  auto shape = [](pmc_u32 kind) {
    return [kind](const Named& in, const Shading&, int) {
      return pmc_op_tiledshape(xy(in.at("texcoord")), xy(in.at("uvtiling")), xy(in.at("uvoffset")),
                               in.at("size").x, in.at("staggered").x != 0.0f, kind);
    };
  };
  e["tiledcircles"] = shape(PMC_SHAPE_CIRCLES);
  e["tiledcloverleafs"] = shape(PMC_SHAPE_CLOVERLEAFS);
  e["tiledhexagons"] = shape(PMC_SHAPE_HEXAGONS);
  auto lines = [](pmc_u32 kind) {
    return [kind](const Named& in, const Shading&, int) {
      return pmc_op_linepattern(xy(in.at("texcoord")), xy(in.at("uvtiling")), xy(in.at("uvoffset")),
                                in.at("thickness").x, in.at("staggered").x != 0.0f, kind);
    };
  };
  e["grid"] = lines(PMC_LINES_GRID);
  e["crosshatch"] = lines(PMC_LINES_CROSSHATCH);
  e["tan"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::tan); };
  e["asin"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::asin); };
  e["acos"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::acos); };
  e["exp"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::exp); };
  e["ln"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::log); };
  e["sign"] = [](const Named& in, const Shading&, int) {
    return map1(in.at("in"), [](float x) { return x > 0 ? 1.0f : x < 0 ? -1.0f : 0.0f; });
  };
  e["round"] = [](const Named& in, const Shading&, int) { return map1(in.at("in"), std::round); };
  e["fract"] = [](const Named& in, const Shading&, int) {
    return map1(in.at("in"), [](float x) { return x - std::floor(x); });
  };
  e["atan2"] = [](const Named& in, const Shading&, int) {
    return map4(in.at("iny"), in.at("inx"), [](float y, float x) { return std::atan2(y, x); });
  };
  e["magnitude"] = [](const Named& in, const Shading&, int) {  // of a vector3 (any_type)
    float4 a = in.at("in");
    return bc(std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z));
  };
  e["crossproduct"] = [](const Named& in, const Shading&, int) {
    float3 c = cross(xyz(in.at("in1")), xyz(in.at("in2")));
    return f4(c.x, c.y, c.z, 0);
  };
  e["and"] = [](const Named& in, const Shading&, int) {
    return bc(in.at("in1").x != 0 && in.at("in2").x != 0 ? 1.0f : 0.0f);
  };
  e["or"] = [](const Named& in, const Shading&, int) {
    return bc(in.at("in1").x != 0 || in.at("in2").x != 0 ? 1.0f : 0.0f);
  };
  e["not"] = [](const Named& in, const Shading&, int) { return bc(in.at("in").x == 0 ? 1.0f : 0.0f); };
  e["ifequal"] = [](const Named& in, const Shading&, int) {
    return in.at("value1").x == in.at("value2").x ? in.at("in1") : in.at("in2");
  };
  // MaterialX's GLSL: mix * f(fg, bg) + (1 - mix) * bg.
  auto blend = [](float (*f)(float, float)) {
    return [f](const Named& in, const Shading&, int) {
      float4 fg = in.at("fg"), bg = in.at("bg");
      float m = in.at("mix").x;
      float4 r;
      for (int l = 0; l < 4; ++l) {
        float v = m * f(lane(fg, l), lane(bg, l)) + (1 - m) * lane(bg, l);
        (l == 0 ? r.x : l == 1 ? r.y : l == 2 ? r.z : r.w) = v;
      }
      return r;
    };
  };
  e["plus"] = blend([](float fg, float bg) { return fg + bg; });
  e["minus"] = blend([](float fg, float bg) { return bg - fg; });
  e["difference"] = blend([](float fg, float bg) { return std::fabs(bg - fg); });
  e["burn"] = blend([](float fg, float bg) { return 1 - (1 - bg) / fg; });
  e["dodge"] = blend([](float fg, float bg) { return bg / (1 - fg); });
  e["screen"] = blend([](float fg, float bg) { return 1 - (1 - fg) * (1 - bg); });
  // MaterialX Standard Nodes, merge nodes: F, B colours, f, b alphas;
  // mix * result + (1 - mix) * bg.
  auto merge = [](float4 (*f)(float4 fg, float4 bg)) {
    return [f](const Named& in, const Shading&, int) {
      float4 bg = in.at("bg");
      float m = in.at("mix").x;
      return f(in.at("fg"), bg) * m + bg * (1 - m);
    };
  };
  e["disjointover"] = merge([](float4 F, float4 B) {
    float4 r = F.w + B.w <= 1 ? F + B : F + B * ((1 - F.w) / B.w);
    r.w = std::fmin(F.w + B.w, 1.0f);
    return r;
  });
  e["in"] = merge([](float4 F, float4 B) { return f4(F.x * B.w, F.y * B.w, F.z * B.w, F.w * B.w); });
  e["mask"] = merge([](float4 F, float4 B) { return f4(B.x * F.w, B.y * F.w, B.z * F.w, B.w * F.w); });
  e["matte"] = merge([](float4 F, float4 B) {
    return f4(F.x * F.w + B.x * (1 - F.w), F.y * F.w + B.y * (1 - F.w), F.z * F.w + B.z * (1 - F.w),
              F.w + B.w * (1 - F.w));
  });
  e["out"] = merge([](float4 F, float4 B) { return F * (1 - B.w); });
  e["over"] = merge([](float4 F, float4 B) { return F + B * (1 - F.w); });
  e["premult"] = [](const Named& in, const Shading&, int) {
    float4 a = in.at("in");
    return f4(a.x * a.w, a.y * a.w, a.z * a.w, a.w);
  };
  e["unpremult"] = [](const Named& in, const Shading&, int) {
    float4 a = in.at("in");
    return f4(a.x / a.w, a.y / a.w, a.z / a.w, a.w);
  };
  e["inside"] = [](const Named& in, const Shading&, int) { return in.at("in") * in.at("mask").x; };
  e["outside"] = [](const Named& in, const Shading&, int) { return in.at("in") * (1 - in.at("mask").x); };
  e["rotate2d"] = [](const Named& in, const Shading&, int) {
    float4 v = in.at("in");
    double a = double(in.at("amount").x) * M_PI / 180.0;
    return f4(float(std::cos(a) * v.x + std::sin(a) * v.y), float(-std::sin(a) * v.x + std::cos(a) * v.y), 0,
              0);
  };
  e["rotate3d"] = [](const Named& in, const Shading&, int) {
    // Rodrigues' rotation of `in` by -amount about the axis (MaterialX's v' = v M).
    float3 v = xyz(in.at("in")), k = normalize(xyz(in.at("axis")));
    double a = double(in.at("amount").x) * M_PI / 180.0;
    float c = float(std::cos(a)), s = float(std::sin(a));
    float3 r = v * c + cross(v, k) * s + k * (dot(k, v) * (1 - c));
    return f4(r.x, r.y, r.z, 0);
  };
  e["transformpoint"] = [](const Named& in, const Shading&, int) { return in.at("in"); };
  e["transformvector"] = [](const Named& in, const Shading&, int) { return in.at("in"); };
  e["transformnormal"] = [](const Named& in, const Shading&, int) {
    float3 n = normalize(xyz(in.at("in")));
    return f4(n.x, n.y, n.z, 0);
  };
  // Special emitters (Emit::Convert ... Emit::WidthImm), with the input types chosen in any_type().
  e["convert"] = [](const Named& in, const Shading&, int w) {  // from vector2
    float4 a = in.at("in");
    return w <= 2 ? a : f4(a.x, a.y, 0, w == 4 ? 1.0f : 0.0f);
  };
  e["extract"] = [](const Named& in, const Shading&, int) { return bc(in.at("in").z); };  // index 2
  e["swizzle"] = [](const Named& in, const Shading&, int) {                               // channels "zxy"
    float4 a = in.at("in");
    return f4(a.z, a.x, a.y, 0);
  };
  e["combine2"] = [](const Named& in, const Shading&, int w) {
    float4 a = in.at("in1"), b = in.at("in2");
    return w == 2 ? f4(a.x, b.x, 0, 0) : f4(a.x, a.y, b.x, b.y);  // vector4 from two vector2
  };
  e["dotproduct"] = [](const Named& in, const Shading&, int) {
    float4 a = in.at("in1"), b = in.at("in2");
    return bc(a.x * b.x + a.y * b.y + a.z * b.z);
  };
  // Multi-output nodes: one answer per output, "category.output".
  for (const char* cat : {"flake2d", "flake3d"}) {
    const bool three = cat[5] == '3';
    auto flake = [three](const Named& in) {
      float4 p = in.at(three ? "position" : "texcoord");
      return pmc_flake(in.at("size").x, in.at("roughness").x, in.at("coverage").x,
                       make_float3(p.x, p.y, three ? p.z : 0.0f), xyz(in.at("normal")), xyz(in.at("tangent")),
                       xyz(in.at("bitangent")));
    };
    const std::string c = cat;
    e[c + ".id"] = [flake](const Named& in, const Shading&, int) { return bc(flake(in).id); };
    e[c + ".rand"] = [flake](const Named& in, const Shading&, int) { return bc(flake(in).rand); };
    e[c + ".presence"] = [flake](const Named& in, const Shading&, int) { return bc(flake(in).presence); };
    e[c + ".flakenormal"] = [flake](const Named& in, const Shading&, int) {
      float3 n = flake(in).normal;
      return f4(n.x, n.y, n.z, 0);
    };
  }
  // pbrlib data nodes: MaterialX's GLSL (libraries/pbrlib/genglsl), in double.
  const double eps = 1.1920928955078125e-7;
  auto clampd = [](double x, double lo, double hi) { return std::min(std::max(x, lo), hi); };
  e["roughness_anisotropy"] = [=](const Named& in, const Shading&, int) {
    double r = in.at("roughness").x, an = in.at("anisotropy").x;
    double a = clampd(r * r, eps, 1.0);
    if (an <= 0) return f4(float(a), float(a), 0, 0);
    double s = std::sqrt(1.0 - clampd(an, 0.0, 0.98));
    return f4(float(std::min(a / s, 1.0)), float(a * s), 0, 0);
  };
  e["roughness_dual"] = [=](const Named& in, const Shading&, int) {
    double x = in.at("roughness").x, y = in.at("roughness").y;
    if (y < 0) y = x;
    return f4(float(clampd(x * x, eps, 1.0)), float(clampd(y * y, eps, 1.0)), 0, 0);
  };
  // Gulbrandsen 2014, eqs. for n(r, g) and k(r, n).
  auto gulbrandsen = [=](const Named& in, bool extinction) {
    float out[3];
    for (int l = 0; l < 3; ++l) {
      double r = clampd(lane(in.at("reflectivity"), l), 0.0, 0.99), g = lane(in.at("edge_color"), l);
      double n = g * (1 - r) / (1 + r) + (1 - g) * (1 + std::sqrt(r)) / (1 - std::sqrt(r));
      double k = std::sqrt(std::max(0.0, ((n + 1) * (n + 1) * r - (n - 1) * (n - 1)) / (1 - r)));
      out[l] = float(extinction ? k : n);
    }
    return f4(out[0], out[1], out[2], 0);
  };
  e["artistic_ior.ior"] = [=](const Named& in, const Shading&, int) { return gulbrandsen(in, false); };
  e["artistic_ior.extinction"] = [=](const Named& in, const Shading&, int) { return gulbrandsen(in, true); };
  // blackbody of the test's temperature input (0.23 + ...): clamped to 800 K; its
  // values are checked against published chromaticities in pbr_data_test.cpp.
  e["blackbody"] = [](const Named& in, const Shading&, int) { return pmc_blackbody(in.at("temperature").x); };
  // Hair data nodes: MaterialX's GLSL (mx_chiang_hair_bsdf.glsl), in double.
  const char* hair_outputs[] = {"roughness_R", "roughness_TT", "roughness_TRT"};
  for (int o = 0; o < 3; ++o)
    e[std::string("chiang_hair_roughness.") + hair_outputs[o]] = [=](const Named& in, const Shading&, int) {
      double l = clampd(in.at("longitudinal").x, 0.001, 1.0), a = clampd(in.at("azimuthal").x, 0.001, 1.0);
      double v = std::pow(0.726 * l + 0.812 * l * l + 3.7 * std::pow(l, 20.0), 2.0);
      double s = 0.265 * a + 1.194 * a * a + 5.372 * std::pow(a, 22.0);
      double scale = o == 0 ? 1.0 : std::pow(in.at(o == 1 ? "scale_TT" : "scale_TRT").x, 2.0);
      return f4(float(v * scale), float(s), 0, 0);
    };
  e["deon_hair_absorption_from_melanin"] = [=](const Named& in, const Shading&, int) {
    double m = -std::log(std::max(1.0 - in.at("melanin_concentration").x, 1e-4));
    double red = in.at("melanin_redness").x;
    float out[3];
    for (int l = 0; l < 3; ++l)
      out[l] = float(std::max(0.0, m * (1 - red) * -std::log(lane(in.at("eumelanin_color"), l)) +
                                       m * red * -std::log(lane(in.at("pheomelanin_color"), l))));
    return f4(out[0], out[1], out[2], 0);
  };
  e["chiang_hair_absorption_from_color"] = [=](const Named& in, const Shading&, int) {
    double b = in.at("azimuthal_roughness").x;
    double fac = 5.969 - 0.215 * b + 2.532 * b * b - 10.73 * std::pow(b, 3) + 5.574 * std::pow(b, 4) +
                 0.245 * std::pow(b, 5);
    float out[3];
    for (int l = 0; l < 3; ++l)
      out[l] = float(std::pow(std::log(clampd(lane(in.at("color"), l), 0.001, 1.0)) / fac, 2));
    return f4(out[0], out[1], out[2], 0);
  };
  return e;
}

// The expectation keys of a node: its category, or "category.output" for
// each output of a multi-output node.
std::vector<std::pair<std::string, std::string>> answer_keys(const NodeDef& def) {
  if (def.outputs.empty()) return {{def.category, ""}};
  std::vector<std::pair<std::string, std::string>> keys;
  for (const OutputDef& o : def.outputs) keys.push_back({def.category + "." + o.name, o.name});
  return keys;
}

// Types of "any" inputs, and string inputs the special emitters read.
ValueType any_type(const std::string& category, const std::string& input, ValueType node_type) {
  if (category == "convert") return ValueType::Vector2;
  if (category == "extract") return ValueType::Color4;
  if (category == "swizzle") return ValueType::Color3;
  if (category == "combine2") return node_type == ValueType::Vector2 ? ValueType::Float : ValueType::Vector2;
  if (category == "dotproduct" || category == "magnitude") return ValueType::Vector3;
  ADD_FAILURE() << category << " input " << input << ": no type chosen for an 'any' input";
  return ValueType::Float;
}

// Distinct values: input k, lane l. Integer and boolean inputs get small
// integers (they select modes, octaves, styles), distinct from the floats.
float4 value_for(const InputDef& d, int k, const std::string& category) {
  if (category == "extract" && d.name == "index") return bc(2);
  if (d.type == "integer" || d.type == "boolean") {
    float v = d.name == "octaves" ? 3.0f : 1.0f;
    return bc(v);
  }
  float base = 0.23f + 0.31f * float(k);
  if (d.name == "scale" && category == "place2d") base = 1.7f;  // not a divisor near 0
  if (category.compare(0, 5, "flake") == 0) {                   // a point that a flake covers (checked below)
    if (d.name == "size") return bc(0.05f);
    if (d.name == "coverage") return bc(0.9f);
    // A frame of distinct directions (the defaults would all lie near (1, 1, 1)).
    if (d.name == "normal") return f4(0.1f, 0.2f, 0.9f, 0.3f);
    if (d.name == "tangent") return f4(0.9f, 0.1f, -0.2f, 0.4f);
    if (d.name == "bitangent") return f4(-0.2f, 0.9f, 0.1f, 0.5f);
  }
  return f4(base, base + 0.07f, base + 0.11f, base + 0.19f);
}

struct Evaluated {
  float4 got;
  Named named;
};

Evaluated evaluate(const NodeDef& def, ValueType type, const Shading& s, const std::string& output = "") {
  Graph g;
  Node n;
  n.name = "n";
  n.category = def.category;
  n.type = type;
  n.output = output;
  n.origin = "node_table_test: " + def.category;
  Evaluated r;
  int k = 0;
  for (const InputDef& d : def.inputs) {
    Input in;
    in.name = d.name;
    in.type = resolve_input_type(d, type);
    if (d.type == "any") in.type = any_type(def.category, d.name, type);
    if (in.type == ValueType::String || in.type == ValueType::Filename) {
      in.value = d.value;
      in.value.type = in.type;
      if (def.category == "swizzle") in.value.text = "zxy";
    } else {
      float4 v = value_for(d, k++, def.category);
      in.value = Value::number(in.type, v.x, v.y, v.z, v.w);
      // What the interpreter sees: a width-1 operand broadcasts.
      r.named[d.name] = type_width(in.type) == 1 ? bc(v.x) : v;
    }
    n.inputs.push_back(in);
  }
  g.add(n);
  TexturePool textures;
  Emitter em;
  EmitContext cx{g, &textures, em,
                 [&](const Input& in) { return em.constant(in.value, type_width(in.type)); }};
  emit_node(cx, g.nodes[0], 0);
  std::vector<uint32_t> code = em.finish(0);
  float stack[PMC_STACK_SIZE] = {0};
  float params[PMC_P_COUNT] = {0};
  PmcShadingInputs in{};
  in.uv = s.uv;
  in.position = s.p;
  in.normal = s.n;
  in.tangent = s.t;
  in.bitangent = s.b;
  PmcTextureSet ts{};
  pmc_interp_run(code.data(), 0, &in, &ts, stack, params, nullptr);
  r.got = f4(stack[0], stack[1], stack[2], stack[3]);
  return r;
}

bool tested_here(const NodeDef& def) { return def.emit != Emit::Lowered && def.emit != Emit::Image; }

TEST(NodeTable, EveryEmittedNodeHasAnExpectedAnswer) {
  const auto e = expectations();
  for (const std::string& c : supported_categories()) {
    const NodeDef* def = find_node_def(c);
    ASSERT_NE(def, nullptr);
    if (tested_here(*def))
      for (const auto& key : answer_keys(*def))
        EXPECT_TRUE(e.count(key.first))
            << "node '" << key.first << "' has no expected answer in node_table_test.cpp: add one";
  }
}

TEST(NodeTable, OperandOrderMatchesTheInterpreterForEveryNode) {
  const auto e = expectations();
  const Shading s;
  int checked = 0;
  for (const std::string& c : supported_categories()) {
    const NodeDef* def = find_node_def(c);
    if (!tested_here(*def)) continue;
    std::vector<std::tuple<std::string, std::string, std::string>> runs;  // key, output, type
    for (const std::string& t : def->output_types) runs.emplace_back(c, "", t);
    for (const OutputDef& o : def->outputs) runs.emplace_back(c + "." + o.name, o.name, o.type);
    for (const auto& [key, output, t] : runs) {
      if (!e.count(key)) continue;
      const ValueType type = parse_type(t);
      const int w = type_width(type);
      Evaluated r = evaluate(*def, type, s, output);
      float4 want = e.at(key)(r.named, s, w);
      for (int l = 0; l < w; ++l) {
        const float got = lane(r.got, l), exp = lane(want, l);
        EXPECT_NEAR(got, exp, 1e-5f * (1.0f + std::fabs(exp))) << key << " (" << t << ") lane " << l;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

// The check above must be able to fail: had the table listed two inputs of
// different roles the other way round, the interpreter would have read each
// one's value in the other's place, which is what the expectation computes
// here with the two named values exchanged. It must differ from the answer.
TEST(NodeTable, SwappedInputsAreDetected) {
  const auto e = expectations();
  const Shading s;
  for (auto [c, a, b] : {std::tuple<const char*, const char*, const char*>{"clamp", "in", "high"},
                         {"remap", "in", "inlow"},
                         {"noise2d", "amplitude", "pivot"},
                         {"ifgreater", "value1", "value2"},
                         {"place2d", "pivot", "offset"},
                         {"flake3d.flakenormal", "normal", "tangent"},
                         {"flake2d.rand", "size", "roughness"},
                         {"roughness_anisotropy", "roughness", "anisotropy"},
                         {"artistic_ior.ior", "reflectivity", "edge_color"},
                         {"chiang_hair_roughness.roughness_TT", "longitudinal", "azimuthal"},
                         {"deon_hair_absorption_from_melanin", "melanin_concentration", "melanin_redness"}}) {
    const std::string key = c;
    const size_t dot = key.find('.');
    const std::string output = dot == std::string::npos ? "" : key.substr(dot + 1);
    const NodeDef* def = find_node_def(key.substr(0, dot));
    const ValueType type =
        parse_type(output.empty() ? def->output_types.front() : find_output(*def, output)->type);
    Evaluated r = evaluate(*def, type, s, output);
    Named swapped = r.named;
    std::swap(swapped[a], swapped[b]);
    float4 right = e.at(key)(r.named, s, type_width(type)), wrong = e.at(key)(swapped, s, type_width(type));
    EXPECT_NEAR(r.got.x, right.x, 1e-5f) << c;
    EXPECT_GT(std::fabs(r.got.x - wrong.x), 1e-3f)
        << c << ": swapping " << a << " and " << b << " went unseen";
  }
}

// The flake answers above check the operand order only if the test point
// lies on a flake (no flake: id, rand and presence are 0 whatever the inputs).
TEST(NodeTable, FlakeTestPointLiesOnAFlake) {
  const Shading s;
  for (const char* c : {"flake2d", "flake3d"}) {
    Evaluated r = evaluate(*find_node_def(c), ValueType::Float, s, "presence");
    EXPECT_GT(r.got.x, 0.0f) << c;
  }
}

// standard_surface's defaults exist once (PMC_STANDARD_SURFACE): the
// table's and the device's agree, and they are MaterialX 1.39's.
TEST(NodeTable, StandardSurfaceDefaultsAreTheDevicesDefaults) {
  float p[PMC_P_COUNT];
  pmc_surface_defaults(p, make_float3(0, 0, 0));
  for (const SurfaceParam& sp : surface_params("standard_surface"))
    for (int k = 0; k < (type_width(sp.type) == 1 ? 1 : 3); ++k)
      EXPECT_EQ(sp.def[k], p[sp.param + k]) << sp.input << " lane " << k;
  EXPECT_EQ(p[PMC_P_BASE_COLOR], 0.8f);  // MaterialX 1.39 standard_surface base_color
  EXPECT_EQ(p[PMC_P_SPECULAR_ROUGHNESS], 0.2f);
  EXPECT_EQ(p[PMC_P_COAT_ROUGHNESS], 0.1f);
}

}  // namespace
}  // namespace pmc

namespace pmc {
namespace {

// The opcode table's operand slots (PMC_OPCODES): operand counts and names.
struct OpcodeSlots {
  unsigned lo, hi;
  std::vector<std::string> names;
};
std::vector<OpcodeSlots> opcode_slots() {
  std::vector<OpcodeSlots> ops;
#define PMC_TEST_OP_SLOTS(name, lo, hi, slots) ops.push_back({lo, hi, split_slot_names(#slots)});
  auto split_slot_names = [](std::string s) {  // "(in, low, high)"
    std::vector<std::string> names;
    std::string cur;
    for (char c : s) {
      if (c == '(' || c == ' ') continue;
      if (c == ',' || c == ')') {
        if (!cur.empty()) names.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
    return names;
  };
  PMC_OPCODES(PMC_TEST_OP_SLOTS)
#undef PMC_TEST_OP_SLOTS
  return ops;
}

// A node's operands as its opcode receives them: the operand inputs in table
// order, and for a texture node the mode Emit::Image adds after `default`.
std::vector<std::string> operand_names(const NodeDef& def) {
  std::vector<std::string> names;
  for (const InputDef& in : def.inputs) {
    if (!in.operand || in.type == "string" || in.type == "filename") continue;
    names.push_back(in.name);
    if (def.emit == Emit::Image && in.name == "default") names.push_back("mode");
  }
  return names;
}

TEST(NodeTable, OperandSlotsNameEveryOpcodesOperandsOnce) {
  const std::vector<OpcodeSlots> ops = opcode_slots();
  ASSERT_EQ(ops.size(), size_t(PMC_OP_COUNT));
  EXPECT_EQ(ops[PMC_OP_CLAMP].names, (std::vector<std::string>{"in", "low", "high"}));
  EXPECT_EQ(unsigned(PMC_ARG_CLAMP_high), 2u);
  EXPECT_EQ(unsigned(PMC_ARG_HEXNORMALMAP_tangent), 14u);
  for (size_t op = 0; op < ops.size(); ++op) {
    EXPECT_EQ(ops[op].names.size(), size_t(ops[op].hi)) << "opcode " << op;
    EXPECT_LE(ops[op].lo, ops[op].hi) << "opcode " << op;
  }
}

// The table's inputs are in the opcode's slot order: every node emitted as an
// opcode passes as many operands as the opcode takes, and a node whose inputs
// carry all of its opcode's slot names has them in the slots' order.
TEST(NodeTable, OperandInputsFollowTheOpcodesSlots) {
  const std::vector<OpcodeSlots> ops = opcode_slots();
  int named = 0;
  for (const std::string& c : supported_categories()) {
    const NodeDef* def = find_node_def(c);
    if (def->opcode < 0 ||
        (def->emit != Emit::Opcode && def->emit != Emit::Image && def->emit != Emit::WidthImm))
      continue;
    const OpcodeSlots& slots = ops[size_t(def->opcode)];
    const std::vector<std::string> names = operand_names(*def);
    EXPECT_GE(names.size(), size_t(slots.lo)) << c;
    EXPECT_LE(names.size(), size_t(slots.hi)) << c;
    if (names.size() == slots.names.size() &&
        std::is_permutation(names.begin(), names.end(), slots.names.begin())) {
      EXPECT_EQ(names, slots.names) << c << ": inputs not in the order of its opcode's slots";
      ++named;
    }
  }
  EXPECT_GT(named, 30);  // most nodes name their operands as their opcode does
}

}  // namespace
}  // namespace pmc
