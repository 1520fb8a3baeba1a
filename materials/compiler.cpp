// compiler.cpp — compile_material(): a material graph into its program, as
// the steps docs/DESIGN.md names them: lowering and graph passes, analysis,
// cache plan, layout, emit. Each step below is one function; the driver at
// the bottom runs them in that order.
#include "materials/compiler.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "core/device/pmc_interp.h"
#include "core/error.h"
#include "materials/emit.h"
#include "materials/node_table.h"

namespace pmc {
namespace {

// A point's sub-samples (a power of two, 1..16) as its CACHE_LOOKUP word's
// PMC_CACHE_SAMPLES_* bits.
uint32_t samples_bits(int samples) {
  PMC_CHECK(samples >= 1 && samples <= int(PMC_CACHE_SAMPLES_MAX) && (samples & (samples - 1)) == 0,
            "cache sub-samples must be a power of two 1..16");
  uint32_t log2k = 0;
  while ((1 << log2k) < samples) ++log2k;
  return log2k << PMC_CACHE_SAMPLES_SHIFT;
}

// Cache plan: the planner's points, less those a cache instruction cannot
// carry. The node id travels in 14 bits of the instruction; the interpreter
// tracks a group's misses in one 32-bit mask.
CachePlan plan_cache_points(const Graph& g, const CompileOptions& options) {
  CachePlan plan =
      plan_cache(g, options.cache_min_nodes, options.cache_position_keys, options.cache_feature_texels,
                 options.cache_model ? &*options.cache_model : nullptr, options.cache_supersample);
  std::vector<CachePoint> kept;
  for (const CachePoint& p : plan.points)
    if (p.node < (1 << 14) && kept.size() < 32) {
      kept.push_back(p);
    } else {
      plan.not_cached.push_back({p.node, p.node >= (1 << 14)
                                             ? "node id beyond the 14 bits a cache instruction holds"
                                             : "the material already has 32 cache points (one miss mask)"});
    }
  // One group per key kind, uv first (ProgramEmitter::cache_groups): the
  // points in the order their lookups run, which is their rank.
  std::stable_partition(kept.begin(), kept.end(),
                        [](const CachePoint& p) { return p.key != CacheKey::Position; });
  plan.points = kept;
  return plan;
}

// Layout: which nodes are cache points, the order the nodes outside the
// cache group are emitted in (inputs first; cache points are leaves there,
// their sub-graphs live in the group), and how often each is read.
struct Layout {
  std::vector<char> is_point;
  std::vector<int> outside_order;
};

// Uses of each node by the nodes of `nodes` (not looking into cache points
// when `stop_at_points`).
std::vector<int> count_uses(const Graph& g, const std::vector<int>& nodes, const std::vector<char>& is_point,
                            bool stop_at_points) {
  std::vector<int> uses(g.nodes.size(), 0);
  for (int i : nodes) {
    if (stop_at_points && is_point[size_t(i)]) continue;
    for (const Input& in : g.nodes[size_t(i)].inputs)
      if (in.linked) ++uses[size_t(in.node)];
  }
  return uses;
}

Layout lay_out(const Graph& g, const CachePlan& plan) {
  Layout layout;
  layout.is_point.assign(g.nodes.size(), 0);
  for (const CachePoint& p : plan.points) layout.is_point[size_t(p.node)] = 1;
  std::vector<char> seen(g.nodes.size(), 0);
  std::function<void(int)> visit = [&](int i) {
    if (seen[size_t(i)]) return;
    seen[size_t(i)] = 1;
    if (!layout.is_point[size_t(i)])
      for (const Input& in : g.nodes[size_t(i)].inputs)
        if (in.linked) visit(in.node);
    layout.outside_order.push_back(i);
  };
  visit(g.surface);
  return layout;
}

// The float stack's slots: first fit, freed after a value's last use; the
// peak sizes the kernel's stack.
class SlotAllocator {
 public:
  explicit SlotAllocator(const Graph& g) : g_(g), used_(PMC_STACK_SIZE + 8, 0) {}
  int allocate(int width, const std::string& who) {
    for (int s = 0; s + width <= PMC_STACK_SIZE; ++s) {
      bool free = true;
      for (int k = 0; k < width && free; ++k) free = !used_[size_t(s + k)];
      if (!free) continue;
      for (int k = 0; k < width; ++k) used_[size_t(s + k)] = 1;
      peak_ = std::max(peak_, uint32_t(s + width));
      return s;
    }
    fail(g_.file, ": material '", g_.material, "' needs more than ", PMC_STACK_SIZE,
         " floats of interpreter stack at ", who, " (the network is too deep or wide to evaluate)");
  }
  void release(int slot, int width) {
    for (int k = 0; k < width; ++k) used_[size_t(slot + k)] = 0;
  }
  uint32_t peak() const { return peak_; }

