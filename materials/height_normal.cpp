// height_normal.cpp — lowers MaterialX heighttonormal and bump into primitive nodes.
//
// heighttonormal turns a scalar height field h(uv) into a tangent-space
// normal map value. pmc takes the gradient with respect to the surface's uv
// by forward differences: the height sub-graph is evaluated at uv (the node's
// own input), and at uv + (d, 0) and uv + (0, d) by two copies of it in which
// every texcoord node is replaced by texcoord + offset. Then
//   n = normalize(-scale * dh/du, -scale * dh/dv, 1),  out = n * 0.5 + 0.5
// (the [0, 1] encoding normalmap decodes). bump is normalmap(heighttonormal(
// height), scale), as MaterialX's NG_bump_vector3 defines it.
//
// The copies are ordinary nodes of their own, so the material cache never
// confuses a shifted evaluation with the centre's: they have other node ids
// (other cache keys), and when the whole normal depends on uv alone it is one
// cache point whose block evaluates all three heights at the same point (the
// texel centre in cache_eval center). Parts of the height that do not
// depend on uv (position, normal) are shared by the copies, so they add
// nothing to the gradient: like MaterialX's own GLSL (which can only offset
// texture samples), pmc bumps with uv-driven heights.
//
// d is a fixed uv step (kHeightStep): a sub-graph that depends only on uv
// stays cacheable, and the result does not depend on the camera. It is one
// texel of a 2048-texel height map; with uvs around 1e7 uv + d == uv in
// float and the gradient is 0 (flat, never NaN).
#include "materials/height_normal.h"

#include <map>

#include "core/error.h"
#include "materials/node_table.h"

namespace pmc {
namespace {

bool is_texcoord(const Node& n) {
  const NodeDef* def = find_node_def(n.category);
  return def && def->opcode == PMC_OP_TEXCOORD;
}

int add_node(Graph& g, const std::string& category, ValueType t, std::vector<Input> inputs,
             const std::string& origin) {
  Node n;
  n.category = category;
  n.type = t;
  n.inputs = std::move(inputs);
  n.origin = origin;
  return g.add(std::move(n));
}

// Copies of the sub-graphs under a heighttonormal's input with every
// texcoord replaced by texcoord + (du, dv). Nodes that do not depend on a
// texcoord are shared, not copied.
class ShiftedCopier {
 public:
  ShiftedCopier(Graph& g, float du, float dv) : g_(g), du_(du), dv_(dv) {}

  int copy(int node) {
    auto it = copies_.find(node);
    if (it != copies_.end()) return it->second;
    int result = node;
    if (uses_uv(node)) {
      if (is_texcoord(g_.nodes[size_t(node)])) {
        const Node& tc = g_.nodes[size_t(node)];
        result = add_node(g_, "add", ValueType::Vector2,
                          {Input::link("in1", ValueType::Vector2, node),
                           Input::constant("in2", ValueType::Vector2, du_, dv_)},
                          tc.origin + " (shifted for heighttonormal)");
      } else {
        Node n = g_.nodes[size_t(node)];  // a copy: g_.nodes may grow below
        for (Input& in : n.inputs)
          if (in.linked) in.node = copy(in.node);
        if (!n.name.empty()) n.name += du_ != 0.0f ? "@+du" : "@+dv";
        n.origin +=
            du_ != 0.0f ? " (at uv + (d, 0) for heighttonormal)" : " (at uv + (0, d) for heighttonormal)";
        result = g_.add(std::move(n));
      }
    }
    copies_[node] = result;
    return result;
  }

 private:
  bool uses_uv(int node) {
    auto it = uses_uv_.find(node);
    if (it != uses_uv_.end()) return it->second;
    const Node& n = g_.nodes[size_t(node)];
    bool uses = is_texcoord(n);
    for (const Input& in : n.inputs)
      if (in.linked && uses_uv(in.node)) uses = true;
    uses_uv_[node] = uses;
    return uses;
  }

