// bad_input_test.cpp — broken input through the real binary.
//
// Every case runs `pmc render` and requires: exit code 2, a message that names
// the offending file or option AND says what was wrong, and no output left
// behind (neither the -o EXR, nor the PNG beside it, nor the --stats JSON).
// Inputs: OBJ (indices out of range, truncated mid-line, no faces,
// unreadable), MTL (missing file, missing texture, a texture that is not an
// image), MaterialX (not XML, unknown node, cycle, type mismatch, dangling
// reference, a 5000-node chain, a network too wide for the interpreter
// stack), options (zero/negative sizes and samples, zero cache cells or
// entries, a cache larger than memory, an unknown device) and a machine with
// no OpenCL platform at all.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "core/device/pmc_interp.h"
#include "tests/hard_cases/hard_support.h"

namespace pmc {
namespace {

using hard::ObjText;

struct Outcome {
  int code = -1;
  std::string log;
};

// `pmc render OBJ -o DIR/out.exr --stats DIR/out.json ... EXTRA`.
// Outputs of an earlier case are removed first, so each case is judged alone.
void clear_outputs(const std::string& dir) {
  for (const char* f : {"/out.exr", "/out.png", "/out.json", "/out.exr.tmp"}) std::remove((dir + f).c_str());
}

Outcome render(const std::string& dir, const std::string& obj, const std::string& extra = "") {
  clear_outputs(dir);
  Outcome o;
  o.code = test::run_pmc("render " + obj + " -o " + dir + "/out.exr --stats " + dir +
                             "/out.json --width 16 --height 16 --spp 1 --quiet " + extra,
                         &o.log);
  return o;
}

// Exit code 2, every `mentions` in the message, nothing written.
void expect_refused(const std::string& dir, const Outcome& o, const std::vector<std::string>& mentions) {
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_NE(o.log.find("pmc: error: "), std::string::npos) << o.log;
  for (const std::string& m : mentions)
    EXPECT_NE(o.log.find(m), std::string::npos) << "expected \"" << m << "\" in:\n" << o.log;
  EXPECT_FALSE(test::file_exists(dir + "/out.exr")) << o.log;
  EXPECT_FALSE(test::file_exists(dir + "/out.png")) << o.log;
  EXPECT_FALSE(test::file_exists(dir + "/out.json")) << o.log;
  EXPECT_FALSE(test::file_exists(dir + "/out.exr.tmp"));
}

// A valid two-triangle quad (uvs, a material from scene.mtl).
std::string quad_obj(const std::string& mtllib = "scene.mtl", const std::string& material = "grey") {
  ObjText o;
  if (!mtllib.empty()) o.line("mtllib " + mtllib + "\nusemtl " + material);
  const double q[4][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  o.quad(q);
  return o.str();
}

std::string dir_with_mtl() {
  std::string dir = test::temp_dir();
  test::write_file(dir + "/scene.mtl", "newmtl grey\nKd 0.5 0.5 0.5\n");
  return dir;
}

// ------------------------------------------------------------------ OBJ

TEST(BadInput, ObjFaceIndexOutOfRange) {
  std::string dir = dir_with_mtl();
  test::write_file(dir + "/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  expect_refused(dir, render(dir, dir + "/tri.obj"), {"tri.obj", "vertex index 9", "3 vertices"});
  // In a quad (tinyobjloader once dropped those with only a warning) and a negative index.
  test::write_file(dir + "/quad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 7\n");
  expect_refused(dir, render(dir, dir + "/quad.obj"), {"quad.obj", "out of range"});
  test::write_file(dir + "/neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
  expect_refused(dir, render(dir, dir + "/neg.obj"), {"neg.obj", "vertex index"});
  // A texture-coordinate index out of range.
  test::write_file(dir + "/vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/5\n");
  expect_refused(dir, render(dir, dir + "/vt.obj"), {"vt.obj", "texture-coordinate index out of range"});
}

TEST(BadInput, ObjTruncatedMidLine) {
  std::string dir = dir_with_mtl();
  // A valid box OBJ, cut in the middle of its last face line ("f 8 6 5" -> "f 8 6").
  ObjText o;
  o.line("mtllib scene.mtl\nusemtl grey");
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  o.box(lo, hi);
  std::string full = o.str();
  size_t last = full.rfind("\nf ");
  ASSERT_NE(last, std::string::npos);
  size_t cut = full.rfind(' ');  // before the last index of the last face
  ASSERT_GT(cut, last);
  test::write_file(dir + "/cut_face.obj", full.substr(0, cut));
  expect_refused(dir, render(dir, dir + "/cut_face.obj"), {"cut_face.obj", "corners"});
  // Cut within the vertex list: faces are gone, or refer to vertices that are.
  size_t in_vertices = full.find("\nv ", full.find("\nv ") + 1) + 5;
  test::write_file(dir + "/cut_vertex.obj", full.substr(0, in_vertices));
  expect_refused(dir, render(dir, dir + "/cut_vertex.obj"), {"cut_vertex.obj", "no faces"});
  std::string faces_kept = full.substr(0, in_vertices) + "\n" + full.substr(full.find("\nf ") + 1);
  test::write_file(dir + "/cut_vertex_faces.obj", faces_kept);
  expect_refused(dir, render(dir, dir + "/cut_vertex_faces.obj"), {"cut_vertex_faces.obj", "vertex index"});
}

TEST(BadInput, ObjWithoutFaces) {
  std::string dir = dir_with_mtl();
  test::write_file(dir + "/nofaces.obj", "mtllib scene.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n");
  expect_refused(dir, render(dir, dir + "/nofaces.obj"), {"nofaces.obj", "no faces"});
  test::write_file(dir + "/empty.obj", "");
  expect_refused(dir, render(dir, dir + "/empty.obj"), {"empty.obj", "no faces"});
  // Only lines and points: still nothing to render.
  test::write_file(dir + "/lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\n");
  expect_refused(dir, render(dir, dir + "/lines.obj"), {"lines.obj", "no faces"});
}

TEST(BadInput, ObjUnreadable) {
  // chmod 000 does not stop root (these tests often run as root in
  // containers), so the unreadable paths are ones nobody can read as a file:
  // a directory, a path through a regular file, a dangling symbolic link.
  std::string dir = dir_with_mtl();
  ASSERT_EQ(mkdir((dir + "/folder.obj").c_str(), 0755), 0);
  expect_refused(dir, render(dir, dir + "/folder.obj"), {"folder.obj", "cannot open"});
  test::write_file(dir + "/plain.obj", quad_obj());
  expect_refused(dir, render(dir, dir + "/plain.obj/inner.obj"), {"inner.obj", "cannot open"});
  ASSERT_EQ(symlink((dir + "/gone.obj").c_str(), (dir + "/link.obj").c_str()), 0);
  expect_refused(dir, render(dir, dir + "/link.obj"), {"link.obj", "cannot open"});
  if (geteuid() != 0) {  // the classic case, where it means something
    test::write_file(dir + "/locked.obj", quad_obj());
    ASSERT_EQ(chmod((dir + "/locked.obj").c_str(), 0), 0);
    expect_refused(dir, render(dir, dir + "/locked.obj"), {"locked.obj", "cannot open"});
  } else {
    RecordProperty("chmod_000_case",
                   "not run: root reads mode-000 files (directory/ENOTDIR/dangling link cases ran)");
  }
}

// ------------------------------------------------------------------ MTL

TEST(BadInput, MtlMissingFile) {
  std::string dir = test::temp_dir();
  test::write_file(dir + "/scene.obj", quad_obj("nothere.mtl"));
  expect_refused(dir, render(dir, dir + "/scene.obj"), {"scene.obj", "nothere.mtl", "MTL"});
}

TEST(BadInput, MtlMissingTexture) {
  std::string dir = test::temp_dir();
  test::write_file(dir + "/scene.mtl", "newmtl wood\nKd 1 1 1\nmap_Kd textures/missing.png\n");
  test::write_file(dir + "/scene.obj", quad_obj("scene.mtl", "wood"));
  expect_refused(dir, render(dir, dir + "/scene.obj"),
                 {"textures/missing.png", "wood", "cannot read texture"});
}

TEST(BadInput, MtlTextureThatIsNotAnImage) {
  std::string dir = test::temp_dir();
  test::write_file(dir + "/notes.png", "these are my notes, not a PNG\n");
  test::write_file(dir + "/scene.mtl", "newmtl paper\nKd 1 1 1\nmap_Kd notes.png\n");
  test::write_file(dir + "/scene.obj", quad_obj("scene.mtl", "paper"));
  expect_refused(dir, render(dir, dir + "/scene.obj"), {"notes.png", "paper", "cannot read texture"});
  // An image with a valid header and a truncated body.
  std::vector<float> px(64 * 64 * 3, 0.5f);
  hard::write_image(dir + "/whole.png", 64, 64, 3, px);
  std::string bytes;
  {
    FILE* f = std::fopen((dir + "/whole.png").c_str(), "rb");
    ASSERT_TRUE(f);
    char buf[4096];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.append(buf, n);
    std::fclose(f);
  }
  test::write_file(dir + "/half.png", bytes.substr(0, 60));
  test::write_file(dir + "/scene2.mtl", "newmtl half\nKd 1 1 1\nmap_Kd half.png\n");
  test::write_file(dir + "/scene2.obj", quad_obj("scene2.mtl", "half"));
  expect_refused(dir, render(dir, dir + "/scene2.obj"), {"half.png", "texture"});
}

// ------------------------------------------------------------------ MaterialX

// A document with material "M": a standard_surface whose base_color links `link_to`.
std::string mtlx_doc(const std::string& body, const std::string& link_to) {
  return "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n" + body +
         "\n<standard_surface name=\"SR\" type=\"surfaceshader\">\n"
         "  <input name=\"base_color\" type=\"color3\" nodename=\"" +
         link_to +
         "\"/>\n</standard_surface>\n<surfacematerial name=\"M\" type=\"material\">\n"
         "  <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR\"/>\n</surfacematerial>\n"
         "</materialx>\n";
}

Outcome render_mtlx(const std::string& dir, const std::string& file, const std::string& text,
                    const std::string& material = "M") {
  test::write_file(dir + "/" + file, text);
  test::write_file(dir + "/scene.obj", quad_obj(""));
  return render(dir, dir + "/scene.obj", "--mtlx " + dir + "/" + file + " --material " + material);
}

TEST(BadInput, MaterialXNotXml) {
  std::string dir = test::temp_dir();
  expect_refused(dir, render_mtlx(dir, "broken.mtlx", "<materialx><nodegraph name=\"x\">"),
                 {"broken.mtlx", "not valid XML"});
  expect_refused(dir, render_mtlx(dir, "binary.mtlx", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16)),
                 {"binary.mtlx", "XML"});
  expect_refused(dir, render_mtlx(dir, "other.mtlx", "<?xml version=\"1.0\"?><scene/>"),
                 {"other.mtlx", "not a MaterialX document"});
}

TEST(BadInput, MaterialXUnknownNode) {
  std::string dir = test::temp_dir();
  expect_refused(
      dir, render_mtlx(dir, "unknown.mtlx", mtlx_doc("<hypernoise name=\"hn\" type=\"color3\"/>", "hn")),
      {"unknown.mtlx", "hypernoise", "hn", "unsupported node"});
}

TEST(BadInput, MaterialXCycle) {
  std::string dir = test::temp_dir();
  std::string body =
      "<add name=\"a\" type=\"color3\"><input name=\"in1\" type=\"color3\" nodename=\"b\"/></add>\n"
      "<multiply name=\"b\" type=\"color3\"><input name=\"in1\" type=\"color3\" nodename=\"c\"/></multiply>\n"
      "<sin name=\"c\" type=\"color3\"><input name=\"in\" type=\"color3\" nodename=\"a\"/></sin>\n";
  expect_refused(dir, render_mtlx(dir, "cycle.mtlx", mtlx_doc(body, "a")),
                 {"cycle.mtlx", "cycle", "'a'", "'b'", "'c'"});
}

TEST(BadInput, MaterialXTypeMismatch) {
  std::string dir = test::temp_dir();
  // A vector2 texcoord linked where a color3 is expected.
  std::string body =
      "<texcoord name=\"uv\" type=\"vector2\"/>\n"
      "<multiply name=\"m\" type=\"color3\"><input name=\"in1\" type=\"color3\" "
      "nodename=\"uv\"/></multiply>\n";
  expect_refused(dir, render_mtlx(dir, "types.mtlx", mtlx_doc(body, "m")), {"types.mtlx", "type mismatch"});
  // A node that cannot output the declared type.
  expect_refused(dir,
                 render_mtlx(dir, "types2.mtlx", mtlx_doc("<dotproduct name=\"d\" type=\"color3\"/>", "d")),
                 {"types2.mtlx", "'d'", "type mismatch"});
}

TEST(BadInput, MaterialXDanglingReference) {
  std::string dir = test::temp_dir();
  expect_refused(dir, render_mtlx(dir, "dangling.mtlx", mtlx_doc("", "nobody")),
                 {"dangling.mtlx", "nobody", "dangling reference"});
  std::string body =
      "<add name=\"a\" type=\"color3\"><input name=\"in1\" type=\"color3\" "
      "nodegraph=\"NG_missing\"/></add>\n";
  expect_refused(dir, render_mtlx(dir, "dangling2.mtlx", mtlx_doc(body, "a")),
                 {"dangling2.mtlx", "NG_missing", "dangling reference"});
  // --material naming a material the documents do not define.
  test::write_file(dir + "/ok.mtlx", mtlx_doc("<constant name=\"k\" type=\"color3\"/>", "k"));
  expect_refused(dir, render(dir, dir + "/scene.obj", "--mtlx " + dir + "/ok.mtlx --material Nope"),
                 {"--material", "Nope"});
  // A --mtlx document that does not exist.
  expect_refused(dir, render(dir, dir + "/scene.obj", "--mtlx " + dir + "/absent.mtlx --material M"),
                 {"absent.mtlx", "cannot read"});
}

TEST(BadInput, MaterialXChainOf5000Nodes) {
  // The reader refuses graphs nested deeper than 2000 nodes (the passes and
  // the compiler recurse along links); it must say so instead of crashing.
  std::string dir = test::temp_dir();
  std::ostringstream body;
  body << "<texcoord name=\"n0\" type=\"vector3\"/>\n";
  for (int i = 1; i <= 5000; ++i)
    body << "<sin name=\"n" << i << "\" type=\"vector3\"><input name=\"in\" type=\"vector3\" nodename=\"n"
         << i - 1 << "\"/></sin>\n";
  body << "<convert name=\"c\" type=\"color3\"><input name=\"in\" type=\"vector3\" "
          "nodename=\"n5000\"/></convert>\n";
  expect_refused(dir, render_mtlx(dir, "deep.mtlx", mtlx_doc(body.str(), "c")),
                 {"deep.mtlx", "nested deeper than 2000"});
}

TEST(BadInput, MaterialXNetworkTooWideForTheInterpreterStack) {
  // The compiler emits nodes depth-first and frees a slot after its last
  // use, so a balanced tree of adds only keeps ~log2(leaves) values alive.
  // What needs a wide stack is a value that stays alive while the rest is
  // computed: here add(L0, add(L1, add(L2, ... L59))) with distinct
  // texcoord-derived vector3 leaves L_i = sin(texcoord * k_i): all 60 leaves
  // (180 floats) are pending before the innermost add runs, more than
  // PMC_STACK_SIZE = 128. The compiler must refuse it, naming the material.
  static_assert(PMC_STACK_SIZE == 128, "the leaf count below assumes 128 floats");
  std::string dir = test::temp_dir();
  const int n = 60;
  std::ostringstream body;
  body << "<texcoord name=\"uv\" type=\"vector3\"/>\n";
  for (int i = 0; i < n; ++i)
    body << "<multiply name=\"m" << i << "\" type=\"vector3\"><input name=\"in1\" type=\"vector3\" "
         << "nodename=\"uv\"/><input name=\"in2\" type=\"vector3\" value=\"" << 1.5 + i << ", " << 2.5 + i
         << ", " << 3.5 + i << "\"/></multiply>\n"
         << "<sin name=\"l" << i << "\" type=\"vector3\"><input name=\"in\" type=\"vector3\" nodename=\"m"
         << i << "\"/></sin>\n";
  body << "<add name=\"a" << n - 1 << "\" type=\"vector3\"><input name=\"in1\" type=\"vector3\" nodename=\"l"
       << n - 1 << "\"/></add>\n";
  for (int i = n - 2; i >= 0; --i)
    body << "<add name=\"a" << i << "\" type=\"vector3\"><input name=\"in1\" type=\"vector3\" nodename=\"l"
         << i << "\"/><input name=\"in2\" type=\"vector3\" nodename=\"a" << i + 1 << "\"/></add>\n";
  body << "<convert name=\"c\" type=\"color3\"><input name=\"in\" type=\"vector3\" "
          "nodename=\"a0\"/></convert>\n";
  const std::string doc = mtlx_doc(body.str(), "c");
  for (const char* cache : {"on", "off"}) {
    SCOPED_TRACE(std::string("--cache ") + cache);
    test::write_file(dir + "/wide.mtlx", doc);
    test::write_file(dir + "/scene.obj", quad_obj(""));
    Outcome o = render(dir, dir + "/scene.obj", "--mtlx " + dir + "/wide.mtlx --material M --cache " + cache);
    expect_refused(dir, o, {"wide.mtlx", "material 'M'", "128 floats of interpreter stack"});
  }
}

// ------------------------------------------------------------------ options

TEST(BadInput, ZeroOrNegativeSizeOrSamples) {
  std::string dir = dir_with_mtl();
  test::write_file(dir + "/scene.obj", quad_obj());
  const std::pair<const char*, const char*> cases[] = {
      {"--width 0", "--width"},
      {"--width -16", "--width"},
      {"--height 0", "--height"},
      {"--height -1", "--height"},
      {"--spp 0", "--spp"},
      {"--spp -4", "--spp"},
      {"--width 99999999999", "--width"},
      {"--max-depth -1", "--max-depth"},
      {"--spp 1.5", "--spp"},
  };
  for (const auto& [args, mentions] : cases) {
    SCOPED_TRACE(args);
    // The later value of a repeated option would be refused as "given twice":
    // so these run without the defaults of render() for that option.
    Outcome o;
    std::string base = " -o " + dir + "/out.exr --stats " + dir + "/out.json --quiet ";
    std::string a = args;
    if (a.find("--width") == std::string::npos) base += "--width 16 ";
    if (a.find("--height") == std::string::npos) base += "--height 16 ";
    if (a.find("--spp") == std::string::npos) base += "--spp 1 ";
    clear_outputs(dir);
    o.code = test::run_pmc("render " + dir + "/scene.obj" + base + a, &o.log);
    expect_refused(dir, o, {mentions});
  }
}

TEST(BadInput, ZeroCacheCellsOrEntries) {
  // Refused whether or not the scene's materials have cache points: an option
  // is checked for what it says, not for whether this scene happens to use it.
  std::string dir = dir_with_mtl();
  test::write_file(dir + "/plain.obj", quad_obj());  // an MTL constant: no cache point
  test::write_file(dir + "/m.mtlx", hard::materials_mtlx("none.png"));
  const std::string plain = dir + "/plain.obj";
  const std::string noisy = "--mtlx " + dir + "/m.mtlx --material M_noise";
  for (const std::string& scene_args : {std::string(""), noisy}) {
    SCOPED_TRACE(scene_args.empty() ? "no cache points" : "cache points");
    expect_refused(dir, render(dir, plain, scene_args + " --cache-cells 0"), {"--cache-cells", "at least 1"});
    expect_refused(dir, render(dir, plain, scene_args + " --cache-cells -5"), {"--cache-cells"});
    expect_refused(dir, render(dir, plain, scene_args + " --cache-entries 0"), {"--cache-entries"});
    expect_refused(dir, render(dir, plain, scene_args + " --cache-cells 16 --cache-entries 0"),
                   {"--cache-entries"});
    expect_refused(dir, render(dir, plain, scene_args + " --cache-entries 5000"),
                   {"--cache-entries", "1..1024"});
  }
}

TEST(BadInput, ContradictoryCacheModes) {
  std::string dir = dir_with_mtl();
  test::write_file(dir + "/plain.obj", quad_obj());
  const std::string plain = dir + "/plain.obj";
  expect_refused(dir, render(dir, plain, "--cache-eval hit --cache-filter bilinear"),
                 {"--cache-filter bilinear", "--cache-eval center"});
  expect_refused(dir, render(dir, plain, "--cache-filter trilinear"), {"--cache-filter", "trilinear"});
  expect_refused(dir, render(dir, plain, "--cache-eval middle"), {"--cache-eval", "middle"});
  expect_refused(dir, render(dir, plain, "--cache-policy lru"),
                 {"--cache-policy", "expected keep-first or priority, got 'lru'"});
}

TEST(BadInput, CacheLargerThanFreeMemory) {
  std::string dir = dir_with_mtl();
  test::write_file(dir + "/plain.obj", quad_obj());
  test::write_file(dir + "/m.mtlx", hard::materials_mtlx("none.png"));
  const std::string noisy = "--mtlx " + dir + "/m.mtlx --material M_noise";
  // 2^40 cells x 8 entries x 8 bytes = 64 TiB; and the largest int64.
  expect_refused(dir, render(dir, dir + "/plain.obj", noisy + " --cache-cells 1099511627776"),
                 {"--cache-cells", "free memory"});
  expect_refused(
      dir, render(dir, dir + "/plain.obj", noisy + " --cache-cells 9223372036854775807 --cache-entries 1024"),
      {"--cache-cells", "free memory"});
  expect_refused(dir, render(dir, dir + "/plain.obj", noisy + " --cache-cells 99999999999999999999"),
                 {"--cache-cells", "not an integer"});
}

// Output paths are checked before the scene is loaded: a render that could
// not be saved fails at once with the option named, not after rendering.
TEST(BadInput, UnwritableOrCollidingOutputsFailBeforeRendering) {
  std::string dir = dir_with_mtl();
  test::write_file(dir + "/scene.obj", quad_obj());
  const std::string obj = dir + "/scene.obj";
  auto run = [&](const std::string& args) {
    clear_outputs(dir);
    Outcome o;
    o.code = test::run_pmc("render " + obj + " " + args + " --width 16 --height 16 --spp 1 --quiet", &o.log);
    return o;
  };
  expect_refused(dir, run("-o " + dir + "/missing_folder/out.exr"),
                 {"-o", "missing_folder", "does not exist"});
  expect_refused(dir, run("-o " + dir + "/out.png"), {"-o", "out.png", ".exr"});
  expect_refused(dir, run("-o " + dir), {"-o", "must end in .exr"});
  expect_refused(dir, run("-o " + dir + "/out.exr --stats " + dir + "/nowhere/s.json"),
                 {"--stats", "nowhere", "does not exist"});
  expect_refused(dir, run("-o " + dir + "/out.exr --hitmap " + dir + "/map.exr"), {"--hitmap", ".png"});
  // --hitmap out.png puts its raw EXR on out.exr, the image itself.
  expect_refused(dir, run("-o " + dir + "/out.exr --hitmap " + dir + "/out.png"), {"would both write"});
  EXPECT_FALSE(test::file_exists(dir + "/map.exr"));
  EXPECT_FALSE(test::file_exists(dir + "/map.png"));
  // The PNG beside -o, and the EXR beside --hitmap, are outputs too: a folder
  // of that name fails at once, and stays (it is the user's, not ours).
  const std::string sub = dir + "/sub";
  std::filesystem::create_directories(sub + "/out.png");
  std::filesystem::create_directories(sub + "/map.exr");
  Outcome o = run("-o " + sub + "/out.exr");
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_NE(o.log.find("-o (its PNG)"), std::string::npos) << o.log;
  EXPECT_NE(o.log.find("is a folder"), std::string::npos) << o.log;
  o = run("-o " + sub + "/img.exr --hitmap " + sub + "/map.png");
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_NE(o.log.find("--hitmap (its EXR)"), std::string::npos) << o.log;
  EXPECT_TRUE(std::filesystem::is_directory(sub + "/out.png"));
  EXPECT_TRUE(std::filesystem::is_directory(sub + "/map.exr"));
  EXPECT_FALSE(test::file_exists(sub + "/out.exr"));
  EXPECT_FALSE(test::file_exists(sub + "/img.exr"));
}

TEST(BadInput, UnknownDevice) {
  std::string dir = dir_with_mtl();
  test::write_file(dir + "/scene.obj", quad_obj());
  Outcome o = render(dir, dir + "/scene.obj", "--device quantum-accelerator-9000");
  expect_refused(dir, o, {"--device", "quantum-accelerator-9000", "available"});
}

TEST(BadInput, NoOpenClPlatformSaysHowToInstallPocl) {
  // ocl-icd finds no platform when its vendor directory does not exist.
  std::string dir = dir_with_mtl();
  test::write_file(dir + "/scene.obj", quad_obj());
  const char* old = std::getenv("OCL_ICD_VENDORS");
  std::string saved = old ? old : "";
  setenv("OCL_ICD_VENDORS", "/nonexistent-dir", 1);
  Outcome o = render(dir, dir + "/scene.obj");
  std::string info_log;
  int info_code = test::run_pmc("info --devices", &info_log);
  if (old)
    setenv("OCL_ICD_VENDORS", saved.c_str(), 1);
  else
    unsetenv("OCL_ICD_VENDORS");
  expect_refused(dir, o, {"no OpenCL platform", "pocl-opencl-icd", "apt-get install"});
  EXPECT_EQ(info_code, 2) << info_log;
  EXPECT_NE(info_log.find("pocl-opencl-icd"), std::string::npos) << info_log;
}

}  // namespace
}  // namespace pmc