 private:
  const Graph& g_;
  std::vector<char> used_;
  uint32_t peak_ = 0;
};

// Emit: one material's instructions, node by node, into `em`.
class ProgramEmitter {
 public:
  ProgramEmitter(const Graph& g, TexturePool& textures, const Layout& layout)
      : g_(g), layout_(layout), slots_(g), slot_of_(g.nodes.size(), -1), cx_{g, &textures, em_, nullptr} {
    cx_.operand = [this](const Input& in) -> uint32_t {
      if (!in.linked) return em_.constant(in.value, std::max(1, type_width(in.type)));
      int s = (*operand_slots_)[size_t(in.node)];
      PMC_CHECK(s >= 0, "operand emitted before its node");
      return Emitter::slot(uint32_t(s), width_of(in.node));
    };
  }

  // The cache groups, one per key kind in the plan's order (uv points
  // first: plan_cache_points), each emitted by cache_group().
  void cache_groups(const CachePlan& plan) {
    for (size_t first = 0; first < plan.points.size();) {
      size_t end = first;
      while (end < plan.points.size() && plan.points[end].key == plan.points[first].key) ++end;
      cache_group(
          std::vector<CachePoint>(plan.points.begin() + long(first), plan.points.begin() + long(end)));
      first = end;
    }
  }

  // One cache group: every point's LOOKUP first, then the union of their
  // sub-graphs (each node once, its own texcoord included, in block-local
  // slots), then one STORE per point. A LOOKUP's skip word carries
  // PMC_CACHE_KEY_POSITION for a position-keyed point and its sub-samples
  // (PMC_CACHE_SAMPLES_*: the union replays once per sub-sample in
  // cache_eval center; the STOREs' destinations, allocated before it, are
  // never its slots, so they can sum the sub-samples); the last LOOKUP jumps
  // past the group when every lookup hit. On any miss the whole union runs
  // once (shared nodes are not evaluated per point) and each STORE inserts
  // and delivers only the values that missed.
  void cache_group(const std::vector<CachePoint>& points) {
    std::vector<int> point_dst;
    size_t last_lookup = 0;
    uint32_t last_kind = 0;
    for (const CachePoint& p : points) {
      const Node& n = g_.nodes[size_t(p.node)];
      int dst = slots_.allocate(width_of(p.node), "cache point '" + n.name + "'");
      slot_of_[size_t(p.node)] = dst;
      point_dst.push_back(dst);
      last_lookup = em_.size();
      last_kind = (p.key == CacheKey::Position ? PMC_CACHE_KEY_POSITION : 0u) | samples_bits(p.supersample);
      em_.instr_raw(PMC_OP_CACHE_LOOKUP, width_of(p.node), uint32_t(p.node) | (p.encoding << 14),
                    uint32_t(dst), {last_kind});
    }
    size_t after_lookups = em_.size();
    std::vector<int> group;
    std::vector<char> seen(g_.nodes.size(), 0);
    for (const CachePoint& p : points)
      for (int i : subgraph_order(g_, p.node))
        if (!seen[size_t(i)]) {
          seen[size_t(i)] = 1;
          group.push_back(i);
        }
    std::vector<int> block_slots(g_.nodes.size(), -1);
    std::vector<int> block_uses = count_uses(g_, group, layout_.is_point, false);
    for (const CachePoint& p : points) ++block_uses[size_t(p.node)];  // read by its STORE
    operand_slots_ = &block_slots;
    emit_nodes(group, block_uses);
    operand_slots_ = &slot_of_;
    for (size_t k = 0; k < points.size(); ++k) {
      const CachePoint& p = points[k];
      int w = width_of(p.node);
      em_.instr(PMC_OP_CACHE_STORE, w, uint32_t(p.node) | (p.encoding << 14), uint32_t(point_dst[k]),
                {Emitter::slot(uint32_t(block_slots[size_t(p.node)]), w)});
      slots_.release(block_slots[size_t(p.node)], w);
    }
    em_.patch(last_lookup + 2, uint32_t(em_.size() - after_lookups) | last_kind);
  }

