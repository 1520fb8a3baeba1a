// mtlx_instantiator.cpp — MtlxInstantiator: scopes, connections, node
// instantiation, library expansion, tokens and filenames, folded matrices.
// (What each step does: mtlx_instantiator.h.)
#include "materials/mtlx_instantiator.h"

#include <deque>
#include <filesystem>
#include <set>
#include <sstream>

#include "core/error.h"
#include "materials/closure_flatten.h"
#include "materials/emit.h"
#include "materials/geom_default.h"
#include "materials/mtlx_include.h"
#include "materials/mtlx_library.h"
#include "materials/mtlx_matrix.h"
#include "materials/node_table.h"

namespace pmc {
namespace {

bool is_closure(const std::string& type) {
  return type == "BSDF" || type == "EDF" || type == "VDF" || type == "surfaceshader" ||
         type == "volumeshader" || type == "displacementshader" || type == "lightshader" ||
         type == "material";
}

// Deepest chain of linked nodes a document may have: the passes walk graphs
// recursively, and no real material comes near this.
constexpr size_t kMaxNesting = 2000;

GeomDefault geom_default(const std::string& name) {
  if (name == "UV0") return GeomDefault::UV0;
  if (name == "Pobject") return GeomDefault::Pobject;
  if (name == "Pworld") return GeomDefault::Pworld;
  if (name == "Nworld") return GeomDefault::Nworld;
  if (name == "Nobject") return GeomDefault::Nobject;
  if (name == "Tworld") return GeomDefault::Tworld;
  if (name == "Tobject") return GeomDefault::Tobject;
  if (name == "Bworld" || name == "Bobject") return GeomDefault::Bworld;
  if (name == "Vworld") return GeomDefault::Vworld;  // nprlib's view direction
  return GeomDefault::None;
}

}  // namespace

bool mtlx_is_surface_shader(const std::string& category) { return !surface_params(category).empty(); }

bool mtlx_is_structural(const std::string& tag) {
  return tag == "input" || tag == "output" || tag == "nodegraph" || tag == "nodedef" || tag == "look" ||
         tag == "materialassign" || tag == "collection" || tag == "geominfo" || tag == "typedef" ||
         tag == "implementation" || tag == "backdrop" || tag == "variantset" || tag == "propertyset" ||
         tag == "token" || tag == "unit" || tag == "unittypedef" || tag == "xi:include" ||
         tag == "attributedef" || tag == "targetdef" || tag == "geompropdef" || tag == "propertysetassign" ||
         tag == "variantassign" || tag == "visibility" || tag == "lookgroup" || tag == "comment" ||
         tag == "typedef";
}

struct MtlxInstantiator::Impl {
  Impl(const std::string& path, const MtlxReadOptions& options, pugi::xml_node root,
       MtlxSurfaceBuilder build_surface)
      : path_(path),
        dir_(path.substr(0, path.find_last_of('/') + 1)),
        options_(options),
        search_(mtlx_search_paths(options)),
        root_(root),
        build_surface_(std::move(build_surface)) {
    doc_defs_.add(root_);
  }

  std::string path_, dir_;
  MtlxReadOptions options_;
  std::vector<std::string> search_;
  pugi::xml_node root_;
  MtlxSurfaceBuilder build_surface_;
  MtlxDefinitions doc_defs_;
  const MtlxLibrary* library_ = nullptr;
  bool library_looked_up_ = false;
  Graph graph_;
  std::map<std::string, int> memo_;  // "scope|node" -> node index
  struct Expansion {
    MtlxScope scope;
    std::map<std::string, int> outputs;  // output name -> node index
    pugi::xml_node nodedef;
    std::string context;
  };
  std::map<std::string, Expansion> expansions_;  // "scope|node" -> its expansion
  std::deque<std::map<std::string, Input>> ifaces_;
  int next_scope_ = 0;
  std::set<std::string> active_;  // instantiation stack, for cycles
  std::vector<std::string> active_path_;
  std::map<int, int> geom_nodes_;  // GeomDefault -> node index
  std::map<int, Value> folded_;    // node index -> its folded value (inputs of matrix nodes)
  std::set<int> closure_nodes_;    // closure nodes kept for flattening

  void begin(const std::string& material) {
    graph_ = Graph();
    graph_.material = material;
    graph_.file = path_;
    memo_.clear();
    expansions_.clear();
    ifaces_.clear();
    active_.clear();
    active_path_.clear();
    geom_nodes_.clear();
    folded_.clear();
    closure_nodes_.clear();
  }

  const MtlxLibrary* library() {
    if (!library_looked_up_) {
      library_looked_up_ = true;
      std::string dir = find_mtlx_library(options_.library_dir);
      if (!dir.empty()) library_ = &MtlxLibrary::load(dir);
    }
    return library_;
  }

