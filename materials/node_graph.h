// node_graph.h — the typed node graph every material becomes before compiling.
//
// A Graph is one material, flattened: nodegraphs are inlined, nodes MaterialX
// defines as nodegraphs are expanded, interface inputs resolved, and every
// input is either a constant Value or a link to another node's output.
// Geometric defaults (an unconnected texcoord means UV0, position means
// Pobject ...) are explicit nodes, so the dependency analysis sees them. The
// root is a surface node (one of node_table.h's surface_params categories,
// or the MTL model) whose inputs become surface parameters. Nodes remember
// the file and element they came from for error messages. A node with
// several outputs (flake2d, artistic_ior) becomes one graph node per output a
// consumer selects (MaterialX's output="..." on the connection), each with
// its `output` set. Matrices (matrix33, matrix44) are no shading values: the
// reader folds every matrix node to a constant (mtlx_matrix.h), and the nodes
// that consume one (transformmatrix, determinant, extract) become nodes on
// vectors; a matrix constant left in a graph reaches no output.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace pmc {

enum class ValueType {
  None,
  Float,
  Integer,
  Boolean,
  Vector2,
  Vector3,
  Vector4,
  Color3,
  Color4,
  String,
  Filename,
  Surface,  // surfaceshader
  Material,
  BSDF,  // closures (closure_flatten.h): only between closure nodes
  EDF,
  VDF,
  Matrix33,  // folded by the reader; width 0 (not a shading value)
  Matrix44
};

// Number of float lanes a value of this type occupies (0 for non-numeric types).
int type_width(ValueType t);
const char* type_name(ValueType t);
ValueType parse_type(const std::string& name);  // None if unknown
bool is_numeric(ValueType t);

struct Value {
  ValueType type = ValueType::None;
  std::array<float, 4> f{0, 0, 0, 0};
  std::string text;           // strings and filenames
  std::vector<float> matrix;  // matrix33 / matrix44 entries, row-major (MaterialX's order)
  static Value number(ValueType t, float a, float b = 0, float c = 0, float d = 0);
};

struct Input {
  std::string name;
  ValueType type = ValueType::None;
  bool linked = false;
  int node = -1;  // source node when linked
  Value value;    // the constant when not linked

  static Input constant(const std::string& name, ValueType t, float a, float b = 0, float c = 0, float d = 0);
  static Input link(const std::string& name, ValueType t, int node);
};

struct Node {
  std::string name;                  // element name in the document ("" for nodes pmc made)
  std::string category;              // MaterialX node category, e.g. "multiply"
  ValueType type = ValueType::None;  // of `output` for a multi-output node
  std::string output;  // which output of a multi-output node (flake2d's "rand" ...); "" otherwise
  std::vector<Input> inputs;
  std::string origin;   // "file.mtlx: nodegraph 'NG' node 'n1'" for messages
  bool dead = false;    // removed by a pass
  int cache_point = 0;  // reserved for the material cache

  const Input* input(const std::string& n) const;
  Input* input(const std::string& n);
};

struct Graph {
  std::string material;  // material name (what `usemtl` binds to)
  std::string file;      // document or MTL file it came from
  std::vector<Node> nodes;
  int surface = -1;   // root node
  std::string error;  // why the material could not be built ("" if it was): it fails when used

  int add(Node n) {
    nodes.push_back(std::move(n));
    return int(nodes.size()) - 1;
  }
  size_t live_count() const;
};

}  // namespace pmc
