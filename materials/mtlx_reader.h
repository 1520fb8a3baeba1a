// mtlx_reader.h — MaterialX documents into flattened material graphs.
//
// Every `surfacematerial` becomes one Graph named after it (what an OBJ's
// `usemtl` binds to). Nodegraphs are inlined, `interfacename` inputs take the
// nodegraph's input values, unconnected inputs take the node library's
// defaults, and geometric defaults become explicit texcoord/position/normal
// nodes. A document without materials (test documents with top-level
// outputs) yields one preview material per output, shown as base colour.
// Errors — not XML, an unsupported node, a type mismatch, a dangling
// reference, a cycle — throw pmc::Error naming the file, the node and the
// problem. Inputs pmc does not model are listed in one warning per node.
#pragma once

#include <string>
#include <vector>

#include "materials/node_graph.h"

namespace pmc {

std::vector<Graph> read_mtlx_file(const std::string& path);
// Parses `xml` as if read from `path` (tests, fuzzing).
std::vector<Graph> read_mtlx_string(const std::string& xml, const std::string& path);

}  // namespace pmc
