// graph_builder.h — material graphs built by hand, as the MaterialX reader builds them.
//
// The compiler, pass and cache-plan tests make small networks node by node:
// add() gives a node every input of its library definition (the default
// unless given), add_surface() a standard_surface with its defaults. Inputs
// are constants (value, text) or links to earlier nodes (link; a link of
// type None takes the declared input type).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "materials/node_graph.h"

namespace pmc::test {

using Given = std::vector<std::pair<std::string, Input>>;

Input value(ValueType t, float a, float b = 0, float c = 0, float d = 0);
Input text(const std::string& s, ValueType t = ValueType::String);
Input link(int node, ValueType t = ValueType::None);
// A graph for material `material` read from `file` (named in node origins).
Graph new_graph(const std::string& material, const std::string& file = "test.mtlx");
// Adds a node the way the MaterialX reader does; returns its index.
int add(Graph& g, const std::string& name, const std::string& category, ValueType type, Given given = {});
// Adds the graph's surface: a standard_surface with its defaults, `given` replacing inputs.
int add_surface(Graph& g, Given given = {});

}  // namespace pmc::test
