// mtlx_upgrade.cpp — the 1.36-1.38 -> 1.39 rewrites listed in mtlx_upgrade.h.
#include "materials/mtlx_upgrade.h"

#include <cerrno>
#include <cstdlib>
#include <functional>
#include <limits>
#include <set>
#include <vector>

#include "core/error.h"
#include "materials/mtlx_upgrade_bsdf.h"

namespace pmc {
namespace {

// "1.38" -> 138; 0 if absent or unreadable (treated as current). Parsed with
// strtol, not sscanf("%d"), so a huge number ("66666666661.39") cannot
// overflow: a major past 99 or a minor past 99 counts as a future version.
int version_of(pugi::xml_node root) {
  const char* text = root.attribute("version").as_string();
  char* end = nullptr;
  errno = 0;
  const long major = std::strtol(text, &end, 10);
  if (end == text || *end != '.' || major < 0) return 0;
  const char* minor_text = end + 1;
  const long minor = std::strtol(minor_text, &end, 10);
  if (end == minor_text || minor < 0) return 0;
  if (errno == ERANGE || major > 99 || minor > 99) return std::numeric_limits<int>::max();
  return static_cast<int>(major * 100 + minor);
}

std::string unique_name(pugi::xml_node graph, const std::string& base) {
  std::set<std::string> names;
  for (pugi::xml_node c : graph.children()) names.insert(c.attribute("name").as_string());
  std::string name = base;
  for (int i = 2; names.count(name); ++i) name = base + std::to_string(i);
  return name;
}

// <material><shaderref node="X"><bindinput .../></shaderref></material> ->
// <X name=shaderref type=surfaceshader><input .../></X> + <surfacematerial>.
void upgrade_materials(pugi::xml_node root, const std::string& path) {
  std::vector<pugi::xml_node> materials;
  for (pugi::xml_node m : root.children("material"))
    if (m.child("shaderref")) materials.push_back(m);
  for (pugi::xml_node m : materials) {
    const std::string name = m.attribute("name").as_string();
    pugi::xml_node surface_material = root.insert_child_after("surfacematerial", m);
    surface_material.append_attribute("name") = name.c_str();
    surface_material.append_attribute("type") = "material";
    for (pugi::xml_node sr : m.children("shaderref")) {
      const std::string node = sr.attribute("node").as_string();
      if (node.empty())
        fail(path, ": material '", name, "': shaderref '", sr.attribute("name").as_string(),
             "' names no shader node");
      pugi::xml_node shader = root.insert_child_before(node.c_str(), surface_material);
      std::string shader_name = unique_name(root, sr.attribute("name").as_string());
      shader.append_attribute("name") = shader_name.c_str();
      std::string type = sr.attribute("type").as_string();
      shader.append_attribute("type") = type.empty() ? "surfaceshader" : type.c_str();
      for (pugi::xml_node b : sr.children()) {
        if (std::string(b.name()) != "bindinput" && std::string(b.name()) != "bindparam") continue;
        pugi::xml_node in = shader.append_child("input");
        for (pugi::xml_attribute a : b.attributes()) in.append_attribute(a.name()) = a.value();
      }
      std::string port = type.empty() || type == "surfaceshader" ? "surfaceshader" : type;
      if (surface_material.find_child_by_attribute("input", "name", port.c_str())) continue;
      pugi::xml_node in = surface_material.append_child("input");
      in.append_attribute("name") = port.c_str();
      in.append_attribute("type") = port.c_str();
      in.append_attribute("nodename") = shader_name.c_str();
    }
    root.remove_child(m);
  }
}

// An input with a `channels` attribute reads a swizzle of its source.
void upgrade_channels(pugi::xml_node root) {
  std::vector<pugi::xml_node> inputs;
  for_each_mtlx_element(root, [&](pugi::xml_node e) {
    if (std::string(e.name()) == "input" && e.attribute("channels") &&
        (e.attribute("nodename") || e.attribute("nodegraph")))
      inputs.push_back(e);
  });
  for (pugi::xml_node in : inputs) {
    pugi::xml_node node = in.parent(), graph = node.parent();
    if (!graph) continue;
    // The source's type: a node of the same graph, or a nodegraph's output.
    std::string source_type;
    if (in.attribute("nodegraph")) {
      pugi::xml_node ng =
          root.find_child_by_attribute("nodegraph", "name", in.attribute("nodegraph").as_string());
      if (!ng) continue;  // dangling: the reader reports it
      std::string out = in.attribute("output").as_string();
      pugi::xml_node o =
          out.empty() ? ng.child("output") : ng.find_child_by_attribute("output", "name", out.c_str());
      if (!o) continue;
      source_type = o.attribute("type").as_string();
    } else {
      for (pugi::xml_node c : graph.children())
        if (std::string(c.attribute("name").as_string()) == in.attribute("nodename").as_string())
          source_type = c.attribute("type").as_string();
      if (source_type.empty()) continue;
    }
    pugi::xml_node sw = graph.insert_child_before("swizzle", node);
    std::string name = unique_name(graph, std::string(node.attribute("name").as_string()) + "_" +
                                              in.attribute("name").as_string() + "_swizzle");
    sw.append_attribute("name") = name.c_str();
    sw.append_attribute("type") = in.attribute("type").as_string();
    pugi::xml_node from = sw.append_child("input");
    from.append_attribute("name") = "in";
    from.append_attribute("type") = source_type.c_str();
    for (const char* a : {"nodename", "nodegraph", "output"})
      if (in.attribute(a)) {
        from.append_attribute(a) = in.attribute(a).as_string();
        if (std::string(a) != "nodename") in.remove_attribute(a);
      }
    if (!in.attribute("nodename")) in.append_attribute("nodename");
    pugi::xml_node ch = sw.append_child("input");
    ch.append_attribute("name") = "channels";
    ch.append_attribute("type") = "string";
    ch.append_attribute("value") = in.attribute("channels").as_string();
    in.attribute("nodename").set_value(name.c_str());
    in.remove_attribute("channels");
  }
}

// 1.37 -> 1.38: the color2 type became vector2. A color2's channels were r
// and a, so separate2's outputs outr/outa become outx/outy, and channel
// strings (a swizzle's `channels`, an input's `channels` attribute) read from
// a color2 turn r/a into x/y.
void upgrade_color2(pugi::xml_node root) {
  auto source_is_color2 = [](pugi::xml_node in) {
    if (std::string(in.attribute("type").as_string()) == "color2") return true;
    pugi::xml_node graph = in.parent().parent();
    const std::string nodename = in.attribute("nodename").as_string();
    if (!graph || nodename.empty()) return false;
    pugi::xml_node src = graph.find_child_by_attribute("name", nodename.c_str());
    return src && std::string(src.attribute("type").as_string()) == "color2";
  };
  auto to_xy = [](std::string channels) {
    for (char& c : channels) c = c == 'r' ? 'x' : (c == 'a' ? 'y' : c);
    return channels;
  };
  std::vector<pugi::xml_node> elements;
  for_each_mtlx_element(root, [&](pugi::xml_node e) { elements.push_back(e); });
  // Channel strings first, while the types still say color2.
  for (pugi::xml_node e : elements) {
    if (std::string(e.name()) != "input") continue;
    pugi::xml_node node = e.parent();
    if (e.attribute("channels") && source_is_color2(e))
      e.attribute("channels").set_value(to_xy(e.attribute("channels").as_string()).c_str());
    if (std::string(node.name()) == "swizzle" && std::string(e.attribute("name").as_string()) == "channels") {
      pugi::xml_node from = node.find_child_by_attribute("input", "name", "in");
      if (from && source_is_color2(from))
        e.attribute("value").set_value(to_xy(e.attribute("value").as_string()).c_str());
    }
    const std::string out = e.attribute("output").as_string();
    const std::string nodename = e.attribute("nodename").as_string();
    if ((out == "outr" || out == "outa") && !nodename.empty() && node.parent()) {
      pugi::xml_node src = node.parent().find_child_by_attribute("separate2", "name", nodename.c_str());
      if (src) e.attribute("output").set_value(out == "outr" ? "outx" : "outy");
    }
  }
  for (pugi::xml_node e : elements)
    if (std::string(e.attribute("type").as_string()) == "color2") e.attribute("type").set_value("vector2");
}

}  // namespace

void upgrade_mtlx_document(pugi::xml_node root, const std::string& path) {
  const int version = version_of(root);
  if (version == 0 || version >= 139) return;
  if (version < 138) {
    for_each_mtlx_element(root, [](pugi::xml_node e) {
      if (std::string(e.name()) == "geomattrvalue") e.set_name("geompropvalue");
    });
  }
  // 1.38: parameters are inputs; materials are surfacematerial nodes; channels are swizzles.
  for_each_mtlx_element(root, [](pugi::xml_node e) {
    if (std::string(e.name()) == "parameter") e.set_name("input");
  });
  if (version < 138) upgrade_color2(root);
  if (version < 138) upgrade_bsdf_nodes_137(root);
  upgrade_thin_film_layers_138(root);
  upgrade_materials(root, path);
  upgrade_channels(root);
  // atan2's inputs: 1.38 swapped in1 and in2, 1.39 named them iny and inx
  // (so 1.36/1.37's in1 is inx, 1.38's in1 is iny).
  for_each_mtlx_element(root, [version](pugi::xml_node e) {
    if (std::string(e.name()) != "atan2") return;
    for (pugi::xml_node in : e.children("input")) {
      std::string n = in.attribute("name").as_string();
      if (n == "in1") in.attribute("name").set_value(version < 138 ? "inx" : "iny");
      if (n == "in2") in.attribute("name").set_value(version < 138 ? "iny" : "inx");
    }
  });
  root.attribute("version").set_value("1.39");
}

}  // namespace pmc
