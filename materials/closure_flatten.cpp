// closure_flatten.cpp — closure trees onto (diffuse, F0, roughness, emission).
#include "materials/closure_flatten.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "core/abi/pmc_bytecode.h"
#include "core/error.h"
#include "materials/node_table.h"

namespace pmc {

bool is_closure_type(ValueType t) {
  return t == ValueType::BSDF || t == ValueType::EDF || t == ValueType::VDF || t == ValueType::Surface;
}

namespace {

using VT = ValueType;

// A closure as pmc's BSDF sees it. Colours are color3, the rest float;
// `normal` unlinked means the shading normal.
struct Lobes {
  Input diffuse, specular, emission;  // Lambert albedo, Schlick F0, radiance
  Input rough;                        // standard_surface roughness (alpha = r²), when has_rough
  bool has_rough = false;
  Input transmission;        // the glass lobe's weight (dielectric_bsdf scatter_mode T or RT)
  Input transmission_color;  // its tint
  Input ior;                 // its IOR
  Input pass;                // the fraction of light a layer below receives
  Input opacity;             // a shader's coverage
  Input normal;
  float spec_hint = 0.0f;  // the specular lobe's strength, as far as constants tell (to share roughness)
};

int width_of(const Input& in) { return std::max(1, type_width(in.type)); }
float lane(const Input& in, int k) { return width_of(in) == 1 ? in.value.f[0] : in.value.f[size_t(k)]; }

class Flattener {
 public:
  Flattener(Graph& g, std::vector<std::string>& notes) : g_(g), notes_(notes) {}

  Lobes of(int id) {
    auto found = memo_.find(id);
    if (found != memo_.end()) return found->second;
    closures_.insert(id);
    if (++depth_ > kMaxClosureDepth)
      fail(g_.nodes[size_t(id)].origin, ": closure graph nested deeper than ", kMaxClosureDepth, " nodes");
    Lobes l = build(id);
    --depth_;
    memo_[id] = l;
    return l;
  }

  const std::set<int>& closures() const { return closures_; }

  // A float as colour (MaterialX's convert broadcasts a float).
  Input widen(const Input& in, VT type) {
    if (width_of(in) == type_width(type) || width_of(in) != 1) return in;
    if (!in.linked) return Input::constant("", type, lane(in, 0), lane(in, 0), lane(in, 0), lane(in, 0));
    return node("convert", type, {named(in, "in")});
  }

  Input c3(float r, float gr, float b) { return Input::constant("", VT::Color3, r, gr, b); }
  Input f1(float x) { return Input::constant("", VT::Float, x, x, x, x); }

  Lobes empty() {
    Lobes l;
    l.diffuse = l.specular = l.emission = c3(0, 0, 0);
    l.rough = f1(0.5f);
    l.transmission = f1(0);
    l.transmission_color = c3(1, 1, 1);
    l.ior = f1(1.5f);
    l.pass = l.opacity = f1(1);
    l.normal = Input::constant("", VT::Vector3, 0, 0, 0);
    return l;
  }

 private:
  Graph& g_;
  std::vector<std::string>& notes_;
  std::map<int, Lobes> memo_;
  std::set<int> closures_;
  std::string origin_;  // of the closure being flattened, for the nodes made
  int depth_ = 0;
  // Closure trees are shallow (MaterialX's standard_surface graph is about
  // 10 deep); the bound keeps a hostile document off the end of the stack.
  static constexpr int kMaxClosureDepth = 256;

  void note(const std::string& what) {
    if (std::find(notes_.begin(), notes_.end(), what) == notes_.end()) notes_.push_back(what);
  }

