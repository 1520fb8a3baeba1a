// cache_plan.cpp — choosing cache points from the dependency bits.
#include "materials/cache_plan.h"

#include <functional>
#include <set>

#include "core/device/pmc_cache.h"
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

CachePlan plan_cache(const Graph& g, int min_nodes) {
  CachePlan plan;
  std::vector<uint32_t> deps = dependencies(g);
  std::vector<int> order = topological_order(g);
  // Is any consumer of a node uv-only too? Then the node is not the highest.
  std::vector<char> has_uv_only_consumer(g.nodes.size(), 0);
  for (int i : order) {
    if (i == g.surface) continue;
    for (const Input& in : g.nodes[size_t(i)].inputs)
      if (in.linked && deps[size_t(i)] == kDepUv) has_uv_only_consumer[size_t(in.node)] = 1;
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
      why = "sub-graph of " + std::to_string(size) + " nodes is cheaper than a lookup (threshold " +
            std::to_string(min_nodes) + ")";
    } else if (node.input("index") && is_texcoord(node)) {
      why = "a bare texcoord";
    } else {
      chosen.insert(n);
      plan.points.push_back({n, size, enc});
      return;
    }
    plan.not_cached.push_back({n, why});
    if (size >= min_nodes)
      for (const Input& in : node.inputs)
        if (in.linked && deps[size_t(in.node)] == kDepUv) consider(in.node);
  };
  for (int i : order) {
    if (i == g.surface) continue;
    uint32_t d = deps[size_t(i)];
    if (d == kDepUv && !has_uv_only_consumer[size_t(i)]) {
      consider(i);
    } else if (d != kDepUv && d != 0 && (d & kDepUv) == 0 && !is_texcoord(g.nodes[size_t(i)])) {
      plan.not_cached.push_back({i, "depends on " + dependency_names(d)});
    } else if (d != kDepUv && (d & kDepUv)) {
      plan.not_cached.push_back({i, "depends on " + dependency_names(d) + ", not only uv"});
    }
  }
  return plan;
}

}  // namespace pmc
