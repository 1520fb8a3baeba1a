// emit.cpp — node-table-driven emission and constant evaluation.
#include "materials/emit.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/device/pmc_interp.h"
#include "materials/node_table.h"

namespace pmc {

uint32_t float_bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

namespace {

uint32_t address_mode(const std::string& s, const std::string& context) {
  if (s == "constant") return PMC_ADDR_CONSTANT;
  if (s == "clamp") return PMC_ADDR_CLAMP;
  if (s == "periodic" || s.empty()) return PMC_ADDR_PERIODIC;
  if (s == "mirror") return PMC_ADDR_MIRROR;
  fail(context, ": unknown address mode '", s, "'");
}

// Footprint scale of a uv chain: how much the node multiplies uv distances
// (uv * 3 makes texels 3x smaller in uv space). Affine chains with constant
// factors only; anything else counts as 1. `*even` is cleared unless the
// chain is the mesh's uv (or a constant) under a uniform scale and shifts:
// only then does the footprint's ellipse keep its direction (a turn, a
// mirror or an uneven stretch would turn it; PMC_IMAGE_ANISO).
float uv_scale(const Graph& g, const Input& uv, bool* even) {
  if (!uv.linked) return 1.0f;
  const Node& n = g.nodes[size_t(uv.node)];
  auto max_abs = [](const Input* in, int w) {
    float m = 0.0f;
    for (int i = 0; i < std::max(1, w); ++i) m = std::max(m, std::fabs(in->value.f[size_t(i)]));
    return m;
  };
  auto uniform = [](const Input* in, int w) {  // the same factor for u and v
    return w <= 1 || in->value.f[0] == in->value.f[1];
  };
  const NodeDef* def = find_node_def(n.category);
  const int op = def && def->emit == Emit::Opcode ? def->opcode : -1;
  const Input* a = n.input("in1");
  const Input* b = n.input("in2");
  if ((op == PMC_OP_MUL || op == PMC_OP_DIV) && a && b && a->linked && !b->linked) {
    float m = max_abs(b, type_width(b->type));
    if (!uniform(b, type_width(b->type))) *even = false;
    if (!(m > 0.0f) || !std::isfinite(m)) {
      *even = false;
      return 1.0f;
    }
    return uv_scale(g, *a, even) * (op == PMC_OP_MUL ? m : 1.0f / m);
  }
  if ((op == PMC_OP_ADD || op == PMC_OP_SUB) && a && b && a->linked && !b->linked)
    return uv_scale(g, *a, even);
  if (op == PMC_OP_PLACE2D) {
    const Input* s = n.input("scale");
    const Input* r = n.input("rotate");
    if (!r || r->linked || r->value.f[0] != 0.0f) *even = false;
    if (s && !s->linked) {
      if (!uniform(s, 2)) *even = false;
      float m = std::min(std::fabs(s->value.f[0]), std::fabs(s->value.f[1]));
      if (m > 0.0f && std::isfinite(m)) return uv_scale(g, *n.input("texcoord"), even) / m;
    }
    *even = false;
    return 1.0f;
  }
  if (op != PMC_OP_TEXCOORD) *even = false;
  return 1.0f;
}

uint32_t swizzle_imm(const std::string& channels, const std::string& context) {
  uint32_t imm = 0;
  if (channels.empty() || channels.size() > 4)
    fail(context, ": swizzle channels '", channels, "' must have 1-4 letters");
  for (size_t i = 0; i < 4; ++i) {
    char c = i < channels.size() ? channels[i] : '0';
    uint32_t sel;
    switch (c) {
      case 'x':
      case 'r':
        sel = 0;
        break;
      case 'y':
      case 'g':
        sel = 1;
        break;
      case 'z':
      case 'b':
        sel = 2;
        break;
      case 'w':
      case 'a':
        sel = 3;
        break;
      case '0':
        sel = 4;
        break;
      case '1':
        sel = 5;
        break;
      default:
        fail(context, ": swizzle channel '", std::string(1, c), "' is not one of xyzwrgba01");
    }
    imm |= sel << (3 * i);
  }
  return imm;
}

}  // namespace

bool emit_node(EmitContext& cx, const Node& n, uint32_t dst) {
  const int w = type_width(n.type);
  auto op = [&](const char* name) { return cx.operand(*n.input(name)); };
  const NodeDef* def = find_node_def(n.category);
  if (!def || (def->emit == Emit::Opcode && def->opcode < 0) || def->emit == Emit::Lowered)
    fail(n.origin, ": node '", n.category, "' has no code generator");
  switch (def->emit) {
    case Emit::Convert: {
      const Input& in = *n.input("in");
      int iw = type_width(in.type);
      if (iw == 1 || iw >= w) {
        cx.em.instr(PMC_OP_MOVE, w, 0, dst, {cx.operand(in)});
      } else {  // widen: pad with 0, and with 1 in the 4th lane (MaterialX convert)
        std::string ch = std::string("xyzw").substr(0, size_t(iw));
        while (int(ch.size()) < w) ch += ch.size() == 3 ? '1' : '0';
        cx.em.instr(PMC_OP_SWIZZLE, w, swizzle_imm(ch, n.origin), dst, {cx.operand(in)});
      }
      return true;
    }
    case Emit::Extract: {
      const float fi = n.input("index")->value.f[0];
      int iw = type_width(n.input("in")->type);
      if (!(fi >= 0.0f && fi < float(iw)))  // before the cast: float-to-int of inf/NaN/1e30 is undefined
        fail(n.origin, ": extract index ", fi, " is out of range for ", type_name(n.input("in")->type));
      int index = int(fi);
      cx.em.instr(PMC_OP_SWIZZLE, 1, uint32_t(index), dst, {op("in")});
      return true;
    }
    case Emit::Swizzle:
      cx.em.instr(PMC_OP_SWIZZLE, w, swizzle_imm(n.input("channels")->value.text, n.origin), dst, {op("in")});
      return true;
    case Emit::Combine2: {
      const Input& a = *n.input("in1");
      const Input& b = *n.input("in2");
      int aw = type_width(a.type);
      cx.em.instr(PMC_OP_MOVE, aw, 0, dst, {cx.operand(a)});
      cx.em.instr(PMC_OP_MOVE, type_width(b.type), 0, dst + uint32_t(aw), {cx.operand(b)});
      return true;
    }
    case Emit::Image: {
      // The operand inputs in table order, with the texture's mode
      // (address modes and filter, footprint scale) right after `default`.
      if (!cx.textures) return false;
      const Input& file = *n.input("file");
      if (file.linked) fail(n.origin, ": 'file' must be a constant filename");
      // No image: `image` is its default; the hex-tiled nodes read it as
      // every texel (a flat normal for the normal map), from no texture.
      const bool image = def->opcode == PMC_OP_IMAGE;
      if (file.value.text.empty() && image) {
        cx.em.instr(PMC_OP_MOVE, w, 0, dst, {op("default")});
        return true;
      }
      uint32_t tex = 0xffffu;  // beyond any texture pool: the texture's reads return `default`
      if (!file.value.text.empty()) {
        bool srgb = file.value.f[0] > 0.5f && (n.type == ValueType::Color3 || n.type == ValueType::Color4);
        tex = uint32_t(cx.textures->load(file.value.text, srgb, n.origin));
      }
      auto text_of = [&](const char* name, const char* fallback) {
        const Input* in = n.input(name);
        return in ? in->value.text : std::string(fallback);
      };
      uint32_t bits =
          address_mode(text_of("uaddressmode", "periodic"), n.origin) |
          (address_mode(text_of("vaddressmode", "periodic"), n.origin) << 2) |
          ((text_of("filtertype", "linear") == "closest" ? PMC_FILTER_CLOSEST : PMC_FILTER_LINEAR) << 4);
      bool even = true;  // the footprint's ellipse keeps its direction: filter anisotropically
      const float scale = uv_scale(cx.g, *n.input("texcoord"), &even);
      if (even) bits |= PMC_IMAGE_ANISO;
      Value mode = Value::number(ValueType::Vector2, float(bits), scale);
      std::vector<uint32_t> operands;
      for (const InputDef& d : def->inputs) {
        const Input* in = n.input(d.name);
        if (!d.operand || !in || !is_numeric(in->type)) continue;
        operands.push_back(cx.operand(*in));
        if (d.name == "default") operands.push_back(cx.em.constant(mode, 2));
      }
      cx.em.instr(def->opcode, w, tex, dst, operands);
      return true;
    }
    case Emit::WidthImm: {
      std::vector<uint32_t> operands;
      uint32_t width = 0;
      for (const InputDef& d : def->inputs) {
        const Input* in = n.input(d.name);
        if (!d.operand || !in || !is_numeric(in->type)) continue;
        if (operands.empty()) width = uint32_t(type_width(in->type));
        operands.push_back(cx.operand(*in));
      }
      cx.em.instr(def->opcode, w, width, dst, operands);
      return true;
    }
    case Emit::Opcode: {
      // The operand inputs, in table order (node_table.h).
      std::vector<uint32_t> operands;
      for (const InputDef& d : def->inputs) {
        const Input* in = n.input(d.name);
        if (!d.operand || !in || !is_numeric(in->type)) continue;
        operands.push_back(cx.operand(*in));
      }
      unsigned imm = def->imm;
      if (!def->outputs.empty() && !find_output(*def, n.output, &imm))  // the reader checked the name
        fail(n.origin, ": node '", n.category, "' has no output '", n.output, "' (it has ",
             output_names(*def), ")");
      cx.em.instr(def->opcode, w, imm, dst, operands);
      return def->folds || cx.textures != nullptr;
    }
    case Emit::Lowered:
      break;
  }
  return false;
}

bool evaluate_constant(const Graph& g, const Node& n, Value& out) {
  if (!is_numeric(n.type)) return false;
  const NodeDef* def = find_node_def(n.category);
  if (def && !def->folds) return false;
  Emitter em;
  EmitContext cx{g, nullptr, em, [&](const Input& in) { return em.constant(in.value, type_width(in.type)); }};
  if (!emit_node(cx, n, 0)) return false;
  std::vector<uint32_t> code = em.finish(0);
  float stack[PMC_STACK_SIZE] = {0};
  float params[PMC_P_COUNT] = {0};
  PmcShadingInputs inputs{};
  PmcTextureSet ts{};
  pmc_interp_run(code.data(), 0, &inputs, &ts, stack, params, nullptr);
  out = Value::number(n.type, stack[0], stack[1], stack[2], stack[3]);
  return true;
}

}  // namespace pmc