  // --- arithmetic on inputs: folded when constant, else a node ----------
  Input node(const char* category, VT type, std::vector<Input> ins) {
    Node n;
    n.category = category;
    n.type = type;
    n.origin = origin_ + " (flattened closure)";
    n.inputs = std::move(ins);
    return Input::link("", type, g_.add(std::move(n)));
  }
  static VT wider(const Input& a, const Input& b) { return width_of(a) >= width_of(b) ? a.type : b.type; }
  static Input named(Input in, const char* name) {
    in.name = name;
    return in;
  }
  template <class F>
  Input fold2(const Input& a, const Input& b, F f) {
    VT t = wider(a, b);
    Input r = Input::constant("", t, 0);
    for (int k = 0; k < 4; ++k) r.value.f[size_t(k)] = f(lane(a, k), lane(b, k));
    return r;
  }
  static bool is_const(const Input& in, float v) {
    if (in.linked) return false;
    for (int k = 0; k < width_of(in); ++k)
      if (lane(in, k) != v) return false;
    return true;
  }
  Input mul(const Input& a, const Input& b) {
    if (is_const(a, 0) || is_const(b, 0)) return Input::constant("", wider(a, b), 0);
    if (is_const(a, 1) && width_of(a) <= width_of(b)) return b;
    if (is_const(b, 1) && width_of(b) <= width_of(a)) return a;
    if (!a.linked && !b.linked) return fold2(a, b, [](float x, float y) { return x * y; });
    // A float operand goes second (MaterialX's multiply_color3FA).
    const bool swap = width_of(a) < width_of(b);
    return node("multiply", wider(a, b), {named(swap ? b : a, "in1"), named(swap ? a : b, "in2")});
  }
  Input add(const Input& a, const Input& b) {
    if (is_const(a, 0) && width_of(a) <= width_of(b)) return b;
    if (is_const(b, 0) && width_of(b) <= width_of(a)) return a;
    if (!a.linked && !b.linked) return fold2(a, b, [](float x, float y) { return x + y; });
    const bool swap = width_of(a) < width_of(b);
    return node("add", wider(a, b), {named(swap ? b : a, "in1"), named(swap ? a : b, "in2")});
  }
  Input one_minus(const Input& a) {
    if (!a.linked) return fold2(f1(1), a, [](float x, float y) { return x - y; });
    return node("subtract", a.type, {named(Input::constant("", a.type, 1, 1, 1, 1), "in1"), named(a, "in2")});
  }
  // bg·(1 − t) + fg·t
  Input lerp(const Input& bg, const Input& fg, const Input& t) {
    if (is_const(t, 0)) return bg;
    if (is_const(t, 1)) return fg;
    if (!bg.linked && !fg.linked && !t.linked && width_of(bg) == width_of(fg)) {
      Input r = bg;
      for (int k = 0; k < 4; ++k)
        r.value.f[size_t(k)] = lane(bg, k) + (lane(fg, k) - lane(bg, k)) * lane(t, 0);
      return r;
    }
    VT type = wider(bg, fg);
    return node("mix", type, {named(widen(fg, type), "fg"), named(widen(bg, type), "bg"), named(t, "mix")});
  }
  // The average of a colour's channels.
  Input average(const Input& c) {
    if (width_of(c) == 1) return c;
    if (!c.linked) return f1((lane(c, 0) + lane(c, 1) + lane(c, 2)) / 3.0f);
    return node("dotproduct", VT::Float,
                {named(c, "in1"), named(Input::constant("", c.type, 1 / 3.0f, 1 / 3.0f, 1 / 3.0f), "in2")});
  }
  static float hint(const Input& in) {
    if (in.linked) return 0.5f;
    float s = 0;
    for (int k = 0; k < 3; ++k) s += lane(in, std::min(k, width_of(in) - 1));
    return s / 3.0f;
  }

