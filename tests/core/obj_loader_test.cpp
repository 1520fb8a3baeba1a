// obj_loader_test.cpp — load_obj on tiny hand-written OBJ/MTL files and on the
// shared third-party scenes (cornell, spider).
//
// Each test writes its files into its own temp_dir() and checks exact results:
// material order and values, normal/uv indices, triangulation, relative
// indices, the default material, the errors (which must name the file), NaN
// positions, and texture loading (Windows paths, only used textures, mips).
#include "core/obj_loader.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

using test::temp_dir;
using test::write_file;

// The message of the pmc::Error that `f` throws, or "" (and a failure) if none.
template <typename F>
std::string error_message(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw something other than pmc::Error: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected a pmc::Error";
  return {};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Writes an 8-bit image through OpenImageIO (format from the extension).
void write_image(const std::string& path, int w, int h, int channels, const std::vector<uint8_t>& pixels) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(w, h, channels, OIIO::TypeDesc::UINT8);
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

std::vector<int> vertex_indices(const Scene& scene) {
  std::vector<int> out;
  for (const PmcTriangle& t : scene.triangles) out.insert(out.end(), {t.v[0], t.v[1], t.v[2]});
  return out;
}

std::vector<std::string> material_names(const Scene& scene) {
  std::vector<std::string> out;
  for (const PmcTriangle& t : scene.triangles) out.push_back(scene.materials.at(size_t(t.material)).name);
  return out;
}

// Twice the signed area, in the XY plane, of one triangle.
double signed_area2_xy(const Scene& s, const PmcTriangle& t) {
  const float* a = &s.positions[3 * size_t(t.v[0])];
  const float* b = &s.positions[3 * size_t(t.v[1])];
  const float* c = &s.positions[3 * size_t(t.v[2])];
  return double(b[0] - a[0]) * (c[1] - a[1]) - double(b[1] - a[1]) * (c[0] - a[0]);
}

const char* kTriangle =
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 0 1 0\n";

TEST(ObjLoader, ReadsMaterialsAndSwitchesMidMesh) {
  std::string dir = temp_dir();
  write_file(dir + "/m.mtl",
             "newmtl red\n"
             "Kd 0.8 0.1 0.2\n"
             "Ks 0.3 0.4 0.5\n"
             "Ns 250\n"
             "\n"
             "newmtl lamp\n"
             "Kd 0 0 0\n"
             "Ke 4 5 6.5\n"
             "\n"
             "newmtl blue\n"
             "Kd 0.1 0.2 0.9\n"
             "Ns 10\n");
  // One object, one group: the material changes between faces of the same mesh.
  write_file(dir + "/m.obj",
             "mtllib m.mtl\n"
             "o thing\n" +
                 std::string(kTriangle) +
                 "usemtl blue\n"
                 "f 1 2 3\n"
                 "usemtl red\n"
                 "f 1 2 3\n"
                 "f 3 2 1\n"
                 "usemtl lamp\n"
                 "f 1 2 3\n"
                 "usemtl blue\n"
                 "f 2 3 1\n");
  Scene s = load_obj(dir + "/m.obj");
  ASSERT_EQ(s.materials.size(), 4u);  // the MTL's three, in MTL order, then the default
  EXPECT_EQ(s.materials[0].name, "red");
  EXPECT_EQ(s.materials[1].name, "lamp");
  EXPECT_EQ(s.materials[2].name, "blue");
  EXPECT_EQ(s.materials[3].name, "(default)");
  ASSERT_EQ(s.triangles.size(), 5u);
  EXPECT_EQ(material_names(s), (std::vector<std::string>{"blue", "red", "red", "lamp", "blue"}));
  std::vector<int> ids;
  for (const PmcTriangle& t : s.triangles) ids.push_back(t.material);
  EXPECT_EQ(ids, (std::vector<int>{2, 0, 0, 1, 2}));
  // Faces keep their own corner order through the material switches.
  EXPECT_EQ(vertex_indices(s), (std::vector<int>{0, 1, 2, 0, 1, 2, 2, 1, 0, 0, 1, 2, 1, 2, 0}));

  const MtlMaterial& red = s.materials[0];
  EXPECT_FLOAT_EQ(red.kd[0], 0.8f);
  EXPECT_FLOAT_EQ(red.kd[1], 0.1f);
  EXPECT_FLOAT_EQ(red.kd[2], 0.2f);
  EXPECT_FLOAT_EQ(red.ks[0], 0.3f);
  EXPECT_FLOAT_EQ(red.ks[1], 0.4f);
  EXPECT_FLOAT_EQ(red.ks[2], 0.5f);
  EXPECT_FLOAT_EQ(red.ns, 250.0f);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(red.ke[i], 0.0f);
  const MtlMaterial& lamp = s.materials[1];
  EXPECT_FLOAT_EQ(lamp.ke[0], 4.0f);
  EXPECT_FLOAT_EQ(lamp.ke[1], 5.0f);
  EXPECT_FLOAT_EQ(lamp.ke[2], 6.5f);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(lamp.kd[i], 0.0f);
  const MtlMaterial& blue = s.materials[2];
  EXPECT_FLOAT_EQ(blue.kd[2], 0.9f);
  EXPECT_FLOAT_EQ(blue.ns, 10.0f);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(blue.ks[i], 0.0f);  // no Ks line
  for (const MtlMaterial& m : s.materials) {
    EXPECT_TRUE(m.map_kd.empty());
    EXPECT_EQ(m.kd_texture, -1);
  }
  EXPECT_EQ(s.textures.size(), 0u);
  EXPECT_EQ(s.skipped_triangles, 0u);
}

// The statements docs/MTL.md maps (Ni, Tf, illum, the PBR extension, their
// maps and the bump options), as tinyobjloader reads them.
TEST(ObjLoader, ReadsTheMtlStatementsTheMappingNeeds) {
  std::string dir = temp_dir();
  write_file(dir + "/m.mtl",
             "newmtl a\nNi 1.45\nTf 0.1 0.2 0.3\nillum 7\nPr 0.3\nPm 0.4\nPs 0.5\nPc 0.6\nPcr 0.7\n"
             "aniso 0.8\nanisor 0.9\nmap_Pr r.png\nmap_Pm m.png\nmap_Ps s.png\nmap_Ke e.png\nmap_Ks k.png\n"
             "bump -bm 0.25 h.png\nnorm -bm 2 n.png\n"
             "newmtl b\nKd 1 1 1\n");
  write_file(dir + "/m.obj",
             "mtllib m.mtl\n" + std::string(kTriangle) + "usemtl a\nf 1 2 3\nusemtl b\nf 3 2 1\n");
  Scene s = load_obj(dir + "/m.obj");
  const MtlMaterial& a = s.materials[0];
  EXPECT_FLOAT_EQ(a.ni, 1.45f);
  EXPECT_FLOAT_EQ(a.tf[0], 0.1f);
  EXPECT_FLOAT_EQ(a.tf[2], 0.3f);
  EXPECT_EQ(a.illum, 7);
  EXPECT_FLOAT_EQ(a.pr, 0.3f);
  EXPECT_FLOAT_EQ(a.pm, 0.4f);
  EXPECT_FLOAT_EQ(a.ps, 0.5f);
  EXPECT_FLOAT_EQ(a.pc, 0.6f);
  EXPECT_FLOAT_EQ(a.pcr, 0.7f);
  EXPECT_FLOAT_EQ(a.aniso, 0.8f);
  EXPECT_FLOAT_EQ(a.anisor, 0.9f);
  EXPECT_EQ(a.map_pr, dir + "/r.png");
  EXPECT_EQ(a.map_pm, dir + "/m.png");
  EXPECT_EQ(a.map_ps, dir + "/s.png");
  EXPECT_EQ(a.map_ke, dir + "/e.png");
  EXPECT_EQ(a.map_ks, dir + "/k.png");
  EXPECT_EQ(a.map_bump, dir + "/h.png");
  EXPECT_EQ(a.map_norm, dir + "/n.png");
  EXPECT_FLOAT_EQ(a.bump_multiplier, 0.25f);
  EXPECT_FLOAT_EQ(a.norm_multiplier, 2.0f);
  EXPECT_TRUE(a.not_modelled.empty());
  // tinyobjloader's defaults where the statements are absent.
  const MtlMaterial& b = s.materials[1];
  EXPECT_FLOAT_EQ(b.ni, 1.0f);
  EXPECT_EQ(b.illum, 0);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(b.tf[i], 0.0f);
  EXPECT_EQ(b.pr, 0.0f);
  EXPECT_FLOAT_EQ(b.bump_multiplier, 1.0f);
  for (std::string* map : const_cast<MtlMaterial&>(b).maps()) EXPECT_TRUE(map->empty());
}

TEST(ObjLoader, MissingNormalsAreMinusOne) {
  std::string dir = temp_dir();
  write_file(dir + "/a.obj", std::string(kTriangle) + "f 1 2 3\nf 3 2 1\n");
  Scene s = load_obj(dir + "/a.obj");
  ASSERT_EQ(s.triangles.size(), 2u);
  EXPECT_TRUE(s.normals.empty());
  EXPECT_TRUE(s.uvs.empty());
  for (const PmcTriangle& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(t.n[k], -1);
      EXPECT_EQ(t.t[k], -1);
    }
  EXPECT_EQ(s.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}));
}

