// mtlx_matrix_test.cpp — MaterialX matrix nodes (folded when read,
// materials/mtlx_matrix.h) and the colour-space nodes built on them.
//
// Independent answers: the published RGB-to-RGB matrices of ACEScg, Adobe
// RGB (1998) and Display P3 to linear Rec.709 (written here in the usual
// column-vector form, M * rgb, from the colour-science literature, not from
// MaterialX's row-major files); and matrix algebra transcribed here
// separately (products by explicit sums, the inverse by Gauss-Jordan
// elimination, the determinant by LU), applied in MaterialX's row-vector
// convention as its specification and genglsl (mx_matrix_mul(M, v) on a
// column-major mat3) define it.
#include "materials/mtlx_matrix.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <string>

#include "core/device/pmc_interp.h"
#include "core/error.h"
#include "materials/compiler.h"
#include "materials/mtlx_reader.h"
#include "tests/support/material_eval.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

const std::string kPath = "/docs/matrix_doc.mtlx";
using M3 = std::array<std::array<double, 3>, 3>;
using V3 = std::array<double, 3>;

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// The error a document's only material fails with (the reader throws when
// every material of a document fails).
std::string read_error(const std::string& xml) {
  return error_of([&] {
    std::vector<Graph> g = read_mtlx_string(xml, kPath);
    if (!g[0].error.empty()) throw Error(g[0].error);
  });
}

#define EXPECT_MENTIONS(message, part) \
  EXPECT_NE((message).find(part), std::string::npos) << "expected \"" << (part) << "\" in: " << (message)

std::string doc(const std::string& body, const std::string& inputs) {
  return "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n" + body +
         "\n<standard_surface name=\"SR\" type=\"surfaceshader\">" + inputs +
         "</standard_surface>\n<surfacematerial name=\"M\" type=\"material\">"
         "<input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR\"/></surfacematerial>\n"
         "</materialx>\n";
}

// base_color and metalness of the document's material at uv.
struct Result {
  V3 color;
  double metal;
};
Result evaluate(const std::string& xml, float u = 0.5f, float v = 0.5f) {
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  EXPECT_EQ(graphs.size(), 1u);
  EXPECT_EQ(graphs[0].error, "");
  float p[PMC_P_COUNT];
  test::surface_params_at(graphs[0], u, v, p);
  return {{p[PMC_P_BASE_COLOR], p[PMC_P_BASE_COLOR + 1], p[PMC_P_BASE_COLOR + 2]}, p[PMC_P_METALNESS]};
}

std::string m3_value(const M3& m) {  // MaterialX's row-major text
  std::string s;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) s += (s.empty() ? "" : ", ") + std::to_string(m[r][c]);
  return s;
}
std::string constant_m3(const std::string& name, const M3& m) {
  return "<constant name=\"" + name +
         "\" type=\"matrix33\"><input name=\"value\" type=\"matrix33\" value=\"" + m3_value(m) +
         "\"/></constant>";
}

// v * M, MaterialX's transformmatrix for vector3 by matrix33.
V3 row_times(const V3& v, const M3& m) {
  V3 r{};
  for (int c = 0; c < 3; ++c) r[c] = v[0] * m[0][c] + v[1] * m[1][c] + v[2] * m[2][c];
  return r;
}
M3 product(const M3& a, const M3& b) {
  M3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
  return r;
}
M3 gauss_jordan_inverse(M3 a) {
  M3 inv{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (int col = 0; col < 3; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 3; ++r)
      if (std::fabs(a[r][col]) > std::fabs(a[pivot][col])) pivot = r;
    std::swap(a[col], a[pivot]);
    std::swap(inv[col], inv[pivot]);
    const double d = a[col][col];
    for (int c = 0; c < 3; ++c) a[col][c] /= d, inv[col][c] /= d;
    for (int r = 0; r < 3; ++r) {
      if (r == col) continue;
      const double f = a[r][col];
      for (int c = 0; c < 3; ++c) a[r][c] -= f * a[col][c], inv[r][c] -= f * inv[col][c];
    }
  }
  return inv;
}
double lu_determinant(M3 a) {
  double det = 1.0;
  for (int col = 0; col < 3; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 3; ++r)
      if (std::fabs(a[r][col]) > std::fabs(a[pivot][col])) pivot = r;
    if (pivot != col) std::swap(a[col], a[pivot]), det = -det;
    det *= a[col][col];
    for (int r = col + 1; r < 3; ++r) {
      const double f = a[r][col] / a[col][col];
      for (int c = col; c < 3; ++c) a[r][c] -= f * a[col][c];
    }
  }
  return det;
}

