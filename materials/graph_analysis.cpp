// graph_analysis.cpp — type and cycle checks, topological order, dependency bits.
#include "materials/graph_analysis.h"

#include <functional>

#include "core/error.h"

namespace pmc {

void check_types(const Graph& g) {
  for (const Node& n : g.nodes) {
    if (n.dead) continue;
    for (const Input& in : n.inputs) {
      if (!in.linked) continue;
      if (in.node < 0 || size_t(in.node) >= g.nodes.size())
        fail(n.origin, ": input '", in.name, "' links to a missing node (dangling reference)");
      const Node& src = g.nodes[size_t(in.node)];
      bool ok = src.type == in.type ||
                (is_numeric(src.type) && type_width(src.type) == type_width(in.type)) ||
                (type_width(src.type) == 1 && is_numeric(in.type));
      if (!ok)
        fail(n.origin, ": input '", in.name, "' expects ", type_name(in.type), " but node '", src.name,
             "' outputs ", type_name(src.type), " (type mismatch)");
    }
  }
}

void check_acyclic(const Graph& g) {
  std::vector<int> state(g.nodes.size(), 0);  // 0 new, 1 on stack, 2 done
  std::vector<int> stack;
  std::function<void(int)> visit = [&](int i) {
    if (state[size_t(i)] == 2) return;
    if (state[size_t(i)] == 1) {
      std::string chain;
      bool on = false;
      for (int s : stack) {
        on = on || s == i;
        if (on) chain += "'" + g.nodes[size_t(s)].name + "' -> ";
      }
      fail(g.nodes[size_t(i)].origin, ": cycle in the node graph: ", chain, "'", g.nodes[size_t(i)].name,
           "'");
    }
    state[size_t(i)] = 1;
    stack.push_back(i);
    for (const Input& in : g.nodes[size_t(i)].inputs)
      if (in.linked) visit(in.node);
    stack.pop_back();
    state[size_t(i)] = 2;
  };
  for (size_t i = 0; i < g.nodes.size(); ++i)
    if (!g.nodes[i].dead) visit(int(i));
}

std::vector<int> topological_order(const Graph& g) {
  std::vector<int> order;
  std::vector<char> seen(g.nodes.size(), 0);
  std::function<void(int)> visit = [&](int i) {
    if (seen[size_t(i)]) return;
    seen[size_t(i)] = 1;
    for (const Input& in : g.nodes[size_t(i)].inputs)
      if (in.linked) visit(in.node);
    order.push_back(i);
  };
  if (g.surface >= 0) visit(g.surface);
  return order;
}

std::vector<uint32_t> dependencies(const Graph& g) {
  std::vector<uint32_t> deps(g.nodes.size(), 0);
  for (int i : topological_order(g)) {
    const Node& n = g.nodes[size_t(i)];
    const NodeDef* def = find_node_def(n.category);
    uint32_t d = def ? def->deps : 0u;
    for (const Input& in : n.inputs)
      if (in.linked) d |= deps[size_t(in.node)];
    deps[size_t(i)] = d;
  }
  return deps;
}

std::string dependency_names(uint32_t bits) {
  if (bits == 0) return "constant";
  std::string s;
  const char* names[] = {"uv", "position", "normal", "tangent", "bitangent"};
  for (int i = 0; i < 5; ++i)
    if (bits & (1u << i)) s += (s.empty() ? "" : "+") + std::string(names[i]);
  return s;
}

}  // namespace pmc