  // Normal-incidence reflectance of a dielectric of this (relative) IOR.
  Input f0_of_ior(const Input& ior) {
    if (!ior.linked) {
      float n = lane(ior, 0), r = (n - 1) / (n + 1);
      return f1(std::isfinite(r) ? r * r : 0.04f);
    }
    Input r = node("divide", VT::Float,
                   {named(node("subtract", VT::Float, {named(ior, "in1"), named(f1(1), "in2")}), "in1"),
                    named(node("add", VT::Float, {named(ior, "in1"), named(f1(1), "in2")}), "in2")});
    return mul(r, r);
  }
  // A conductor's normal-incidence reflectance from its complex IOR n + ik:
  // ((n−1)² + k²) / ((n+1)² + k²). An artistic_ior's `reflectivity` is
  // that value by construction.
  Input f0_of_conductor(const Input& n, const Input& k) {
    if (n.linked && k.linked) {
      const Node& a = g_.nodes[size_t(n.node)];
      const Node& b = g_.nodes[size_t(k.node)];
      // Both outputs of one artistic_ior node (one graph node per output, same element).
      if (a.category == "artistic_ior" && b.category == "artistic_ior" && a.input("reflectivity") &&
          a.origin == b.origin) {
        const Input* edge = a.input("edge_color");
        if (edge && !is_const(*edge, 1))
          note("conductor_bsdf edge colour (pmc's Fresnel is Schlick's, white at grazing angles)");
        return *a.input("reflectivity");
      }
    }
    if (!n.linked && !k.linked) {
      Input r = c3(0, 0, 0);
      for (int c = 0; c < 3; ++c) {
        float nn = lane(n, c), kk = lane(k, c);
        float v = ((nn - 1) * (nn - 1) + kk * kk) / ((nn + 1) * (nn + 1) + kk * kk);
        r.value.f[size_t(c)] = std::isfinite(v) ? v : 1.0f;
      }
      return r;
    }
    Input nm = node("subtract", VT::Color3, {named(n, "in1"), named(f1(1), "in2")});
    Input np = node("add", VT::Color3, {named(n, "in1"), named(f1(1), "in2")});
    Input k2 = mul(k, k);
    return node("divide", VT::Color3,
                {named(add(mul(nm, nm), k2), "in1"), named(add(mul(np, np), k2), "in2")});
  }
  // MaterialX roughness is GGX alpha per tangent axis; pmc's is sqrt(alpha), isotropic.
  Input rough_of_alpha(const Input& alpha) {
    if (!alpha.linked) {
      float ax = lane(alpha, 0), ay = lane(alpha, std::min(1, width_of(alpha) - 1));
      if (ax != ay) note("anisotropic roughness (pmc's GGX lobe is isotropic)");
      return f1(std::sqrt(std::max(0.0f, 0.5f * (ax + ay))));
    }
    Input avg = width_of(alpha) == 1
                    ? alpha
                    : node("dotproduct", VT::Float,
                           {named(alpha, "in1"), named(Input::constant("", alpha.type, 0.5f, 0.5f), "in2")});
    return node("sqrt", VT::Float, {named(avg, "in")});
  }

  const Input& in(const Node& n, const char* name) {
    const Input* i = n.input(name);
    if (!i) fail(n.origin, ": closure node '", n.category, "' lacks its '", name, "' input");
    return *i;
  }
  Lobes closure_input(const Node& n, const char* name) {
    const Input* i = n.input(name);
    if (!i || !i->linked) return empty();
    const Node& src = g_.nodes[size_t(i->node)];
    if (!is_closure_type(src.type) && !is_surface_category(src.category))
      fail(n.origin, ": input '", name, "' is connected to ", type_name(src.type), " data, not a closure");
    if (is_closure_type(i->type) && src.type != i->type)
      fail(n.origin, ": input '", name, "' takes a ", type_name(i->type), " but node '", src.name, "' (",
           src.origin, ") outputs a ", type_name(src.type), " (type mismatch)");
    const int from = i->node;  // `n` may be the graph's: read before the graph grows
    const std::string origin = n.origin;
    Lobes l = of(from);
    origin_ = origin;
    return l;
  }
  static bool is_surface_category(const std::string& c) { return !surface_params(c).empty(); }

  // A data normal that is not the geometric default (a normal map) replaces the shading normal.
  Input normal_of(const Node& n) {
    const Input* i = n.input("normal");
    if (!i || !i->linked || g_.nodes[size_t(i->node)].category == "normal")
      return Input::constant("", VT::Vector3, 0, 0, 0);
    return *i;
  }
  // The glass whose tint and IOR a combination keeps (pmc's BSDF has one glass lobe).
  static const Lobes& glass_of(const Lobes& a, const Lobes& b) {
    return (a.transmission.linked || lane(a.transmission, 0) != 0) ? a : b;
  }
  static const Input& pick_normal(const Lobes& a, const Lobes& b) {
    return a.normal.linked ? a.normal : b.normal;
  }

