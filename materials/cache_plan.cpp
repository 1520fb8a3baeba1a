// cache_plan.cpp — choosing cache points from the dependency bits.
#include "materials/cache_plan.h"

#include <algorithm>
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

// Groups of points for level floors. Points whose sub-graphs share a node
// (other than a bare texcoord or position) stay in one group, at the highest
// of their floors: splitting them would evaluate the shared nodes once per
// group on a miss (on the default scene's floor, whose three points share
// most of their nodes, that made --cache-bandwidth on 1.28x slower than
// one group). Points that share nothing keep their own floors, so a coarse
// pattern next to a fine one is still looked up at its footprint's texel.
// Lists the groups by floor, highest first (the material's floors, which
// the shade kernel computes texels with, are then the first group's).
void group_by_shared_nodes(const Graph& g, std::vector<CachePoint>& points) {
  const size_t n = points.size();
  std::vector<size_t> parent(n);
  for (size_t i = 0; i < n; ++i) parent[i] = i;
  std::function<size_t(size_t)> root = [&](size_t i) {
    return parent[i] == i ? i : parent[i] = root(parent[i]);
  };
  std::vector<std::vector<char>> member(n, std::vector<char>(g.nodes.size(), 0));
  for (size_t i = 0; i < n; ++i)
    for (int node : subgraph_order(g, points[i].node))
      if (!is_texcoord(g.nodes[size_t(node)]) && !is_position(g.nodes[size_t(node)]))
        member[i][size_t(node)] = 1;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      for (size_t node = 0; node < g.nodes.size(); ++node)
        if (member[i][node] && member[j][node]) {
          parent[root(i)] = root(j);
          break;
        }
  std::vector<int> floor_of(n, PMC_LEVEL_NO_FLOOR);
  for (size_t i = 0; i < n; ++i) floor_of[root(i)] = std::max(floor_of[root(i)], points[i].level_floor);
  for (size_t i = 0; i < n; ++i) {
    points[i].group = int(root(i));
    points[i].group_floor = floor_of[root(i)];
  }
  // Highest floor first, a group's points together, otherwise in plan order.
  std::stable_sort(points.begin(), points.end(), [](const CachePoint& a, const CachePoint& b) {
    return a.group_floor != b.group_floor ? a.group_floor > b.group_floor : a.group < b.group;
  });
  int next = 0;
  for (size_t i = 0; i < n; ++i) {
    const int old_group = points[i].group;
    if (old_group < 0) continue;
    for (size_t j = i; j < n; ++j)
      if (points[j].group == old_group) points[j].group = -1 - next;
    ++next;
  }
  for (CachePoint& p : points) p.group = -1 - p.group;
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

const char* cache_key_name(CacheKey k) { return k == CacheKey::Position ? "position" : "uv"; }

int material_level_floor(const CachePlan& plan, CacheKey key) {
  int floor_level = PMC_LEVEL_NO_FLOOR;
  for (const CachePoint& p : plan.points)
    if (p.key == key) floor_level = std::max(floor_level, p.level_floor);
  return floor_level;
}

CachePlan plan_cache(const Graph& g, int min_nodes, bool position_keys, double feature_texels) {
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
    } else {
      chosen.insert(n);
      CachePoint p;
      p.node = n;
      p.subgraph_nodes = size;
      p.encoding = enc;
      p.key = deps[size_t(n)] == kDepPosition ? CacheKey::Position : CacheKey::Uv;
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
  if (bandwidth) group_by_shared_nodes(g, plan.points);
  return plan;
}

}  // namespace pmc