TEST(ObjLoader, NormalsIndexIntoNormals) {
  std::string dir = temp_dir();
  write_file(dir + "/a.obj", std::string(kTriangle) +
                                 "vn 0 0 1\n"
                                 "vn 0 1 0\n"
                                 "vn 1 0 0\n"
                                 "f 1//2 2//1 3//3\n"
                                 "f 1//3 2//3 3//3\n"
                                 "f 1 2 3\n"
                                 "f 1//1 2 3//1\n");  // a corner without a normal: none for the triangle
  Scene s = load_obj(dir + "/a.obj");
  ASSERT_EQ(s.triangles.size(), 4u);
  EXPECT_EQ(s.normals, (std::vector<float>{0, 0, 1, 0, 1, 0, 1, 0, 0}));
  const PmcTriangle* t = s.triangles.data();
  EXPECT_EQ(t[0].n[0], 1);
  EXPECT_EQ(t[0].n[1], 0);
  EXPECT_EQ(t[0].n[2], 2);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(t[1].n[k], 2);
    EXPECT_EQ(t[2].n[k], -1);
    EXPECT_EQ(t[3].n[k], -1);
    EXPECT_EQ(t[0].t[k], -1);
  }
}

TEST(ObjLoader, TriangulatesQuads) {
  std::string dir = temp_dir();
  // the parser splits (tinyobjloader's rule) a quad along its shorter diagonal: 0-2 here ...
  // ... and 1-3 in the second quad.
  write_file(dir + "/q.obj",
             "v 0 0 0\n"
             "v 3 0 0\n"
             "v 2 1 0\n"
             "v 0 1 0\n"
             "v 0 0 1\n"
             "v 1 0 1\n"
             "v 3 1 1\n"
             "v 0 1 1\n"
             "f 1 2 3 4\n"
             "f 5 6 7 8\n");
  Scene s = load_obj(dir + "/q.obj");
  ASSERT_EQ(s.triangles.size(), 4u);                                // 2 quads -> 4 triangles
  EXPECT_EQ(vertex_indices(s), (std::vector<int>{0, 1, 2, 0, 2, 3,  //
                                                 4, 5, 7, 5, 6, 7}));
  // Both halves keep the quad's counter-clockwise winding and cover its area.
  EXPECT_DOUBLE_EQ(signed_area2_xy(s, s.triangles[0]) + signed_area2_xy(s, s.triangles[1]), 2 * 2.5);
  EXPECT_DOUBLE_EQ(signed_area2_xy(s, s.triangles[2]) + signed_area2_xy(s, s.triangles[3]), 2 * 2.0);
  for (const PmcTriangle& t : s.triangles) EXPECT_GT(signed_area2_xy(s, t), 0.0);
  EXPECT_EQ(s.skipped_triangles, 0u);
}

