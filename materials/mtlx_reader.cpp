// mtlx_reader.cpp — pugixml walk, nodegraph inlining, defaults, diagnostics.
#include "materials/mtlx_reader.h"

#include <cstdlib>
#include <map>
#include <pugixml.hpp>
#include <set>
#include <sstream>

#include "core/error.h"
#include "materials/node_table.h"

namespace pmc {
namespace {

std::string dirname_of(const std::string& path) {
  size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

bool is_structural(const std::string& tag) {
  return tag == "input" || tag == "output" || tag == "nodegraph" || tag == "nodedef" || tag == "look" ||
         tag == "materialassign" || tag == "collection" || tag == "geominfo" || tag == "typedef" ||
         tag == "implementation" || tag == "backdrop" || tag == "variantset" || tag == "propertyset" ||
         tag == "token" || tag == "unit" || tag == "unittypedef" || tag == "xi:include";
}

bool is_surface(const std::string& category) { return !surface_params(category).empty(); }

// Deepest chain of linked nodes a document may have: the passes walk graphs
// recursively, and no real material comes near this.
constexpr size_t kMaxNesting = 2000;

class Reader {
 public:
  Reader(const std::string& path) : path_(path), dir_(dirname_of(path)) {}

  std::vector<Graph> read(const pugi::xml_document& doc) {
    root_ = doc.child("materialx");
    if (!root_) fail(path_, ": not a MaterialX document (no <materialx> root element)");
    doc_colorspace_ = root_.attribute("colorspace").as_string();
    std::vector<Graph> out;
    for (pugi::xml_node el : root_.children("surfacematerial")) {
      begin(el.attribute("name").as_string());
      pugi::xml_node in = el.find_child_by_attribute("input", "name", "surfaceshader");
      if (!in) fail(where(el), ": surfacematerial has no 'surfaceshader' input");
      std::string target = in.attribute("nodename").as_string();
      pugi::xml_node shader = find_node(root_, target);
      if (!shader)
        fail(where(el), ": surfaceshader refers to '", target,
             "', which does not exist (dangling reference)");
      if (!is_surface(shader.name()))
        fail(where(shader), ": '", shader.name(),
             "' is not a supported surface shader (pmc supports standard_surface and "
             "UsdPreviewSurface)");
      graph_.surface = instantiate(root_, shader);
      out.push_back(std::move(graph_));
    }
    if (out.empty()) preview_outputs(out);
    if (out.empty()) fail(path_, ": no surfacematerial and no outputs: nothing to render");
    return out;
  }

 private:
  std::string path_, dir_, doc_colorspace_;
  pugi::xml_node root_;
  Graph graph_;
  std::map<std::string, int> memo_;  // "scope|node" -> node index
  std::set<std::string> active_;     // instantiation stack, for cycles
  std::vector<std::string> active_path_;
  std::map<int, int> geom_nodes_;  // GeomDefault -> node index

  void begin(const std::string& material) {
    graph_ = Graph();
    graph_.material = material;
    graph_.file = path_;
    memo_.clear();
    active_.clear();
    active_path_.clear();
    geom_nodes_.clear();
  }

  std::string scope_name(pugi::xml_node scope) const {
    return scope == root_ ? std::string() : std::string(scope.attribute("name").as_string());
  }

  std::string where(pugi::xml_node el) const {
    std::ostringstream os;
    os << path_;
    pugi::xml_node parent = el.parent();
    if (parent && parent != root_ && std::string(parent.name()) == "nodegraph")
      os << ": nodegraph '" << parent.attribute("name").as_string() << "'";
    os << ": " << el.name() << " '" << el.attribute("name").as_string() << "'";
    return os.str();
  }

  static pugi::xml_node find_node(pugi::xml_node scope, const std::string& name) {
    for (pugi::xml_node c : scope.children())
      if (!is_structural(c.name()) && name == c.attribute("name").as_string()) return c;
    return {};
  }

  Value parse_value(const std::string& s, ValueType t, const std::string& context) {
    Value v;
    v.type = t;
    if (t == ValueType::String || t == ValueType::Filename) {
      v.text = s;
      return v;
    }
    if (t == ValueType::Boolean) {
      v.f[0] = (s == "true" || s == "1") ? 1.0f : 0.0f;
      if (s != "true" && s != "false" && s != "1" && s != "0") fail(context, ": '", s, "' is not a boolean");
      return v;
    }
    int n = type_width(t);
    if (n == 0) fail(context, ": values of type ", type_name(t), " are not supported");
    const char* p = s.c_str();
    for (int i = 0; i < n; ++i) {
      char* end = nullptr;
      float x = std::strtof(p, &end);
      if (end == p) fail(context, ": '", s, "' is not a ", type_name(t), " value");
      v.f[size_t(i)] = x;
      p = end;
      while (*p == ' ' || *p == ',') ++p;
    }
    return v;
  }

  int geom_node(GeomDefault g) {
    auto it = geom_nodes_.find(int(g));
    if (it != geom_nodes_.end()) return it->second;
    Node n;
    n.origin = path_ + ": implicit geometric default";
    switch (g) {
      case GeomDefault::UV0:
        n.category = "texcoord", n.type = ValueType::Vector2;
        break;
      case GeomDefault::Pobject:
      case GeomDefault::Pworld:
        n.category = "position", n.type = ValueType::Vector3;
        break;
      case GeomDefault::Nworld:
      case GeomDefault::Nobject:
        n.category = "normal", n.type = ValueType::Vector3;
        break;
      case GeomDefault::Tworld:
      case GeomDefault::Tobject:
        n.category = "tangent", n.type = ValueType::Vector3;
        break;
      case GeomDefault::Bworld:
        n.category = "bitangent", n.type = ValueType::Vector3;
        break;
      default:
        PMC_CHECK(false, "geometric default");
    }
    int id = graph_.add(n);
    geom_nodes_[int(g)] = id;
    return id;
  }

  // Resolves an <input> (or <output>) element found in `scope` into `in`.
  void connect(pugi::xml_node scope, pugi::xml_node el, Input& in, const std::string& context) {
    std::string nodename = el.attribute("nodename").as_string();
    std::string nodegraph = el.attribute("nodegraph").as_string();
    std::string iface = el.attribute("interfacename").as_string();
    if (!nodegraph.empty()) {
      pugi::xml_node ng = root_.find_child_by_attribute("nodegraph", "name", nodegraph.c_str());
      if (!ng)
        fail(context, ": refers to nodegraph '", nodegraph, "', which does not exist (dangling reference)");
      std::string out_name = el.attribute("output").as_string();
      pugi::xml_node out = out_name.empty() ? ng.child("output")
                                            : ng.find_child_by_attribute("output", "name", out_name.c_str());
      if (!out)
        fail(context, ": nodegraph '", nodegraph, "' has no output '", out_name, "' (dangling reference)");
      connect(ng, out, in,
              path_ + ": nodegraph '" + nodegraph + "' output '" + out.attribute("name").as_string() + "'");
      return;
    }
    if (!iface.empty()) {
      pugi::xml_node decl = scope.find_child_by_attribute("input", "name", iface.c_str());
      if (!decl || scope == root_)
        fail(context, ": interfacename '", iface,
             "' is not an input of the enclosing nodegraph (dangling reference)");
      if (decl.attribute("nodename") || decl.attribute("nodegraph")) {
        connect(root_, decl, in, context);
        return;
      }
      ValueType t = parse_type(decl.attribute("type").as_string());
      in.linked = false;
      in.value =
          parse_value(decl.attribute("value").as_string(), t, context + " (interface '" + iface + "')");
      if (t == ValueType::Filename) in.value.text = resolve_file(in.value.text);
      return;
    }
    if (!nodename.empty()) {
      pugi::xml_node src = find_node(scope, nodename);
      if (!src) {
        std::string in_scope = scope == root_ ? "the document" : "nodegraph '" + scope_name(scope) + "'";
        fail(context, ": refers to node '", nodename, "', which does not exist in ", in_scope,
             " (dangling reference)");
      }
      in.linked = true;
      in.node = instantiate(scope, src);
      return;
    }
    if (std::string(el.name()) == "output") fail(context, ": output is not connected to anything");
    in.linked = false;
    in.value = parse_value(el.attribute("value").as_string(), in.type, context);
    if (in.type == ValueType::Filename) in.value.text = resolve_file(in.value.text);
  }

  std::string resolve_file(const std::string& f) {
    if (f.empty() || f[0] == '/') return f;
    return dir_ + f;
  }

  int instantiate(pugi::xml_node scope, pugi::xml_node el) {
    const std::string key = scope_name(scope) + "|" + el.attribute("name").as_string();
    auto found = memo_.find(key);
    if (found != memo_.end()) return found->second;
    if (active_.count(key)) {
      std::string chain;
      bool on = false;
      for (const std::string& k : active_path_) {
        on = on || k == key;
        if (on) chain += "'" + k.substr(k.find('|') + 1) + "' -> ";
      }
      fail(where(el), ": cycle in the node graph: ", chain, "'", el.attribute("name").as_string(), "'");
    }
    if (active_path_.size() >= kMaxNesting)
      fail(where(el), ": the node graph is nested deeper than ", kMaxNesting,
           " nodes (a chain this long would overflow the compiler and interpreter)");
    active_.insert(key);
    active_path_.push_back(key);

    Node node;
    node.name = el.attribute("name").as_string();
    node.category = el.name();
    node.origin = where(el);
    node.type = parse_type(el.attribute("type").as_string());
    const std::string context = node.origin;
    if (is_surface(node.category)) {
      build_surface(scope, el, node, context);
    } else {
      build_node(scope, el, node, context);
    }
    int id = graph_.add(std::move(node));
    memo_[key] = id;
    active_.erase(key);
    active_path_.pop_back();
    return id;
  }

  void build_surface(pugi::xml_node scope, pugi::xml_node el, Node& node, const std::string& context) {
    std::vector<SurfaceParam> params = surface_params(node.category);
    std::string ignored;
    for (const SurfaceParam& p : params) {
      Input in;
      in.name = p.input;
      in.type = p.type;
      in.value = Value::number(p.type, p.def[0], p.def[1], p.def[2]);
      node.inputs.push_back(in);
    }
    for (pugi::xml_node c : el.children("input")) {
      std::string name = c.attribute("name").as_string();
      Input* in = node.input(name);
      if (!in) {
        ignored += (ignored.empty() ? "" : ", ") + name;
        continue;
      }
      ValueType declared = parse_type(c.attribute("type").as_string());
      if (declared != ValueType::None && declared != in->type &&
          !(declared == ValueType::Float && type_width(in->type) > 1))
        fail(context, ": input '", name, "' must be ", type_name(in->type), ", the document says ",
             type_name(declared), " (type mismatch)");
      connect(scope, c, *in, context + " input '" + name + "'");
    }
    if (!ignored.empty()) warn(context + ": inputs pmc does not model (ignored): " + ignored);
  }

  void build_node(pugi::xml_node scope, pugi::xml_node el, Node& node, const std::string& context) {
    const NodeDef* def = find_node_def(node.category);
    if (!def) {
      std::string list;
      for (const std::string& c : supported_categories()) list += (list.empty() ? "" : " ") + c;
      fail(context, ": unsupported node '", node.category, "' (pmc supports: ", list, ")");
    }
    if (node.type == ValueType::None)
      fail(context, ": missing or unknown type '", el.attribute("type").as_string(), "'");
    bool type_ok = false;
    for (const std::string& t : def->output_types) type_ok = type_ok || parse_type(t) == node.type;
    if (!type_ok)
      fail(context, ": node '", node.category, "' cannot output ", type_name(node.type), " (type mismatch)");
    for (const InputDef& d : def->inputs) {
      Input in;
      in.name = d.name;
      in.type = resolve_input_type(d, node.type);
      pugi::xml_node c = el.find_child_by_attribute("input", "name", d.name.c_str());
      if (c) {
        ValueType declared = parse_type(c.attribute("type").as_string());
        if (in.type == ValueType::None) {
          in.type = declared;  // "any" inputs take the document's type
          if (!is_numeric(declared)) fail(context, " input '", d.name, "': missing or non-numeric type");
        } else if (declared != ValueType::None && declared != in.type) {
          bool broadcast = d.type == "T" && declared == ValueType::Float;
          bool same_width = type_width(declared) == type_width(in.type) && is_numeric(declared);
          if (!broadcast && !same_width)
            fail(context, " input '", d.name, "': expects ", type_name(in.type), ", the document says ",
                 type_name(declared), " (type mismatch)");
          in.type = declared;
        }
        connect(scope, c, in, context + " input '" + d.name + "'");
        if (in.type == ValueType::Filename && !in.linked) {
          std::string cs = c.attribute("colorspace").as_string();
          if (cs.empty()) cs = doc_colorspace_;
          in.value.f[0] = cs == "srgb_texture" ? 1.0f : 0.0f;  // decode flag for the image loader
        }
      } else if (d.geom != GeomDefault::None) {
        in.linked = true;
        in.node = geom_node(d.geom);
        if (in.type == ValueType::None) in.type = graph_.nodes[size_t(in.node)].type;
      } else {
        in.value = d.value;
        if (in.type == ValueType::None) in.type = ValueType::Float;
        in.value.type = in.type;
        if (d.type == "T" && type_width(in.type) > 1)  // broadcast scalar defaults
          for (int i = 1; i < 4; ++i) in.value.f[size_t(i)] = in.value.f[0];
      }
      node.inputs.push_back(in);
    }
    for (pugi::xml_node c : el.children("input")) {
      std::string name = c.attribute("name").as_string();
      if (!node.input(name)) warn(context + ": unknown input '" + name + "' ignored");
    }
  }

  void preview_outputs(std::vector<Graph>& out) {
    auto add_preview = [&](pugi::xml_node scope, pugi::xml_node output, const std::string& name) {
      begin(name);
      Node conv;
      conv.category = "convert";
      conv.type = ValueType::Color3;
      conv.origin = path_ + ": output '" + name + "'";
      Input in;
      in.name = "in";
      in.type = parse_type(output.attribute("type").as_string());
      if (!is_numeric(in.type))
        fail(conv.origin, ": output type '", output.attribute("type").as_string(), "' cannot be shown");
      connect(scope, output, in, conv.origin);
      in.type = graph_.nodes[size_t(in.node)].type;
      conv.inputs.push_back(in);
      int c = graph_.add(conv);
      Node surface;
      surface.category = "standard_surface";
      surface.type = ValueType::Surface;
      surface.origin = conv.origin + " (preview surface)";
      for (const SurfaceParam& p : surface_params("standard_surface")) {
        Input si;
        si.name = p.input;
        si.type = p.type;
        si.value = Value::number(p.type, p.def[0], p.def[1], p.def[2]);
        if (si.name == "base_color") si.linked = true, si.node = c;
        if (si.name == "specular") si.value.f[0] = 0.0f;  // a flat preview shows the pattern itself
        surface.inputs.push_back(si);
      }
      graph_.surface = graph_.add(surface);
      out.push_back(std::move(graph_));
    };
    for (pugi::xml_node o : root_.children("output")) add_preview(root_, o, o.attribute("name").as_string());
    for (pugi::xml_node ng : root_.children("nodegraph")) {
      std::string ng_name = ng.attribute("name").as_string();
      int count = 0;
      for (pugi::xml_node o : ng.children("output")) {
        (void)o;
        ++count;
      }
      for (pugi::xml_node o : ng.children("output")) {
        std::string name = count == 1 ? ng_name : ng_name + "/" + o.attribute("name").as_string();
        add_preview(ng, o, name);
      }
    }
  }
};

}  // namespace

std::vector<Graph> read_mtlx_string(const std::string& xml, const std::string& path) {
  pugi::xml_document doc;
  pugi::xml_parse_result r = doc.load_buffer(xml.data(), xml.size());
  if (!r) fail(path, ": not valid XML at byte ", r.offset, ": ", r.description());
  return Reader(path).read(doc);
}

std::vector<Graph> read_mtlx_file(const std::string& path) {
  pugi::xml_document doc;
  pugi::xml_parse_result r = doc.load_file(path.c_str());
  if (r.status == pugi::status_file_not_found || r.status == pugi::status_io_error)
    fail(path, ": cannot read MaterialX file");
  if (!r) fail(path, ": not valid XML at byte ", r.offset, ": ", r.description());
  return Reader(path).read(doc);
}

}  // namespace pmc
