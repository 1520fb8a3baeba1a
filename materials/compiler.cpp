// compiler.cpp — emission, slot allocation, inline constants, disassembly.
#include "materials/compiler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <sstream>

#include "core/device/pmc_interp.h"
#include "core/error.h"
#include "materials/node_library.h"

namespace pmc {
namespace {

uint32_t float_bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

// Appends instructions for one material into a local buffer; constants are
// collected and placed after END by finish(), which patches the operands.
class Emitter {
 public:
  uint32_t constant(const Value& v, int width) {
    width = std::max(1, std::min(4, width));
    std::vector<uint32_t> bits;
    for (int i = 0; i < width; ++i) bits.push_back(float_bits(v.f[size_t(i)]));
    auto it = const_index_.find(bits);
    uint32_t offset;
    if (it != const_index_.end()) {
      offset = it->second;
    } else {
      offset = uint32_t(consts_.size());
      consts_.insert(consts_.end(), bits.begin(), bits.end());
      const_index_[bits] = offset;
    }
    return pmc_operand(1, offset, uint32_t(width));  // patched in finish()
  }
  static uint32_t slot(uint32_t index, int width) {
    return pmc_operand(0, index, uint32_t(std::max(1, width)));
  }

  void instr(int op, int width, uint32_t imm, uint32_t dst, const std::vector<uint32_t>& operands) {
    PMC_CHECK(imm < 65536u && operands.size() < 16, "instruction encoding");
    code_.push_back(pmc_op_header(uint32_t(op), uint32_t(std::max(1, std::min(4, width))),
                                  uint32_t(operands.size()), imm));
    code_.push_back(dst);
    for (uint32_t o : operands) {
      if (o & PMC_OPERAND_CONST) fixups_.push_back(code_.size());
      code_.push_back(o);
    }
    ++instructions_;
  }

  // An instruction whose operand words are raw integers (not patched as constants).
  void instr_raw(int op, int width, uint32_t imm, uint32_t dst, const std::vector<uint32_t>& words) {
    code_.push_back(
        pmc_op_header(uint32_t(op), uint32_t(std::max(1, std::min(4, width))), uint32_t(words.size()), imm));
    code_.push_back(dst);
    code_.insert(code_.end(), words.begin(), words.end());
    ++instructions_;
  }
  size_t size() const { return code_.size(); }
  void patch(size_t at, uint32_t word) { code_[at] = word; }

  // END, then constants; operands become absolute indices from `base`.
  std::vector<uint32_t> finish(uint32_t base) {
    code_.push_back(pmc_op_header(PMC_OP_END, 1, 0, 0));
    code_.push_back(0);
    uint32_t const_base = base + uint32_t(code_.size());
    for (size_t at : fixups_) {
      uint32_t o = code_[at];
      code_[at] = (o & ~PMC_OPERAND_INDEX_MASK) | ((o & PMC_OPERAND_INDEX_MASK) + const_base);
    }
    std::vector<uint32_t> out = code_;
    out.insert(out.end(), consts_.begin(), consts_.end());
    return out;
  }
  uint32_t instructions() const { return instructions_; }

