// compiler.cpp — program layout: cache group, slot allocation, surface outputs, disassembly.
#include "materials/compiler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <sstream>

#include "core/device/pmc_interp.h"
#include "core/error.h"
#include "materials/emit.h"
#include "materials/node_table.h"

namespace pmc {

const CompiledMaterial& compile_material(Graph& g, TexturePool& textures, MaterialProgram& program,
                                         const CompileOptions& options) {
  CompiledMaterial cm;
  cm.name = g.material;
  cm.file = g.file;
  cm.passes = optimize(g);
  std::vector<uint32_t> deps = dependencies(g);
  std::vector<char> is_point(g.nodes.size(), 0);
  if (options.cache) {
    cm.cache_plan = plan_cache(g, options.cache_min_nodes, options.cache_position_keys, options.cache_feature_texels);
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
  // block-local slots), then one STORE per point. A LOOKUP's skip word
  // carries PMC_CACHE_KEY_POSITION for a position-keyed point; the last
  // LOOKUP jumps past the group when every lookup hit. On any miss the whole
  // union runs once (shared nodes are not evaluated per point) and each
  // STORE inserts and delivers only the values that missed.
  if (!cm.cache_plan.points.empty()) {
    std::vector<int> point_dst;
    size_t last_lookup = 0;
    uint32_t last_kind = 0;
    for (const CachePoint& p : cm.cache_plan.points) {
      const Node& n = g.nodes[size_t(p.node)];
      int dst = allocate(width_of(p.node), "cache point '" + n.name + "'");
      slot_of[size_t(p.node)] = dst;
      point_dst.push_back(dst);
      last_lookup = em.size();
      last_kind = p.key == CacheKey::Position ? PMC_CACHE_KEY_POSITION : 0u;
      em.instr_raw(PMC_OP_CACHE_LOOKUP, width_of(p.node), uint32_t(p.node) | (p.encoding << 14),
                   uint32_t(dst), {last_kind});
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
    em.patch(last_lookup + 2, uint32_t(em.size() - after_lookups) | last_kind);
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
#define PMC_OP_NAME(name, lo, hi, slots) #name,
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
      const uint32_t word = program.code[pc + 2];
      os << " node " << (pmc_op_imm(h) & 0x3fffu) << " enc " << (pmc_op_imm(h) >> 14) << " key "
         << ((word & PMC_CACHE_KEY_POSITION) ? "position" : "uv") << " (hit: skip "
         << (word & ~PMC_CACHE_KEY_POSITION) << " words)\n";
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
