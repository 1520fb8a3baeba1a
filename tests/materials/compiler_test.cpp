// compiler_test.cpp — materials/compiler.h: slots, constants, entries, limits.
//
// The compiler turns an optimised graph into stack-machine code every shading
// point runs, so its resource use is what the kernels pay for: the peak stack
// sizes each work-item's private array (kernels are built with
// -DPMC_STACK_SIZE=<peak>). Checked here on graphs built in code:
//  * slots are freed after their last use (a long unary chain needs two
//    values' worth of stack, not N), while a wide fan-in needs one per value;
//  * a network needing more than PMC_STACK_SIZE floats is refused with a
//    pmc::Error naming the material, and leaves the program untouched;
//  * inline constants are stored once per material;
//  * two materials share one code buffer with distinct entries, and each
//    entry's constants lie within its own words;
//  * evaluate_constant() (constant folding) computes the right values;
//  * the disassembly names the opcodes;
//  * the host interpreter running a compiled material gives the analytic
//    answer (ramplr at a uv), with the cache blocks on or off;
//  * a program reads the ray cone's footprint (PMC_MAT_FOOTPRINT: the shade
//    kernel computes it only then) exactly when it filters an image, inside
//    the cache group or outside it, and for hex-tiled images and normal maps;
//  * a program is uniform (PMC_MAT_UNIFORM: the shade kernel runs it once per
//    batch) exactly when it reads nothing of the shading point and keeps its
//    normal, and the interpreter then gives two different points the same
//    parameters.
#include "materials/compiler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/device/pmc_interp.h"
#include "core/error.h"
#include "core/texture.h"
#include "materials/mtlx_reader.h"
#include "materials/node_graph.h"
#include "materials/node_table.h"
#include "tests/hard_cases/hard_support.h"
#include "tests/support/graph_builder.h"
#include "tests/support/material_eval.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

using VT = ValueType;

using test::add;
using test::add_surface;
using test::link;
using test::new_graph;
using test::text;
using test::value;

// position -> sin -> sin -> ... (n times), into base_color.
Graph unary_chain(int n) {
  Graph g = new_graph("M_chain");
  int prev = add(g, "pos", "position", VT::Vector3);
  for (int i = 0; i < n; ++i)
    prev = add(g, "s" + std::to_string(i), "sin", VT::Vector3, {{"in", link(prev)}});
  add_surface(g, {{"base_color", link(prev)}});
  return g;
}

// add(s0, add(s1, add(s2, ...))) with s_i = sin(position * k_i): the
// depth-first emission keeps every s_i alive until the outermost add.
Graph fan_in(int n, const std::string& material) {
  Graph g = new_graph(material);
  int pos = add(g, "pos", "position", VT::Vector3);
  std::vector<int> leaves;
  for (int i = 0; i < n; ++i) {
    float k = 1.0f + 0.5f * float(i);
    int m = add(g, "m" + std::to_string(i), "multiply", VT::Vector3,
                {{"in1", link(pos)}, {"in2", value(VT::Vector3, k, k, k)}});
    leaves.push_back(add(g, "s" + std::to_string(i), "sin", VT::Vector3, {{"in", link(m)}}));
  }
  int acc = leaves.back();
  for (int i = n - 2; i >= 0; --i)
    acc = add(g, "a" + std::to_string(i), "add", VT::Vector3,
              {{"in1", link(leaves[size_t(i)])}, {"in2", link(acc)}});
  add_surface(g, {{"base_color", link(acc)}});
  return g;
}

// Instruction start offsets of a compiled material, up to (not including) END.
std::vector<uint32_t> instructions(const MaterialProgram& p, const CompiledMaterial& m, uint32_t* end_at) {
  std::vector<uint32_t> at;
  uint32_t pc = m.entry;
  while (pc < m.entry + m.code_words) {
    uint32_t h = p.code[pc];
    if (pmc_op_code(h) == PMC_OP_END) break;
    at.push_back(pc);
    pc += 2 + pmc_op_nargs(h);
  }
  if (end_at) *end_at = pc;
  return at;
}

