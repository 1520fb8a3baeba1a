// graph_builder.cpp — see graph_builder.h.
#include "tests/support/graph_builder.h"

#include <gtest/gtest.h>

#include "materials/node_table.h"

namespace pmc::test {

Input value(ValueType t, float a, float b, float c, float d) {
  Input in;
  in.type = t;
  in.value = Value::number(t, a, b, c, d);
  return in;
}

Input text(const std::string& s, ValueType t) {
  Input in;
  in.type = t;
  in.value.type = t;
  in.value.text = s;
  return in;
}

Input link(int node, ValueType t) {
  Input in;
  in.linked = true;
  in.node = node;
  in.type = t;
  return in;
}

Graph new_graph(const std::string& material, const std::string& file) {
  Graph g;
  g.material = material;
  g.file = file;
  return g;
}

static std::string origin_file(const Graph& g) { return g.file.empty() ? "test.mtlx" : g.file; }

int add(Graph& g, const std::string& name, const std::string& category, ValueType type, Given given) {
  const NodeDef* def = find_node_def(category);
  EXPECT_NE(def, nullptr) << category;
  Node n;
  n.name = name;
  n.category = category;
  n.type = type;
  n.origin = origin_file(g) + ": " + category + " '" + name + "'";
  if (!def) return g.add(n);
  for (const InputDef& d : def->inputs) {
    Input in;
    bool found = false;
    for (auto& [k, v] : given)
      if (k == d.name) in = v, found = true;
    const ValueType declared = resolve_input_type(d, type);
    if (!found) {
      in = default_input(d, type);
    } else if (in.type == ValueType::None) {
      in.type = declared;
    }
    in.name = d.name;
    n.inputs.push_back(in);
  }
  return g.add(n);
}

int add_surface(Graph& g, Given given) {
  Node s;
  s.name = "surface";
  s.category = "standard_surface";
  s.type = ValueType::Surface;
  s.origin = origin_file(g) + ": standard_surface 'surface'";
  for (const SurfaceParam& p : surface_params("standard_surface")) {
    Input in = value(p.type, p.def[0], p.def[1], p.def[2]);
    for (auto& [k, v] : given)
      if (k == p.input) {
        in = v;
        if (in.type == ValueType::None) in.type = p.type;
      }
    in.name = p.input;
    s.inputs.push_back(in);
  }
  g.surface = g.add(s);
  return g.surface;
}

}  // namespace pmc::test