TEST(ObjLoader, TriangulatesPentagon) {
  std::string dir = temp_dir();
  write_file(dir + "/p.obj",
             "v 0 0 0\n"
             "v 2 0 0\n"
             "v 3 1.5 0\n"
             "v 1 3 0\n"
             "v -1 1.5 0\n"
             "f 1 2 3 4 5\n");
  Scene s = load_obj(dir + "/p.obj");
  ASSERT_EQ(s.triangles.size(), 3u);  // 5 corners -> 3 triangles
  // ear clipping on a convex polygon: a fan around corner 0.
  EXPECT_EQ(vertex_indices(s), (std::vector<int>{0, 1, 2, 0, 2, 3, 0, 3, 4}));
  double area2 = 0;
  for (const PmcTriangle& t : s.triangles) {
    EXPECT_GT(signed_area2_xy(s, t), 0.0);
    area2 += signed_area2_xy(s, t);
  }
  EXPECT_DOUBLE_EQ(area2, 2 * 7.5);  // shoelace area of the pentagon
}

TEST(ObjLoader, UvsPresentAndAbsent) {
  std::string dir = temp_dir();
  write_file(dir + "/uv.obj", std::string(kTriangle) +
                                  "vt 0 0\n"
                                  "vt 1 0\n"
                                  "vt 0 1\n"
                                  "vt 0.5 0.25\n"
                                  "vn 0 0 1\n"
                                  "f 1/1 2/2 3/3\n"
                                  "f 1/4/1 2/2/1 3/1/1\n"
                                  "f 1 2 3\n");
  Scene s = load_obj(dir + "/uv.obj");
  ASSERT_EQ(s.triangles.size(), 3u);
  EXPECT_EQ(s.uvs, (std::vector<float>{0, 0, 1, 0, 0, 1, 0.5f, 0.25f}));
  const PmcTriangle* t = s.triangles.data();
  EXPECT_EQ(t[0].t[0], 0);
  EXPECT_EQ(t[0].t[1], 1);
  EXPECT_EQ(t[0].t[2], 2);
  EXPECT_EQ(t[1].t[0], 3);
  EXPECT_EQ(t[1].t[1], 1);
  EXPECT_EQ(t[1].t[2], 0);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(t[0].n[k], -1);
    EXPECT_EQ(t[1].n[k], 0);
    EXPECT_EQ(t[2].t[k], -1);
    EXPECT_EQ(t[2].n[k], -1);
  }
}

