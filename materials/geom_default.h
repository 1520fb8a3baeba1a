// geom_default.h — the node a geometric default stands for.
//
// An input left unconnected whose definition names a geometric property
// (MaterialX's defaultgeomprop="UV0", "Nworld" ...; node_table.h's InputDef::geom)
// reads it from an explicit node: texcoord, position, normal, tangent,
// bitangent or viewdirection. The MaterialX instantiator and the MTL networks
// add one such node per graph and property.
#pragma once

#include <map>
#include <string>

#include "materials/node_graph.h"
#include "materials/node_table.h"

namespace pmc {

// The node (category, type and inputs) that `g` stands for, its origin `origin`.
Node geom_default_node(GeomDefault g, const std::string& origin);

// The index of `g`'s node in `graph`, added the first time (`added` remembers
// the nodes added so far, by GeomDefault).
int geom_default_in(Graph& graph, std::map<int, int>& added, GeomDefault g, const std::string& origin);

}  // namespace pmc