  // The nodes outside the group, inputs first (the surface's inputs are
  // emitted as OUTPUTs by surface_outputs()).
  void outside_nodes() {
    std::vector<int> uses = count_uses(g_, layout_.outside_order, layout_.is_point, true);
    for (int i : layout_.outside_order) {
      if (i == g_.surface || layout_.is_point[size_t(i)]) continue;
      emit_nodes({i}, uses);
    }
  }

  // Surface parameters: links always, constants when they differ from the
  // interpreter's defaults; records each parameter's dependency bits.
  void surface_outputs(const std::vector<uint32_t>& deps, CompiledMaterial& cm) {
    const Node& surface = g_.nodes[size_t(g_.surface)];
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
      em_.instr(PMC_OP_OUTPUT, pw, uint32_t(p.param), 0, {cx_.operand(*in)});
    }
  }

  Emitter& emitter() { return em_; }
  uint32_t peak_stack() const { return slots_.peak(); }

 private:
  int width_of(int node) const { return std::max(1, type_width(g_.nodes[size_t(node)].type)); }

  // Emits `nodes` (inputs first), freeing slots after their last use.
  void emit_nodes(const std::vector<int>& nodes, std::vector<int>& use_count) {
    for (int i : nodes) {
      const Node& n = g_.nodes[size_t(i)];
      int dst = slots_.allocate(width_of(i), "node '" + n.name + "' (" + n.origin + ")");
      emit_node(cx_, n, uint32_t(dst));
      (*operand_slots_)[size_t(i)] = dst;
      for (const Input& in : n.inputs)
        if (in.linked && --use_count[size_t(in.node)] == 0)
          slots_.release((*operand_slots_)[size_t(in.node)], width_of(in.node));
    }
  }