// The host interpreter on one compiled material.
void run_host(const MaterialProgram& p, const CompiledMaterial& m, float u, float v,
              float params[PMC_P_COUNT], const float3& pos = make_float3(0.3f, -0.2f, 0.7f)) {
  test::run_program_at(p, m, u, v, params, pos);
}

TEST(Compiler, FreesStackSlotsAfterLastUse) {
  Graph g = unary_chain(40);
  TexturePool tex;
  MaterialProgram prog;
  const CompiledMaterial& m = compile_material(g, tex, prog);
  // The input of each sin is freed once the sin is emitted, so two vector3
  // values are ever alive at once: 6 floats, whatever the chain length.
  EXPECT_EQ(m.peak_stack, 6u);
  EXPECT_EQ(m.instructions, 42u);  // POSITION, 40 x SIN, OUTPUT
}

TEST(Compiler, WideFanInNeedsOneSlotPerLiveValue) {
  const int n = 10;
  Graph g = fan_in(n, "M_fan");
  TexturePool tex;
  MaterialProgram prog;
  const CompiledMaterial& m = compile_material(g, tex, prog);
  EXPECT_GE(m.peak_stack, uint32_t(3 * n)) << "all " << n << " sin results are alive before the outer add";
  EXPECT_LE(m.peak_stack, uint32_t(3 * (n + 3)));
  EXPECT_LE(m.peak_stack, uint32_t(PMC_STACK_SIZE));
}

TEST(Compiler, RefusesANetworkThatNeedsTooMuchStackNamingTheMaterial) {
  TexturePool tex;
  MaterialProgram prog;
  Graph small = unary_chain(3);
  compile_material(small, tex, prog);
  const size_t words = prog.code.size();
  Graph g = fan_in(45, "M_too_wide");  // 45 vector3 values alive: 135 > 128 floats
  try {
    compile_material(g, tex, prog);
    FAIL() << "a network needing more than PMC_STACK_SIZE floats must be refused";
  } catch (const Error& e) {
    std::string w = e.what();
    EXPECT_NE(w.find("M_too_wide"), std::string::npos) << w;
    EXPECT_NE(w.find("test.mtlx"), std::string::npos) << w;
    EXPECT_NE(w.find(std::to_string(PMC_STACK_SIZE)), std::string::npos) << w;
  }
  EXPECT_EQ(prog.code.size(), words) << "a refused material must not leave code behind";
  EXPECT_EQ(prog.materials.size(), 1u);
}

TEST(Compiler, InlineConstantsAreStoredOnce) {
  Graph g = new_graph("M_consts");
  int pos = add(g, "pos", "position", VT::Vector3);
  int s = add(g, "s", "sin", VT::Vector3, {{"in", link(pos)}});
  int c = add(g, "c", "cos", VT::Vector3, {{"in", link(pos)}});
  const Input k = value(VT::Color3, 0.25f, 0.5f, 0.75f);
  int m1 = add(g, "m1", "multiply", VT::Color3, {{"in1", link(s)}, {"in2", k}});
  int m2 = add(g, "m2", "add", VT::Color3, {{"in1", link(c)}, {"in2", k}});
  int m3 = add(g, "m3", "mix", VT::Color3, {{"fg", link(s)}, {"bg", link(c)}, {"mix", k}});
  add_surface(g, {{"base_color", link(m1)}, {"specular_color", link(m2)}, {"coat_color", link(m3)}});
  TexturePool tex;
  MaterialProgram prog;
  const CompiledMaterial& m = compile_material(g, tex, prog);
  uint32_t end_at = 0;
  std::vector<uint32_t> ins = instructions(prog, m, &end_at);
  ASSERT_LT(end_at, m.entry + m.code_words);
  // The constant's three words appear once after END ...
  uint32_t bits[3];
  for (int i = 0; i < 3; ++i) std::memcpy(&bits[i], &k.value.f[size_t(i)], 4);
  int copies = 0;
  uint32_t where = 0;
  for (uint32_t w = end_at + 2; w + 3 <= m.entry + m.code_words; ++w)
    if (prog.code[w] == bits[0] && prog.code[w + 1] == bits[1] && prog.code[w + 2] == bits[2])
      ++copies, where = w;
  EXPECT_EQ(copies, 1);
  // ... and all three instructions read it from there.
  int readers = 0;
  for (uint32_t pc : ins)
    for (uint32_t a = 0; a < pmc_op_nargs(prog.code[pc]); ++a) {
      uint32_t o = prog.code[pc + 2 + a];
      if ((o & PMC_OPERAND_CONST) && (o & PMC_OPERAND_INDEX_MASK) == where && pmc_operand_width(o) == 3)
        ++readers;
    }
  EXPECT_EQ(readers, 3);
}