  // The roughness two specular lobes share: weighted by their strength.
  void share_rough(Lobes& out, const Lobes& a, float wa, const Lobes& b, float wb) {
    if (!a.has_rough || !b.has_rough) {
      out.has_rough = a.has_rough || b.has_rough;
      out.rough = a.has_rough ? a.rough : b.rough;
      return;
    }
    out.has_rough = true;
    if (!a.rough.linked && !b.rough.linked && lane(a.rough, 0) == lane(b.rough, 0)) {
      out.rough = a.rough;
      return;
    }
    if (wa > 0 && wb > 0)
      note(
          "specular lobes of different roughness (pmc's BSDF has one GGX lobe: their roughness is averaged)");
    float t = wa + wb > 0 ? wb / (wa + wb) : 0.5f;
    out.rough = lerp(a.rough, b.rough, f1(t));
  }

  Lobes specular_leaf(const Node& n, const Input& f0, const Input& pass) {
    Lobes l = empty();
    l.specular = mul(in(n, "weight"), f0);
    l.pass = pass;
    l.rough = rough_of_alpha(in(n, "roughness"));
    l.has_rough = true;
    l.spec_hint = hint(l.specular);
    l.normal = normal_of(n);
    const Input* film = n.input("thinfilm_thickness");
    if (film && (film->linked || lane(*film, 0) != 0)) note(n.category + " thin film");
    return l;
  }