  const Graph& g_;
  const Layout& layout_;
  SlotAllocator slots_;
  Emitter em_;
  std::vector<int> slot_of_;
  std::vector<int>* operand_slots_ = &slot_of_;  // the slot map operands read (outside or group-local)
  EmitContext cx_;
};

// The surface's constant emission, for light sampling (textured emission
// uses its constant part). A patterned (linked) emission is left to BSDF
// sampling: the light table would treat it as uniform and bias the image.
// Its MIS weight is then 1.
void constant_emission(const Graph& g, float out[3]) {
  const Node& surface = g.nodes[size_t(g.surface)];
  float params[PMC_P_COUNT];
  pmc_surface_defaults(params, make_float3(0, 0, 1));
  bool linked_emission = false;
  for (const SurfaceParam& p : surface_params(surface.category)) {
    const Input* in = surface.input(p.input);
    const bool emission = p.param == PMC_P_EMISSION || p.param == PMC_P_EMISSION_COLOR;
    linked_emission |= in && in->linked && emission;
    if (!in || in->linked || !emission) continue;
    for (int k = 0; k < type_width(p.type); ++k)
      params[p.param + k] = type_width(in->type) == 1 ? in->value.f[0] : in->value.f[size_t(k)];
  }
  for (int k = 0; k < 3; ++k)
    out[k] =
        linked_emission ? 0.0f : std::max(0.0f, params[PMC_P_EMISSION] * params[PMC_P_EMISSION_COLOR + k]);
}

// Whether a program (its words from its first instruction) filters an image
// by the ray cone's footprint: the only instructions that read it.
bool reads_footprint(const std::vector<uint32_t>& code) {
  for (size_t pc = 0; pc < code.size(); pc += 2 + pmc_op_nargs(code[pc])) {
    const uint32_t op = pmc_op_code(code[pc]);
    if (op == PMC_OP_END) return false;
    if (op == PMC_OP_IMAGE || op == PMC_OP_HEXIMAGE || op == PMC_OP_HEXNORMALMAP) return true;
  }
  return false;
}

// Whether a program writes the surface's emission or its colour: the only
// way it emits (both default to no emission, and a constant equal to its
// default is not written).
bool writes_emission(const std::vector<uint32_t>& code) {
  for (size_t pc = 0; pc < code.size(); pc += 2 + pmc_op_nargs(code[pc])) {
    const uint32_t h = code[pc], op = pmc_op_code(h);
    if (op == PMC_OP_END) return false;
    if (op == PMC_OP_OUTPUT && pmc_op_imm(h) <= PMC_P_EMISSION_COLOR + 2u &&
        pmc_op_imm(h) + pmc_op_width(h) > PMC_P_EMISSION)
      return true;
  }
  return false;
}

}  // namespace

// The interpreter's only per-point inputs are what these instructions read:
// the point's uv, position, frame, footprint, or a cache key made of them. A
// written normal replaces the point's own (the default), so it too differs.
bool program_is_uniform(const std::vector<uint32_t>& code) {
  for (size_t pc = 0; pc < code.size(); pc += 2 + pmc_op_nargs(code[pc])) {
    const uint32_t h = code[pc], op = pmc_op_code(h);
    switch (op) {
      case PMC_OP_END:
        return true;
      case PMC_OP_TEXCOORD:
      case PMC_OP_POSITION:
      case PMC_OP_NORMAL:
      case PMC_OP_TANGENT:
      case PMC_OP_BITANGENT:
      case PMC_OP_IMAGE:
      case PMC_OP_HEXIMAGE:
      case PMC_OP_HEXNORMALMAP:
      case PMC_OP_CACHE_LOOKUP:
      case PMC_OP_CACHE_STORE:
        return false;
      case PMC_OP_OUTPUT:
        if (pmc_op_imm(h) <= PMC_P_NORMAL + 2u && pmc_op_imm(h) + pmc_op_width(h) > PMC_P_NORMAL)
          return false;
        break;
      default:
        break;
    }
  }
  return true;
}

const CompiledMaterial& compile_material(Graph& g, TexturePool& textures, MaterialProgram& program,
                                         const CompileOptions& options) {
  CompiledMaterial cm;
  cm.name = g.material;
  cm.file = g.file;
  cm.passes = optimize(g);                                           // lowering and graph passes
  const std::vector<uint32_t> deps = dependencies(g);                // analysis
  if (options.cache) cm.cache_plan = plan_cache_points(g, options);  // cache plan
  const Layout layout = lay_out(g, cm.cache_plan);                   // layout
  ProgramEmitter emit(g, textures, layout);                          // emit
  emit.cache_groups(cm.cache_plan);
  emit.outside_nodes();
  emit.surface_outputs(deps, cm);
  constant_emission(g, cm.constant_emission);
  cm.entry = uint32_t(program.code.size());
  std::vector<uint32_t> code = emit.emitter().finish(cm.entry);
  cm.code_words = uint32_t(code.size());
  cm.reads_footprint = reads_footprint(code);
  cm.uniform = program_is_uniform(code);
  cm.may_emit = writes_emission(code);
  cm.instructions = emit.emitter().instructions();
  cm.peak_stack = emit.peak_stack();
  program.code.insert(program.code.end(), code.begin(), code.end());
  program.materials.push_back(cm);
  return program.materials.back();
}

}  // namespace pmc
