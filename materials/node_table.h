// node_table.h — the one table of node semantics: every node pmc compiles natively.
//
// Each NodeDef says, for one MaterialX node category:
//  - inputs: names, types ("T" = the node's own type, which also accepts a
//    broadcast float), MaterialX 1.39 defaults and geometric defaults (an
//    unconnected texcoord is UV0), listed in the order the opcode reads its
//    operands; `operand = false` marks inputs the opcode does not read (space
//    strings, texcoord indices, filenames);
//  - deps: the shading-point inputs the node itself reads (texcoord -> uv),
//    from which graph_analysis.cpp computes every node's dependency bits;
//  - folds: whether a node whose inputs are all constant is evaluated at
//    compile time (false for geometric nodes, images, normal maps);
//  - algebra: the identities the folding pass applies (x*1, x+0, x*0, mix by
//    0 or 1, pass-throughs), as data;
//  - how it lowers: `emit` (an opcode with the inputs as operands, or one of
//    the few emitters in emit.cpp: convert, extract, swizzle, combine2, images,
//    operand-width opcodes), or `lower` (rewritten into other nodes before
//    compiling, by lowering.cpp: invert, tiledimage, heighttonormal, bump,
//    and the scene-constant nodes time, frame, geomcolor, geompropvalue).
// Surface shaders (standard_surface, UsdPreviewSurface, pmc_mtl_surface) are
// listed by surface_params(): which inputs become which BSDF parameters.
//
// Adding a node touches:
//  1. this table (node_table.cpp): one def() line, with its inputs in operand order;
//  2. the interpreter, if no existing opcode computes it: the opcode in
//     PMC_OPCODES (core/abi/pmc_bytecode.h) with its operand slots named in
//     the order of the inputs here, its case in one of pmc_interp_lanes'
//     opcode groups, reading the operands by slot name
//     (core/device/pmc_interp.h; the math of a larger node in its own
//     core/device/pmc_*.h, included there, which the host reference and the
//     kernels both compile), and a parity case in
//     tests/gpu/interpreter_parity_test.cpp (device against host);
//  3. tests/materials/node_table_test.cpp: an expected value for the node from
//     its named inputs (an analytic formula or a direct call of the device
//     function), which checks the operand order; the test fails for a table
//     node without one. The device function itself needs a test against an
//     independent answer (a formula, published values, MaterialX's own code).
// A node with several outputs (MaterialX type "multioutput": flake2d,
// artistic_ior) lists them in `outputs` instead of `output_types`; the
// opcode's imm is the index of the output a graph node computes
// (Node::output, from the consumer's output="..."), and node_table_test.cpp
// expects an answer per output ("flake2d.rand").
// A node MaterialX defines as a nodegraph needs no entry: the reader expands
// it from the MaterialX library's implementation.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/abi/pmc_bytecode.h"
#include "materials/node_graph.h"

