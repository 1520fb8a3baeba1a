// height_normal.h — heighttonormal and bump as primitive nodes (see the .cpp).
#pragma once

#include "materials/node_graph.h"

namespace pmc {

// The uv step of heighttonormal's finite differences.
constexpr float kHeightStep = 1.0f / 2048.0f;

// Rewrites heighttonormal node `node` in place into subtract / multiply /
// combine3 / normalize nodes over shifted copies of its height sub-graph
// (which must be acyclic and already lowered). Throws pmc::Error for an
// unsupported texcoord input.
void lower_height_to_normal(Graph& g, int node);
// Rewrites bump node `node` in place into normalmap(heighttonormal(height)).
void lower_bump(Graph& g, int node);
// Both are lowering rules of the node table, applied by lowering.cpp.

}  // namespace pmc