  Lobes build(int id) {
    const Node n = g_.nodes[size_t(id)];  // a copy: the nodes made below may move the graph's
    origin_ = n.origin;
    const std::string& c = n.category;
    if (is_surface_category(c)) return surface_shader(n);
    if (c == "surface") {
      Lobes l = closure_input(n, "bsdf");
      Lobes e = closure_input(n, "edf");
      l.emission = add(l.emission, e.emission);
      l.opacity = in(n, "opacity");
      return l;
    }
    if (c == "oren_nayar_diffuse_bsdf" || c == "burley_diffuse_bsdf" || c == "subsurface_bsdf") {
      Lobes l = empty();
      l.diffuse = mul(in(n, "weight"), in(n, "color"));
      l.pass = one_minus(in(n, "weight"));
      l.normal = normal_of(n);
      const Input* r = n.input("roughness");
      if (c != "subsurface_bsdf" && r && (r->linked || lane(*r, 0) != 0))
        note(c + " roughness (pmc's diffuse lobe is Lambert)");
      if (c == "subsurface_bsdf") note("subsurface_bsdf (rendered as diffuse reflection)");
      return l;
    }
    if (c == "dielectric_bsdf" || c == "generalized_schlick_bsdf") {
      const std::string mode = n.input("scatter_mode") ? n.input("scatter_mode")->value.text : "R";
      if (c == "dielectric_bsdf" && mode != "R") {
        // Glass: pmc's rough dielectric lobe reflects and refracts with the
        // exact Fresnel of `ior` (T alone keeps the reflection: one interface
        // cannot refract what it does not reflect).
        if (mode == "T") note("dielectric_bsdf scatter_mode T (rendered as RT: glass reflects too)");
        Lobes l = empty();
        l.transmission = in(n, "weight");
        l.transmission_color = in(n, "tint");
        l.ior = in(n, "ior");
        l.rough = rough_of_alpha(in(n, "roughness"));
        l.has_rough = true;
        l.spec_hint = hint(l.transmission);
        l.pass = one_minus(in(n, "weight"));
        l.normal = normal_of(n);
        return l;
      }
      const bool reflects = mode != "T";
      if (mode != "R") note(c + " transmission (scatter_mode " + mode + ")");
      Input f0 = c == "dielectric_bsdf" ? mul(in(n, "tint"), f0_of_ior(in(n, "ior"))) : in(n, "color0");
      if (c == "generalized_schlick_bsdf")
        for (const char* s : {"color82", "color90"})
          if (n.input(s) && !is_const(*n.input(s), 1))
            note(std::string("generalized_schlick_bsdf ") + s + " (pmc's Fresnel is Schlick's to white)");
      if (!reflects) {
        Lobes l = empty();
        l.normal = normal_of(n);
        return l;
      }
      return specular_leaf(n, f0, one_minus(mul(in(n, "weight"), average(f0))));
    }
    if (c == "conductor_bsdf")
      return specular_leaf(n, f0_of_conductor(in(n, "ior"), in(n, "extinction")), one_minus(in(n, "weight")));
    if (c == "translucent_bsdf" || c == "sheen_bsdf" || c == "chiang_hair_bsdf") {
      Lobes l = empty();
      if (c == "translucent_bsdf") l.pass = one_minus(in(n, "weight"));
      note(c + (c == "translucent_bsdf" ? " (diffuse transmission)" : ""));
      return l;
    }
    if (c == "uniform_edf" || c == "conical_edf" || c == "measured_edf") {
      Lobes l = empty();
      l.emission = in(n, "color");
      if (c != "uniform_edf") note(c + " (emitted uniformly)");
      return l;
    }
    if (c == "generalized_schlick_edf") {
      Lobes l = closure_input(n, "base");
      l.emission = mul(l.emission, in(n, "color0"));
      note("generalized_schlick_edf (its colour at normal incidence everywhere)");
      return l;
    }
    if (c == "dot") return closure_input(n, "in");  // an organisational pass-through
    if (c == "layer") {
      Lobes top = closure_input(n, "top"), base = closure_input(n, "base");
      Lobes l = empty();
      l.diffuse = add(top.diffuse, mul(base.diffuse, top.pass));
      l.specular = add(top.specular, mul(base.specular, top.pass));
      l.emission = add(top.emission, mul(base.emission, top.pass));
      l.transmission = add(top.transmission, mul(base.transmission, top.pass));
      l.transmission_color = glass_of(top, base).transmission_color;
      l.ior = glass_of(top, base).ior;
      l.pass = mul(top.pass, base.pass);
      share_rough(l, top, top.spec_hint, base, base.spec_hint * hint(top.pass));
      l.spec_hint = top.spec_hint + base.spec_hint * hint(top.pass);
      l.normal = pick_normal(top, base);
      return l;
    }
    if (c == "mix") {
      Lobes fg = closure_input(n, "fg"), bg = closure_input(n, "bg");
      const Input& t = in(n, "mix");
      Lobes l = empty();
      l.diffuse = lerp(bg.diffuse, fg.diffuse, t);
      l.specular = lerp(bg.specular, fg.specular, t);
      l.emission = lerp(bg.emission, fg.emission, t);
      l.transmission = lerp(bg.transmission, fg.transmission, t);
      l.transmission_color = glass_of(fg, bg).transmission_color;
      l.ior = glass_of(fg, bg).ior;
      l.pass = lerp(bg.pass, fg.pass, t);
      l.opacity = lerp(bg.opacity, fg.opacity, t);
      if (fg.has_rough && bg.has_rough) {
        l.has_rough = true;
        l.rough = lerp(bg.rough, fg.rough, t);
      } else {
        share_rough(l, fg, 0, bg, 0);
      }
      const float h = hint(t);
      l.spec_hint = bg.spec_hint * (1 - h) + fg.spec_hint * h;
      l.normal = pick_normal(fg, bg);
      return l;
    }
    if (c == "add") {
      Lobes a = closure_input(n, "in1"), b = closure_input(n, "in2");
      Lobes l = empty();
      l.diffuse = add(a.diffuse, b.diffuse);
      l.specular = add(a.specular, b.specular);
      l.emission = add(a.emission, b.emission);
      l.transmission = add(a.transmission, b.transmission);
      l.transmission_color = glass_of(a, b).transmission_color;
      l.ior = glass_of(a, b).ior;
      l.pass = mul(a.pass, b.pass);
      l.opacity = mul(a.opacity, b.opacity);
      share_rough(l, a, a.spec_hint, b, b.spec_hint);
      l.spec_hint = a.spec_hint + b.spec_hint;
      l.normal = pick_normal(a, b);
      return l;
    }
    if (c == "multiply") {
      Lobes l = closure_input(n, "in1");
      const Input& s = in(n, "in2");
      l.diffuse = mul(l.diffuse, s);
      l.specular = mul(l.specular, s);
      l.emission = mul(l.emission, s);
      l.spec_hint *= hint(s);
      return l;
    }
    if (n.type == VT::VDF || c == "absorption_vdf" || c == "anisotropic_vdf") {
      note("volume scattering (" + c + ")");
      return empty();
    }
    note(c + " (a closure pmc does not know: it contributes nothing)");
    return empty();
  }