TEST(ObjLoader, NegativeIndicesAreRelative) {
  std::string dir = temp_dir();
  // As in the Cornell box: each face refers to the vertices just written.
  write_file(dir + "/neg.obj",
             "v 0 0 0\n"
             "v 1 0 0\n"
             "v 1 1 0\n"
             "v 0 1 0\n"
             "f -4 -3 -2 -1\n"
             "v 0 0 5\n"
             "v 1 0 5\n"
             "v 0 1 5\n"
             "vt 0 0\n"
             "vt 1 0\n"
             "vt 0 1\n"
             "vn 0 0 1\n"
             "f -3/-3/-1 -2/-2/-1 -1/-1/-1\n");
  Scene s = load_obj(dir + "/neg.obj");
  ASSERT_EQ(s.triangles.size(), 3u);
  // The square's diagonals are equally long: the parser then splits along 1-3.
  EXPECT_EQ(vertex_indices(s), (std::vector<int>{0, 1, 3, 1, 2, 3, 4, 5, 6}));
  const PmcTriangle& t = s.triangles[2];
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(t.t[k], k);
    EXPECT_EQ(t.n[k], 0);
  }
  EXPECT_EQ(s.bounds.lo[2], 0.0f);
  EXPECT_EQ(s.bounds.hi[2], 5.0f);
}

TEST(ObjLoader, MissingMtlThrowsNamingObj) {
  std::string dir = temp_dir();
  std::string obj = dir + "/a.obj";
  write_file(obj, "mtllib nothere.mtl\n" + std::string(kTriangle) + "usemtl x\nf 1 2 3\n");
  EXPECT_THROW(load_obj(obj), Error);
  std::string msg = error_message([&] { load_obj(obj); });
  EXPECT_TRUE(contains(msg, obj)) << msg;
  EXPECT_TRUE(contains(msg, "nothere.mtl")) << msg;
}

TEST(ObjLoader, NoMtllibUsesDefaultMaterial) {
  std::string dir = temp_dir();
  write_file(dir + "/a.obj", std::string(kTriangle) + "f 1 2 3\nf 1 3 2\n");
  Scene s = load_obj(dir + "/a.obj");
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials.back().name, "(default)");
  ASSERT_EQ(s.triangles.size(), 2u);
  for (const PmcTriangle& t : s.triangles) EXPECT_EQ(t.material, 0);
  const MtlMaterial& d = s.materials[0];
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(d.kd[i], 0.5f);
    EXPECT_EQ(d.ks[i], 0.0f);
    EXPECT_EQ(d.ke[i], 0.0f);
  }
  EXPECT_EQ(d.kd_texture, -1);
}

// A usemtl name no MTL defines keeps its name (a MaterialX material of that
// name binds to it) with the default material's values; faces before any
// usemtl get the default material.
TEST(ObjLoader, UndefinedMaterialKeepsItsNameWithDefaultValues) {
  std::string dir = temp_dir();
  write_file(dir + "/m.mtl", "newmtl red\nKd 1 0 0\n");
  write_file(dir + "/a.obj", "mtllib m.mtl\n" + std::string(kTriangle) +
                                 "f 1 2 3\n"  // before any usemtl
                                 "usemtl nosuchmaterial\n"
                                 "f 1 2 3\n"
                                 "usemtl red\n"
                                 "f 1 2 3\n");
  Scene s = load_obj(dir + "/a.obj");
  ASSERT_EQ(s.materials.size(), 3u);
  EXPECT_EQ(material_names(s), (std::vector<std::string>{"(default)", "nosuchmaterial", "red"}));
  const MtlMaterial& undefined = s.materials[size_t(s.triangles[1].material)];
  EXPECT_FALSE(undefined.defined_by_mtl);
  EXPECT_EQ(undefined.kd[0], MtlMaterial().kd[0]);
  EXPECT_TRUE(s.materials[size_t(s.triangles[2].material)].defined_by_mtl);
  EXPECT_EQ(s.materials[size_t(s.triangles[2].material)].kd[1], 0.0f);
  // Without any MTL file too.
  write_file(dir + "/b.obj", std::string(kTriangle) + "usemtl M_Brick\nf 1 2 3\n");
  Scene b = load_obj(dir + "/b.obj");
  EXPECT_EQ(material_names(b), (std::vector<std::string>{"M_Brick"}));
}

