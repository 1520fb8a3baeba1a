// graph_analysis.h — read-only questions about a material graph.
//
// The order nodes are evaluated in, whether links are well typed and acyclic,
// and which shading-point inputs (uv, position, normal, tangent, bitangent)
// each node's value depends on: a node's own reads come from the node table
// (NodeDef::deps), the rest from its inputs, bottom-up. The cache plan keys
// its choices on these bits, so every node — native, lowered or expanded from
// a MaterialX nodegraph — gets accurate ones.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "materials/node_graph.h"
#include "materials/node_table.h"

namespace pmc {

void check_types(const Graph& g);    // throws pmc::Error on a mismatch
void check_acyclic(const Graph& g);  // throws pmc::Error naming the cycle

// Nodes in dependency order (inputs first), reachable from the surface.
std::vector<int> topological_order(const Graph& g);

// Shading-point dependency bits (kDep*) of every node.
std::vector<uint32_t> dependencies(const Graph& g);
std::string dependency_names(uint32_t bits);

}  // namespace pmc