// base_color = ramplr(left, right) over u.
Graph ramp_material(const std::string& name, float3 left, float3 right) {
  Graph g = new_graph(name);
  int tc = add(g, "uv", "texcoord", VT::Vector2);
  int r = add(g, "ramp", "ramplr", VT::Color3,
              {{"valuel", value(VT::Color3, left.x, left.y, left.z)},
               {"valuer", value(VT::Color3, right.x, right.y, right.z)},
               {"texcoord", link(tc)}});
  add_surface(g, {{"base_color", link(r)}});
  return g;
}

TEST(Compiler, TwoMaterialsShareOneBufferWithDistinctEntries) {
  Graph a = ramp_material("M_a", make_float3(1, 0, 0), make_float3(0, 0, 1));
  Graph b = ramp_material("M_b", make_float3(0, 1, 0), make_float3(1, 1, 0));
  TexturePool tex;
  MaterialProgram prog;
  compile_material(a, tex, prog);
  compile_material(b, tex, prog);
  ASSERT_EQ(prog.materials.size(), 2u);
  const CompiledMaterial& ma = prog.materials[0];
  const CompiledMaterial& mb = prog.materials[1];
  EXPECT_EQ(ma.entry, 0u);
  EXPECT_EQ(mb.entry, ma.code_words);
  EXPECT_EQ(prog.code.size(), size_t(ma.code_words) + mb.code_words);
  // Constant operands are absolute indices into the shared buffer: each must
  // point into its own material's words.
  for (const CompiledMaterial* m : {&ma, &mb})
    for (uint32_t pc : instructions(prog, *m, nullptr))
      for (uint32_t k = 0; k < pmc_op_nargs(prog.code[pc]); ++k) {
        uint32_t o = prog.code[pc + 2 + k];
        if (!(o & PMC_OPERAND_CONST)) continue;
        uint32_t idx = o & PMC_OPERAND_INDEX_MASK;
        EXPECT_GE(idx, m->entry) << m->name;
        EXPECT_LE(idx + pmc_operand_width(o), m->entry + m->code_words) << m->name;
      }
  float pa[PMC_P_COUNT], pb[PMC_P_COUNT];
  run_host(prog, ma, 0.25f, 0.5f, pa);
  run_host(prog, mb, 0.25f, 0.5f, pb);
  EXPECT_NEAR(pa[PMC_P_BASE_COLOR + 0], 0.75f, 1e-6f);
  EXPECT_NEAR(pa[PMC_P_BASE_COLOR + 2], 0.25f, 1e-6f);
  EXPECT_NEAR(pb[PMC_P_BASE_COLOR + 0], 0.25f, 1e-6f);
  EXPECT_NEAR(pb[PMC_P_BASE_COLOR + 1], 1.0f, 1e-6f);
}