  // A surface shader pmc maps (standard_surface, open_pbr_surface ...), as
  // pmc_surface_to_bsdf (core/device/pmc_interp.h) reads its parameters.
  Lobes surface_shader(const Node& n) {
    std::map<int, Input> p;
#define PMC_FLATTEN_DEFAULT(input, param, width, x, y, z) \
  p[param] =                                              \
      width == 1 ? f1(x) : Input::constant("", param == PMC_P_NORMAL ? VT::Vector3 : VT::Color3, x, y, z);
    PMC_STANDARD_SURFACE(PMC_FLATTEN_DEFAULT)
#undef PMC_FLATTEN_DEFAULT
    for (const SurfaceParam& sp : surface_params(n.category))
      if (const Input* i = n.input(sp.input)) p[sp.param] = *i;
    if (n.category == "pmc_mtl_surface") fail(n.origin, ": an MTL surface cannot be a MaterialX closure");
    Lobes l = empty();
    Input bc = mul(p[PMC_P_BASE_COLOR], p[PMC_P_BASE]);
    Input metal = p[PMC_P_METALNESS];
    Input f0 = f0_of_ior(p[PMC_P_SPECULAR_IOR]);
    Input spec_w = p[PMC_P_SPECULAR];
    Input dielectric = mul(p[PMC_P_SPECULAR_COLOR], mul(f0, spec_w));
    Input coat = mul(p[PMC_P_COAT_COLOR], mul(f1(0.04f), p[PMC_P_COAT]));
    l.specular = add(lerp(dielectric, bc, metal), coat);
    Input kept =
        one_minus(mul(f0, spec_w.linked ? node("min", VT::Float, {named(spec_w, "in1"), named(f1(1), "in2")})
                                        : f1(std::min(1.0f, lane(spec_w, 0)))));
    l.diffuse = mul(bc, mul(one_minus(metal), kept));
    l.rough = p[PMC_P_SPECULAR_ROUGHNESS];
    l.has_rough = true;
    l.spec_hint = hint(l.specular);
    l.emission = mul(p[PMC_P_EMISSION_COLOR], p[PMC_P_EMISSION]);
    l.opacity = p[PMC_P_OPACITY];
    l.pass = f1(0);
    l.normal = p[PMC_P_NORMAL];
    return l;
  }
};

}  // namespace

int flatten_closure_shader(Graph& g, int shader, std::vector<std::string>& unmodelled) {
  Flattener f(g, unmodelled);
  Lobes l = f.of(shader);
  const std::string origin = g.nodes[size_t(shader)].origin + " (flattened onto pmc's BSDF)";
  Node s;
  s.category = "pmc_mtl_surface";
  s.type = ValueType::Surface;
  s.origin = origin;
  auto param = [&](const char* name, VT type, Input v) {
    if (type_width(type) == 3) v = f.widen(v, type);
    v.name = name;
    if (v.linked) v.type = g.nodes[size_t(v.node)].type;
    s.inputs.push_back(v);
  };
  param("model", VT::Float, f.f1(1));
  param("base_color", VT::Color3, l.diffuse);
  param("specular_color", VT::Color3, l.specular);
  param("specular_roughness", VT::Float, l.has_rough ? l.rough : f.f1(1));
  param("emission", VT::Float, f.f1(1));
  param("transmission", VT::Float, l.transmission);
  param("transmission_color", VT::Color3, l.transmission_color);
  param("specular_IOR", VT::Float, l.ior);
  param("emission_color", VT::Color3, l.emission);
  param("opacity", VT::Float, l.opacity);
  param("normal", VT::Vector3, l.normal);
  for (int id : f.closures()) g.nodes[size_t(id)].dead = true;
  return g.add(std::move(s));
}

}  // namespace pmc
