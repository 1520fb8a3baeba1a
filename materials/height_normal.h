// height_normal.h — heighttonormal and bump as primitive nodes (see the .cpp).
#pragma once

#include "materials/node_graph.h"

namespace pmc {

// The uv step of heighttonormal's finite differences.
constexpr float kHeightStep = 1.0f / 2048.0f;

// Rewrites every heighttonormal and bump node of `g` into subtract /
// multiply / combine3 / normalize / normalmap nodes over shifted copies of
// the height sub-graph. Throws pmc::Error on a cycle or an unsupported
// texcoord input.
void lower_height_to_normal(Graph& g);

}  // namespace pmc
