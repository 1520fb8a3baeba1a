// passes.cpp — lowering, checks, folding, deduplication, dead-node removal.
// (heighttonormal and bump are lowered in height_normal.cpp.)
#include "materials/passes.h"

#include <cstring>
#include <functional>
#include <map>
#include <sstream>

#include "core/error.h"
#include "materials/compiler.h"
#include "materials/height_normal.h"

namespace pmc {
namespace {

Input copy_input(const Input& src, const std::string& name) {
  Input in = src;
  in.name = name;
  return in;
}

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

void lower_composites(Graph& g) {
  const size_t count = g.nodes.size();
  for (size_t i = 0; i < count; ++i) {
    if (g.nodes[i].dead) continue;
    if (g.nodes[i].category == "invert") {  // invert = amount - in
      Node& n = g.nodes[i];
      Input a = copy_input(*n.input("amount"), "in1"), b = copy_input(*n.input("in"), "in2");
      n.category = "subtract";
      n.inputs = {a, b};
    } else if (g.nodes[i].category == "tiledimage") {
      // MaterialX NG_tiledimage: ((uv * uvtiling - uvoffset) / realworldimagesize) * realworldtilesize
      Node tiled = g.nodes[i];
      auto make = [&](const std::string& cat, Input a, Input b) {
        Node m;
        m.category = cat;
        m.type = ValueType::Vector2;
        m.origin = tiled.origin + " (" + cat + ")";
        a.name = "in1";
        b.name = "in2";
        m.inputs = {a, b};
        return g.add(m);
      };
      auto link = [](int node) {
        Input in;
        in.linked = true;
        in.node = node;
        in.type = ValueType::Vector2;
        return in;
      };
      int mul = make("multiply", *tiled.input("texcoord"), *tiled.input("uvtiling"));
      int sub = make("subtract", link(mul), *tiled.input("uvoffset"));
      int div = make("divide", link(sub), *tiled.input("realworldimagesize"));
      int scale = make("multiply", link(div), *tiled.input("realworldtilesize"));
      Node& n = g.nodes[i];  // g.nodes may have moved
      Input uv = link(scale);
      uv.name = "texcoord";
      Input file = *n.input("file"), def = *n.input("default"), filter = *n.input("filtertype");
      n.category = "image";
      n.inputs = {file, def, uv};
      Input periodic;
      periodic.type = ValueType::String;
      periodic.value.type = ValueType::String;
      periodic.value.text = "periodic";
      periodic.name = "uaddressmode";
      n.inputs.push_back(periodic);
      periodic.name = "vaddressmode";
      n.inputs.push_back(periodic);
      n.inputs.push_back(filter);
    }
  }
  lower_height_to_normal(g);
}

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
    // Identities. A pass-through input replaces the node only if it has the node's width.
    auto pass = [&](const char* name) {
      const Input* in = n.input(name);
      if (!in || (in->linked && type_width(g.nodes[size_t(in->node)].type) != type_width(n.type)))
        return false;
      Input copy = *in;
      replace_uses(g, i, copy);
      ++removed;
      return true;
    };
    const std::string& c = n.category;
    Input* a = n.input("in1");
    Input* b = n.input("in2");
    if (c == "multiply" && a && b) {
      if (all_lanes(*a, 0.0f) || all_lanes(*b, 0.0f)) {
        replace_uses(g, i, Input::constant("", n.type, 0, 0, 0, 0));
        ++removed;
      } else if (all_lanes(*b, 1.0f)) {
        pass("in1");
      } else if (all_lanes(*a, 1.0f)) {
        pass("in2");
      }
    } else if ((c == "add") && a && b) {
      if (all_lanes(*b, 0.0f))
        pass("in1");
      else if (all_lanes(*a, 0.0f))
        pass("in2");
    } else if ((c == "subtract") && a && b) {
      if (all_lanes(*b, 0.0f)) pass("in1");
    } else if ((c == "divide" || c == "power") && a && b) {
      if (all_lanes(*b, 1.0f)) pass("in1");
    } else if (c == "mix") {
      const Input* m = n.input("mix");
      if (m && all_lanes(*m, 0.0f))
        pass("bg");
      else if (m && all_lanes(*m, 1.0f))
        pass("fg");
    } else if (c == "dot" ||
               (c == "convert" && n.input("in") && type_width(n.input("in")->type) == type_width(n.type))) {
      pass("in");
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
    key << n.category << '|' << int(n.type);
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

std::vector<uint32_t> dependencies(const Graph& g) {
  std::vector<uint32_t> deps(g.nodes.size(), 0);
  for (int i : topological_order(g)) {
    const Node& n = g.nodes[size_t(i)];
    uint32_t d = 0;
    if (n.category == "texcoord") d |= kDepUv;
    if (n.category == "position") d |= kDepPosition;
    if (n.category == "normal") d |= kDepNormal;
    if (n.category == "tangent") d |= kDepTangent;
    if (n.category == "bitangent") d |= kDepBitangent;
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