TEST(Compiler, HostInterpreterGivesTheAnalyticRamp) {
  Graph g = ramp_material("M_ramp", make_float3(1, 0, 0), make_float3(0, 0, 1));
  TexturePool tex;
  MaterialProgram prog;
  const CompiledMaterial& m = compile_material(g, tex, prog);
  struct Probe {
    float u, v;
    float r, g, b;
  };
  // ramplr = left + (right - left) * clamp(u, 0, 1).
  for (Probe p : {Probe{0.3f, 0.7f, 0.7f, 0, 0.3f}, Probe{0.0f, 0.2f, 1, 0, 0}, Probe{1.0f, 0.9f, 0, 0, 1},
                  Probe{1.5f, 0.0f, 0, 0, 1}, Probe{-0.5f, 3.0f, 1, 0, 0}}) {
    float params[PMC_P_COUNT];
    run_host(prog, m, p.u, p.v, params);
    EXPECT_NEAR(params[PMC_P_BASE_COLOR + 0], p.r, 1e-6f) << "u " << p.u;
    EXPECT_NEAR(params[PMC_P_BASE_COLOR + 1], p.g, 1e-6f) << "u " << p.u;
    EXPECT_NEAR(params[PMC_P_BASE_COLOR + 2], p.b, 1e-6f) << "u " << p.u;
    EXPECT_EQ(params[PMC_P_SPECULAR_ROUGHNESS], 0.2f) << "unwritten parameters keep their defaults";
  }
}

TEST(Compiler, CacheBlocksMissToTheSameValuesAsThePlainProgram) {
  // With the cache on, uv-only sub-graphs sit in CACHE_LOOKUP ... CACHE_STORE
  // blocks with their own slots; with no cache context every lookup misses,
  // so the program must compute exactly what the cache-off program computes.
  auto build = [] {
    Graph g = new_graph("M_cached");
    int tc = add(g, "uv", "texcoord", VT::Vector2);
    int tile =
        add(g, "tile", "multiply", VT::Vector2, {{"in1", link(tc)}, {"in2", value(VT::Vector2, 3, 3)}});
    int noise = add(g, "noise", "noise2d", VT::Float, {{"texcoord", link(tile)}});
    int s = add(g, "s", "sin", VT::Float, {{"in", link(noise)}});
    int a = add(g, "a", "add", VT::Float, {{"in1", link(s)}, {"in2", value(VT::Float, 1.5f)}});
    int pos = add(g, "pos", "position", VT::Vector3);
    int c = add(g, "c", "cos", VT::Vector3, {{"in", link(pos)}});
    int m = add(g, "m", "multiply", VT::Color3, {{"in1", link(a, VT::Float)}, {"in2", link(c, VT::Color3)}});
    add_surface(g, {{"base_color", link(m)}, {"specular_roughness", link(s)}});
    return g;
  };
  Graph plain = build(), cached = build();
  TexturePool tex;
  MaterialProgram prog;
  const CompiledMaterial& mp = compile_material(plain, tex, prog);
  CompileOptions opts;
  opts.cache = true;
  opts.cache_min_nodes = 4;  // the uv-only branch has 5 nodes
  const CompiledMaterial& mc = compile_material(cached, tex, prog, opts);
  EXPECT_FALSE(mc.cache_plan.points.empty()) << disassemble(prog, mc);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uni(-2.0f, 3.0f);
  for (int i = 0; i < 200; ++i) {
    float u = uni(rng), v = uni(rng);
    float3 pos = make_float3(uni(rng), uni(rng), uni(rng));
    float a[PMC_P_COUNT], b[PMC_P_COUNT];
    run_host(prog, prog.materials[0], u, v, a, pos);
    run_host(prog, prog.materials[1], u, v, b, pos);
    for (int k = 0; k < PMC_P_COUNT; ++k)
      ASSERT_EQ(a[k], b[k]) << "param " << k << " at uv " << u << " " << v;
  }
  (void)mp;
}