void expect_near(const V3& got, const V3& want, double tol, const std::string& what) {
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(got[i], want[i], tol * std::max(1.0, std::fabs(want[i]))) << what << " component " << i;
}

const M3 kA = {{{0.9, -0.2, 0.3}, {0.1, 1.1, -0.4}, {0.25, 0.05, 0.8}}};
const M3 kB = {{{1.2, 0.3, -0.1}, {-0.2, 0.7, 0.5}, {0.4, -0.3, 1.5}}};
const V3 kV = {0.3, 0.6, 0.2};

// A document computing transformmatrix(kV, <matrix node `mat`>) into base_color.
std::string transformed(const std::string& body) {
  return doc(constant_m3("A", kA) + constant_m3("B", kB) + body +
                 "<transformmatrix name=\"t\" type=\"vector3\"><input name=\"in\" type=\"vector3\" value=\"" +
                 std::to_string(kV[0]) + ", " + std::to_string(kV[1]) + ", " + std::to_string(kV[2]) +
                 "\"/><input name=\"mat\" type=\"matrix33\" nodename=\"mat\"/></transformmatrix>"
                 "<convert name=\"c\" type=\"color3\"><input name=\"in\" type=\"vector3\" "
                 "nodename=\"t\"/></convert>",
             "<input name=\"base_color\" type=\"color3\" nodename=\"c\"/>");
}

TEST(MtlxMatrix, ColourSpaceNodesMatchThePublishedMatrices) {
  struct Case {
    const char* node;
    M3 m;  // column-vector form: rec709 = m * rgb
    double tol;
  };
  const Case cases[] = {
      // ACEScg (AP1, D60) to linear Rec.709 (D65), Bradford adaptation (ACES documentation).
      {"acescg_to_lin_rec709",
       {{{1.70505, -0.62179, -0.08326}, {-0.13026, 1.14080, -0.01055}, {-0.02400, -0.12897, 1.15297}}},
       2e-5},
      // Adobe RGB (1998) to sRGB primaries, both D65 (Lindbloom).
      {"lin_adobergb_to_lin_rec709",
       {{{1.3983557, -0.3983557, 0}, {0, 1, 0}, {0, -0.0429290, 1.0429290}}},
       2e-6},
      // Display P3 to sRGB primaries, both D65.
      {"lin_displayp3_to_lin_rec709",
       {{{1.22494, -0.22494, 0}, {-0.04206, 1.04206, 0}, {-0.01964, -0.07864, 1.09828}}},
       2e-5},
  };
  for (const Case& c : cases) {
    // A colour that varies with uv (so the transform runs in the program, not only folded).
    const std::string xml =
        doc("<texcoord name=\"uv\" type=\"vector2\"/>"
            "<separate2 name=\"s\" type=\"multioutput\"><input name=\"in\" type=\"vector2\" "
            "nodename=\"uv\"/></separate2>"
            "<combine3 name=\"rgb\" type=\"color3\"><input name=\"in1\" type=\"float\" nodename=\"s\" "
            "output=\"outx\"/>"
            "<input name=\"in2\" type=\"float\" nodename=\"s\" output=\"outy\"/>"
            "<input name=\"in3\" type=\"float\" value=\"0.35\"/></combine3>"
            "<" +
                std::string(c.node) +
                " name=\"cs\" type=\"color3\"><input name=\"in\" type=\"color3\" nodename=\"rgb\"/></" +
                c.node + ">",
            "<input name=\"base_color\" type=\"color3\" nodename=\"cs\"/>");
    for (auto [u, v] : {std::pair<float, float>{0.2f, 0.7f}, {0.9f, 0.1f}}) {
      const V3 rgb = {u, v, 0.35};
      V3 want{};
      for (int i = 0; i < 3; ++i) want[i] = c.m[i][0] * rgb[0] + c.m[i][1] * rgb[1] + c.m[i][2] * rgb[2];
      expect_near(evaluate(xml, u, v).color, want, c.tol * 10, c.node);
    }
  }
}

