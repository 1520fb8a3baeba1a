// passes.h — the graph passes run before compiling, in optimize()'s order.
//
// Lower composite nodes into primitive ones (lowering.h), check types, check
// for cycles (graph_analysis.h), fold constants and the node table's
// identities (x*1, x+0, x*0, mix by 0 or 1, pass-throughs), deduplicate equal
// sub-graphs, remove nodes that reach no output. Each pass reports the live
// node count before and after, which pmc info's bytecode dump prints
// (app/info_command.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "materials/graph_analysis.h"
#include "materials/node_graph.h"

namespace pmc {

struct PassStat {
  std::string pass;
  size_t before = 0, after = 0;
};

size_t fold_constants(Graph& g);  // returns nodes removed
size_t deduplicate(Graph& g);
size_t remove_dead(Graph& g);
std::vector<PassStat> optimize(Graph& g);

}  // namespace pmc
