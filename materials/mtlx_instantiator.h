// mtlx_instantiator.h — MaterialX elements into graph nodes: scopes, library
// expansion, tokens, node instantiation and connections.
//
// The instantiator builds one material's Graph at a time from a loaded
// document (MtlxDocument). Given an <input> or <output> element and the scope
// it was found in, connect() resolves it into an Input: a value parsed by its
// type (filenames with their [token]s substituted and resolved against
// fileprefix, the file's folder and the search paths), an interface value, or
// a link to a node it instantiates. A node of the node table (node_table.h)
// becomes one graph node (one per output used for multi-output nodes); any
// other node is expanded from its definition's nodegraph — the document's
// own or the MaterialX library's (mtlx_library.h) — in a new scope whose
// `interfacename`s read the instance's inputs; pbrlib closures stay as
// written for closure_flatten.h; nodes on matrices fold into constants
// (mtlx_matrix.h). Unconnected inputs take their definition's defaults, and
// geometric defaults become explicit texcoord/position/normal nodes.
// Instances are memoised per scope, so a node two inputs share is built once,
// and a cycle or a chain deeper than the compiler can walk fails naming it.
//
// What it does not know is surface shaders: a node whose category is one
// (node_table.h: surface_params) is handed to the MtlxSurfaceBuilder the
// surface mapper (mtlx_surface_mapper.cpp) gives it, which maps its inputs
// through connect() and stands_for_default().
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <pugixml.hpp>
#include <string>

#include "materials/mtlx_reader.h"
#include "materials/node_graph.h"

namespace pmc {

// Where a nodegraph's nodes are instantiated from: the document (id 0: the
// root and the document's own nodegraphs, keyed by their names), or one
// expansion of a node's implementation graph (its own id; `iface` holds the
// instance's inputs, which the graph's `interfacename`s stand for).
struct MtlxScope {
  pugi::xml_node graph;
  int id = 0;
  const std::map<std::string, Input>* iface = nullptr;
  std::string origin;                 // what expansion messages name
  const MtlxScope* parent = nullptr;  // a nested nodegraph's enclosing scope
  pugi::xml_node instance;            // an expansion's node (its <token>s fill filenames)
  pugi::xml_node nodedef;             // and that node's definition (token defaults)
};

// Fills the inputs of surface shader node `node` (its category set) from
// element `el` found in `scope`; errors name `context`.
using MtlxSurfaceBuilder =
    std::function<void(const MtlxScope& scope, pugi::xml_node el, Node& node, const std::string& context)>;

// Is `category` a surface shader pmc maps onto its BSDF (standard_surface ...)?
bool mtlx_is_surface_shader(const std::string& category);
// Is `tag` an element that is not a node (input, output, nodegraph, look ...)?
bool mtlx_is_structural(const std::string& tag);

class MtlxInstantiator {
 public:
  // `root` is the <materialx> element of a document MtlxDocument loaded.
  MtlxInstantiator(const std::string& path, const MtlxReadOptions& options, pugi::xml_node root,
                   MtlxSurfaceBuilder build_surface);
  ~MtlxInstantiator();

  // Starts material `material`: an empty graph, no instances remembered.
  void begin(const std::string& material);
  // The graph of the material begun last.
  Graph& graph();

  // Resolves <input> or <output> element `el`, found in `scope`, into `in`
  // (its name and type set by the caller; a type of None takes the element's).
  void connect(const MtlxScope& scope, pugi::xml_node el, Input& in, const std::string& context);
  // Does input element `el` stand for its definition's default (no value and
  // no connection, or a nodename that names a nodegraph)? Warns when it does.
  bool stands_for_default(const MtlxScope& scope, pugi::xml_node el, const std::string& context);
  // The scope of the implementation graph of custom node `node` (a node
  // whose definition has a nodegraph), its inputs as the graph's interface.
  MtlxScope implementation_scope(const MtlxScope& scope, pugi::xml_node node, const std::string& context);
  // The value of `in`, or of the sub-graph it links to, which must be constant.
  Value constant_of(const Input& in, const std::string& context);
  // Is graph node `id` a closure kept for closure_flatten.h?
  bool is_closure_node(int id) const;

  // "file: nodegraph 'g': category 'name'" for element `el` of the document,
  // or of an expansion (then the expansion's origin leads).
  std::string where(pugi::xml_node el) const;
  std::string where(const MtlxScope& scope, pugi::xml_node el) const;
  // The node (not an input, output or other structural element) named
  // `name` among the children of `graph`, or a null node.
  static pugi::xml_node find_node(pugi::xml_node graph, const std::string& name);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pmc