namespace pmc {

// Shading-point dependency bits.
enum : uint32_t { kDepUv = 1, kDepPosition = 2, kDepNormal = 4, kDepTangent = 8, kDepBitangent = 16 };

enum class GeomDefault { None, UV0, Pobject, Pworld, Nworld, Nobject, Tworld, Tobject, Bworld, Vworld };

struct InputDef {
  std::string name;
  std::string type;  // "T" (the node's type), "any", "float", "vector2", ..., "string", "filename",
                     // "integer", "boolean"
  Value value;       // default when not geometric
  GeomDefault geom = GeomDefault::None;
  bool operand = true;  // read by the opcode (strings and filenames never are)
};

// How a node becomes instructions (emit.cpp).
enum class Emit {
  Opcode,    // `opcode` with imm `imm`, the operand inputs in table order
  Convert,   // MOVE, or SWIZZLE when widening (MaterialX pads with 0, and 1 in the 4th lane)
  Extract,   // SWIZZLE of one lane
  Swizzle,   // SWIZZLE by the `channels` string
  Combine2,  // two MOVEs of any widths side by side
  Image,     // a texture from the pool; `opcode` (IMAGE, HEXIMAGE, HEXNORMALMAP), imm = its index
  WidthImm,  // `opcode` with imm = the first operand's width (dotproduct, magnitude)
  Lowered,   // rewritten by lowering.cpp before emission
};

// Graph rewrites before compiling (lowering.cpp), in three phases: plain
// rewrites in node order, then bumps into normalmap(heighttonormal), then
// heighttonormal inputs-first (it copies its height sub-graph).
enum class Lower {
  None,
  Invert,
  TiledImage,
  Bump,
  HeightToNormal,
  Time,
  Frame,
  GeomColor,
  GeomPropValue,
  ViewDirection
};

// Identities the folding pass applies (passes.cpp). in1/in2 are the binary
// operands; NaN means "no such identity".
struct Algebra {
  float right_identity = std::numeric_limits<float>::quiet_NaN();  // in2 == it: the node is in1
  float left_identity = std::numeric_limits<float>::quiet_NaN();   // in1 == it: the node is in2
  bool zero_absorbs = false;                                       // in1 or in2 == 0: the node is 0
  const char* selector = nullptr;                                  // mix: 0 picks select0, 1 select1
  const char* select0 = nullptr;
  const char* select1 = nullptr;
  const char* pass_through = nullptr;  // the node equals this input when their widths match
};

// One named output of a node with several (MaterialX type "multioutput").
struct OutputDef {
  std::string name;
  std::string type;
};

struct NodeDef {
  std::string category;
  std::vector<std::string> output_types;  // allowed output types (nodes with one output)
  // Nodes with several outputs: their names and types, in the order of the
  // imm that selects one (a graph node computes the output Node::output
  // names; emit.cpp passes its index as the opcode's imm).
  std::vector<OutputDef> outputs;
  std::vector<InputDef> inputs;  // in operand order
  int opcode = -1;               // PMC_OP_*, or -1
  unsigned imm = 0;
  Emit emit = Emit::Opcode;
  uint32_t deps = 0;  // kDep* bits the node itself reads
  bool folds = true;
  Algebra algebra;
  Lower lower = Lower::None;
};

// The definition for `category`, or nullptr if pmc has no native one.
const NodeDef* find_node_def(const std::string& category);
// The output named `name` of a multi-output node, or nullptr; its index in
// def.outputs goes to *index.
const OutputDef* find_output(const NodeDef& def, const std::string& name, unsigned* index = nullptr);
// "id, rand, presence, flakenormal", for messages.
std::string output_names(const NodeDef& def);
// Resolves an input's declared type for a node of output type `node_type`.
ValueType resolve_input_type(const InputDef& def, ValueType node_type);
// The input a node of type `node_type` gets when `def` is not given: its
// default value, typed (a T-typed default broadcast to every lane).
Input default_input(const InputDef& def, ValueType node_type);
// Categories in the table (for error messages, docs and tests).
std::vector<std::string> supported_categories();

// Surface shader inputs that become surface parameters.
// An input named "pmc_*" is no input of the shader: a constant the mapping
// sets (surface_unlit has no diffuse lobe: pmc_base = 0).
struct SurfaceParam {
  const char* input;
  int param;  // PMC_P_*
  ValueType type;
  float def[3];                       // the surface's own default (MaterialX 1.39 library values)
  float scale = 1.0f, offset = 0.0f;  // parameter = input * scale + offset
};
// Parameters of a surface category (standard_surface, UsdPreviewSurface,
// open_pbr_surface, gltf_pbr, disney_principled, surface_unlit,
// pmc_mtl_surface); empty if the category is not a surface. Inputs of the
// shader not listed here are not modelled (the reader warns once per material).
std::vector<SurfaceParam> surface_params(const std::string& category);

}  // namespace pmc
