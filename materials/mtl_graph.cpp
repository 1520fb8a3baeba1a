// mtl_graph.cpp — MTL parameters into pmc_mtl_surface networks.
#include "materials/mtl_graph.h"

#include <cmath>

#include "core/error.h"
#include "core/image_backend.h"
#include "materials/node_table.h"

namespace pmc {
namespace {

int image_node(Graph& g, const std::string& file, ValueType type, bool srgb, const std::string& origin) {
  Node uv;
  uv.category = "texcoord";
  uv.type = ValueType::Vector2;
  uv.origin = origin;
  int uv_id = g.add(uv);
  Node n;
  n.category = "image";
  n.type = type;
  n.origin = origin;
  Input f;
  f.name = "file";
  f.type = ValueType::Filename;
  f.value.type = ValueType::Filename;
  f.value.text = file;
  f.value.f[0] = srgb ? 1.0f : 0.0f;
  n.inputs.push_back(f);
  n.inputs.push_back(Input::constant("default", type, 0, 0, 0));
  n.inputs.push_back(Input::link("texcoord", ValueType::Vector2, uv_id));
  for (const char* mode : {"uaddressmode", "vaddressmode"}) {
    Input s;
    s.name = mode;
    s.type = ValueType::String;
    s.value.type = ValueType::String;
    s.value.text = "periodic";
    n.inputs.push_back(s);
  }
  Input filter;
  filter.name = "filtertype";
  filter.type = ValueType::String;
  filter.value.type = ValueType::String;
  filter.value.text = "linear";
  n.inputs.push_back(filter);
  return g.add(n);
}

int binary(Graph& g, const std::string& cat, ValueType t, Input a, Input b, const std::string& origin) {
  Node n;
  n.category = cat;
  n.type = t;
  n.origin = origin;
  a.name = "in1";
  b.name = "in2";
  n.inputs = {a, b};
  return g.add(n);
}

bool has_alpha_channel(const std::string& path) {
  std::string why;
  auto in = image_backend().open(path, false, why);
  return in && in->header().channels == 4;
}

}  // namespace

Graph mtl_to_graph(const MtlMaterial& m, const std::string& mtl_file) {
  Graph g;
  g.material = m.name;
  g.file = mtl_file;
  const std::string origin = mtl_file + ": material '" + m.name + "'";
  Node surface;
  surface.category = "pmc_mtl_surface";
  surface.type = ValueType::Surface;
  surface.origin = origin;
  for (const SurfaceParam& p : surface_params("pmc_mtl_surface"))
    surface.inputs.push_back(Input::constant(p.input, p.type, p.def[0], p.def[1], p.def[2]));

  Input* base = surface.input("base_color");
  *base = Input::constant("base_color", ValueType::Color3, m.kd[0], m.kd[1], m.kd[2]);
  if (!m.map_kd.empty()) {
    int img = image_node(g, m.map_kd, ValueType::Color3, true, origin + " map_Kd");
    int mul =
        binary(g, "multiply", ValueType::Color3, Input::link("", ValueType::Color3, img),
               Input::constant("", ValueType::Color3, m.kd[0], m.kd[1], m.kd[2]), origin + " Kd*map_Kd");
    *base = Input::link("base_color", ValueType::Color3, mul);
  }
  *surface.input("specular_color") =
      Input::constant("specular_color", ValueType::Color3, m.ks[0], m.ks[1], m.ks[2]);
  float alpha = std::sqrt(2.0f / (std::max(0.0f, m.ns) + 2.0f));
  *surface.input("specular_roughness") =
      Input::constant("specular_roughness", ValueType::Float, std::sqrt(alpha));
  *surface.input("emission_color") =
      Input::constant("emission_color", ValueType::Color3, m.ke[0], m.ke[1], m.ke[2]);
  Input* opacity = surface.input("opacity");
  *opacity = Input::constant("opacity", ValueType::Float, m.dissolve);
  if (!m.map_d.empty()) {
    bool alpha_channel = has_alpha_channel(m.map_d);
    int img = image_node(g, m.map_d, ValueType::Color4, false, origin + " map_d");
    Node ex;
    ex.category = "extract";
    ex.type = ValueType::Float;
    ex.origin = origin + " map_d channel";
    ex.inputs = {Input::link("in", ValueType::Color4, img),
                 Input::constant("index", ValueType::Integer, alpha_channel ? 3.0f : 0.0f)};
    int e = g.add(ex);
    *opacity = Input::link("opacity", ValueType::Float, e);
  }
  std::vector<std::string> dropped;
  if (!m.map_bump.empty()) dropped.push_back("bump map (" + m.map_bump + ")");
  if (!m.map_ks.empty()) dropped.push_back("specular map (" + m.map_ks + ")");
  dropped.insert(dropped.end(), m.not_modelled.begin(), m.not_modelled.end());
  std::string list;
  for (const std::string& what : dropped) list += (list.empty() ? " " : ", ") + what;
  if (!list.empty()) warn(origin + ": not modelled:" + list);
  g.surface = g.add(surface);
  return g;
}

}  // namespace pmc
