// mtlx_matrix.h — MaterialX matrix33/matrix44 nodes, folded when a document is read.
//
// Design: pmc's shading values are at most 4 floats wide (the bytecode's
// operands, the cache's encodings), and matrices in real documents are
// constants: the colour-space nodes of cmlib (acescg_to_lin_rec709 ...)
// are a `constant` matrix33 feeding `transformmatrix`. So a matrix never
// becomes a shading value. The reader evaluates every matrix-valued node
// (constant, creatematrix, add/subtract (also with a float), multiply, divide,
// transpose, invertmatrix, ifgreater/ifgreatereq/ifequal, dot, and switch
// through its library nodegraph) to a constant as it reads it; the nodes that
// consume a matrix become ordinary nodes: determinant and extract (a row)
// constants, transformmatrix a sum of the matrix's constant rows scaled by the
// vector's components (lower_transformmatrix). A matrix whose value depends on
// the shading point (a creatematrix from a texture) is an error naming the
// node and the input that varies.
//
// Conventions are MaterialX's (its C++ Matrix33/Matrix44 and genglsl agree):
// values are written row-major, vectors are rows (transformmatrix computes
// v * M, with v = (x, y, 1) for vector2 by matrix33 and (x, y, z, 1) for
// vector3 by matrix44), multiply is in1 * in2, divide is in1 * inverse(in2),
// extract picks a row.
#pragma once

#include <array>
#include <map>
#include <string>

#include "materials/node_graph.h"

namespace pmc {

inline bool is_matrix(ValueType t) { return t == ValueType::Matrix33 || t == ValueType::Matrix44; }

// A matrix33/matrix44 value in double precision, row-major.
struct Matrix {
  int n = 3;
  std::array<double, 16> m{};
  double& at(int r, int c) { return m[size_t(r * n + c)]; }
  double at(int r, int c) const { return m[size_t(r * n + c)]; }
  static Matrix identity(int n);
  static Matrix of(const Value& v);  // v.matrix holds n*n entries
  Value value() const;               // a Matrix33/Matrix44 Value
};

Matrix matrix_multiply(const Matrix& a, const Matrix& b);
Matrix matrix_transpose(const Matrix& a);
double matrix_determinant(const Matrix& a);
// Throws pmc::Error naming `context` when `a` is singular.
Matrix matrix_inverse(const Matrix& a, const std::string& context);

// The value of a matrix node of `category` whose inputs (by name, all
// constant) are `in`, with output type `out` (a matrix, or determinant's
// float, or extract's row). Throws pmc::Error naming `context` for a
// category pmc does not fold, an input of the wrong type or a singular
// inverse.
Value fold_matrix_node(const std::string& category, ValueType out, const std::map<std::string, Value>& in,
                       const std::string& context);

// Adds the nodes that compute transformmatrix(in, m) (out: vector2, vector3 or
// vector4, as the node's definition says) to `g` and returns the last one.
int lower_transformmatrix(Graph& g, const Input& in, const Matrix& m, ValueType out,
                          const std::string& origin);

}  // namespace pmc