TEST(Compiler, EvaluateConstantComputesNodeValues) {
  Graph g = new_graph("M_eval");
  auto eval = [&](int node, int lanes, std::vector<float> want) {
    Value out;
    ASSERT_TRUE(evaluate_constant(g, g.nodes[size_t(node)], out)) << g.nodes[size_t(node)].category;
    for (int i = 0; i < lanes; ++i)
      EXPECT_NEAR(out.f[size_t(i)], want[size_t(i)], 1e-6f * (1 + std::fabs(want[size_t(i)])))
          << g.nodes[size_t(node)].category << " lane " << i;
  };
  eval(add(g, "p", "power", VT::Float, {{"in1", value(VT::Float, 2)}, {"in2", value(VT::Float, 10)}}), 1,
       {1024});
  eval(add(g, "h", "hsvtorgb", VT::Color3, {{"in", value(VT::Color3, 0, 1, 1)}}), 3, {1, 0, 0});
  eval(add(g, "r", "ramplr", VT::Float,
           {{"valuel", value(VT::Float, 0)},
            {"valuer", value(VT::Float, 10)},
            {"texcoord", value(VT::Vector2, 0.3f, 0)}}),
       1, {3});
  eval(add(g, "d", "dotproduct", VT::Float,
           {{"in1", value(VT::Vector3, 1, 2, 3)}, {"in2", value(VT::Vector3, 4, 5, 6)}}),
       1, {32});
  eval(add(g, "n", "normalize", VT::Vector3, {{"in", value(VT::Vector3, 3, 4, 0)}}), 3, {0.6f, 0.8f, 0});
  eval(add(g, "mod", "modulo", VT::Float, {{"in1", value(VT::Float, -1)}, {"in2", value(VT::Float, 3)}}), 1,
       {2});
  eval(add(g, "c2", "combine2", VT::Vector2, {{"in1", value(VT::Float, 5)}, {"in2", value(VT::Float, 6)}}), 2,
       {5, 6});
  eval(add(g, "inv", "ifgreatereq", VT::Float,
           {{"value1", value(VT::Float, 1)},
            {"value2", value(VT::Float, 1)},
            {"in1", value(VT::Float, 7)},
            {"in2", value(VT::Float, 8)}}),
       1, {7});
  Value out;
  int tc = add(g, "uv", "texcoord", VT::Vector2);
  EXPECT_FALSE(evaluate_constant(g, g.nodes[size_t(tc)], out)) << "texcoord depends on the shading point";
  int img = add(g, "img", "image", VT::Color3, {{"texcoord", value(VT::Vector2, 0.5f, 0.5f)}});
  EXPECT_FALSE(evaluate_constant(g, g.nodes[size_t(img)], out)) << "images are not folded";
}

TEST(Compiler, DisassemblyNamesTheOpcodes) {
  Graph g = unary_chain(2);
  g.nodes[size_t(g.surface)].input("metalness")->value.f[0] =
      0.5f;  // a constant that differs from the default
  TexturePool tex;
  MaterialProgram prog;
  const CompiledMaterial& m = compile_material(g, tex, prog);
  std::string text = disassemble(prog, m);
  for (const char* s : {"POSITION.3", "SIN.3", "OUTPUT.3 param[2]", "OUTPUT.1 param[5]", "(0.5)", "END"})
    EXPECT_NE(text.find(s), std::string::npos) << s << " in\n" << text;
  // Constant inputs equal to the interpreter's defaults emit nothing.
  EXPECT_EQ(text.find("param[10]"), std::string::npos) << text;
}

