// passes.h — graph checks and optimisations run before compiling.
//
// Order (optimize()): lower composite nodes (tiledimage, invert,
// heighttonormal, bump) into primitive ones, check types, check for cycles,
// fold constants and identities (x*1, x+0, x*0, mix by 0 or 1 ...), deduplicate equal
// sub-graphs, remove nodes that reach no output. Each pass reports the live
// node count before and after, which `pmc info --dump-bytecode` prints.
// Dependencies: which shading-point inputs (uv, position, normal, tangent)
// each node's value depends on, computed bottom-up.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "materials/node_graph.h"

namespace pmc {

struct PassStat {
  std::string pass;
  size_t before = 0, after = 0;
};

void lower_composites(Graph& g);
void check_types(const Graph& g);    // throws pmc::Error on a mismatch
void check_acyclic(const Graph& g);  // throws pmc::Error naming the cycle
size_t fold_constants(Graph& g);     // returns nodes removed
size_t deduplicate(Graph& g);
size_t remove_dead(Graph& g);
std::vector<PassStat> optimize(Graph& g);

// Shading-point dependency bits.
enum : uint32_t { kDepUv = 1, kDepPosition = 2, kDepNormal = 4, kDepTangent = 8, kDepBitangent = 16 };
std::vector<uint32_t> dependencies(const Graph& g);
std::string dependency_names(uint32_t bits);

// Nodes in dependency order (inputs first), reachable from the surface.
std::vector<int> topological_order(const Graph& g);

}  // namespace pmc