 private:
  std::vector<uint32_t> code_, consts_;
  std::vector<size_t> fixups_;
  std::map<std::vector<uint32_t>, uint32_t> const_index_;
  uint32_t instructions_ = 0;
};

uint32_t address_mode(const std::string& s, const std::string& context) {
  if (s == "constant") return PMC_ADDR_CONSTANT;
  if (s == "clamp") return PMC_ADDR_CLAMP;
  if (s == "periodic" || s.empty()) return PMC_ADDR_PERIODIC;
  if (s == "mirror") return PMC_ADDR_MIRROR;
  fail(context, ": unknown address mode '", s, "'");
}

// Footprint scale of a uv chain: how much the node multiplies uv distances
// (uv * 3 makes texels 3x smaller in uv space). Affine chains with constant
// factors only; anything else counts as 1.
float uv_scale(const Graph& g, const Input& uv) {
  if (!uv.linked) return 1.0f;
  const Node& n = g.nodes[size_t(uv.node)];
  auto max_abs = [](const Input* in, int w) {
    float m = 0.0f;
    for (int i = 0; i < std::max(1, w); ++i) m = std::max(m, std::fabs(in->value.f[size_t(i)]));
    return m;
  };
  const Input* a = n.input("in1");
  const Input* b = n.input("in2");
  if ((n.category == "multiply" || n.category == "divide") && a && b && a->linked && !b->linked) {
    float m = max_abs(b, type_width(b->type));
    if (!(m > 0.0f) || !std::isfinite(m)) return 1.0f;
    return uv_scale(g, *a) * (n.category == "multiply" ? m : 1.0f / m);
  }
  if ((n.category == "add" || n.category == "subtract") && a && b && a->linked && !b->linked)
    return uv_scale(g, *a);
  if (n.category == "place2d") {
    const Input* s = n.input("scale");
    if (s && !s->linked) {
      float m = std::min(std::fabs(s->value.f[0]), std::fabs(s->value.f[1]));
      if (m > 0.0f && std::isfinite(m)) return uv_scale(g, *n.input("texcoord")) / m;
    }
  }
  return 1.0f;
}

struct EmitContext {
  const Graph& g;
  TexturePool* textures;  // null when folding
  Emitter& em;
  std::function<uint32_t(const Input&)> operand;  // maps an input to an operand word
};

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

// Emits `n` writing its value to slot `dst`. Returns false if it cannot be
// evaluated without a shading point (only matters when folding).
bool emit_node(EmitContext& cx, const Node& n, uint32_t dst) {
  const int w = type_width(n.type);
  auto op = [&](const char* name) { return cx.operand(*n.input(name)); };
  const NodeDef* def = find_node_def(n.category);
  const std::string& c = n.category;
  if (c == "convert") {
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
  if (c == "extract") {
    const float fi = n.input("index")->value.f[0];
    int iw = type_width(n.input("in")->type);
    if (!(fi >= 0.0f && fi < float(iw)))  // before the cast: float-to-int of inf/NaN/1e30 is undefined
      fail(n.origin, ": extract index ", fi, " is out of range for ", type_name(n.input("in")->type));
    int index = int(fi);
    cx.em.instr(PMC_OP_SWIZZLE, 1, uint32_t(index), dst, {op("in")});
    return true;
  }
  if (c == "swizzle") {
    cx.em.instr(PMC_OP_SWIZZLE, w, swizzle_imm(n.input("channels")->value.text, n.origin), dst, {op("in")});
    return true;
  }
  if (c == "combine2") {
    const Input& a = *n.input("in1");
    const Input& b = *n.input("in2");
    int aw = type_width(a.type);
    cx.em.instr(PMC_OP_MOVE, aw, 0, dst, {cx.operand(a)});
    cx.em.instr(PMC_OP_MOVE, type_width(b.type), 0, dst + uint32_t(aw), {cx.operand(b)});
    return true;
  }
  if (!def || def->opcode < 0) fail(n.origin, ": node '", c, "' has no code generator");
  switch (def->opcode) {
    case PMC_OP_TEXCOORD:
    case PMC_OP_POSITION:
    case PMC_OP_NORMAL:
    case PMC_OP_TANGENT:
    case PMC_OP_BITANGENT:
      cx.em.instr(def->opcode, w, 0, dst, {});
      return cx.textures != nullptr;
    case PMC_OP_IMAGE: {
      if (!cx.textures) return false;
      const Input& file = *n.input("file");
      if (file.linked) fail(n.origin, ": 'file' must be a constant filename");
      if (file.value.text.empty()) {  // no image: MaterialX returns the default
        cx.em.instr(PMC_OP_MOVE, w, 0, dst, {op("default")});
        return true;
      }
      bool srgb = file.value.f[0] > 0.5f && (n.type == ValueType::Color3 || n.type == ValueType::Color4);
      int tex = cx.textures->load(file.value.text, srgb, n.origin);
      uint32_t bits =
          address_mode(n.input("uaddressmode")->value.text, n.origin) |
          (address_mode(n.input("vaddressmode")->value.text, n.origin) << 2) |
          ((n.input("filtertype")->value.text == "closest" ? PMC_FILTER_CLOSEST : PMC_FILTER_LINEAR) << 4);
      Value mode = Value::number(ValueType::Vector2, float(bits), uv_scale(cx.g, *n.input("texcoord")));
      cx.em.instr(PMC_OP_IMAGE, w, uint32_t(tex), dst,
                  {op("texcoord"), op("default"), cx.em.constant(mode, 2)});
      return true;
    }
    case PMC_OP_DOT:
      cx.em.instr(PMC_OP_DOT, 1, uint32_t(type_width(n.input("in1")->type)), dst, {op("in1"), op("in2")});
      return true;
    case PMC_OP_NORMALMAP:
      cx.em.instr(PMC_OP_NORMALMAP, 3, 0, dst, {op("in"), op("scale"), op("normal"), op("tangent")});
      return cx.textures != nullptr;
    default: {
      std::vector<uint32_t> operands;
      // The noise opcodes read their lookup point first (pmc_bytecode.h);
      // the MaterialX definitions list it last.
      const char* point = nullptr;
      if (def->opcode == PMC_OP_NOISE2D || def->opcode == PMC_OP_FRACTAL2D) point = "texcoord";
      if (def->opcode == PMC_OP_NOISE3D || def->opcode == PMC_OP_FRACTAL3D) point = "position";
      if (point) operands.push_back(op(point));
      for (const InputDef& d : def->inputs) {
        if (point && d.name == point) continue;
        const Input* in = n.input(d.name);
        if (!in || in->type == ValueType::String || in->type == ValueType::Filename) continue;
        operands.push_back(cx.operand(*in));
      }
      cx.em.instr(def->opcode, w, def->imm, dst, operands);
      return true;
    }
  }
}

}  // namespace

bool evaluate_constant(const Graph& g, const Node& n, Value& out) {
  if (!is_numeric(n.type)) return false;
  const std::string& c = n.category;
  if (c == "texcoord" || c == "position" || c == "normal" || c == "tangent" || c == "bitangent" ||
      c == "image" || c == "normalmap")
    return false;
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

const CompiledMaterial& compile_material(Graph& g, TexturePool& textures, MaterialProgram& program,
                                         const CompileOptions& options) {
  CompiledMaterial cm;
  cm.name = g.material;
  cm.file = g.file;
  cm.passes = optimize(g);
  std::vector<uint32_t> deps = dependencies(g);
  std::vector<char> is_point(g.nodes.size(), 0);
  if (options.cache) {
    cm.cache_plan = plan_cache(g, options.cache_min_nodes);
    std::vector<CachePoint> kept;
    for (const CachePoint& p : cm.cache_plan.points)
      // The node id travels in 14 bits of the instruction; the interpreter
      // tracks a group's misses in one 32-bit mask.
      if (p.node < (1 << 14) && kept.size() < 32) {
        kept.push_back(p);
        is_point[size_t(p.node)] = 1;
      } else {
        cm.cache_plan.not_cached.push_back(
            {p.node, p.node >= (1 << 14) ? "node id beyond the 14 bits a cache instruction holds"
                                         : "the material already has 32 cache points (one miss mask)"});
      }
    cm.cache_plan.points = kept;
  }

  // Outside order: cache points are leaves here (their sub-graphs live in blocks).
  std::vector<int> order;
  {
    std::vector<char> seen(g.nodes.size(), 0);
    std::function<void(int)> visit = [&](int i) {
      if (seen[size_t(i)]) return;
      seen[size_t(i)] = 1;
      if (!is_point[size_t(i)])
        for (const Input& in : g.nodes[size_t(i)].inputs)
          if (in.linked) visit(in.node);
      order.push_back(i);
    };
    visit(g.surface);
  }
  auto count_uses = [&](const std::vector<int>& nodes, bool stop_at_points) {
    std::vector<int> uses(g.nodes.size(), 0);
    for (int i : nodes) {
      if (stop_at_points && is_point[size_t(i)]) continue;
      for (const Input& in : g.nodes[size_t(i)].inputs)
        if (in.linked) ++uses[size_t(in.node)];
    }
    return uses;
  };
  std::vector<int> uses = count_uses(order, true);

  std::vector<char> used(PMC_STACK_SIZE + 8, 0);
  uint32_t peak = 0;
  auto allocate = [&](int width, const std::string& who) {
    for (int s = 0; s + width <= PMC_STACK_SIZE; ++s) {
      bool free = true;
      for (int k = 0; k < width && free; ++k) free = !used[size_t(s + k)];
      if (!free) continue;
      for (int k = 0; k < width; ++k) used[size_t(s + k)] = 1;
      peak = std::max(peak, uint32_t(s + width));
      return s;
    }
    fail(g.file, ": material '", g.material, "' needs more than ", PMC_STACK_SIZE,
         " floats of interpreter stack at ", who, " (the network is too deep or wide to evaluate)");
  };
  auto release = [&](int slot, int width) {
    for (int k = 0; k < width; ++k) used[size_t(slot + k)] = 0;
  };
  auto width_of = [&](int node) { return std::max(1, type_width(g.nodes[size_t(node)].type)); };

  Emitter em;
  std::vector<int> slot_of(g.nodes.size(), -1);
  std::vector<int>* slots = &slot_of;  // the slot map operands read (outside or block-local)
  EmitContext cx{g, &textures, em, nullptr};
  cx.operand = [&](const Input& in) -> uint32_t {
    if (!in.linked) return em.constant(in.value, std::max(1, type_width(in.type)));
    int s = (*slots)[size_t(in.node)];
    PMC_CHECK(s >= 0, "operand emitted before its node");
    return Emitter::slot(uint32_t(s), width_of(in.node));
  };
  // Emits the nodes of `nodes` (inputs first) with slots freed after their last use.
  auto emit_nodes = [&](const std::vector<int>& nodes, std::vector<int>& use_count, int last_dst) {
    for (size_t k = 0; k < nodes.size(); ++k) {
      int i = nodes[k];
      const Node& n = g.nodes[size_t(i)];
      int dst = (last_dst >= 0 && k + 1 == nodes.size())
                    ? last_dst
                    : allocate(width_of(i), "node '" + n.name + "' (" + n.origin + ")");
      emit_node(cx, n, uint32_t(dst));
      (*slots)[size_t(i)] = dst;
      for (const Input& in : n.inputs)
        if (in.linked && --use_count[size_t(in.node)] == 0)
          release((*slots)[size_t(in.node)], width_of(in.node));
    }
  };
  // The cache group: every cache point's LOOKUP first, then the union of
  // their sub-graphs (each node once, its own texcoord included, in
  // block-local slots), then one STORE per point. All points of an
  // evaluation share the texel, so they hit or miss together; the last
  // LOOKUP jumps past the group when every lookup hit. On any miss the whole
  // union runs once (shared nodes are not evaluated per point) and each
  // STORE inserts and delivers only the values that missed.
  if (!cm.cache_plan.points.empty()) {
    std::vector<int> point_dst;
    size_t last_lookup = 0;
    for (const CachePoint& p : cm.cache_plan.points) {
      const Node& n = g.nodes[size_t(p.node)];
      int dst = allocate(width_of(p.node), "cache point '" + n.name + "'");
      slot_of[size_t(p.node)] = dst;
      point_dst.push_back(dst);
      last_lookup = em.size();
      em.instr_raw(PMC_OP_CACHE_LOOKUP, width_of(p.node), uint32_t(p.node) | (p.encoding << 14),
                   uint32_t(dst), {0u});
    }
    size_t after_lookups = em.size();
    std::vector<int> group;
    {
      std::vector<char> seen(g.nodes.size(), 0);
      for (const CachePoint& p : cm.cache_plan.points)
        for (int i : subgraph_order(g, p.node))
          if (!seen[size_t(i)]) {
            seen[size_t(i)] = 1;
            group.push_back(i);
          }
    }
    std::vector<int> block_slots(g.nodes.size(), -1);
    std::vector<int> block_uses = count_uses(group, false);
    for (const CachePoint& p : cm.cache_plan.points) ++block_uses[size_t(p.node)];  // read by its STORE
    slots = &block_slots;
    emit_nodes(group, block_uses, -1);
    slots = &slot_of;
    for (size_t k = 0; k < cm.cache_plan.points.size(); ++k) {
      const CachePoint& p = cm.cache_plan.points[k];
      int w = width_of(p.node);
      em.instr(PMC_OP_CACHE_STORE, w, uint32_t(p.node) | (p.encoding << 14), uint32_t(point_dst[k]),
               {Emitter::slot(uint32_t(block_slots[size_t(p.node)]), w)});
      release(block_slots[size_t(p.node)], w);
    }
    em.patch(last_lookup + 2, uint32_t(em.size() - after_lookups));
  }
  for (int i : order) {
    if (i == g.surface || is_point[size_t(i)]) continue;
    std::vector<int> one{i};
    emit_nodes(one, uses, -1);
  }
  // Surface parameters: links always, constants when they differ from the interpreter's defaults.
  const Node& surface = g.nodes[size_t(g.surface)];
  float defaults[PMC_P_COUNT];
  pmc_surface_defaults(defaults, make_float3(0, 0, 0));
  for (const SurfaceParam& p : surface_params(surface.category)) {
    const Input* in = surface.input(p.input);
    if (!in) continue;
    // Opacity is three floats in the block whatever the surface's type (a float broadcasts).
    int pw = p.param == PMC_P_OPACITY ? 3 : type_width(p.type);
    uint32_t d = in->linked ? deps[size_t(in->node)] : 0;
    cm.param_dependencies.push_back({p.input, d});
    if (p.param == PMC_P_OPACITY && in->linked && d != 0) cm.has_cutout = true;
    if (!in->linked) {
      if (p.param == PMC_P_NORMAL) continue;  // a constant normal means "keep the shading normal"
      bool differs = false;
      for (int k = 0; k < pw; ++k) {
        float v = type_width(in->type) == 1 ? in->value.f[0] : in->value.f[size_t(k)];
        differs = differs || v != defaults[p.param + k];
      }
      if (!differs) continue;
    }
    em.instr(PMC_OP_OUTPUT, pw, uint32_t(p.param), 0, {cx.operand(*in)});
  }
  // Constant emission, for light sampling (textured emission uses its constant part).
  {
    float params[PMC_P_COUNT];
    pmc_surface_defaults(params, make_float3(0, 0, 1));
    for (const SurfaceParam& p : surface_params(surface.category)) {
      const Input* in = surface.input(p.input);
      if (!in || in->linked || (p.param != PMC_P_EMISSION && p.param != PMC_P_EMISSION_COLOR)) continue;
      for (int k = 0; k < type_width(p.type); ++k)
        params[p.param + k] = type_width(in->type) == 1 ? in->value.f[0] : in->value.f[size_t(k)];
    }
    // A patterned (linked) emission is left to BSDF sampling: the light table
    // would treat it as uniform and bias the image. Its MIS weight is then 1.
    bool linked_emission = false;
    for (const SurfaceParam& p : surface_params(surface.category)) {
      const Input* in = surface.input(p.input);
      linked_emission |= in && in->linked && (p.param == PMC_P_EMISSION || p.param == PMC_P_EMISSION_COLOR);
    }
    for (int k = 0; k < 3; ++k)
      cm.constant_emission[k] =
          linked_emission ? 0.0f : std::max(0.0f, params[PMC_P_EMISSION] * params[PMC_P_EMISSION_COLOR + k]);
  }
  cm.entry = uint32_t(program.code.size());
  std::vector<uint32_t> code = em.finish(cm.entry);
  cm.code_words = uint32_t(code.size());
  cm.instructions = em.instructions();
  cm.peak_stack = peak;
  program.code.insert(program.code.end(), code.begin(), code.end());
  program.materials.push_back(cm);
  return program.materials.back();
}

std::string disassemble(const MaterialProgram& program, const CompiledMaterial& m) {
  static const char* names[] = {
#define PMC_OP_NAME(name, lo, hi) #name,
      PMC_OPCODES(PMC_OP_NAME)
#undef PMC_OP_NAME
  };
  std::ostringstream os;
  uint32_t pc = m.entry;
  const uint32_t end = m.entry + m.code_words;
  while (pc < end) {
    uint32_t h = program.code[pc];
    uint32_t op = pmc_op_code(h);
    os << "  " << pc - m.entry << ": " << (op < PMC_OP_COUNT ? names[op] : "?");
    if (op == PMC_OP_END) {
      os << "\n";
      break;
    }
    os << "." << pmc_op_width(h) << " ";
    if (op == PMC_OP_OUTPUT)
      os << "param[" << pmc_op_imm(h) << "]";
    else
      os << "s" << program.code[pc + 1];
    if (op == PMC_OP_CACHE_LOOKUP) {
      os << " node " << (pmc_op_imm(h) & 0x3fffu) << " enc " << (pmc_op_imm(h) >> 14) << " (hit: skip "
         << program.code[pc + 2] << " words)\n";
      pc += 3;
      continue;
    }
    if (pmc_op_imm(h) && op != PMC_OP_OUTPUT) os << " #" << pmc_op_imm(h);
    for (uint32_t k = 0; k < pmc_op_nargs(h); ++k) {
      uint32_t o = program.code[pc + 2 + k];
      uint32_t idx = o & PMC_OPERAND_INDEX_MASK, w = pmc_operand_width(o);
      os << (k ? ", " : " <- ");
      if (o & PMC_OPERAND_CONST) {
        os << "(";
        for (uint32_t j = 0; j < w; ++j) {
          float f;
          std::memcpy(&f, &program.code[idx + j], 4);
          os << (j ? " " : "") << f;
        }
        os << ")";
      } else {
        os << "s" << idx << (w > 1 ? "." + std::to_string(w) : "");
      }
    }
    os << "\n";
    pc += 2 + pmc_op_nargs(h);
  }
  return os.str();
}

}  // namespace pmc
