// node_library.h — the MaterialX nodes pmc understands, and how each compiles.
//
// A NodeDef lists a node category's inputs with their types and defaults
// (taken from the MaterialX 1.39 standard library definitions), the geometric
// default of inputs like `texcoord` (UV0) or `position` (Pobject), and the
// opcode that evaluates it. Type rules: "T" is the node's own output type
// (polymorphic nodes), and an input declared T also accepts a float that is
// broadcast (MaterialX's FA variants). Nodes no document uses cost nothing:
// the library is a table, not code per node.
#pragma once

#include <string>
#include <vector>

#include "core/abi/pmc_bytecode.h"
#include "materials/node_graph.h"

namespace pmc {

enum class GeomDefault { None, UV0, Pobject, Pworld, Nworld, Nobject, Tworld, Tobject, Bworld };

struct InputDef {
  std::string name;
  std::string
      type;     // "T" (the node's type), "float", "vector2", ..., "string", "filename", "integer", "boolean"
  Value value;  // default when not geometric
  GeomDefault geom = GeomDefault::None;
};

struct NodeDef {
  std::string category;
  std::vector<std::string> output_types;  // allowed output types; {"T"} not used
  std::vector<InputDef> inputs;
  int opcode = -1;  // PMC_OP_*, or -1 for nodes the compiler lowers itself
  unsigned imm = 0;
};

// The definition for `category`, or nullptr if pmc does not support it.
const NodeDef* find_node_def(const std::string& category);
// Resolves an input's declared type for a node of output type `node_type`.
ValueType resolve_input_type(const InputDef& def, ValueType node_type);
// Categories pmc supports (for error messages and docs).
std::vector<std::string> supported_categories();

// Surface shader inputs that become surface parameters.
struct SurfaceParam {
  const char* input;
  int param;  // PMC_P_*
  ValueType type;
  float def[3];  // the surface's own default (UsdPreviewSurface differs from standard_surface)
};
// Parameters of a surface category ("standard_surface", "UsdPreviewSurface",
// "pmc_mtl_surface"); empty if the category is not a surface.
std::vector<SurfaceParam> surface_params(const std::string& category);

}  // namespace pmc