  Graph& g_;
  float du_, dv_;
  std::map<int, int> copies_;
  std::map<int, bool> uses_uv_;
};

}  // namespace

void lower_height_to_normal(Graph& g, int i) {
  const Node h = g.nodes[size_t(i)];
  const Input* texcoord = h.input("texcoord");
  if (texcoord && texcoord->linked && !is_texcoord(g.nodes[size_t(texcoord->node)]))
    fail(h.origin,
         ": heighttonormal computes the gradient with respect to the surface's uv; a texcoord "
         "input linked to '",
         g.nodes[size_t(texcoord->node)].name, "' (", g.nodes[size_t(texcoord->node)].category,
         ") is not supported");
  const Input* height = h.input("in");
  const Input* scale = h.input("scale");
  PMC_CHECK(height && scale, "heighttonormal inputs");
  const std::string origin = h.origin;
  if (!height->linked) {  // a constant height field is flat
    Node& n = g.nodes[size_t(i)];
    n.category = "constant";
    n.inputs = {Input::constant("value", ValueType::Vector3, 0.5f, 0.5f, 1.0f)};
    return;
  }
  const int h0 = height->node;
  const Node& source = g.nodes[size_t(h0)];
  if (type_width(source.type) != 1)
    fail(h.origin, ": input 'in' expects float but node '", source.name, "' outputs ", type_name(source.type),
         " (type mismatch)");
  ShiftedCopier along_u(g, kHeightStep, 0.0f), along_v(g, 0.0f, kHeightStep);
  const int hu = along_u.copy(h0), hv = along_v.copy(h0);
  const ValueType F = ValueType::Float;
  auto diff = [&](int shifted, const char* axis) {
    return add_node(g, "subtract", F, {Input::link("in1", F, shifted), Input::link("in2", F, h0)},
                    origin + " (height difference along " + axis + ")");
  };
  const int dh_u = diff(hu, "u"), dh_v = diff(hv, "v");
  // -scale / d: a constant, or a node when the scale is linked.
  Input k = Input::constant("in2", F, scale->linked ? -1.0f / kHeightStep : -scale->value.f[0] / kHeightStep);
  if (scale->linked) {
    Input s = *scale;
    s.name = "in1";
    k = Input::link("in2", F, add_node(g, "multiply", F, {s, k}, origin + " (gradient scale)"));
  }
  auto slope = [&](int d, const char* axis) {
    return add_node(g, "multiply", F, {Input::link("in1", F, d), k}, origin + " (slope along " + axis + ")");
  };
  const int sx = slope(dh_u, "u"), sy = slope(dh_v, "v");
  const ValueType V3 = ValueType::Vector3;
  const int v =
      add_node(g, "combine3", V3,
               {Input::link("in1", F, sx), Input::link("in2", F, sy), Input::constant("in3", F, 1.0f)},
               origin + " (unnormalised normal)");
  const int n = add_node(g, "normalize", V3, {Input::link("in", V3, v)}, origin + " (normal)");
  const int half = add_node(g, "multiply", V3, {Input::link("in1", V3, n), Input::constant("in2", F, 0.5f)},
                            origin + " (normal / 2)");
  Node& out = g.nodes[size_t(i)];  // g.nodes has grown: index again
  out.category = "add";
  out.type = V3;
  out.inputs = {Input::link("in1", V3, half), Input::constant("in2", F, 0.5f)};
}

void lower_bump(Graph& g, int i) {
  Node h2n;
  h2n.category = "heighttonormal";
  h2n.type = ValueType::Vector3;
  h2n.origin = g.nodes[size_t(i)].origin + " (heighttonormal)";
  Input in = *g.nodes[size_t(i)].input("height");
  in.name = "in";
  h2n.inputs = {in, Input::constant("scale", ValueType::Float, 1.0f)};
  int h = g.add(std::move(h2n));
  Node& b = g.nodes[size_t(i)];
  Input scale = *b.input("scale"), normal = *b.input("normal"), tangent = *b.input("tangent"),
        bitangent = *b.input("bitangent");
  b.category = "normalmap";
  Input space = Input::constant("space", ValueType::String, 0.0f);
  space.value.text = "tangent";
  b.inputs = {Input::link("in", ValueType::Vector3, h), scale, normal, tangent, bitangent, space};
}

}  // namespace pmc