TEST(MtlxMatrix, ArithmeticFollowsMaterialXsConventions) {
  auto inv = gauss_jordan_inverse;
  M3 sum{}, diff{}, plus_f{}, minus_f{}, t{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      sum[i][j] = kA[i][j] + kB[i][j];
      diff[i][j] = kA[i][j] - kB[i][j];
      plus_f[i][j] = kA[i][j] + 0.5;
      minus_f[i][j] = kA[i][j] - 0.5;
      t[i][j] = kA[j][i];
    }
  auto bin = [](const std::string& cat, const std::string& in2) {
    return "<" + cat +
           " name=\"mat\" type=\"matrix33\"><input name=\"in1\" type=\"matrix33\" nodename=\"A\"/>" + in2 +
           "</" + cat + ">";
  };
  const std::string B = "<input name=\"in2\" type=\"matrix33\" nodename=\"B\"/>";
  const std::string half = "<input name=\"in2\" type=\"float\" value=\"0.5\"/>";
  struct Case {
    std::string body;
    M3 want;
  };
  const Case cases[] = {
      {bin("multiply", B), product(kA, kB)},
      {bin("divide", B), product(kA, inv(kB))},
      {bin("add", B), sum},
      {bin("subtract", B), diff},
      {bin("add", half), plus_f},
      {bin("subtract", half), minus_f},
      {"<transpose name=\"mat\" type=\"matrix33\"><input name=\"in\" type=\"matrix33\" "
       "nodename=\"A\"/></transpose>",
       t},
      {"<invertmatrix name=\"mat\" type=\"matrix33\"><input name=\"in\" type=\"matrix33\" nodename=\"A\"/>"
       "</invertmatrix>",
       inv(kA)},
      {"<dot name=\"mat\" type=\"matrix33\"><input name=\"in\" type=\"matrix33\" nodename=\"B\"/></dot>", kB},
      // Rows from vectors (the second row a folded data sub-graph).
      {"<constant name=\"r1\" type=\"vector3\"><input name=\"value\" type=\"vector3\" value=\"0.05, 0.55, "
       "-0.2\"/>"
       "</constant><multiply name=\"r1x2\" type=\"vector3\"><input name=\"in1\" type=\"vector3\" "
       "nodename=\"r1\"/>"
       "<input name=\"in2\" type=\"float\" value=\"2\"/></multiply>"
       "<creatematrix name=\"mat\" type=\"matrix33\"><input name=\"in1\" type=\"vector3\" value=\"0.9, -0.2, "
       "0.3\"/>"
       "<input name=\"in2\" type=\"vector3\" nodename=\"r1x2\"/>"
       "<input name=\"in3\" type=\"vector3\" value=\"0.25, 0.05, 0.8\"/></creatematrix>",
       kA},
      // Conditionals pick in1 when the comparison holds; switch (a library nodegraph of ifgreater) its
      // which-th.
      {"<ifgreater name=\"mat\" type=\"matrix33\"><input name=\"value1\" type=\"float\" value=\"2\"/>"
       "<input name=\"value2\" type=\"float\" value=\"1\"/><input name=\"in1\" type=\"matrix33\" "
       "nodename=\"A\"/>"
       "<input name=\"in2\" type=\"matrix33\" nodename=\"B\"/></ifgreater>",
       kA},
      {"<ifgreatereq name=\"mat\" type=\"matrix33\"><input name=\"value1\" type=\"float\" value=\"1\"/>"
       "<input name=\"value2\" type=\"float\" value=\"2\"/><input name=\"in1\" type=\"matrix33\" "
       "nodename=\"A\"/>"
       "<input name=\"in2\" type=\"matrix33\" nodename=\"B\"/></ifgreatereq>",
       kB},
      {"<ifequal name=\"mat\" type=\"matrix33\"><input name=\"value1\" type=\"integer\" value=\"3\"/>"
       "<input name=\"value2\" type=\"integer\" value=\"3\"/><input name=\"in1\" type=\"matrix33\" "
       "nodename=\"A\"/>"
       "<input name=\"in2\" type=\"matrix33\" nodename=\"B\"/></ifequal>",
       kA},
      {"<switch name=\"mat\" type=\"matrix33\"><input name=\"in1\" type=\"matrix33\" nodename=\"A\"/>"
       "<input name=\"in2\" type=\"matrix33\" nodename=\"B\"/><input name=\"which\" type=\"integer\" "
       "value=\"1\"/>"
       "</switch>",
       kB},
  };
  for (const Case& c : cases) {
    expect_near(evaluate(transformed(c.body)).color, row_times(kV, c.want), 1e-5, c.body.substr(0, 40));
  }
}

