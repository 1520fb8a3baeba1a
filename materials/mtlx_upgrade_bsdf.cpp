// mtlx_upgrade_bsdf.cpp — pbrlib closure renames and layering, 1.37 -> 1.39.
#include "materials/mtlx_upgrade_bsdf.h"

#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace pmc {
namespace {

bool is(pugi::xml_node e, const char* tag) { return std::string(e.name()) == tag; }

pugi::xml_node input(pugi::xml_node node, const char* name) {
  return node.find_child_by_attribute("input", "name", name);
}

void set_attr(pugi::xml_node e, const char* name, const std::string& value) {
  (e.attribute(name) ? e.attribute(name) : e.append_attribute(name)).set_value(value.c_str());
}

pugi::xml_node add_input(pugi::xml_node node, const char* name, const char* type) {
  pugi::xml_node in = node.append_child("input");
  in.append_attribute("name") = name;
  in.append_attribute("type") = type;
  return in;
}

// A connected `base` becomes a layer operator that takes the node's name.
void upgrade_layering(pugi::xml_node node) {
  pugi::xml_node base = input(node, "base");
  if (!base) return;
  const std::string base_node = base.attribute("nodename").as_string();
  if (!base_node.empty()) {
    const std::string name = node.attribute("name").as_string();
    set_attr(node, "name", name + "__layer_top");
    pugi::xml_node layer = node.parent().insert_child_after("layer", node);
    layer.append_attribute("name") = name.c_str();
    layer.append_attribute("type") = "BSDF";
    add_input(layer, "top", "BSDF").append_attribute("nodename") = (name + "__layer_top").c_str();
    add_input(layer, "base", "BSDF").append_attribute("nodename") = base_node.c_str();
  }
  node.remove_child(base);
}

// An input copied with its value or connection under a new name (MaterialX's copyInputWithBindings).
void copy_input(pugi::xml_node from, const char* name, pugi::xml_node to, const char* new_name) {
  pugi::xml_node src = input(from, name);
  if (!src) return;
  if (pugi::xml_node old = input(to, new_name)) to.remove_child(old);
  pugi::xml_node dst = to.append_copy(src);
  set_attr(dst, "name", new_name);
}

// The nodes of `graph` upstream of node `start` (by nodename), `start` included.
std::vector<pugi::xml_node> upstream(pugi::xml_node graph, pugi::xml_node start) {
  std::map<std::string, pugi::xml_node> by_name;
  for (pugi::xml_node c : graph.children()) by_name[c.attribute("name").as_string()] = c;
  std::vector<pugi::xml_node> out, stack{start};
  std::set<std::string> seen;
  while (!stack.empty()) {
    pugi::xml_node n = stack.back();
    stack.pop_back();
    if (!n || !seen.insert(n.attribute("name").as_string()).second) continue;
    out.push_back(n);
    for (pugi::xml_node in : n.children("input")) {
      auto it = by_name.find(in.attribute("nodename").as_string());
      if (it != by_name.end()) stack.push_back(it->second);
    }
  }
  return out;
}

}  // namespace

void for_each_mtlx_element(pugi::xml_node n, const std::function<void(pugi::xml_node)>& fn) {
  for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling()) {
    if (c.type() != pugi::node_element) continue;
    fn(c);
    for_each_mtlx_element(c, fn);
  }
}