TEST(ObjLoader, ObjectAndGroupNamesAreKeptPerTriangle) {
  std::string dir = temp_dir();
  write_file(dir + "/a.obj", std::string(kTriangle) + "o wall\nf 1 2 3\ng shelf\nf 1 3 2\nf 2 1 3\n");
  Scene s = load_obj(dir + "/a.obj");
  ASSERT_EQ(s.triangle_shapes.size(), 3u);
  EXPECT_EQ(s.shape_names[s.triangle_shapes[0]], "wall");
  EXPECT_EQ(s.shape_names[s.triangle_shapes[1]], "shelf");
  EXPECT_EQ(s.shape_names[s.triangle_shapes[2]], "shelf");
}

// tinyobjloader quoted material names inside the warnings pmc once read; a
// material named like one of those warnings must not be read as one
// (fuzz_mtl found both: the OBJ was refused as truncated / missing its MTL).
TEST(ObjLoader, MaterialNamedLikeAWarningIsJustAName) {
  std::string dir = temp_dir();
  write_file(dir + "/m.mtl",
             "newmtl Degenerated face found\nd 0.5\nTr 0.5\nKd 1 0 0\n"
             "newmtl Failed to load material file\nd 1\nTr 0\nKd 0 1 0\n");
  write_file(dir + "/a.obj", "mtllib m.mtl\n" + std::string(kTriangle) +
                                 "usemtl Degenerated face found\nf 1 2 3\n"
                                 "usemtl Failed to load material file\nf 1 3 2\n");
  // Before the fix: "a face has fewer than 3 corners (is the file truncated?)".
  // (usemtl reads one word, as tinyobj did, so the faces get a material named "Degenerated".)
  Scene s = load_obj(dir + "/a.obj");
  EXPECT_EQ(s.triangles.size(), 2u);
}

TEST(ObjLoader, FaceIndexOutOfRangeThrows) {
  std::string dir = temp_dir();
  struct Case {
    const char* name;
    const char* face;
  };
  // Past the end, before the start (relative), a quad (tinyobjloader once dropped bad
  // quads with only a warning), a normal index past the end, and index 0.
  const Case cases[] = {{"tri", "f 1 2 9\n"},
                        {"rel", "f -9 1 2\n"},
                        {"quad", "f 1 2 3 9\n"},
                        {"normal", "f 1//1 2//1 3//5\n"},
                        {"relnormal", "f 1//-5 2//1 3//1\n"},
                        {"zero", "f 0 1 2\n"}};
  for (const Case& c : cases) {
    std::string obj = dir + "/" + c.name + ".obj";
    write_file(obj, std::string(kTriangle) + "vn 0 0 1\nf 1 2 3\n" + c.face);
    EXPECT_THROW(load_obj(obj), Error) << c.name;
    std::string msg = error_message([&] { load_obj(obj); });
    EXPECT_TRUE(contains(msg, obj)) << c.name << ": " << msg;
  }
}

TEST(ObjLoader, NoFacesThrows) {
  std::string dir = temp_dir();
  std::string obj = dir + "/empty.obj";
  write_file(obj, std::string(kTriangle) + "vn 0 0 1\n");
  EXPECT_THROW(load_obj(obj), Error);
  std::string msg = error_message([&] { load_obj(obj); });
  EXPECT_TRUE(contains(msg, obj)) << msg;
}

TEST(ObjLoader, MissingObjThrowsNamingPath) {
  std::string dir = temp_dir();
  std::string obj = dir + "/does_not_exist.obj";
  EXPECT_THROW(load_obj(obj), Error);
  std::string msg = error_message([&] { load_obj(obj); });
  EXPECT_TRUE(contains(msg, obj)) << msg;
  // A directory is not a readable OBJ either.
  std::string msg_dir = error_message([&] { load_obj(dir); });
  EXPECT_TRUE(contains(msg_dir, dir)) << msg_dir;
}

TEST(ObjLoader, NanVertexTriangleIsSkipped) {
  std::string dir = temp_dir();
  write_file(dir + "/nan.obj",
             "v 0 0 0\n"
             "v 1 0 0\n"
             "v 0 1 0\n"
             "v nan 0 0\n"
             "v 0 1e999 0\n"  // overflows to inf
             "v 7 7 7\n"
             "f 1 2 3\n"
             "f 1 2 4\n"
             "f 1 5 2\n"
             "f 3 2 1\n");
  Scene s = load_obj(dir + "/nan.obj");
  EXPECT_EQ(s.skipped_triangles, 2u);
  EXPECT_EQ(vertex_indices(s), (std::vector<int>{0, 1, 2, 2, 1, 0}));
  ASSERT_EQ(s.positions.size(), 18u);
  EXPECT_TRUE(std::isnan(s.positions[9])) << s.positions[9];
  EXPECT_TRUE(std::isinf(s.positions[13])) << s.positions[13];
  // Bounds cover the triangles kept, not the NaN/inf or unused vertices.
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(s.bounds.lo[i], 0.0f);
    EXPECT_EQ(s.bounds.hi[i], i < 2 ? 1.0f : 0.0f);
  }
}