TEST(MtlxMatrix, DeterminantExtractAndHomogeneousTransforms) {
  // determinant into metalness, a row (extract) into base_color.
  const std::string xml =
      doc(constant_m3("A", kA) +
              "<determinant name=\"d\" type=\"float\"><input name=\"in\" type=\"matrix33\" "
              "nodename=\"A\"/></determinant>"
              "<extract name=\"row\" type=\"vector3\"><input name=\"in\" type=\"matrix33\" "
              "nodename=\"A\"/><input name=\"index\" type=\"integer\" value=\"2\"/></extract>"
              "<convert name=\"c\" type=\"color3\"><input name=\"in\" type=\"vector3\" "
              "nodename=\"row\"/></convert>",
          "<input name=\"base_color\" type=\"color3\" nodename=\"c\"/>"
          "<input name=\"metalness\" type=\"float\" nodename=\"d\"/>");
  const Result r = evaluate(xml);
  EXPECT_NEAR(r.metal, lu_determinant(kA), 1e-6);
  expect_near(r.color, kA[2], 1e-7, "extract row 2");

  // vector2 by matrix33: (u, v, 1) * M; vector3 by matrix44: (x, y, z, 1) * M,
  // whose 4th row is a translation (creatematrix_vector3_matrix44 keeps the 4th column (0, 0, 0, 1)).
  const std::string xml2 = doc(
      constant_m3("A", kA) +
          "<texcoord name=\"uv\" type=\"vector2\"/>"
          "<transformmatrix name=\"t2\" type=\"vector2\"><input name=\"in\" type=\"vector2\" "
          "nodename=\"uv\"/>"
          "<input name=\"mat\" type=\"matrix33\" nodename=\"A\"/></transformmatrix>"
          "<creatematrix name=\"m4\" type=\"matrix44\"><input name=\"in1\" type=\"vector3\" value=\"2, 0, "
          "0\"/>"
          "<input name=\"in2\" type=\"vector3\" value=\"0, 3, 1\"/><input name=\"in3\" type=\"vector3\" "
          "value=\"0, 0, 1\"/>"
          "<input name=\"in4\" type=\"vector3\" value=\"0.1, 0.2, 0.3\"/></creatematrix>"
          "<combine3 name=\"p\" type=\"vector3\"><input name=\"in1\" type=\"float\" value=\"0.25\"/>"
          "<input name=\"in2\" type=\"float\" value=\"0.5\"/><input name=\"in3\" type=\"float\" "
          "value=\"0.75\"/></combine3>"
          "<transformmatrix name=\"t3\" type=\"vector3\"><input name=\"in\" type=\"vector3\" nodename=\"p\"/>"
          "<input name=\"mat\" type=\"matrix44\" nodename=\"m4\"/></transformmatrix>"
          "<extract name=\"t2x\" type=\"float\"><input name=\"in\" type=\"vector2\" nodename=\"t2\"/>"
          "<input name=\"index\" type=\"integer\" value=\"1\"/></extract>"
          "<convert name=\"c\" type=\"color3\"><input name=\"in\" type=\"vector3\" "
          "nodename=\"t3\"/></convert>",
      "<input name=\"base_color\" type=\"color3\" nodename=\"c\"/>"
      "<input name=\"metalness\" type=\"float\" nodename=\"t2x\"/>");
  const float u = 0.3f, v = 0.8f;
  const Result r2 = evaluate(xml2, u, v);
  EXPECT_NEAR(r2.metal, u * kA[0][1] + v * kA[1][1] + kA[2][1], 1e-6);
  expect_near(r2.color, {0.25 * 2 + 0.1, 0.5 * 3 + 0.2, 0.5 + 0.75 + 0.3}, 1e-6, "vector3 by matrix44");
}

