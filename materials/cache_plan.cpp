// cache_plan.cpp — choosing cache points from the dependency bits.
#include "materials/cache_plan.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <set>

#include "core/device/pmc_cache.h"
#include "materials/bandwidth.h"
#include "materials/graph_analysis.h"
#include "materials/node_table.h"

namespace pmc {
namespace {

bool encoding_for(ValueType t, uint32_t& enc) {
  switch (t) {
    case ValueType::Float:
    case ValueType::Integer:
    case ValueType::Boolean:
      enc = PMC_ENC_FLOAT;
      return true;
    case ValueType::Color3:
    case ValueType::Vector3:
      enc = PMC_ENC_RGB9E5;
      return true;
    case ValueType::Vector2:
      enc = PMC_ENC_HALF2;
      return true;
    default:
      return false;
  }
}

bool is_texcoord(const Node& n) {
  const NodeDef* def = find_node_def(n.category);
  return def && def->opcode == PMC_OP_TEXCOORD;
}

bool is_position(const Node& n) {
  const NodeDef* def = find_node_def(n.category);
  return def && def->opcode == PMC_OP_POSITION;
}

// The dependency bits a cache point may have: exactly one key input.
bool keyable(uint32_t d, bool position_keys) { return d == kDepUv || (position_keys && d == kDepPosition); }

}  // namespace

std::vector<int> subgraph_order(const Graph& g, int node) {
  std::vector<int> order;
  std::set<int> seen;
  std::function<void(int)> visit = [&](int i) {
    if (!seen.insert(i).second) return;
    for (const Input& in : g.nodes[size_t(i)].inputs)
      if (in.linked) visit(in.node);
    order.push_back(i);
  };
  visit(node);
  return order;
}

const char* cache_key_name(CacheKey k) { return k == CacheKey::Position ? "position" : "uv"; }

int material_level_floor(const CachePlan& plan, CacheKey key) {
  int floor_level = PMC_LEVEL_NO_FLOOR;
  for (const CachePoint& p : plan.points)
    if (p.key == key) floor_level = std::max(floor_level, p.level_floor);
  return floor_level;
}

namespace {

// Why a point the node count admits does not pay, with the figures.
std::string unpaid_reason(const PointEconomics& e, const CacheCosts& costs) {
  char text[400];
  std::snprintf(text, sizeof text,
                "does not pay on this device: sub-graph cost C %.1f unit nodes, expected hit rate h %.1f%%, "
                "h C = %.1f <= lookup L %.1f + (1 - h) x miss M %.1f (K %d sub-samples; gain %.1f unit nodes "
                "per lookup; costs: %s)",
                e.cost, 100.0 * e.hit_rate, e.hit_rate * e.cost, e.lookup, e.miss, e.samples, e.gain,
                costs.source.c_str());
  return text;
}

}  // namespace

CachePlan plan_cache(const Graph& g, int min_nodes, bool position_keys, double feature_texels,
                     const CacheCostModel* model, CacheSupersample supersample) {
  const bool bandwidth = feature_texels > 0;
  CachePlan plan;
  std::vector<uint32_t> deps = dependencies(g);
  std::vector<NodeBandwidth> bw;
  if (bandwidth) bw = node_bandwidths(g);
  std::vector<int> order = topological_order(g);
  // Does any consumer of a node depend on the same single key input? Then the
  // node is not the highest of its kind.
  std::vector<char> has_keyed_consumer(g.nodes.size(), 0);
  for (int i : order) {
    if (i == g.surface) continue;
    for (const Input& in : g.nodes[size_t(i)].inputs)
      if (in.linked && keyable(deps[size_t(i)], position_keys) && deps[size_t(i)] == deps[size_t(in.node)])
        has_keyed_consumer[size_t(in.node)] = 1;
  }
  std::set<int> chosen;
  std::function<void(int)> consider = [&](int n) {
    if (chosen.count(n)) return;
    const Node& node = g.nodes[size_t(n)];
    uint32_t enc = 0;
    int size = int(subgraph_order(g, n).size());
    std::string why;
    if (!encoding_for(node.type, enc)) {
      why = std::string(type_name(node.type)) + " values have no 32-bit encoding; trying its inputs";
    } else if (size < min_nodes) {
      why = dependency_names(deps[size_t(n)]) + "-only sub-graph of " + std::to_string(size) +
            " nodes is cheaper than a lookup (threshold " + std::to_string(min_nodes) + ")";
    } else if ((node.input("index") && is_texcoord(node)) || is_position(node)) {
      why = is_position(node) ? "a bare position" : "a bare texcoord";
    } else if (PointEconomics e;
               model &&
               !cache_point_pays(e = point_economics(subgraph_cost(g, n), deps[size_t(n)] == kDepPosition,
                                                     model->costs, model->frame,
                                                     supersample.of(deps[size_t(n)] == kDepPosition)))) {
      plan.not_cached.push_back({n, unpaid_reason(e, model->costs)});
      return;  // its inputs cost less at the same hit rate: they would pay less
    } else {
      chosen.insert(n);
      CachePoint p;
      p.node = n;
      p.subgraph_nodes = size;
      p.encoding = enc;
      p.key = deps[size_t(n)] == kDepPosition ? CacheKey::Position : CacheKey::Uv;
      p.supersample = supersample.of(p.key == CacheKey::Position);
      if (model) {
        p.modelled = true;
        p.economics = point_economics(subgraph_cost(g, n), p.key == CacheKey::Position, model->costs,
                                      model->frame, p.supersample);
      }
      if (bandwidth) {
        p.feature = bw[size_t(n)].feature();
        p.level_floor =
            level_floor_for_feature(p.feature, feature_texels, PMC_LEVEL_NO_FLOOR, PMC_LAMBDA_MAX);
        p.bandwidth_note = bw[size_t(n)].unbounded;
      }
      plan.points.push_back(p);
      return;
    }
    plan.not_cached.push_back({n, why});
    if (size >= min_nodes)
      for (const Input& in : node.inputs)
        if (in.linked && deps[size_t(in.node)] == deps[size_t(n)]) consider(in.node);
  };
  for (int i : order) {
    if (i == g.surface) continue;
    uint32_t d = deps[size_t(i)];
    const Node& node = g.nodes[size_t(i)];
    if (keyable(d, position_keys) && !has_keyed_consumer[size_t(i)]) {
      consider(i);
    } else if (keyable(d, position_keys) || d == 0 || is_texcoord(node) || is_position(node)) {
      continue;  // below a point of its kind, constant, or a bare key input
    } else if (d == kDepPosition) {
      plan.not_cached.push_back({i, "depends on position (position keys are off)"});
    } else {
      plan.not_cached.push_back(
          {i, "depends on " + dependency_names(d) + ", not on uv alone or position alone"});
    }
  }
  return plan;
}

}  // namespace pmc