// PMC_MAT_EMITS: the shade kernel skips a material at hits past a path's last
// one unless its program writes the emission (or its colour).
TEST(Compiler, OnlyProgramsThatWriteTheEmissionMayEmit) {
  TexturePool tex;
  MaterialProgram prog;
  Graph plain = ramp_material("M_plain", make_float3(0, 0, 0), make_float3(1, 1, 1));
  EXPECT_FALSE(compile_material(plain, tex, prog).may_emit);
  Graph zero = new_graph("M_zero");
  add_surface(zero, {{"emission", value(VT::Float, 0)}});  // the default: written nowhere
  EXPECT_FALSE(compile_material(zero, tex, prog).may_emit);
  Graph lamp = new_graph("M_lamp");
  add_surface(lamp, {{"emission", value(VT::Float, 1)}, {"emission_color", value(VT::Color3, 2, 2, 2)}});
  EXPECT_TRUE(compile_material(lamp, tex, prog).may_emit);
  Graph glow = new_graph("M_glow");  // an emission colour driven by a pattern
  int tc = add(glow, "uv", "texcoord", VT::Vector2);
  int r = add(glow, "ramp", "ramplr", VT::Color3,
              {{"valuel", value(VT::Color3, 0, 0, 0)},
               {"valuer", value(VT::Color3, 3, 3, 3)},
               {"texcoord", link(tc)}});
  add_surface(glow, {{"emission", value(VT::Float, 1)}, {"emission_color", link(r)}});
  EXPECT_TRUE(compile_material(glow, tex, prog).may_emit);
}

TEST(Compiler, OnlyImageFilteringProgramsReadTheFootprint) {
  const std::string png = test::temp_dir() + "/checker.png";
  hard::write_checker_png(png);
  TexturePool tex;
  MaterialProgram prog;
  Graph chain = unary_chain(3);
  EXPECT_FALSE(compile_material(chain, tex, prog).reads_footprint) << "position and sin read no footprint";
  Graph ramp = ramp_material("M_ramp", make_float3(0, 0, 0), make_float3(1, 1, 1));
  EXPECT_FALSE(compile_material(ramp, tex, prog).reads_footprint) << "texcoord alone reads no footprint";

  // texcoord * 4 -> image -> base_color, plain and with the image in the cache group.
  for (const bool cache : {false, true}) {
    Graph g = new_graph(cache ? "M_image_cached" : "M_image");
    int tc = add(g, "uv", "texcoord", VT::Vector2);
    int m = add(g, "tile", "multiply", VT::Vector2, {{"in1", link(tc)}, {"in2", value(VT::Vector2, 4, 4)}});
    int img = add(g, "img", "image", VT::Color3, {{"file", text(png, VT::Filename)}, {"texcoord", link(m)}});
    int s = img;
    for (int i = 0; i < 8; ++i) s = add(g, "s" + std::to_string(i), "sin", VT::Color3, {{"in", link(s)}});
    add_surface(g, {{"base_color", link(s)}});
    CompileOptions options;
    options.cache = cache;
    options.cache_min_nodes = 2;
    const CompiledMaterial& cm = compile_material(g, tex, prog, options);
    EXPECT_EQ(cm.cache_plan.points.empty(), !cache);
    EXPECT_TRUE(cm.reads_footprint) << (cache ? "cached" : "plain");
  }

  for (const std::string node : {"hextiledimage", "hextilednormalmap"}) {
    const bool normal = node == "hextilednormalmap";
    const std::string type = normal ? "vector3" : "color3";
    const std::string doc =
        R"(<?xml version="1.0"?><materialx version="1.39"><)" + node + R"( name="n" type=")" + type +
        R"("><input name="file" type="filename" value=")" + png + R"("/></)" + node +
        R"(><standard_surface name="S" type="surfaceshader"><input name=")" +
        (normal ? "normal" : "base_color") + R"(" type=")" + type + R"(" nodename="n"/></standard_surface>
<surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial></materialx>)";
    std::vector<Graph> graphs = read_mtlx_string(doc, "mem.mtlx");
    ASSERT_EQ(graphs.size(), 1u);
    EXPECT_TRUE(compile_material(graphs[0], tex, prog).reads_footprint) << node;
  }
}