TEST(MtlxMatrix, MatrixOutputsPreviewTheirFirstRow) {
  const std::string xml =
      "<?xml version=\"1.0\"?><materialx version=\"1.39\">" + constant_m3("A", kA) + constant_m3("B", kB) +
      "<multiply name=\"ab\" type=\"matrix33\"><input name=\"in1\" type=\"matrix33\" nodename=\"A\"/>"
      "<input name=\"in2\" type=\"matrix33\" nodename=\"B\"/></multiply>"
      "<output name=\"o\" type=\"matrix33\" nodename=\"ab\"/></materialx>";
  std::vector<Graph> graphs = read_mtlx_string(xml, kPath);
  ASSERT_EQ(graphs.size(), 1u);
  ASSERT_EQ(graphs[0].error, "");
  const M3 ab = product(kA, kB);
  bool found = false;
  for (const Node& n : graphs[0].nodes)
    if (n.category == "convert" && !n.inputs[0].linked) {
      found = true;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(n.inputs[0].value.f[size_t(c)], ab[0][c], 1e-6);
    }
  EXPECT_TRUE(found);

  // An output that declares a vector but names a matrix node is a type
  // mismatch (found by fuzz_mtlx: it compiled to a MOVE without operand).
  const std::string mismatch = "<?xml version=\"1.0\"?><materialx version=\"1.39\">" + constant_m3("A", kA) +
                               "<output name=\"o\" type=\"vector2\" nodename=\"A\"/></materialx>";
  const std::string e = read_error(mismatch);
  EXPECT_MENTIONS(e, "output 'o'");
  EXPECT_MENTIONS(e, "node 'A' outputs matrix33");
  EXPECT_MENTIONS(e, "type mismatch");
}

TEST(MtlxMatrix, MatricesThatVaryOrCannotBeBuiltFailNamingTheNode) {
  // A row from the texture coordinates: not a constant.
  const std::string varying = transformed(
      "<texcoord name=\"uv\" type=\"vector2\"/><convert name=\"uv3\" type=\"vector3\">"
      "<input name=\"in\" type=\"vector2\" nodename=\"uv\"/></convert>"
      "<creatematrix name=\"mat\" type=\"matrix33\"><input name=\"in1\" type=\"vector3\" nodename=\"uv3\"/>"
      "</creatematrix>");
  std::string e = read_error(varying);
  EXPECT_MENTIONS(e, kPath);
  EXPECT_MENTIONS(e, "creatematrix 'mat'");
  EXPECT_MENTIONS(e, "input 'in1'");
  EXPECT_MENTIONS(e, "varies over the surface");

  const std::string singular = transformed(constant_m3("Z", M3{{{1, 2, 3}, {2, 4, 6}, {0, 0, 1}}}) +
                                           "<invertmatrix name=\"mat\" type=\"matrix33\"><input name=\"in\" "
                                           "type=\"matrix33\" nodename=\"Z\"/></invertmatrix>");
  e = read_error(singular);
  EXPECT_MENTIONS(e, "invertmatrix 'mat'");
  EXPECT_MENTIONS(e, "singular");

  const std::string short_value = transformed(
      "<constant name=\"mat\" type=\"matrix33\"><input name=\"value\" type=\"matrix33\" value=\"1, 0, 0, 0, "
      "1, 0, 0, "
      "0\"/></constant>");
  e = read_error(short_value);
  EXPECT_MENTIONS(e, "constant 'mat'");
  EXPECT_MENTIONS(e, "9 numbers expected, 8 given");

  const std::string bad_index =
      doc(constant_m3("A", kA) +
              "<extract name=\"row\" type=\"vector3\"><input name=\"in\" type=\"matrix33\" "
              "nodename=\"A\"/><input name=\"index\" type=\"integer\" value=\"3\"/></extract>"
              "<convert name=\"c\" type=\"color3\"><input name=\"in\" type=\"vector3\" "
              "nodename=\"row\"/></convert>",
          "<input name=\"base_color\" type=\"color3\" nodename=\"c\"/>");
  e = read_error(bad_index);
  EXPECT_MENTIONS(e, "extract 'row'");
  EXPECT_MENTIONS(e, "out of range");
}