void upgrade_bsdf_nodes_137(pugi::xml_node root) {
  static const std::map<std::string, std::string> renamed = {
      {"diffuse_brdf", "oren_nayar_diffuse_bsdf"},
      {"burley_diffuse_brdf", "burley_diffuse_bsdf"},
      {"diffuse_btdf", "translucent_bsdf"},
      {"subsurface_brdf", "subsurface_bsdf"},
      {"dielectric_brdf", "dielectric_bsdf"},
      {"generalized_schlick_brdf", "generalized_schlick_bsdf"},
      {"sheen_brdf", "sheen_bsdf"},
      {"thin_film_brdf", "thin_film_bsdf"},
      {"conductor_brdf", "conductor_bsdf"},
      {"dielectric_btdf", "dielectric_bsdf"}};
  std::vector<pugi::xml_node> nodes;
  for_each_mtlx_element(root, [&](pugi::xml_node e) {
    if (renamed.count(e.name())) nodes.push_back(e);
  });
  for (pugi::xml_node node : nodes) {
    const std::string old = node.name();
    node.set_name(renamed.at(old).c_str());
    if (old == "dielectric_brdf" || old == "generalized_schlick_brdf" || old == "sheen_brdf" ||
        old == "thin_film_brdf") {
      upgrade_layering(node);
    } else if (old == "dielectric_btdf") {
      if (pugi::xml_node interior = input(node, "interior")) node.remove_child(interior);
      add_input(node, "scatter_mode", "string").append_attribute("value") = "T";
    } else if (old == "conductor_brdf") {
      const std::string name = std::string(node.attribute("name").as_string()) + "__artistic_ior";
      pugi::xml_node ior = node.parent().append_child("artistic_ior");
      ior.append_attribute("name") = name.c_str();
      ior.append_attribute("type") = "multioutput";
      copy_input(node, "reflectivity", ior, "reflectivity");
      copy_input(node, "edge_color", ior, "edge_color");
      for (const char* gone : {"reflectivity", "edge_color"})
        if (pugi::xml_node in = input(node, gone)) node.remove_child(in);
      for (const char* out : {"ior", "extinction"}) {
        if (pugi::xml_node in = input(node, out)) node.remove_child(in);
        pugi::xml_node in = add_input(node, out, "color3");
        in.append_attribute("nodename") = name.c_str();
        in.append_attribute("output") = out;
      }
    }
  }
}

void upgrade_thin_film_layers_138(pugi::xml_node root) {
  std::vector<pugi::xml_node> layers;
  for_each_mtlx_element(root, [&](pugi::xml_node e) {
    if (is(e, "layer")) layers.push_back(e);
  });
  std::vector<pugi::xml_node> unused;
  for (pugi::xml_node layer : layers) {
    pugi::xml_node graph = layer.parent();
    auto connected = [&](const char* name) {
      pugi::xml_node in = input(layer, name);
      const std::string node = in ? in.attribute("nodename").as_string() : "";
      for (pugi::xml_node c : graph.children())
        if (!node.empty() && node == c.attribute("name").as_string() && !is(c, "input") && !is(c, "output"))
          return c;
      return pugi::xml_node();
    };
    pugi::xml_node top = connected("top"), base = connected("base");
    if (!top || !base || !is(top, "thin_film_bsdf")) continue;
    for (pugi::xml_node n : upstream(graph, base)) {
      if (!is(n, "dielectric_bsdf") && !is(n, "conductor_bsdf") && !is(n, "generalized_schlick_bsdf"))
        continue;
      pugi::xml_node mode = input(n, "scatter_mode");
      if (mode && std::string(mode.attribute("value").as_string()) == "T") continue;
      copy_input(top, "thickness", n, "thinfilm_thickness");
      copy_input(top, "ior", n, "thinfilm_ior");
    }
    const std::string layer_name = layer.attribute("name").as_string();
    const std::string base_name = base.attribute("name").as_string();
    for_each_mtlx_element(graph, [&](pugi::xml_node e) {
      if ((is(e, "input") || is(e, "output")) && layer_name == e.attribute("nodename").as_string())
        e.attribute("nodename").set_value(base_name.c_str());
    });
    unused.push_back(layer);
    unused.push_back(top);
  }
  std::set<pugi::xml_node> removed;  // a film may top several layers
  for (pugi::xml_node n : unused)
    if (removed.insert(n).second) n.parent().remove_child(n);
}

}  // namespace pmc
