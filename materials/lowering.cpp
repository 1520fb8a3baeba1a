// lowering.cpp — the node table's `lower` rules, applied in three phases.
#include "materials/lowering.h"

#include <functional>

#include "core/error.h"
#include "materials/graph_analysis.h"
#include "materials/height_normal.h"
#include "materials/node_table.h"

namespace pmc {
namespace {

Input copy_input(const Input& src, const std::string& name) {
  Input in = src;
  in.name = name;
  return in;
}

// invert = amount - in
void lower_invert(Graph& g, int i) {
  Node& n = g.nodes[size_t(i)];
  Input a = copy_input(*n.input("amount"), "in1"), b = copy_input(*n.input("in"), "in2");
  n.category = "subtract";
  n.inputs = {a, b};
}

// MaterialX NG_tiledimage: ((uv * uvtiling - uvoffset) / realworldimagesize) * realworldtilesize
void lower_tiled_image(Graph& g, int i) {
  Node tiled = g.nodes[size_t(i)];
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
  Node& n = g.nodes[size_t(i)];  // g.nodes may have moved
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

// Scene constants of a still OBJ render (node_table.cpp says why).
void lower_to_constant(Graph& g, int i, float v) {
  Node& n = g.nodes[size_t(i)];
  n.inputs = {Input::constant("value", n.type, v, v, v, v)};
  n.category = "constant";
}

void lower_time(Graph& g, int i) {
  const Input* fps = g.nodes[size_t(i)].input("fps");
  if (fps->linked || !(fps->value.f[0] > 0.0f))
    fail(g.nodes[size_t(i)].origin, ": time needs a constant, positive fps");
  lower_to_constant(g, i, 1.0f / fps->value.f[0]);
}

void lower_geompropvalue(Graph& g, int i) {
  Node& n = g.nodes[size_t(i)];
  Input def = *n.input("default");
  def.name = "in";
  n.category = "dot";  // a pass-through of the default
  n.inputs = {def};
}

// viewdirection ~ -N: the shading inputs have no ray direction.
void lower_viewdirection(Graph& g, int i) {
  warn(
      g.nodes[size_t(i)].origin +
      ": viewdirection is approximated by the negated shading normal (pmc's materials see no ray direction)");
  Node nrm;
  nrm.category = "normal";
  nrm.type = ValueType::Vector3;
  nrm.origin = g.nodes[size_t(i)].origin + " (normal)";
  int id = g.add(std::move(nrm));
  Node& n = g.nodes[size_t(i)];
  n.category = "multiply";
  n.inputs = {Input::link("in1", ValueType::Vector3, id), Input::constant("in2", ValueType::Float, -1.0f)};
}

Lower lower_rule(const Node& n) {
  const NodeDef* def = find_node_def(n.category);
  return def ? def->lower : Lower::None;
}

}  // namespace

void lower_composites(Graph& g) {
  // Phase 1: plain rewrites, in node order.
  const size_t count = g.nodes.size();
  for (size_t i = 0; i < count; ++i) {
    if (g.nodes[i].dead) continue;
    switch (lower_rule(g.nodes[i])) {
      case Lower::Invert:
        lower_invert(g, int(i));
        break;
      case Lower::TiledImage:
        lower_tiled_image(g, int(i));
        break;
      case Lower::Time:
        lower_time(g, int(i));
        break;
      case Lower::Frame:
        lower_to_constant(g, int(i), 1.0f);
        break;
      case Lower::GeomColor:
        lower_to_constant(g, int(i), 1.0f);
        break;
      case Lower::GeomPropValue:
        lower_geompropvalue(g, int(i));
        break;
      case Lower::ViewDirection:
        lower_viewdirection(g, int(i));
        break;
      default:
        break;
    }
  }
  bool any = false;
  for (const Node& n : g.nodes)
    any = any || (!n.dead && (lower_rule(n) == Lower::Bump || lower_rule(n) == Lower::HeightToNormal));
  if (!any) return;
  check_acyclic(g);  // the copies below recurse through the graph
  // Phase 2: bump = normalmap(heighttonormal(height), scale, normal, tangent, bitangent).
  const size_t with_composites = g.nodes.size();
  for (size_t i = 0; i < with_composites; ++i)
    if (!g.nodes[i].dead && lower_rule(g.nodes[i]) == Lower::Bump) lower_bump(g, int(i));
  // Phase 3: heighttonormal, inputs first, so one under another is lowered before it is copied.
  std::vector<char> done(g.nodes.size(), 0);
  std::function<void(int)> visit = [&](int i) {
    if (done[size_t(i)]) return;
    done[size_t(i)] = 1;
    for (const Input& in : g.nodes[size_t(i)].inputs)
      if (in.linked) visit(in.node);
    if (lower_rule(g.nodes[size_t(i)]) == Lower::HeightToNormal) lower_height_to_normal(g, i);
  };
  const size_t with_bumps = g.nodes.size();
  for (size_t i = 0; i < with_bumps; ++i)
    if (!g.nodes[i].dead) visit(int(i));
}

}  // namespace pmc