TEST(MtlxMatrix, SharedDataSubGraphsFoldOnce) {
  // 40 levels of x_k = x_{k-1} + x_{k-1}, each level's two inputs the same node:
  // folded without memory, the creatematrix's row would take 2^40 evaluations.
  std::string body =
      "<constant name=\"x0\" type=\"float\"><input name=\"value\" type=\"float\" "
      "value=\"1e-12\"/></constant>";
  for (int k = 1; k <= 40; ++k) {
    const std::string prev = "x" + std::to_string(k - 1);
    body += "<add name=\"x" + std::to_string(k) +
            "\" type=\"float\"><input name=\"in1\" type=\"float\" nodename=\"" + prev +
            "\"/><input name=\"in2\" type=\"float\" nodename=\"" + prev + "\"/></add>";
  }
  body +=
      "<combine3 name=\"row\" type=\"vector3\"><input name=\"in1\" type=\"float\" "
      "nodename=\"x40\"/></combine3>"
      "<creatematrix name=\"mat\" type=\"matrix33\"><input name=\"in1\" type=\"vector3\" "
      "nodename=\"row\"/></creatematrix>";
  // v * M with row 0 = (2^40 * 1e-12, 0, 0), rows 1 and 2 the identity's.
  const double x = std::ldexp(1e-12, 40);
  expect_near(evaluate(transformed(body)).color, {kV[0] * x, kV[1], kV[2]}, 1e-5, "shared sub-graph");
}

TEST(MtlxMatrix, FourByFourAlgebraAgreesWithItsDefinitions) {
  // The folding arithmetic itself on a 4x4: A * inverse(A) = I, det(A^T) = det(A),
  // det(A B) = det(A) det(B).
  Matrix a, b;
  a.n = b.n = 4;
  const double va[16] = {2, 0.5, -1, 0.3, 0.1, 1.5, 0.2, -0.7, 0.4, -0.3, 1.2, 0.9, 0.0, 0.6, -0.2, 1.1};
  const double vb[16] = {1, 0.2, 0.3, 0, -0.5, 2, 0.1, 0.4, 0.3, 0.3, 0.9, -0.2, 0.7, -0.1, 0.5, 1.3};
  for (int i = 0; i < 16; ++i) a.m[size_t(i)] = va[i], b.m[size_t(i)] = vb[i];
  Matrix id = matrix_multiply(a, matrix_inverse(a, "test"));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(id.at(i, j), i == j ? 1.0 : 0.0, 1e-12);
  EXPECT_NEAR(matrix_determinant(matrix_transpose(a)), matrix_determinant(a), 1e-12);
  EXPECT_NEAR(matrix_determinant(matrix_multiply(a, b)), matrix_determinant(a) * matrix_determinant(b),
              1e-12);
  // A permutation's determinant is its sign.
  Matrix p;
  p.n = 4;
  p.at(0, 1) = p.at(1, 0) = p.at(2, 2) = p.at(3, 3) = 1;
  EXPECT_EQ(matrix_determinant(p), -1.0);
}

}  // namespace
}  // namespace pmc