TEST(ObjLoader, NanVertexWithCrlfLineEnds) {
  std::string dir = temp_dir();
  write_file(dir + "/nan.obj", "v 0 0 0\r\nv 1 0 0\r\n  v\t0 NaN 0\r\nv 0 1 0\r\nf 1 2 3\r\nf 1 2 4\r\n");
  Scene s = load_obj(dir + "/nan.obj");
  EXPECT_EQ(s.skipped_triangles, 1u);
  EXPECT_EQ(vertex_indices(s), (std::vector<int>{0, 1, 3}));
  EXPECT_TRUE(std::isnan(s.positions[7]));
}

TEST(ObjLoader, AllTrianglesNanThrows) {
  std::string dir = temp_dir();
  std::string obj = dir + "/nan.obj";
  write_file(obj, "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  std::string msg = error_message([&] { load_obj(obj); });
  EXPECT_TRUE(contains(msg, obj)) << msg;
}

// A scene in `dir`: sub/scene.obj + sub/scene.mtl using material "tex" (with
// `map_Kd tex_line`) and defining "unused" (with `map_Kd unused_line`).
std::string write_textured_scene(const std::string& dir, const std::string& tex_line,
                                 const std::string& unused_line = "map_Kd .\\tex\\not_there.png") {
  std::filesystem::create_directories(dir + "/sub/tex");
  write_file(dir + "/sub/scene.mtl",
             "newmtl unused\nKd 1 1 1\n" + unused_line + "\n\nnewmtl tex\nKd 1 1 1\n" + tex_line + "\n");
  write_file(dir + "/sub/scene.obj", "mtllib scene.mtl\n" + std::string(kTriangle) +
                                         "vt 0 0\nvt 1 0\nvt 0 1\n"
                                         "usemtl tex\n"
                                         "f 1/1 2/2 3/3\n");
  return dir + "/sub/scene.obj";
}

TEST(ObjLoader, LoadsTextureWithWindowsPath) {
  std::string dir = temp_dir();
  std::string obj = write_textured_scene(dir, "map_Kd .\\tex\\a.png");
  const int w = 4, h = 2;
  std::vector<uint8_t> rgb(size_t(w) * h * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = uint8_t(17 + 29 * i);
  write_image(dir + "/sub/tex/a.png", w, h, 3, rgb);

  Scene s = load_obj(obj);
  ASSERT_EQ(s.materials.size(), 3u);
  const MtlMaterial& m = s.materials[1];
  EXPECT_EQ(m.name, "tex");
  EXPECT_EQ(m.map_kd, dir + "/sub/tex/a.png");
  ASSERT_GE(m.kd_texture, 0);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(m.kd_texture, 0);
  const PmcTexture& t = s.textures.textures()[0];
  EXPECT_EQ(t.width, 4);
  EXPECT_EQ(t.height, 2);
  EXPECT_EQ(t.levels, 3);  // 4x2, 2x1, 1x1
  EXPECT_EQ(t.offset, 0u);
  EXPECT_EQ(t.flags & PMC_TEX_SRGB, PMC_TEX_SRGB);  // a colour texture
  ASSERT_EQ(s.textures.texels().size(), size_t(4 * (8 + 2 + 1)));
  // Level 0 holds the bytes written, RGB -> RGBA with opaque alpha.
  for (int i = 0; i < w * h; ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(s.textures.texels()[4 * i + c], rgb[3 * i + c]) << i << "," << c;
    EXPECT_EQ(s.textures.texels()[4 * i + 3], 255) << i;
  }
  // The unused material's (missing) texture was not looked at.
  EXPECT_EQ(s.materials[0].kd_texture, -1);
  EXPECT_EQ(s.materials[0].map_kd, dir + "/sub/tex/not_there.png");
}

TEST(ObjLoader, AbsoluteTexturePathIsUsedAsWritten) {
  // Exporters often write absolute paths; they must not be put under the OBJ's folder.
  std::string dir = temp_dir();
  const std::string image = std::filesystem::absolute(dir + "/elsewhere/a.png").string();
  std::filesystem::create_directories(dir + "/elsewhere");
  write_image(image, 2, 2, 3, std::vector<uint8_t>(12, 200));
  std::string obj = write_textured_scene(dir, "map_Kd " + image);
  Scene s = load_obj(obj);
  ASSERT_EQ(s.materials.size(), 3u);
  EXPECT_EQ(s.materials[1].map_kd, image);
  EXPECT_EQ(s.materials[1].kd_texture, 0);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures.textures()[0].width, 2);
}

TEST(ObjLoader, UnusedMaterialTextureIsNotLoaded) {
  std::string dir = temp_dir();
  // Both files exist and are valid images; only the used one is loaded.
  std::string obj = write_textured_scene(dir, "Kd 1 1 1", "map_Kd tex/b.png");
  write_image(dir + "/sub/tex/b.png", 2, 2, 3, std::vector<uint8_t>(12, 200));
  Scene s = load_obj(obj);
  EXPECT_EQ(s.textures.size(), 0u);
  EXPECT_TRUE(s.textures.texels().empty());
  EXPECT_EQ(s.materials[0].name, "unused");
  EXPECT_EQ(s.materials[0].map_kd, dir + "/sub/tex/b.png");
  EXPECT_EQ(s.materials[0].kd_texture, -1);
  EXPECT_EQ(s.materials[1].kd_texture, -1);
}

TEST(ObjLoader, LoadTexturesOptionOff) {
  std::string dir = temp_dir();
  std::string obj = write_textured_scene(dir, "map_Kd tex/missing.png");
  ObjLoadOptions options;
  options.load_textures = false;
  Scene s = load_obj(obj, options);
  EXPECT_EQ(s.textures.size(), 0u);
  EXPECT_EQ(s.materials[1].map_kd, dir + "/sub/tex/missing.png");
  EXPECT_EQ(s.materials[1].kd_texture, -1);
}

TEST(ObjLoader, MissingTextureThrowsNamingTexture) {
  std::string dir = temp_dir();
  std::string obj = write_textured_scene(dir, "map_Kd .\\tex\\missing.png");
  EXPECT_THROW(load_obj(obj), Error);
  std::string msg = error_message([&] { load_obj(obj); });
  EXPECT_TRUE(contains(msg, dir + "/sub/tex/missing.png")) << msg;
  EXPECT_TRUE(contains(msg, obj)) << msg;
}

TEST(ObjLoader, NonImageTextureThrows) {
  std::string dir = temp_dir();
  std::string obj = write_textured_scene(dir, "map_Kd tex/text.png");
  write_file(dir + "/sub/tex/text.png", "this is not an image\n");
  EXPECT_THROW(load_obj(obj), Error);
  std::string msg = error_message([&] { load_obj(obj); });
  EXPECT_TRUE(contains(msg, dir + "/sub/tex/text.png")) << msg;
}

TEST(ObjLoader, NormalizeTexturePath) {
  EXPECT_EQ(normalize_texture_path(".\\a\\b.png"), "a/b.png");
  EXPECT_EQ(normalize_texture_path(".\\x.jpg"), "x.jpg");
  EXPECT_EQ(normalize_texture_path("a\\b.png"), "a/b.png");
  EXPECT_EQ(normalize_texture_path("tex/c.png"), "tex/c.png");
  EXPECT_EQ(normalize_texture_path("../up.png"), "../up.png");
}

TEST(ObjLoader, CornellBox) {
  Scene s = load_obj(test::shared_scene("cornell/cornell_box.obj"));
  // 17 `f` lines are live, all quads: floor 3, ceiling, back wall, green wall,
  // red wall 1 each, short block 5, tall block 5. The light and front-wall `f`
  // lines are commented out and are not counted in those 17. 17 quads = 34.
  ASSERT_EQ(s.triangles.size(), 34u);
  EXPECT_EQ(s.positions.size(), 76u * 3);  // every `v` is kept, used or not
  EXPECT_TRUE(s.normals.empty());
  EXPECT_TRUE(s.uvs.empty());
  EXPECT_EQ(s.skipped_triangles, 0u);
  // The floor (x to 552.8) and ceiling (x to 556, y 548.8) span the box; the
  // missing front wall (z = 0) would not widen it: the floor reaches z = 0.
  const float lo[3] = {0.0f, 0.0f, 0.0f}, hi[3] = {556.0f, 548.8f, 559.2f};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.bounds.lo[i], lo[i], 1e-3) << i;
    EXPECT_NEAR(s.bounds.hi[i], hi[i], 1e-3) << i;
  }
  ASSERT_EQ(s.materials.size(), 6u);
  const char* names[] = {"white", "red", "green", "blue", "light", "(default)"};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(s.materials[size_t(i)].name, names[i]);
  // `light` has Ka 20 20 20, not Ke: nothing in this scene emits.
  for (const MtlMaterial& m : s.materials)
    for (int i = 0; i < 3; ++i) EXPECT_EQ(m.ke[i], 0.0f) << m.name;
  EXPECT_FLOAT_EQ(s.materials[1].kd[0], 1.0f);
  EXPECT_FLOAT_EQ(s.materials[1].kd[1], 0.0f);
  int per_material[6] = {};
  for (const PmcTriangle& t : s.triangles) {
    ASSERT_GE(t.material, 0);
    ASSERT_LT(t.material, 6);
    ++per_material[t.material];
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(t.n[k], -1);
      EXPECT_EQ(t.t[k], -1);
    }
  }
  EXPECT_EQ(per_material[0], 30);  // white: 15 quads
  EXPECT_EQ(per_material[1], 2);   // red wall
  EXPECT_EQ(per_material[2], 2);   // green wall
  EXPECT_EQ(per_material[3], 0);   // blue: the front wall is commented out
  EXPECT_EQ(per_material[4], 0);   // light: commented out
  EXPECT_EQ(per_material[5], 0);
  // Relative indices: the ceiling (`f -4 -3 -2 -1` after the light's 4 unused
  // vertices) uses vertices 17..20, i.e. 16..19; the floor's 3 quads come first.
  for (int tri = 6; tri < 8; ++tri)
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(s.triangles[size_t(tri)].v[k], 16);
      EXPECT_LE(s.triangles[size_t(tri)].v[k], 19);
    }
  // The last face is the tall block's last side: vertices 73..76 -> 72..75.
  for (int k = 0; k < 3; ++k) EXPECT_GE(s.triangles.back().v[k], 72);
}

