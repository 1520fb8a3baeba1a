// mtlx_matrix.cpp — matrix arithmetic for folding MaterialX matrix nodes, and
// transformmatrix as nodes on vectors (mtlx_matrix.h says why).
#include "materials/mtlx_matrix.h"

#include <cmath>

#include "core/error.h"

namespace pmc {

Matrix Matrix::identity(int n) {
  Matrix r;
  r.n = n;
  for (int i = 0; i < n; ++i) r.at(i, i) = 1.0;
  return r;
}

Matrix Matrix::of(const Value& v) {
  Matrix r;
  r.n = v.type == ValueType::Matrix44 ? 4 : 3;
  PMC_CHECK(v.matrix.size() == size_t(r.n * r.n), "matrix value size");
  for (size_t i = 0; i < v.matrix.size(); ++i) r.m[i] = double(v.matrix[i]);
  return r;
}

Value Matrix::value() const {
  Value v;
  v.type = n == 4 ? ValueType::Matrix44 : ValueType::Matrix33;
  for (int i = 0; i < n * n; ++i) v.matrix.push_back(float(m[size_t(i)]));
  return v;
}

Matrix matrix_multiply(const Matrix& a, const Matrix& b) {
  Matrix r;
  r.n = a.n;
  for (int i = 0; i < a.n; ++i)
    for (int j = 0; j < a.n; ++j) {
      double s = 0.0;
      for (int k = 0; k < a.n; ++k) s += a.at(i, k) * b.at(k, j);
      r.at(i, j) = s;
    }
  return r;
}

Matrix matrix_transpose(const Matrix& a) {
  Matrix r;
  r.n = a.n;
  for (int i = 0; i < a.n; ++i)
    for (int j = 0; j < a.n; ++j) r.at(i, j) = a.at(j, i);
  return r;
}

namespace {

// The minor of `a` without row `row` and column `col`.
Matrix minor_of(const Matrix& a, int row, int col) {
  Matrix r;
  r.n = a.n - 1;
  for (int i = 0, ri = 0; i < a.n; ++i) {
    if (i == row) continue;
    for (int j = 0, rj = 0; j < a.n; ++j) {
      if (j == col) continue;
      r.m[size_t(ri * r.n + rj)] = a.at(i, j);
      ++rj;
    }
    ++ri;
  }
  return r;
}

double cofactor(const Matrix& a, int row, int col) {
  return ((row + col) % 2 ? -1.0 : 1.0) * matrix_determinant(minor_of(a, row, col));
}

}  // namespace

double matrix_determinant(const Matrix& a) {  // cofactor expansion along the first row
  if (a.n == 1) return a.m[0];
  if (a.n == 2) return a.m[0] * a.m[3] - a.m[1] * a.m[2];
  double d = 0.0;
  for (int j = 0; j < a.n; ++j) d += a.at(0, j) * cofactor(a, 0, j);
  return d;
}

Matrix matrix_inverse(const Matrix& a, const std::string& context) {  // adjugate / determinant
  const double det = matrix_determinant(a);
  if (det == 0.0 || !std::isfinite(det))
    fail(context, ": the matrix is singular (determinant ", det, "), so it has no inverse");
  Matrix r;
  r.n = a.n;
  for (int i = 0; i < a.n; ++i)
    for (int j = 0; j < a.n; ++j) r.at(i, j) = cofactor(a, j, i) / det;
  return r;
}

namespace {

const Value& get(const std::map<std::string, Value>& in, const char* name, const std::string& context) {
  auto it = in.find(name);
  if (it == in.end()) fail(context, ": matrix node has no input '", name, "'");
  return it->second;
}

Matrix matrix_input(const std::map<std::string, Value>& in, const char* name, const std::string& context) {
  const Value& v = get(in, name, context);
  if (!is_matrix(v.type))
    fail(context, " input '", name, "': expects a matrix, the document gives ", type_name(v.type),
         " (type mismatch)");
  return Matrix::of(v);
}

// add/subtract: a matrix or a float (the "FA" definitions) as in2.
Matrix elementwise(const Matrix& a, const Value& b, double sign, const std::string& context) {
  Matrix r = a;
  if (is_matrix(b.type)) {
    Matrix mb = Matrix::of(b);
    if (mb.n != a.n) fail(context, ": matrix33 and matrix44 operands (type mismatch)");
    for (int i = 0; i < a.n * a.n; ++i) r.m[size_t(i)] += sign * mb.m[size_t(i)];
  } else {
    for (int i = 0; i < a.n * a.n; ++i) r.m[size_t(i)] += sign * double(b.f[0]);
  }
  return r;
}

}  // namespace

Value fold_matrix_node(const std::string& category, ValueType out, const std::map<std::string, Value>& in,
                       const std::string& context) {
  const int n = out == ValueType::Matrix44 ? 4 : 3;
  if (category == "constant" || category == "dot") {
    const char* name = category == "constant" ? "value" : "in";
    return matrix_input(in, name, context).value();
  }
  if (category == "creatematrix") {
    Matrix r = Matrix::identity(n);  // creatematrix_vector3_matrix44 keeps (0, 0, 0, 1) as its 4th column
    for (int row = 0; row < n; ++row) {
      const Value& v = get(in, ("in" + std::to_string(row + 1)).c_str(), context);
      const int w = std::min(type_width(v.type), n);
      for (int c = 0; c < w; ++c) r.at(row, c) = double(v.f[size_t(c)]);
    }
    return r.value();
  }
  if (category == "add" || category == "subtract")
    return elementwise(matrix_input(in, "in1", context), get(in, "in2", context),
                       category == "add" ? 1.0 : -1.0, context)
        .value();
  if (category == "multiply" || category == "divide") {
    Matrix a = matrix_input(in, "in1", context), b = matrix_input(in, "in2", context);
    if (a.n != b.n) fail(context, ": matrix33 and matrix44 operands (type mismatch)");
    return matrix_multiply(a, category == "divide" ? matrix_inverse(b, context + " input 'in2'") : b).value();
  }
  if (category == "transpose") return matrix_transpose(matrix_input(in, "in", context)).value();
  if (category == "invertmatrix") return matrix_inverse(matrix_input(in, "in", context), context).value();
  if (category == "determinant")
    return Value::number(ValueType::Float, float(matrix_determinant(matrix_input(in, "in", context))));
  if (category == "extract") {
    Matrix a = matrix_input(in, "in", context);
    const float fi = get(in, "index", context).f[0];
    if (!(fi >= 0.0f && fi < float(a.n)))
      fail(context, ": extract index ", fi, " is out of range for a matrix with ", a.n, " rows");
    const int row = int(fi);
    Value v = Value::number(a.n == 4 ? ValueType::Vector4 : ValueType::Vector3, 0);
    for (int c = 0; c < a.n; ++c) v.f[size_t(c)] = float(a.at(row, c));
    return v;
  }
  if (category == "ifgreater" || category == "ifgreatereq" || category == "ifequal") {
    const float v1 = get(in, "value1", context).f[0], v2 = get(in, "value2", context).f[0];
    const bool pick1 = category == "ifgreater" ? v1 > v2 : category == "ifgreatereq" ? v1 >= v2 : v1 == v2;
    return matrix_input(in, pick1 ? "in1" : "in2", context).value();
  }
  fail(context, ": node '", category,
       "' on matrices is not supported (pmc folds constant, creatematrix, add, subtract, multiply, "
       "divide, transpose, determinant, invertmatrix, extract, dot, switch, ifgreater, ifgreatereq, "
       "ifequal and transformmatrix)");
}

int lower_transformmatrix(Graph& g, const Input& in, const Matrix& m, ValueType out,
                          const std::string& origin) {
  const int w = type_width(out);  // 2, 3 or 4 components of the result
  const int k = type_width(in.type);
  if (w < 2 || k != w || m.n < w || m.n > w + 1 || (m.n == w + 1 && w == 4))
    fail(origin, ": transformmatrix of a ", type_name(in.type), " by a matrix", m.n, m.n, " to ",
         type_name(out), " is not a MaterialX definition (type mismatch)");
  auto row = [&](int r) {
    Value v = Value::number(out, 0);
    for (int c = 0; c < w; ++c) v.f[size_t(c)] = float(m.at(r, c));
    return v;
  };
  auto add_node = [&](const std::string& category, ValueType t, std::vector<Input> inputs) {
    Node node;
    node.category = category;
    node.type = t;
    node.origin = origin + " (" + category + ")";
    node.inputs = std::move(inputs);
    return g.add(std::move(node));
  };
  int sum = -1;
  for (int r = 0; r < k; ++r) {  // v * M = sum over r of v[r] * row r
    Input src = in;
    src.name = "in";
    int comp =
        add_node("extract", ValueType::Float, {src, Input::constant("index", ValueType::Integer, float(r))});
    Input rv;
    rv.name = "in1";
    rv.type = out;
    rv.value = row(r);
    int term = add_node("multiply", out, {rv, Input::link("in2", ValueType::Float, comp)});
    sum =
        sum < 0 ? term : add_node("add", out, {Input::link("in1", out, sum), Input::link("in2", out, term)});
  }
  if (m.n == w + 1) {  // the homogeneous 1: the last row is a translation
    Input t;
    t.name = "in2";
    t.type = out;
    t.value = row(m.n - 1);
    sum = add_node("add", out, {Input::link("in1", out, sum), t});
  }
  return sum;
}

}  // namespace pmc
