// lowering.h — composite nodes rewritten into primitive ones, before compiling.
//
// The one place where a node becomes other nodes: every node whose table
// entry has a `lower` rule (node_table.h) is rewritten here. invert becomes
// amount - in; tiledimage becomes MaterialX's NG_tiledimage uv math feeding
// an image; bump becomes normalmap(heighttonormal(height), scale ...); and
// heighttonormal becomes finite differences over shifted copies of its height
// sub-graph (height_normal.cpp); time, frame, geomcolor and geompropvalue
// become constants (a still render of an OBJ). How a primitive node becomes instructions is
// the emitter's (emit.h), driven by the same table.
#pragma once

#include "materials/node_graph.h"

namespace pmc {

// Rewrites every composite node of `g` in place. Throws pmc::Error (a cycle
// under a heighttonormal, an unsupported texcoord input ...).
void lower_composites(Graph& g);

}  // namespace pmc