TEST(Compiler, UniformProgramsReadNothingOfTheShadingPoint) {
  const std::string png = test::temp_dir() + "/checker.png";
  hard::write_checker_png(png);
  TexturePool tex;
  MaterialProgram prog;
  std::vector<std::pair<std::string, Graph>> graphs;
  // An MTL material without maps: constants only.
  Graph flat = new_graph("M_flat");
  add_surface(flat, {{"base_color", value(VT::Color3, 0.2f, 0.4f, 0.6f)},
                     {"specular_roughness", value(VT::Float, 0.3f)},
                     {"metalness", value(VT::Float, 0.5f)}});
  graphs.push_back({"uniform", flat});
  // A pattern at a constant position: the passes fold it into its value.
  Graph noise = new_graph("M_noise_at_a_constant");
  int n = add(noise, "n", "noise3d", VT::Float, {{"position", value(VT::Vector3, 0.3f, 0.1f, 0.7f)}});
  add_surface(noise, {{"base", link(n)}});
  graphs.push_back({"uniform", noise});
  graphs.push_back({"texcoord", ramp_material("M_ramp", make_float3(0, 0, 0), make_float3(1, 1, 1))});
  graphs.push_back({"position", unary_chain(2)});
  for (const char* node : {"normal", "tangent", "bitangent"}) {
    Graph g = new_graph(std::string("M_") + node);
    int v = add(g, "v", node, VT::Vector3);
    add_surface(g, {{"base_color", link(v)}});
    graphs.push_back({node, g});
  }
  Graph image = new_graph("M_image");
  int img = add(image, "img", "image", VT::Color3,
                {{"file", text(png, VT::Filename)}, {"texcoord", value(VT::Vector2, 0.25f, 0.5f)}});
  add_surface(image, {{"base_color", link(img)}});
  graphs.push_back({"image (its footprint)", image});

  for (auto& [why, g] : graphs) {
    SCOPED_TRACE(why);
    const CompiledMaterial& cm = compile_material(g, tex, prog);
    EXPECT_EQ(cm.uniform, why == "uniform");
    // The interpreter's own reading: two points apart in uv and position.
    float a[PMC_P_COUNT], b[PMC_P_COUNT];
    test::run_program_at(prog, cm, 0.1f, 0.2f, a, make_float3(0.3f, -0.2f, 0.7f));
    test::run_program_at(prog, cm, 0.7f, 0.9f, b, make_float3(-1.5f, 2.0f, 0.25f));
    if (cm.uniform) EXPECT_EQ(std::memcmp(a, b, sizeof a), 0);
    if (why == "texcoord" || why == "position") EXPECT_NE(std::memcmp(a, b, sizeof a), 0);
  }

  // A cached program reads its key, whatever its sub-graph.
  Graph cached = unary_chain(8);
  CompileOptions options;
  options.cache = true;
  options.cache_min_nodes = 2;
  const CompiledMaterial& cm = compile_material(cached, tex, prog, options);
  ASSERT_FALSE(cm.cache_plan.points.empty());
  EXPECT_FALSE(cm.uniform);

  // A program that writes the normal replaces each point's own: not uniform,
  // though it reads nothing (OUTPUT.3 param[normal] of a constant, END, the constant).
  const uint32_t c = pmc_operand(1, 4, 3);
  const std::vector<uint32_t> writes_normal = {pmc_op_header(PMC_OP_OUTPUT, 3, 1, PMC_P_NORMAL), 0u, c,
                                               pmc_op_header(PMC_OP_END, 1, 0, 0), 0u};
  EXPECT_FALSE(program_is_uniform(writes_normal));
  const std::vector<uint32_t> writes_base = {pmc_op_header(PMC_OP_OUTPUT, 3, 1, PMC_P_BASE_COLOR), 0u, c,
                                             pmc_op_header(PMC_OP_END, 1, 0, 0), 0u};
  EXPECT_TRUE(program_is_uniform(writes_base));
}

}  // namespace
}  // namespace pmc
