// mtlx_reader.h — MaterialX documents into flattened material graphs.
//
// Every `surfacematerial` becomes one Graph named after it (what an OBJ's
// `usemtl` binds to). Its shader may be a node of the document or the output
// of a nodegraph. Nodes of the node table (node_table.h) become graph nodes
// directly; any other node is expanded from its nodegraph implementation —
// the document's own (custom nodes) or the MaterialX library's
// (mtlx_library.h) — with the instance's inputs standing for the graph's
// interface; multi-output nodes (separate3 ...) pick the output an input
// names. Nodegraphs are inlined, `interfacename` inputs take the nodegraph's
// input values, unconnected inputs take their definition's defaults, and
// geometric defaults become explicit texcoord/position/normal nodes.
// Surface shaders (standard_surface, UsdPreviewSurface, open_pbr_surface,
// gltf_pbr, disney_principled, surface_unlit) map onto pmc's BSDF parameters
// (node_table.h: surface_params); inputs that cannot be modelled are named in
// one warning per material. Documents older than 1.39 are upgraded on load
// (mtlx_upgrade.h), and root-level <xi:include>s are expanded
// (mtlx_include.h). A document without materials (test documents with
// top-level outputs) yields one preview material per output: a data output
// is shown as base colour, a surfaceshader output is a material.
// Filenames resolve against `fileprefix`, then the document's folder, then
// MATERIALX_SEARCH_PATH, then the options' search paths.
// The work is split in steps, one file each: mtlx_reader.cpp loads the
// document (MtlxDocument); mtlx_surface_mapper.cpp finds its materials and
// maps their surface shaders, over mtlx_instantiator.h, which turns elements
// into graph nodes (scopes, library expansion, tokens, connections);
// mtlx_looks.cpp reads the looks.
// A material that cannot be built (an unsupported node, a BSDF graph ...)
// keeps its error in Graph::error and fails only when it is used; a document
// none of whose materials can be built throws it. Errors name the file, the
// element and the problem.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "materials/node_graph.h"

namespace pmc {

struct MtlxReadOptions {
  std::string library_dir;                // mtlx_library; "" = find_mtlx_library's default
  std::vector<std::string> search_paths;  // mtlx_search_paths, after MATERIALX_SEARCH_PATH
};
// Where filenames and includes are looked up last: MATERIALX_SEARCH_PATH's
// folders (':' or ';' separated), then the options' search paths.
std::vector<std::string> mtlx_search_paths(const MtlxReadOptions& options);

// One MaterialX document, loaded once: parsed, upgraded to 1.39 syntax
// (mtlx_upgrade.h) and its root-level includes expanded (mtlx_include.h).
// The readers below take it, so a document read for its materials and its
// looks is loaded once. Throws pmc::Error naming the file when it cannot be
// read, is not XML or has no <materialx> root.
class MtlxDocument {
 public:
  static MtlxDocument from_file(const std::string& path, const MtlxReadOptions& options = {});
  static MtlxDocument from_string(const std::string& xml, const std::string& path,
                                  const MtlxReadOptions& options = {});
  const std::string& path() const { return path_; }
  const MtlxReadOptions& options() const { return options_; }
  struct Xml;  // the pugixml document (mtlx_reader.cpp)
  const Xml& xml() const { return *xml_; }

 private:
  // Upgrades and expands the parsed document.
  MtlxDocument(const std::string& path, const MtlxReadOptions& options, std::shared_ptr<Xml> parsed);
  std::string path_;
  MtlxReadOptions options_;
  std::shared_ptr<Xml> xml_;
};

// The document's materials as graphs.
std::vector<Graph> read_mtlx_graphs(const MtlxDocument& doc);
// read_mtlx_graphs of the document at `path`.
std::vector<Graph> read_mtlx_file(const std::string& path, const MtlxReadOptions& options = {});

// One <materialassign> of a <look>: `material` on the geometry paths in
// `geom` (comma-separated, MaterialX geometry names such as "/wall" or
// "/shelf*"), or on its collection's includegeom minus excludegeom.
struct MtlxAssignment {
  std::string material;
  std::string geom;
  std::string exclude;
  std::string origin;  // "file: look 'L' materialassign 'A'"
};
// Every materialassign of every <look> of the document, in
// document order (a later one overrides an earlier one for the same geometry).
std::vector<MtlxAssignment> read_mtlx_assignments(const MtlxDocument& doc);
// Does geometry `path` ("/name") match `pattern` (one geometry name of a geom
// list)? "/" matches everything, `*` any characters within a path component,
// `?` one character, and a pattern that names an ancestor matches its
// descendants.
bool mtlx_geom_matches(const std::string& pattern, const std::string& path);
// Does the assignment cover geometry `path`?
bool mtlx_assignment_covers(const MtlxAssignment& a, const std::string& path);
// Parses `xml` as if read from `path` (tests, fuzzing).
std::vector<Graph> read_mtlx_string(const std::string& xml, const std::string& path,
                                    const MtlxReadOptions& options = {});

}  // namespace pmc
