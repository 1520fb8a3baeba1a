// obj_parser_test.cpp — pmc's own OBJ geometry parser (core/obj_parser.h):
// files that span many parallel chunks against the faces they were written
// from, thread-count independence, numbers, names, polygons and errors.
#include "core/obj_parser.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tiny_obj_loader.h>

#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/obj_loader.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

std::string parse_error(const std::string& text) {
  try {
    parse_obj("test.obj", text);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return {};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A strip of `quads` unit quads along x, written in blocks that mix absolute
// and relative indices, with a material every 7 quads and a group every 11,
// so their state crosses chunk boundaries (the file is several MiB). Each
// quad's expected triangles, material and group are recorded as written.
struct Strip {
  std::string text;
  std::vector<int> v;  // 6 vertex indices per quad (0-based)
  std::vector<std::string> material, group;
};

Strip make_strip(int quads) {
  Strip s;
  std::ostringstream os;
  os << "# a comment line\nmtllib none.mtl\n";
  std::string material = "", group = "";
  int written = 0;  // vertices so far
  for (int q = 0; q < quads; ++q) {
    if (q % 7 == 3) {
      material = "m" + std::to_string(q % 5);
      os << "usemtl " << material << "\n";
    }
    if (q % 11 == 5) {
      group = "g" + std::to_string(q);
      os << "g " << group << " part\n";
    }
    // Four new corners: (q,0) (q+1,0) (q+1,1) (q,1), padded so each line is long.
    for (int c = 0; c < 4; ++c) {
      const int x = q + (c == 1 || c == 2 ? 1 : 0), y = c >= 2 ? 1 : 0;
      os << "v " << x << ".000000000 " << y << ".00000000000 0.000000000000000\n";
    }
    os << "vt 0.5 0.5\nvn 0 0 1\n";
    const int a = written + 1;  // the first new vertex, 1-based
    written += 4;
    if (q % 2 == 0)
      os << "f " << a << "/" << q + 1 << "/" << q + 1 << " " << a + 1 << "/" << q + 1 << "/" << q + 1 << " "
         << a + 2 << "/" << q + 1 << "/" << q + 1 << " " << a + 3 << "/" << q + 1 << "/" << q + 1 << "\n";
    else
      os << "f -4/-1/-1 -3/-1/-1 -2/-1/-1 -1/-1/-1\n";
    // The diagonals are equally long: corners 0-1-3 and 1-2-3.
    const int b = a - 1;
    s.v.insert(s.v.end(), {b, b + 1, b + 3, b + 1, b + 2, b + 3});
    s.material.push_back(material);
    s.group.push_back(group.empty() ? "" : group + " part");
  }
  s.text = os.str();
  return s;
}

void expect_strip(const Strip& s, const ObjGeometry& g) {
  const size_t quads = s.material.size();
  ASSERT_EQ(g.triangles.size(), 2 * quads);
  ASSERT_EQ(g.positions.size(), 12 * quads);
  ASSERT_EQ(g.uvs.size(), 2 * quads);
  ASSERT_EQ(g.normals.size(), 3 * quads);
  for (size_t q = 0; q < quads; ++q) {
    for (int h = 0; h < 2; ++h) {
      const ObjTriangle& t = g.triangles[2 * q + size_t(h)];
      for (int k = 0; k < 3; ++k) {
        ASSERT_EQ(t.v[k], s.v[6 * q + 3 * size_t(h) + size_t(k)]) << "quad " << q;
        ASSERT_EQ(t.t[k], int(q)) << "quad " << q;
        ASSERT_EQ(t.n[k], int(q)) << "quad " << q;
      }
      ASSERT_EQ(t.usemtl < 0 ? std::string() : g.usemtl_names.at(size_t(t.usemtl)), s.material[q]) << q;
      ASSERT_EQ(g.shape_names.at(size_t(t.shape)), s.group[q]) << q;
    }
  }
  EXPECT_EQ(g.usemtl_names, (std::vector<std::string>{"m3", "m0", "m2", "m4", "m1"}));
  ASSERT_EQ(g.mtllibs.size(), 1u);
  EXPECT_EQ(g.mtllibs[0], (std::vector<std::string>{"none.mtl"}));
}

TEST(ObjParser, ManyChunksMatchTheFacesWritten) {
  const Strip s = make_strip(60000);
  ASSERT_GT(s.text.size(), size_t(6) << 20);  // several parallel chunks
  expect_strip(s, parse_obj("strip.obj", s.text));
}

TEST(ObjParser, OneThreadGivesTheSameGeometry) {
  const Strip s = make_strip(30000);
  const ObjGeometry parallel = parse_obj("strip.obj", s.text);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const ObjGeometry serial = parse_obj("strip.obj", s.text);
  expect_strip(s, serial);
  ASSERT_EQ(serial.triangles.size(), parallel.triangles.size());
  for (size_t i = 0; i < serial.triangles.size(); ++i)
    ASSERT_EQ(std::memcmp(&serial.triangles[i], &parallel.triangles[i], sizeof(ObjTriangle)), 0) << i;
  EXPECT_EQ(serial.positions, parallel.positions);
}

TEST(ObjParser, NumbersAsTinyobjReadsThemPlusNonFinite) {
  const ObjGeometry g = parse_obj("n.obj",
                                  "v +1.5 -2e-3 .25\n"  // sign, exponent, leading dot
                                  "v 1.5abc junk\n"     // numeric prefix, then 0
                                  "v 1\n"               // missing components are 0
                                  "v nan inf -INF\n"
                                  "v 1e39 -1e39 1e-50\n"  // past float: +-inf, underflow 0
                                  "vt 0.25\tx\n"
                                  "f 1 2 3\n");
  const std::vector<float>& p = g.positions;
  ASSERT_EQ(p.size(), 15u);
  EXPECT_EQ(p[0], 1.5f);
  EXPECT_EQ(p[1], -2e-3f);
  EXPECT_EQ(p[2], 0.25f);
  EXPECT_EQ(p[3], 1.5f);
  EXPECT_EQ(p[4], 0.0f);
  EXPECT_EQ(p[6], 1.0f);
  EXPECT_EQ(p[7], 0.0f);
  EXPECT_TRUE(std::isnan(p[9]));
  EXPECT_EQ(p[10], INFINITY);
  EXPECT_EQ(p[11], -INFINITY);
  EXPECT_EQ(p[12], INFINITY);
  EXPECT_EQ(p[13], -INFINITY);
  EXPECT_EQ(p[14], 0.0f);
  EXPECT_EQ(g.uvs, (std::vector<float>{0.25f, 0.0f}));
}

TEST(ObjParser, NamesAndLineEnds) {
  // \r\n, a lone \r, tabs; o keeps the rest of its line, g joins its names.
  const ObjGeometry g = parse_obj("names.obj",
                                  "v 0 0 0\r\nv 1 0 0\rv 0 1 0\n"
                                  "o my object\n"
                                  "\tusemtl\tred  trailing words\n"
                                  "f 1 2 3\r\n"
                                  "g  a\t b \n"
                                  "usemtl\n"
                                  "f 1 2 3\n"
                                  "g\n"
                                  "o empty\n"  // no faces: dropped
                                  "o last\n"
                                  "f 3 2 1");  // no line end
  ASSERT_EQ(g.triangles.size(), 3u);
  EXPECT_EQ(g.shape_names, (std::vector<std::string>{"my object", "a b", "last"}));
  EXPECT_EQ(g.usemtl_names, (std::vector<std::string>{"red"}));
  EXPECT_EQ(g.triangles[0].usemtl, 0);
  EXPECT_EQ(g.triangles[1].usemtl, -1);  // a bare usemtl: the default material
  EXPECT_EQ(g.triangles[2].shape, 2);
  EXPECT_EQ(g.triangles[2].v[0], 2);
}

// Twice the signed area of a triangle of `g` projected along axis `axis`
// (the component of its edges' cross product).
double area2(const ObjGeometry& g, const ObjTriangle& t, int axis = 2) {
  auto p = [&](int k, int c) { return double(g.positions[3 * size_t(t.v[k]) + size_t(c)]); };
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  return (p(1, a) - p(0, a)) * (p(2, b) - p(0, b)) - (p(1, b) - p(0, b)) * (p(2, a) - p(0, a));
}

TEST(ObjParser, ConcavePolygonIsEarClipped) {
  // An L (area 3) that corner 0 does not see whole: a fan around it would
  // fold over (its second triangle winds the other way). The triangles
  // must all keep the L's winding and add up to its area.
  const char* corners[6] = {"2 0", "2 1", "1 1", "1 2", "0 2", "0 0"};
  std::string flat, tilted;
  for (const char* c : corners) {
    flat += std::string("v ") + c + " 0\n";
    tilted += std::string("v 0 ") + c + "\n";  // the same L in the x = 0 plane, normal +x
  }
  for (int axis : {2, 0}) {
    const ObjGeometry g = parse_obj("l.obj", (axis == 2 ? flat : tilted) + "f 1 2 3 4 5 6\n");
    ASSERT_EQ(g.triangles.size(), 4u);
    double total = 0;
    for (const ObjTriangle& t : g.triangles) {
      EXPECT_GT(area2(g, t, axis), 0.0) << axis;
      total += area2(g, t, axis);
    }
    EXPECT_DOUBLE_EQ(total, 2 * 3.0) << axis;
  }
}

// A star of `points` points (2 * points corners, concave), as OBJ text with its face.
std::string star(int points, double* area) {
  std::ostringstream os;
  const int n = 2 * points;
  *area = 0;
  std::vector<double> x(static_cast<size_t>(n)), y(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n, r = i % 2 ? 0.5 : 1.0;
    x[size_t(i)] = r * std::cos(a);
    y[size_t(i)] = r * std::sin(a);
    os << "v " << x[size_t(i)] << " " << y[size_t(i)] << " 0\n";
  }
  for (int i = 0; i < n; ++i) {
    const size_t j = size_t((i + 1) % n);
    *area += 0.5 * (x[size_t(i)] * y[j] - x[j] * y[size_t(i)]);
  }
  os << "f";
  for (int i = 1; i <= n; ++i) os << " " << i;
  return os.str() + "\n";
}

TEST(ObjParser, LargePolygons) {
  // A 100-corner circle is convex: a fan around corner 0, found without ear clipping.
  const int n = 100;
  std::ostringstream os;
  double area = 0;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n, b = 2 * M_PI * (i + 1) / n;
    os << "v " << std::cos(a) << " " << std::sin(a) << " 0\n";
    area += 0.5 * std::sin(b - a);
  }
  os << "f";
  for (int i = 1; i <= n; ++i) os << " " << i;
  const ObjGeometry g = parse_obj("circle.obj", os.str() + "\n");
  ASSERT_EQ(g.triangles.size(), size_t(n - 2));
  double total = 0;
  for (size_t i = 0; i < g.triangles.size(); ++i) {
    EXPECT_EQ(g.triangles[i].v[0], 0);
    EXPECT_EQ(g.triangles[i].v[1], int(i) + 1);
    EXPECT_GT(area2(g, g.triangles[i]), 0.0);
    total += area2(g, g.triangles[i]);
  }
  EXPECT_NEAR(total / 2, area, 1e-4);
  EXPECT_EQ(g.approximate_polygons, 0u);
  // A 200-corner star is concave: ear clipping, every triangle inside it.
  double star_area = 0;
  const ObjGeometry s = parse_obj("star.obj", star(100, &star_area));
  ASSERT_EQ(s.triangles.size(), 198u);
  total = 0;
  for (const ObjTriangle& t : s.triangles) {
    EXPECT_GT(area2(s, t), 0.0);
    total += area2(s, t);
  }
  EXPECT_NEAR(total / 2, star_area, 1e-4);
  EXPECT_EQ(s.approximate_polygons, 0u);
  // Past 1024 corners a concave polygon is a fan, and counted.
  EXPECT_EQ(parse_obj("big.obj", star(600, &star_area)).approximate_polygons, 1u);
}

TEST(ObjParser, ErrorsNameTheLine) {
  EXPECT_TRUE(
      contains(parse_error("v 0 0 0\nv 1 0 0\n\nf 1 2\n"), "test.obj: line 4: a face has fewer than 3"));
  EXPECT_TRUE(contains(parse_error("v 0 0 0\nf 0 1 1\n"), "line 2: a face corner '0' has an index of 0"));
  EXPECT_TRUE(contains(parse_error("v 0 0 0\nf 1/ 1 1\n"), "'1/'"));
  EXPECT_TRUE(contains(parse_error("v 0 0 0\nf 1 1 x\n"), "'x'"));
  EXPECT_TRUE(contains(parse_error("v 0 0 0\nf 1 1 2\n"), "line 2: vertex index out of range"));
  EXPECT_TRUE(contains(parse_error("v 0 0 0\nf 1 1 -2\n"), "points before the first vertex"));
  EXPECT_TRUE(contains(parse_error("v 0 0 0\nvn 0 0 1\nf 1//1 1//1 1//2\n"), "normal index out of range"));
  EXPECT_TRUE(contains(parse_error("v 0 0 0\nf 1/1 1/1 1/1\n"), "texture-coordinate index out of range"));
  // Control bytes in a quoted corner are escaped.
  EXPECT_TRUE(contains(parse_error(std::string("v 0 0 0\nf 1 1 \x01\n")), "'\\x01'"));
  // An error far into a many-chunk file still names its line.
  std::string big = make_strip(40000).text;
  size_t lines = 0;
  for (char c : big) lines += c == '\n' ? 1 : 0;
  EXPECT_TRUE(contains(parse_error(big + "f 1 2 999999999\n"), "line " + std::to_string(lines + 1) + ":"));
}

// The loader against tinyobjloader itself (the library pmc used before its
// own parser) on real scenes: the same triangles, corners, materials and
// object/group names, in the same order.
TEST(ObjParser, SameSceneAsTinyobjOnRealScenes) {
  for (const std::string& path :
       {test::source_path("data/default/room.obj"), test::shared_scene("cornell/cornell_box.obj"),
        test::shared_scene("spider/spider.obj")}) {
    SCOPED_TRACE(path);
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = path.substr(0, path.find_last_of('/') + 1);
    tinyobj::ObjReader reader;
    ASSERT_TRUE(reader.ParseFromFile(path, config)) << reader.Error();
    ObjLoadOptions options;
    options.load_textures = false;
    const Scene scene = load_obj(path, options);
    size_t at = 0;
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
      for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f, ++at) {
        ASSERT_LT(at, scene.triangles.size());
        const PmcTriangle& t = scene.triangles[at];
        for (int k = 0; k < 3; ++k) {
          const tinyobj::index_t& ix = shape.mesh.indices[3 * f + size_t(k)];
          ASSERT_EQ(t.v[k], ix.vertex_index) << "triangle " << at;
          if (t.n[k] >= 0) ASSERT_EQ(t.n[k], ix.normal_index) << "triangle " << at;
          if (t.t[k] >= 0) ASSERT_EQ(t.t[k], ix.texcoord_index) << "triangle " << at;
        }
        const int m = shape.mesh.material_ids[f];
        ASSERT_EQ(scene.materials[size_t(t.material)].name,
                  m >= 0 ? reader.GetMaterials()[size_t(m)].name : std::string("(default)"));
        ASSERT_EQ(scene.shape_names[scene.triangle_shapes[at]], shape.name);
      }
    }
    EXPECT_EQ(at, scene.triangles.size());
    ASSERT_EQ(scene.positions.size(), reader.GetAttrib().vertices.size());
    for (size_t i = 0; i < scene.positions.size(); ++i)
      ASSERT_EQ(scene.positions[i], float(reader.GetAttrib().vertices[i])) << i;
  }
}

}  // namespace
}  // namespace pmc
