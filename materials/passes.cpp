// passes.cpp — folding, deduplication, dead-node removal, and the pass order.
#include "materials/passes.h"

#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

#include "core/error.h"
#include "materials/emit.h"
#include "materials/lowering.h"
#include "materials/node_table.h"

namespace pmc {
namespace {

// Points every consumer of `from` at what `replacement` holds.
void replace_uses(Graph& g, int from, const Input& replacement) {
  for (Node& n : g.nodes) {
    if (n.dead) continue;
    for (Input& in : n.inputs) {
      if (!in.linked || in.node != from) continue;
      ValueType t = in.type;
      std::string name = in.name;
      in = replacement;
      in.name = name;
      in.type = t;
      if (!in.linked) {
        in.value.type = t;
        if (type_width(replacement.type) == 1)
          for (int i = 1; i < 4; ++i) in.value.f[size_t(i)] = in.value.f[0];
      }
    }
  }
  g.nodes[size_t(from)].dead = true;
}

bool all_lanes(const Input& in, float v) {
  if (in.linked) return false;
  int w = std::max(1, type_width(in.type));
  for (int i = 0; i < w; ++i)
    if (in.value.f[size_t(i)] != v) return false;
  return true;
}

}  // namespace

size_t fold_constants(Graph& g) {
  size_t removed = 0;
  for (int i : topological_order(g)) {
    Node& n = g.nodes[size_t(i)];
    if (n.dead || i == g.surface) continue;
    bool all_const = true;
    for (const Input& in : n.inputs) all_const = all_const && !in.linked;
    Value v;
    if (all_const && evaluate_constant(g, n, v)) {
      Input c;
      c.type = n.type;
      c.value = v;
      c.value.type = n.type;
      replace_uses(g, i, c);
      ++removed;
      continue;
    }
    // Identities (the node table's Algebra). A pass-through input replaces
    // the node only if it has the node's width.
    auto pass = [&](const char* name) {
      const Input* in = n.input(name);
      if (!in || (in->linked && type_width(g.nodes[size_t(in->node)].type) != type_width(n.type)))
        return false;
      Input copy = *in;
      replace_uses(g, i, copy);
      ++removed;
      return true;
    };
    const NodeDef* def = find_node_def(n.category);
    if (!def) continue;
    const Algebra& alg = def->algebra;
    Input* a = n.input("in1");
    Input* b = n.input("in2");
    auto is = [](const Input& in, float v) { return !std::isnan(v) && all_lanes(in, v); };
    if (a && b && (alg.zero_absorbs || !std::isnan(alg.right_identity) || !std::isnan(alg.left_identity))) {
      if (alg.zero_absorbs && (all_lanes(*a, 0.0f) || all_lanes(*b, 0.0f))) {
        replace_uses(g, i, Input::constant("", n.type, 0, 0, 0, 0));
        ++removed;
      } else if (is(*b, alg.right_identity)) {
        pass("in1");
      } else if (is(*a, alg.left_identity)) {
        pass("in2");
      }
    } else if (alg.selector) {
      const Input* m = n.input(alg.selector);
      if (m && all_lanes(*m, 0.0f))
        pass(alg.select0);
      else if (m && all_lanes(*m, 1.0f))
        pass(alg.select1);
    } else if (alg.pass_through) {
      const Input* in = n.input(alg.pass_through);
      if (in && type_width(in->type) == type_width(n.type)) pass(alg.pass_through);
    }
  }
  return removed;
}

size_t deduplicate(Graph& g) {
  size_t removed = 0;
  std::map<std::string, int> canonical;
  for (int i : topological_order(g)) {
    Node& n = g.nodes[size_t(i)];
    if (n.dead || i == g.surface) continue;
    std::ostringstream key;
    key << n.category << '.' << n.output << '|' << int(n.type);  // each output of a multi-output node
    for (const Input& in : n.inputs) {
      key << '|' << in.name << ':';
      if (in.linked) {
        key << 'n' << in.node;
      } else {
        key << int(in.type);
        for (float f : in.value.f) {  // exact bits: printing rounds to 6 digits
          uint32_t bits;
          std::memcpy(&bits, &f, 4);
          key << ',' << bits;
        }
        key << ',' << in.value.text;
      }
    }
    auto [it, inserted] = canonical.emplace(key.str(), i);
    if (!inserted) {
      Input link;
      link.linked = true;
      link.node = it->second;
      link.type = n.type;
      replace_uses(g, i, link);
      ++removed;
    }
  }
  return removed;
}

size_t remove_dead(Graph& g) {
  std::vector<char> live(g.nodes.size(), 0);
  for (int i : topological_order(g)) live[size_t(i)] = 1;
  size_t removed = 0;
  for (size_t i = 0; i < g.nodes.size(); ++i)
    if (!live[i] && !g.nodes[i].dead) {
      g.nodes[i].dead = true;
      ++removed;
    }
  return removed;
}

std::vector<PassStat> optimize(Graph& g) {
  std::vector<PassStat> stats;
  auto run = [&](const char* name, auto&& fn) {
    PassStat s{name, g.live_count(), 0};
    fn();
    s.after = g.live_count();
    stats.push_back(s);
  };
  if (g.surface < 0) fail(g.file, ": material '", g.material, "' has no surface shader");
  run("lower", [&] { lower_composites(g); });
  run("check types", [&] { check_types(g); });
  run("check cycles", [&] { check_acyclic(g); });
  run("remove dead", [&] { remove_dead(g); });
  run("fold constants", [&] { fold_constants(g); });
  run("deduplicate", [&] { deduplicate(g); });
  run("remove dead", [&] { remove_dead(g); });
  return stats;
}

}  // namespace pmc