TEST(ObjLoader, Spider) {
  std::string obj = test::shared_scene("spider/spider.obj");
  Scene s = load_obj(obj);
  ASSERT_EQ(s.triangles.size(), 1368u);
  EXPECT_EQ(s.positions.size(), 762u * 3);
  EXPECT_EQ(s.uvs.size(), 302u * 2);
  EXPECT_EQ(s.normals.size(), 747u * 3);
  EXPECT_EQ(s.skipped_triangles, 0u);
  for (const PmcTriangle& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      ASSERT_GE(t.n[k], 0);  // every face is v/vt/vn
      ASSERT_GE(t.t[k], 0);
    }
  const float lo[3] = {-92.7f, -42.2f, -106.7f}, hi[3] = {57.9f, 37.5f, 86.7f};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.bounds.lo[i], lo[i], 0.05) << i;
    EXPECT_NEAR(s.bounds.hi[i], hi[i], 0.05) << i;
  }

  ASSERT_EQ(s.materials.size(), 6u);  // 5 defined + default
  const std::string dir = obj.substr(0, obj.find_last_of('/') + 1);
  struct Expect {
    const char* name;
    const char* file;
    bool used;
  };
  const Expect expect[] = {{"Skin", "wal67ar_small.jpg", true},
                           {"Brusttex", "wal69ar_small.jpg", false},
                           {"HLeibTex", "SpiderTex.jpg", true},
                           {"BeinTex", "drkwood2.jpg", true},
                           {"Augentex", "engineflare1.jpg", true}};
  std::vector<int> uses(s.materials.size(), 0);
  for (const PmcTriangle& t : s.triangles) ++uses.at(size_t(t.material));
  std::vector<bool> texture_seen(4, false);
  for (int i = 0; i < 5; ++i) {
    const MtlMaterial& m = s.materials[size_t(i)];
    EXPECT_EQ(m.name, expect[i].name);
    // `map_Kd .\name.jpg` resolves next to the OBJ with no backslash left.
    EXPECT_EQ(m.map_kd, dir + expect[i].file) << m.name;
    EXPECT_EQ(uses[size_t(i)] > 0, expect[i].used) << m.name;
    if (expect[i].used) {
      ASSERT_GE(m.kd_texture, 0) << m.name;
      ASSERT_LT(m.kd_texture, 4) << m.name;
      EXPECT_FALSE(texture_seen[size_t(m.kd_texture)]) << m.name;  // one texture each
      texture_seen[size_t(m.kd_texture)] = true;
      EXPECT_EQ(s.textures.names()[size_t(m.kd_texture)], m.map_kd);
      const PmcTexture& t = s.textures.textures()[size_t(m.kd_texture)];
      EXPECT_GT(t.width, 0);
      EXPECT_LE(t.width, 768);
      EXPECT_LE(t.height, 768);
      int expected_levels = 1;
      for (int w = t.width, h = t.height; w > 1 || h > 1; w = std::max(1, w >> 1), h = std::max(1, h >> 1))
        ++expected_levels;
      EXPECT_EQ(t.levels, expected_levels) << m.name;
    } else {
      EXPECT_EQ(m.kd_texture, -1) << m.name;  // Brusttex's texture is not loaded
    }
  }
  EXPECT_EQ(uses[5], 0);  // every face has a defined material
  EXPECT_EQ(s.textures.size(), 4u);
  for (const std::string& name : s.textures.names()) EXPECT_FALSE(contains(name, "wal69ar_small")) << name;
}

}  // namespace
}  // namespace pmc