  // nested nodegraph).
  std::string scope_name(const MtlxScope& scope) const {
    std::string path;
    for (pugi::xml_node g = scope.graph; g && g != root_; g = g.parent())
      path = std::string(g.attribute("name").as_string()) + (path.empty() ? "" : "/" + path);
    return std::to_string(scope.id) + ":" + path;
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
  std::string where(const MtlxScope& scope, pugi::xml_node el) const {
    if (scope.id == 0) return where(el);
    return scope.origin + ": " + el.name() + " '" + el.attribute("name").as_string() + "'";
  }

  static pugi::xml_node find_node(pugi::xml_node scope, const std::string& name) {
    for (pugi::xml_node c : scope.children())
      if (!mtlx_is_structural(c.name()) && name == c.attribute("name").as_string()) return c;
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
    if (is_matrix(t)) {  // 9 or 16 numbers, row-major
      const size_t count = t == ValueType::Matrix44 ? 16 : 9;
      std::istringstream is(s);
      std::string item;
      while (std::getline(is, item, ',')) {
        char* end = nullptr;
        float x = std::strtof(item.c_str(), &end);
        while (end && (*end == ' ' || *end == '\t')) ++end;
        if (end == item.c_str() || (end && *end != '\0'))
          fail(context, ": '", s, "' is not a ", type_name(t), " value");
        v.matrix.push_back(x);
      }
      if (v.matrix.size() != count)
        fail(context, ": '", s, "' is not a ", type_name(t), " value (", count, " numbers expected, ",
             v.matrix.size(), " given)");
      return v;
    }
    if (is_closure_type(t)) {  // a closure input holds no value: "" is "not connected"
      if (!s.empty()) fail(context, ": a ", type_name(t), " input cannot hold the value '", s, "'");
      return v;
    }
    int n = type_width(t);
    if (n == 0) fail(context, ": values of type ", type_name(t), " are not supported");
    const char* p = s.c_str();
    for (int i = 0; i < n; ++i) {
      char* end = nullptr;
      float x = std::strtof(p, &end);
      if (end == p) {
        if (i == 1 &&
            *p == '\0') {  // a single number for a vector: MaterialX broadcasts nothing, but be lenient
          for (int k = 1; k < n; ++k) v.f[size_t(k)] = v.f[0];
          return v;
        }
        fail(context, ": '", s, "' is not a ", type_name(t), " value");
      }
      v.f[size_t(i)] = x;
      p = end;
      while (*p == ' ' || *p == ',') ++p;
    }
    return v;
  }

  int geom_node(GeomDefault g) {
    return geom_default_in(graph_, geom_nodes_, g, path_ + ": implicit geometric default");
  }

  // The nearest `attr` on `el` or its ancestors ("" if none).
  std::string inherited(pugi::xml_node el, const char* attr) const {
    for (pugi::xml_node e = el; e; e = e.parent())
      if (e.attribute(attr)) return e.attribute(attr).as_string();
    return "";
  }

  // fileprefix, then the folder of the file the element came from (an
  // included one's, mtlx_include.h), the document's folder, the search paths.
  std::string resolve_file(pugi::xml_node el, const std::string& f) {
    if (f.empty()) return f;
    std::string name = inherited(el, "fileprefix") + f;
    if (name[0] == '/') return name;
    std::error_code ec;
    const std::string included_from = inherited(el, kIncludeDirAttr);
    if (!included_from.empty() && std::filesystem::exists(included_from + name, ec))
      return included_from + name;
    if (std::filesystem::exists(dir_ + name, ec)) return dir_ + name;
    for (const std::string& sp : search_) {
      std::string candidate = sp + (sp.back() == '/' ? "" : "/") + name;
      if (std::filesystem::exists(candidate, ec)) return candidate;
    }
    return dir_ + name;  // not found: the texture loader names it
  }

  // The value of interface token `name` for a filename on `el`: a <token> of
  // el's node or of an enclosing nodegraph (the nearest; not the document's:
  // MaterialX ignores top-level tokens), then the expanded instance's, then
  // its definition's default, then that of the definition a functional
  // nodegraph names. A token may pass the lookup on with `interfacename`.
  bool token_value(const MtlxScope* scope, pugi::xml_node el, std::string name, std::string* value) {
    auto from = [&](pugi::xml_node holder) {
      pugi::xml_node t =
          holder ? holder.find_child_by_attribute("token", "name", name.c_str()) : pugi::xml_node();
      if (!t) return false;
      if (t.attribute("interfacename")) {
        name = t.attribute("interfacename").as_string();
        return false;
      }
      *value = t.attribute("value").as_string();
      return true;
    };
    for (pugi::xml_node e = el.parent(); e && e != root_; e = e.parent())
      if (from(e)) return true;
    if (scope && (from(scope->instance) || from(scope->nodedef))) return true;
    if (scope && scope->graph != root_ && scope->graph.attribute("nodedef")) {
      pugi::xml_node nd =
          root_.find_child_by_attribute("nodedef", "name", scope->graph.attribute("nodedef").as_string());
      if (from(nd)) return true;
    }
    return false;
  }

  // Filename substitutions (the specification's "[interface token]"):
  // each [name] whose token is found becomes its value; others stay.
  std::string substitute_tokens(const MtlxScope* scope, pugi::xml_node el, const std::string& text) {
    std::string out;
    size_t at = 0;
    while (at < text.size()) {
      size_t open = text.find('[', at), close = open == std::string::npos ? open : text.find(']', open);
      if (close == std::string::npos) break;
      std::string value;
      out += text.substr(at, open - at);
      out += token_value(scope, el, text.substr(open + 1, close - open - 1), &value)
                 ? value
                 : text.substr(open, close - open + 1);
      at = close + 1;
    }
    return out + text.substr(std::min(at, text.size()));
  }

  // A filename input's value: tokens substituted, resolved path, and the
  // sRGB decode flag (f[0]) from its (inherited) colorspace.
  void finish_filename(pugi::xml_node el, Input& in, const MtlxScope* scope = nullptr) {
    if (in.type != ValueType::Filename || in.linked) return;
    in.value.text = resolve_file(el, substitute_tokens(scope, el, in.value.text));
    std::string cs = inherited(el, "colorspace");
    in.value.f[0] = cs == "srgb_texture" ? 1.0f : 0.0f;
  }

  // MaterialX reads a nodename= that names a nodegraph of the document, not
  // a node, as no connection at all (Input::getConnectedOutput is null): the
  // input keeps its value, or else its definition's default. Older
  // documents do this (MaterialX's usd_preview_surface_brick_procedural).
  bool names_graph_not_node(const MtlxScope& scope, pugi::xml_node el) {
    const std::string nodename = el.attribute("nodename").as_string();
    if (nodename.empty() || el.attribute("nodegraph") || el.attribute("interfacename")) return false;
    return scope.graph == root_ && !find_node(root_, nodename) &&
           root_.find_child_by_attribute("nodegraph", "name", nodename.c_str());
  }

  // An input element with no value and no connection, or one that names a
  // nodegraph as its node and has no value, stands for nothing: the caller
  // uses the definition's default, as MaterialX does for an unset input.
  bool stands_for_default(const MtlxScope& scope, pugi::xml_node el, const std::string& context) {
    if (el.attribute("value")) return false;
    if (!el.attribute("nodename") && !el.attribute("nodegraph") && !el.attribute("interfacename") &&
        !el.attribute("output")) {
      warn(context + ": no value and no connection; its default is used");
      return true;
    }
    if (!names_graph_not_node(scope, el)) return false;
    warn(context + ": nodename '" + el.attribute("nodename").as_string() +
         "' names a nodegraph, not a node: not a connection (as in MaterialX); the input keeps its default");
    return true;
  }

  // Resolves an <input> (or <output>) element found in `scope` into `in`.
  void connect(const MtlxScope& scope, pugi::xml_node el, Input& in, const std::string& context) {
    std::string nodename = el.attribute("nodename").as_string();
    std::string nodegraph = el.attribute("nodegraph").as_string();
    std::string iface = el.attribute("interfacename").as_string();
    std::string output = el.attribute("output").as_string();
    if (!nodegraph.empty()) {
      // A nodegraph nested in the enclosing one (its interface reads the
      // enclosing graph's), else one of the document's.
      pugi::xml_node nested =
          scope.graph == root_ ? pugi::xml_node()
                               : scope.graph.find_child_by_attribute("nodegraph", "name", nodegraph.c_str());
      pugi::xml_node ng =
          nested ? nested : root_.find_child_by_attribute("nodegraph", "name", nodegraph.c_str());
      if (!ng)
        fail(context, ": refers to nodegraph '", nodegraph, "', which does not exist (dangling reference)");
      pugi::xml_node out =
          output.empty() ? ng.child("output") : ng.find_child_by_attribute("output", "name", output.c_str());
      if (!out)
        fail(context, ": nodegraph '", nodegraph, "' has no output '", output, "' (dangling reference)");
      const std::string out_context =
          path_ + ": nodegraph '" + nodegraph + "' output '" + out.attribute("name").as_string() + "'";
      if (nested)
        connect(MtlxScope{ng, scope.id, nullptr, scope.origin, &scope}, out, in, out_context);
      else
        connect(MtlxScope{ng, 0, nullptr, ""}, out, in, out_context);
      return;
    }
    if (!iface.empty()) {
      if (scope.iface) {  // an implementation graph: the instance's input
        auto it = scope.iface->find(iface);
        if (it == scope.iface->end())
          fail(context, ": interfacename '", iface, "' is not an input of the node's definition");
        const ValueType t = in.type;
        const std::string name = in.name;
        in = it->second;
        in.name = name;
        if (t != ValueType::None) in.type = t;
        if (!in.linked && type_width(it->second.type) == 1)
          for (int i = 1; i < 4; ++i) in.value.f[size_t(i)] = in.value.f[0];
        return;
      }
      // The enclosing nodegraph's interface input (at the document's root: a
      // top-level <input>, which MaterialX's test suite also uses).
      pugi::xml_node decl = scope.graph.find_child_by_attribute("input", "name", iface.c_str());
      if (!decl) {
        if (!el.attribute("value"))
          fail(context, ": interfacename '", iface,
               "' is not an input of the enclosing nodegraph (dangling reference)");
        // Like MaterialX, an interface name with nothing behind it leaves the input's own value.
        warn(context + ": interfacename '" + iface + "' has no enclosing nodegraph input; using its value");
        in.linked = false;
        ValueType t = in.type != ValueType::None ? in.type : parse_type(el.attribute("type").as_string());
        in.value = parse_value(el.attribute("value").as_string(), t, context);
        finish_filename(el, in, &scope);
        return;
      }
      if (scope.parent && (decl.attribute("interfacename") || decl.attribute("nodename") ||
                           decl.attribute("nodegraph"))) {  // a nested graph's input: the enclosing scope's
        connect(*scope.parent, decl, in, context);
        return;
      }
      if (decl.attribute("nodename") || decl.attribute("nodegraph")) {
        connect(MtlxScope{root_, 0, nullptr, ""}, decl, in, context);
        return;
      }
      ValueType t = parse_type(decl.attribute("type").as_string());
      if (!decl.attribute("value") && decl.attribute("defaultgeomprop")) {  // e.g. texcoord = UV0
        GeomDefault g = geom_default(decl.attribute("defaultgeomprop").as_string());
        if (g == GeomDefault::None)
          fail(context, " (interface '", iface, "'): unknown defaultgeomprop '",
               decl.attribute("defaultgeomprop").as_string(), "'");
        in.linked = true;
        in.node = geom_node(g);
        if (in.type == ValueType::None) in.type = t;
        return;
      }
      in.linked = false;
      in.value =
          parse_value(decl.attribute("value").as_string(), t, context + " (interface '" + iface + "')");
      if (in.type == ValueType::None) in.type = t;
      finish_filename(decl, in, &scope);
      return;
    }
    if (!nodename.empty()) {
      pugi::xml_node src = find_node(scope.graph, nodename);
      if (names_graph_not_node(scope, el)) {  // no connection, as MaterialX reads it
        warn(
            context + ": nodename '" + nodename +
            "' names a nodegraph, not a node: not a connection (as in MaterialX); the input keeps its value");
        in.linked = false;
        ValueType t = in.type != ValueType::None ? in.type : parse_type(el.attribute("type").as_string());
        in.value = parse_value(el.attribute("value").as_string(), t, context);
        finish_filename(el, in, &scope);
        return;
      }
      if (!src) {
        std::string in_scope =
            scope.graph == root_
                ? "the document"
                : "nodegraph '" + std::string(scope.graph.attribute("name").as_string()) + "'";
        fail(context, ": refers to node '", nodename, "', which does not exist in ", in_scope,
             " (dangling reference)");
      }
      in.linked = true;
      in.node = instantiate(scope, src, output);
      return;
    }
    if (!output.empty() && std::string(el.name()) == "input") {
      // Only `output`: a top-level <output> of the document, as MaterialX
      // reads it (Input::getConnectedOutput).
      pugi::xml_node out = root_.find_child_by_attribute("output", "name", output.c_str());
      if (!out)
        fail(context, ": refers to output '", output,
             "', which the document does not have (dangling reference)");
      connect(MtlxScope{root_, 0, nullptr, ""}, out, in, path_ + ": output '" + output + "'");
      return;
    }
    if (std::string(el.name()) == "output") fail(context, ": output is not connected to anything");
    in.linked = false;
    ValueType t = in.type;
    if (t == ValueType::None) t = parse_type(el.attribute("type").as_string());
    in.value = parse_value(el.attribute("value").as_string(), t, context);
    finish_filename(el, in, &scope);
  }

  int instantiate(const MtlxScope& scope, pugi::xml_node el, const std::string& output) {
    const std::string key = scope_name(scope) + "|" + el.attribute("name").as_string();
    // A native node with several outputs is one graph node per output used.
    const NodeDef* def = find_node_def(el.name());
    const bool multi = def && !def->outputs.empty();
    const std::string memo_key = multi ? key + "|" + output : key;
    auto found = memo_.find(memo_key);
    if (found != memo_.end()) return found->second;
    auto expanded = expansions_.find(key);
    if (expanded != expansions_.end()) return expansion_output(expanded->second, output);
    if (active_.count(key)) {
      std::string chain;
      bool on = false;
      for (const std::string& k : active_path_) {
        on = on || k == key;
        if (on) chain += "'" + k.substr(k.find('|') + 1) + "' -> ";
      }
      fail(where(scope, el), ": cycle in the node graph: ", chain, "'", el.attribute("name").as_string(),
           "'");
    }
    if (active_path_.size() >= kMaxNesting)
      fail(where(scope, el), ": the node graph is nested deeper than ", kMaxNesting,
           " nodes (a chain this long would overflow the compiler and interpreter)");
    active_.insert(key);
    active_path_.push_back(key);

    Node node;
    node.name = el.attribute("name").as_string();
    node.category = el.name();
    node.origin = where(scope, el);
    node.type = parse_type(el.attribute("type").as_string());
    const std::string context = node.origin;
    int id;
    bool native = false;
    if (multi) {
      if (output.empty())
        fail(context, ": node '", node.category, "' has several outputs (", output_names(*def),
             "): the connection must name one with output=\"...\"");
      const OutputDef* o = find_output(*def, output);
      if (!o)
        fail(context, ": node '", node.category, "' has no output '", output, "' (it has ",
             output_names(*def), ")");
      node.type = parse_type(o->type);
      node.output = output;
      native = true;
    } else if (def && node.type != ValueType::None) {
      for (const std::string& t : def->output_types) native = native || parse_type(t) == node.type;
    }
    if (mtlx_is_surface_shader(node.category)) {
      build_surface_(scope, el, node, context);
      id = graph_.add(std::move(node));
      memo_[memo_key] = id;
    } else if (native) {
      build_node(scope, el, *def, node, context);
      id = graph_.add(std::move(node));
      memo_[memo_key] = id;
    } else if (pugi::xml_node cd = closure_nodedef(el, node)) {
      // A pbrlib closure (a *_bsdf, surface, layer, mix of closures ...):
      // kept as written, with its definition's inputs; shader_of flattens.
      std::map<std::string, Input> ins = instance_inputs(scope, el, cd, context);
      for (auto& kv : ins) node.inputs.push_back(kv.second);
      if (node.type == ValueType::None)
        node.type = parse_type(cd.child("output").attribute("type").as_string());
      id = graph_.add(std::move(node));
      closure_nodes_.insert(id);
      memo_[memo_key] = id;
    } else if (pugi::xml_node nd = matrix_nodedef(el, node.category)) {
      id = fold_matrix(scope, el, nd, node, context);
      memo_[memo_key] = id;
    } else {
      Expansion& e = expansions_[key];
      e = expand(scope, el, node, def, context);
      id = expansion_output(e, output);
    }
    active_.erase(key);
    active_path_.pop_back();
    return id;
  }

  // The definition of a closure node pmc flattens (closure_flatten.h): one
  // whose output is a closure and that MaterialX implements natively (no
  // nodegraph: a custom closure node with a graph expands as usual).
  pugi::xml_node closure_nodedef(pugi::xml_node el, const Node& node) {
    if (!is_closure_type(node.type) || mtlx_is_surface_shader(node.category)) return {};
    pugi::xml_node nd = match_nodedef(el, node.category, el.attribute("type").as_string());
    if (!nd) return {};
    const std::string name = nd.attribute("name").as_string();
    if (doc_defs_.implementation(name) || (library() && library()->definitions().implementation(name)))
      return {};
    return nd;
  }

  // The definition of a node on matrices that pmc folds (mtlx_matrix.h): one
  // with a matrix input or output and no implementation nodegraph (switch
  // on matrices has one: it expands into ifgreater nodes, which fold).
  pugi::xml_node matrix_nodedef(pugi::xml_node el, const std::string& category) {
    bool maybe = category == "transformmatrix" || category == "determinant" ||
                 !el.attribute("nodedef").empty() || is_matrix(parse_type(el.attribute("type").as_string()));
    for (pugi::xml_node c : el.children("input"))
      maybe = maybe || is_matrix(parse_type(c.attribute("type").as_string()));
    if (!maybe) return {};
    pugi::xml_node nd = match_nodedef(el, category, el.attribute("type").as_string());
    if (!nd) return {};
    bool matrix = false;
    for (pugi::xml_node o : nd.children("output"))
      matrix = matrix || is_matrix(parse_type(o.attribute("type").as_string()));
    for (pugi::xml_node i : nodedef_inputs(nd))
      matrix = matrix || is_matrix(parse_type(i.attribute("type").as_string()));
    const std::string name = nd.attribute("name").as_string();
    if (!matrix || doc_defs_.implementation(name) ||
        (library() && library()->definitions().implementation(name)))
      return {};
    return nd;
  }

  // A matrix node, folded: a constant (a matrix, determinant's float,
  // extract's row), or transformmatrix's nodes on vectors.
  int fold_matrix(const MtlxScope& scope, pugi::xml_node el, pugi::xml_node nd, const Node& node,
                  const std::string& context) {
    const std::string nd_name = nd.attribute("name").as_string();
    std::map<std::string, Input> ins = instance_inputs(scope, el, nd, context);
    const ValueType out = parse_type(nd.child("output").attribute("type").as_string());
    if (node.category == "transformmatrix") {
      auto mat = ins.find("mat"), vec = ins.find("in");
      if (mat == ins.end() || vec == ins.end() || !is_matrix(mat->second.type))
        fail(context, ": transformmatrix definition ", nd_name, " lacks its 'in' or matrix 'mat' input");
      Matrix m = Matrix::of(constant_of(mat->second, context + " input 'mat'"));
      return lower_transformmatrix(graph_, vec->second, m, out, context);
    }
    std::map<std::string, Value> values;
    for (const auto& [name, in] : ins) values[name] = constant_of(in, context + " input '" + name + "'");
    Value r = fold_matrix_node(node.category, out, values, context + " (" + nd_name + ")");
    Node c;
    c.name = node.name;
    c.category = "constant";
    c.type = r.type;
    c.origin = context;
    Input v;
    v.name = "value";
    v.type = r.type;
    v.value = r;
    c.inputs = {v};
    return graph_.add(std::move(c));
  }

  // The constant value of an input of a matrix node: its value, or the
  // folded value of the sub-graph it links to (which must not vary).
  Value constant_of(const Input& in, const std::string& context) {
    if (!in.linked) {
      Value v = in.value;
      v.type = in.type;
      return v;
    }
    return folded_value(in.node, context, 0);
  }
  Value folded_value(int id, const std::string& context, size_t depth) {
    const Node& n = graph_.nodes[size_t(id)];
    if (is_matrix(n.type)) return n.inputs.at(0).value;  // matrix nodes are folded constants
    auto known = folded_.find(id);                       // shared sub-graphs fold once
    if (known != folded_.end()) return known->second;
    if (depth >= kMaxNesting) fail(context, ": the sub-graph feeding a matrix is nested too deeply");
    Node copy = n;
    for (Input& i : copy.inputs) {
      if (!i.linked) continue;
      Value v = folded_value(i.node, context, depth + 1);
      const ValueType t = i.type;
      i.linked = false;
      i.node = -1;
      i.value = v;
      i.value.type = t;
      if (type_width(v.type) == 1)
        for (int k = 1; k < 4; ++k) i.value.f[size_t(k)] = i.value.f[0];
    }
    Value out;
    if (!evaluate_constant(graph_, copy, out))
      fail(context, ": pmc folds matrices when it reads a document, so this must be constant, but node '",
           n.name.empty() ? n.category : n.name, "' (", n.category, ", ", n.origin,
           ") varies over the surface");
    out.type = n.type;
    folded_[id] = out;
    return out;
  }

  // A nodedef's inputs, its `inherit`ed definitions' included (its own win).
  std::vector<pugi::xml_node> nodedef_inputs(pugi::xml_node nd) {
    std::vector<pugi::xml_node> out;
    std::set<std::string> seen;
    for (int depth = 0; nd && depth < 16; ++depth) {
      for (pugi::xml_node in : nd.children("input"))
        if (seen.insert(in.attribute("name").as_string()).second) out.push_back(in);
      std::string base = nd.attribute("inherit").as_string();
      if (base.empty()) break;
      pugi::xml_node next = doc_defs_.nodedef(base);
      if (!next && library()) next = library()->definitions().nodedef(base);
      nd = next;
    }
    return out;
  }
  pugi::xml_node nodedef_input(pugi::xml_node nd, const std::string& name) {
    for (pugi::xml_node in : nodedef_inputs(nd))
      if (name == in.attribute("name").as_string()) return in;
    return {};
  }

  // The definition of a node pmc does not compile natively: by its
  // `nodedef` attribute, else the first definition of its category whose
  // output type and declared input types match (MaterialX's rule).
  pugi::xml_node match_nodedef(pugi::xml_node el, const std::string& category, const std::string& type) {
    std::string explicit_nd = el.attribute("nodedef").as_string();
    std::vector<pugi::xml_node> candidates;
    const MtlxDefinitions* lib = library() ? &library()->definitions() : nullptr;
    for (const MtlxDefinitions* defs : {static_cast<const MtlxDefinitions*>(&doc_defs_), lib}) {
      if (!defs) continue;
      if (!explicit_nd.empty()) {
        if (pugi::xml_node nd = defs->nodedef(explicit_nd)) return nd;
        continue;
      }
      for (pugi::xml_node nd : defs->nodedefs_for(category)) candidates.push_back(nd);
    }
    for (pugi::xml_node nd : candidates) {
      int outputs = 0;
      bool type_ok = false;
      for (pugi::xml_node o : nd.children("output")) {
        ++outputs;
        type_ok = type_ok || type == o.attribute("type").as_string();
      }
      if (type == "multioutput" || type.empty()) type_ok = outputs > 1 || type.empty();
      if (!type_ok) continue;
      bool inputs_ok = true;
      for (pugi::xml_node c : el.children("input")) {
        std::string declared = c.attribute("type").as_string();
        pugi::xml_node d = nodedef_input(nd, c.attribute("name").as_string());
        if (!d || (!declared.empty() && declared != d.attribute("type").as_string())) inputs_ok = false;
      }
      if (inputs_ok) return nd;
    }
    return {};
  }

  Expansion expand(const MtlxScope& scope, pugi::xml_node el, const Node& node, const NodeDef* def,
                   const std::string& context) {
    const std::string type = el.attribute("type").as_string();
    pugi::xml_node nd = match_nodedef(el, node.category, type);
    if (!nd) {
      if (def && node.type != ValueType::None)
        fail(context, ": node '", node.category, "' cannot output ", type, " (type mismatch)");
      if (!library())
        fail(context, ": unsupported node '", node.category,
             "' (not in pmc's node table, and no MaterialX data library to expand it from: run "
             "scripts/setup, set PMC_MTLX_LIBRARY or name a library folder in the mtlx_library setting)");
      fail(context, ": unsupported node '", node.category, "' of type ", type.empty() ? "(none)" : type,
           " (no definition matches it in the document or the MaterialX library in ", library()->dir(), ")");
    }
    const std::string nd_name = nd.attribute("name").as_string();
    pugi::xml_node ng = doc_defs_.implementation(nd_name);
    if (!ng && library()) ng = library()->definitions().implementation(nd_name);
    if (!ng) {
      for (pugi::xml_node o : nd.children("output"))
        if (is_closure(o.attribute("type").as_string()))
          fail(context, ": node '", node.category, "' (", nd_name, ") outputs a ",
               o.attribute("type").as_string(),
               " closure, which pmc cannot render here (it flattens BSDF and EDF nodes that declare their "
               "type under a surface shader; volume, light and displacement shaders are not supported)");
      fail(context, ": unsupported node '", node.category, "' (", nd_name,
           "): pmc has no native implementation and MaterialX defines no nodegraph for it");
    }
    // The instance's inputs, as the implementation graph's interface.
    std::map<std::string, Input>& iface = ifaces_.emplace_back();
    iface = instance_inputs(scope, el, nd, context);
    Expansion e;
    e.scope = MtlxScope{ng, ++next_scope_, &iface,
                        context + " (expanded from " + ng.attribute("name").as_string() + ")"};
    e.scope.instance = el;
    e.scope.nodedef = nd;
    e.nodedef = nd;
    e.context = context;
    return e;
  }

  // A node's inputs as its definition `nd` lists them: connected, the
  // document's values, or the definition's defaults.
  std::map<std::string, Input> instance_inputs(const MtlxScope& scope, pugi::xml_node el, pugi::xml_node nd,
                                               const std::string& context) {
    const std::string nd_name = nd.attribute("name").as_string();
    std::map<std::string, Input> iface;
    for (pugi::xml_node d : nodedef_inputs(nd)) {
      Input in;
      in.name = d.attribute("name").as_string();
      in.type = parse_type(d.attribute("type").as_string());
      const std::string ctx = context + " input '" + in.name + "'";
      pugi::xml_node c = el.find_child_by_attribute("input", "name", in.name.c_str());
      if (in.type == ValueType::None && !c) continue;  // a type pmc does not read, unset
      if (in.type == ValueType::None)
        fail(ctx, ": inputs of type ", d.attribute("type").as_string(), " are not supported");
      if (c && stands_for_default(scope, c, ctx)) c = pugi::xml_node();
      if (c) {
        connect(scope, c, in, ctx);
      } else if (d.attribute("defaultgeomprop")) {
        GeomDefault g = geom_default(d.attribute("defaultgeomprop").as_string());
        if (g == GeomDefault::None)
          fail(ctx, ": unknown defaultgeomprop '", d.attribute("defaultgeomprop").as_string(), "'");
        in.linked = true;
        in.node = geom_node(g);
      } else {
        in.value =
            parse_value(d.attribute("value").as_string(), in.type, ctx + " (definition " + nd_name + ")");
        finish_filename(d, in);
      }
      iface[in.name] = in;
    }
    for (pugi::xml_node c : el.children("input"))
      if (!nodedef_input(nd, c.attribute("name").as_string()))
        warn(context + ": unknown input '" + c.attribute("name").as_string() + "' ignored");
    return iface;
  }

  int expansion_output(Expansion& e, const std::string& output) {
    pugi::xml_node out = output.empty()
                             ? e.scope.graph.child("output")
                             : e.scope.graph.find_child_by_attribute("output", "name", output.c_str());
    if (!out) fail(e.context, ": has no output '", output, "' (dangling reference)");
    const std::string name = out.attribute("name").as_string();
    auto it = e.outputs.find(name);
    if (it != e.outputs.end()) return it->second;
    Input in;
    in.name = name;
    in.type = parse_type(out.attribute("type").as_string());
    connect(e.scope, out, in, e.scope.origin + ": output '" + name + "'");
    int id;
    if (in.linked) {
      id = in.node;
    } else {  // an output fed straight by a constant or an interface value
      Node c;
      c.category = "constant";
      c.type = in.type;
      c.origin = e.scope.origin + ": output '" + name + "'";
      in.name = "value";
      c.inputs = {in};
      id = graph_.add(std::move(c));
    }
    e.outputs[name] = id;
    return id;
  }

  void build_node(const MtlxScope& scope, pugi::xml_node el, const NodeDef& def, Node& node,
                  const std::string& context) {
    for (const InputDef& d : def.inputs) {
      Input in;
      in.name = d.name;
      in.type = resolve_input_type(d, node.type);
      pugi::xml_node c = el.find_child_by_attribute("input", "name", d.name.c_str());
      if (c && stands_for_default(scope, c, context + " input '" + d.name + "'")) c = pugi::xml_node();
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
    // The boolean comparisons (ND_ifgreater_floatB ...) have no in1/in2:
    // their value is the comparison itself, i.e. in1 = true, in2 = false.
    if (node.type == ValueType::Boolean && def.opcode != PMC_OP_MIN && def.opcode != PMC_OP_MAX &&
        node.input("in1") && node.input("in2") && !el.find_child_by_attribute("input", "name", "in1") &&
        node.input("value1"))
      node.input("in1")->value.f = {1, 1, 1, 1};
  }
};

MtlxInstantiator::MtlxInstantiator(const std::string& path, const MtlxReadOptions& options,
                                   pugi::xml_node root, MtlxSurfaceBuilder build_surface)
    : impl_(std::make_unique<Impl>(path, options, root, std::move(build_surface))) {}
MtlxInstantiator::~MtlxInstantiator() = default;

void MtlxInstantiator::begin(const std::string& material) { impl_->begin(material); }
Graph& MtlxInstantiator::graph() { return impl_->graph_; }

void MtlxInstantiator::connect(const MtlxScope& scope, pugi::xml_node el, Input& in,
                               const std::string& context) {
  impl_->connect(scope, el, in, context);
}
bool MtlxInstantiator::stands_for_default(const MtlxScope& scope, pugi::xml_node el,
                                          const std::string& context) {
  return impl_->stands_for_default(scope, el, context);
}
MtlxScope MtlxInstantiator::implementation_scope(const MtlxScope& scope, pugi::xml_node node,
                                                 const std::string& context) {
  Node n;
  n.name = node.attribute("name").as_string();
  n.category = node.name();
  n.type = ValueType::None;
  return impl_->expand(scope, node, n, nullptr, context).scope;
}
Value MtlxInstantiator::constant_of(const Input& in, const std::string& context) {
  return impl_->constant_of(in, context);
}
bool MtlxInstantiator::is_closure_node(int id) const { return impl_->closure_nodes_.count(id) != 0; }

std::string MtlxInstantiator::where(pugi::xml_node el) const { return impl_->where(el); }
std::string MtlxInstantiator::where(const MtlxScope& scope, pugi::xml_node el) const {
  return impl_->where(scope, el);
}
pugi::xml_node MtlxInstantiator::find_node(pugi::xml_node graph, const std::string& name) {
  return Impl::find_node(graph, name);
}

}  // namespace pmc
