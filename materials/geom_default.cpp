// geom_default.cpp — each GeomDefault's node, added to a graph once.
#include "materials/geom_default.h"

#include "core/error.h"

namespace pmc {

Node geom_default_node(GeomDefault g, const std::string& origin) {
  // By GeomDefault, in its order: None, UV0, Pobject, Pworld, Nworld, Nobject,
  // Tworld, Tobject, Bworld, Vworld (nprlib's view direction, lowered like a
  // viewdirection node: -N, with a warning).
  static const char* const kCategory[] = {nullptr,  "texcoord", "position", "position",  "normal",
                                          "normal", "tangent",  "tangent",  "bitangent", "viewdirection"};
  static_assert(sizeof(kCategory) / sizeof(kCategory[0]) == size_t(GeomDefault::Vworld) + 1);
  PMC_CHECK(g != GeomDefault::None, "geometric default");
  Node n;
  n.category = kCategory[int(g)];
  n.type = g == GeomDefault::UV0 ? ValueType::Vector2 : ValueType::Vector3;
  n.origin = origin;
  if (g == GeomDefault::Vworld) {
    n.inputs = {Input::constant("space", ValueType::String, 0)};
    n.inputs[0].value.text = "world";
  }
  return n;
}

int geom_default_in(Graph& graph, std::map<int, int>& added, GeomDefault g, const std::string& origin) {
  auto it = added.find(int(g));
  if (it != added.end()) return it->second;
  const int id = graph.add(geom_default_node(g, origin));
  added[int(g)] = id;
  return id;
}

}  // namespace pmc
