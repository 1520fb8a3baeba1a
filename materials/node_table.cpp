// node_table.cpp — the node table (node_table.h says what each field means and
// what adding a node touches). Defaults are MaterialX 1.39 stdlib_defs.mtlx.
#include "materials/node_table.h"

#include <limits>
#include <map>

namespace pmc {
namespace {

using VT = ValueType;

Value num(float a, float b = 0, float c = 0, float d = 0) { return Value::number(VT::Float, a, b, c, d); }
Value broadcast(float a) { return Value::number(VT::Float, a, a, a, a); }
Value text(const std::string& s) {
  Value v;
  v.type = VT::String;
  v.text = s;
  return v;
}

InputDef in_t(const std::string& name, float def) { return {name, "T", broadcast(def), GeomDefault::None}; }
InputDef in_f(const std::string& name, float def) { return {name, "float", num(def), GeomDefault::None}; }
InputDef in_i(const std::string& name, int def) {
  return {name, "integer", num(float(def)), GeomDefault::None};
}
InputDef in_b(const std::string& name, bool def) {
  return {name, "boolean", num(def ? 1.0f : 0.0f), GeomDefault::None};
}
InputDef in_v2(const std::string& name, float x, float y) {
  return {name, "vector2", num(x, y), GeomDefault::None};
}
InputDef in_s(const std::string& name, const std::string& def) {
  return {name, "string", text(def), GeomDefault::None};
}
InputDef in_geom(const std::string& name, const std::string& type, GeomDefault g) {
  return {name, type, num(0), g};
}
// An input the opcode does not read (a texcoord set index, a frame input).
InputDef not_operand(InputDef d) {
  d.operand = false;
  return d;
}
InputDef in_any(const std::string& name) { return {name, "any", num(0), GeomDefault::None}; }

const std::vector<std::string> kFloatVec = {"float", "vector2", "vector3", "vector4", "color3", "color4"};
// Integers and booleans are floats of one lane in pmc.
const std::vector<std::string> kAllNumeric = {"float",  "vector2", "vector3", "vector4",
                                              "color3", "color4",  "integer", "boolean"};

std::map<std::string, NodeDef> build() {
  std::map<std::string, NodeDef> m;
  auto def = [&](const std::string& cat, std::vector<std::string> outs, std::vector<InputDef> ins, int op,
                 unsigned imm = 0) -> NodeDef& {
    NodeDef& d = m[cat];
    d.category = cat;
    d.output_types = std::move(outs);
    d.inputs = std::move(ins);
    d.opcode = op;
    d.imm = imm;
    d.emit = op >= 0 ? Emit::Opcode : Emit::Lowered;
    return d;
  };
  // A node of the shading point: reads `deps`, never folded.
  auto geometric = [](NodeDef& d, uint32_t deps) {
    d.deps = deps;
    d.folds = false;
  };

  def("constant", kAllNumeric, {in_t("value", 0)}, PMC_OP_MOVE);
  def("dot", kAllNumeric, {in_t("in", 0)}, PMC_OP_MOVE).algebra.pass_through =
      "in";  // MaterialX "dot" is a pass-through
  geometric(def("texcoord", {"vector2", "vector3"}, {not_operand(in_i("index", 0))}, PMC_OP_TEXCOORD),
            kDepUv);
  geometric(def("position", {"vector3"}, {in_s("space", "object")}, PMC_OP_POSITION), kDepPosition);
  geometric(def("normal", {"vector3"}, {in_s("space", "object")}, PMC_OP_NORMAL), kDepNormal);
  geometric(
      def("tangent", {"vector3"}, {in_s("space", "object"), not_operand(in_i("index", 0))}, PMC_OP_TANGENT),
      kDepTangent);
  geometric(def("bitangent", {"vector3"}, {in_s("space", "object"), not_operand(in_i("index", 0))},
                PMC_OP_BITANGENT),
            kDepBitangent);

  std::vector<InputDef> frame_inputs = {in_s("framerange", ""), not_operand(in_i("frameoffset", 0)),
                                        in_s("frameendaction", "constant")};
  std::vector<InputDef> image = {{"file", "filename", text(""), GeomDefault::None},
                                 in_s("layer", ""),
                                 in_geom("texcoord", "vector2", GeomDefault::UV0),
                                 in_t("default", 0),
                                 in_s("uaddressmode", "periodic"),
                                 in_s("vaddressmode", "periodic"),
                                 in_s("filtertype", "linear")};
  image.insert(image.end(), frame_inputs.begin(), frame_inputs.end());
  NodeDef& img = def("image", kAllNumeric, image, PMC_OP_IMAGE);
  img.emit = Emit::Image;
  img.folds = false;
  std::vector<InputDef> tiled = {{"file", "filename", text(""), GeomDefault::None},
                                 in_t("default", 0),
                                 in_geom("texcoord", "vector2", GeomDefault::UV0),
                                 in_v2("uvtiling", 1, 1),
                                 in_v2("uvoffset", 0, 0),
                                 in_v2("realworldimagesize", 1, 1),
                                 in_v2("realworldtilesize", 1, 1),
                                 in_s("filtertype", "linear")};
  tiled.insert(tiled.end(), frame_inputs.begin(), frame_inputs.end());
  def("tiledimage", kAllNumeric, tiled, -1).lower = Lower::TiledImage;  // place math + image
  // Hex-tiled images (core/device/pmc_hextile.h): one opcode each, which
  // reads the texture like `image` (Emit::Image adds the mode operand after
  // `default`). The texture reads depend on the uv only, like image's.
  std::vector<InputDef> hextile = {{"file", "filename", text(""), GeomDefault::None},
                                   in_geom("texcoord", "vector2", GeomDefault::UV0),
                                   in_v2("tiling", 1, 1),
                                   in_f("rotation", 1),
                                   in_v2("rotationrange", 0, 360),
                                   in_f("scale", 1),
                                   in_v2("scalerange", 0.5f, 2),
                                   in_f("offset", 1),
                                   in_v2("offsetrange", 0, 1),
                                   in_f("falloff", 0.5f)};
  std::vector<InputDef> heximage = hextile;
  heximage.insert(heximage.end(), {in_t("default", 0),
                                   in_f("falloffcontrast", 0.5f),
                                   {"lumacoeffs", "color3", num(0.2722287f, 0.6740818f, 0.0536895f)}});
  NodeDef& hex = def("hextiledimage", {"color3", "color4"}, heximage, PMC_OP_HEXIMAGE);
  hex.emit = Emit::Image;
  hex.folds = false;
  std::vector<InputDef> hexnormal = hextile;
  hexnormal.insert(hexnormal.end(), {{"default", "vector3", num(0.5f, 0.5f, 1.0f)},
                                     in_f("strength", 1),
                                     in_b("flip_g", false),
                                     in_geom("normal", "vector3", GeomDefault::Nworld),
                                     in_geom("tangent", "vector3", GeomDefault::Tworld),
                                     not_operand(in_geom("bitangent", "vector3", GeomDefault::Bworld))});
  NodeDef& hexn = def("hextilednormalmap", {"vector3"}, hexnormal, PMC_OP_HEXNORMALMAP);
  hexn.emit = Emit::Image;
  hexn.folds = false;
  def("place2d", {"vector2"},
      {in_v2("texcoord", 0, 0), in_v2("pivot", 0, 0), in_v2("scale", 1, 1), in_f("rotate", 0),
       in_v2("offset", 0, 0), in_i("operationorder", 0)},
      PMC_OP_PLACE2D);

  def("noise2d", kFloatVec,
      {in_geom("texcoord", "vector2", GeomDefault::UV0), in_t("amplitude", 1),
       in_f("pivot", 0)},  // opcode operand order
      PMC_OP_NOISE2D);
  def("noise3d", kFloatVec,
      {in_geom("position", "vector3", GeomDefault::Pobject), in_t("amplitude", 1), in_f("pivot", 0)},
      PMC_OP_NOISE3D);
  def("fractal2d", kFloatVec,
      {in_geom("texcoord", "vector2", GeomDefault::UV0), in_t("amplitude", 1), in_i("octaves", 3),
       in_f("lacunarity", 2), in_f("diminish", 0.5f)},
      PMC_OP_FRACTAL2D);
  def("fractal3d", kFloatVec,
      {in_geom("position", "vector3", GeomDefault::Pobject), in_t("amplitude", 1), in_i("octaves", 3),
       in_f("lacunarity", 2), in_f("diminish", 0.5f)},
      PMC_OP_FRACTAL3D);
  def("cellnoise2d", {"float", "vector3", "color3"}, {in_geom("texcoord", "vector2", GeomDefault::UV0)},
      PMC_OP_CELLNOISE2D);
  def("cellnoise3d", {"float", "vector3", "color3"}, {in_geom("position", "vector3", GeomDefault::Pobject)},
      PMC_OP_CELLNOISE3D);
  def("worleynoise2d", {"float", "vector2", "vector3"},
      {in_geom("texcoord", "vector2", GeomDefault::UV0), in_f("jitter", 1), in_i("style", 0)},
      PMC_OP_WORLEY2D);
  def("worleynoise3d", {"float", "vector2", "vector3"},
      {in_geom("position", "vector3", GeomDefault::Pobject), in_f("jitter", 1), in_i("style", 0)},
      PMC_OP_WORLEY3D);

  const float none = std::numeric_limits<float>::quiet_NaN();
  struct Bin {
    const char* name;
    int op;
    float in2;
    float right_identity, left_identity;
    bool zero_absorbs;
  };
  for (Bin b : {Bin{"add", PMC_OP_ADD, 0, 0, 0, false}, Bin{"subtract", PMC_OP_SUB, 0, 0, none, false},
                Bin{"multiply", PMC_OP_MUL, 1, 1, 1, true}, Bin{"divide", PMC_OP_DIV, 1, 1, none, false},
                Bin{"modulo", PMC_OP_MOD, 1, none, none, false}, Bin{"power", PMC_OP_POW, 1, 1, none, false},
                Bin{"min", PMC_OP_MIN, 0, none, none, false}, Bin{"max", PMC_OP_MAX, 0, none, none, false}}) {
    Algebra& a = def(b.name, kAllNumeric, {in_t("in1", 0), in_t("in2", b.in2)}, b.op).algebra;
    a.right_identity = b.right_identity;
    a.left_identity = b.left_identity;
    a.zero_absorbs = b.zero_absorbs;
  }
  struct Un {
    const char* name;
    int op;
  };
  for (Un u :
       {Un{"absval", PMC_OP_ABS}, Un{"floor", PMC_OP_FLOOR}, Un{"ceil", PMC_OP_CEIL}, Un{"sin", PMC_OP_SIN},
        Un{"cos", PMC_OP_COS}, Un{"sqrt", PMC_OP_SQRT}, Un{"normalize", PMC_OP_NORMALIZE}})
    def(u.name, kAllNumeric, {in_t("in", 0)}, u.op);
  struct Un2 {
    const char* name;
    int op;
    float in;
  };
  for (Un2 u : {Un2{"tan", PMC_OP_TAN, 0}, Un2{"asin", PMC_OP_ASIN, 0}, Un2{"acos", PMC_OP_ACOS, 0},
                Un2{"exp", PMC_OP_EXP, 0}, Un2{"ln", PMC_OP_LN, 1}, Un2{"sign", PMC_OP_SIGN, 0},
                Un2{"round", PMC_OP_ROUND, 0}, Un2{"fract", PMC_OP_FRACT, 0}})
    def(u.name, kAllNumeric, {in_t("in", u.in)}, u.op);
  def("atan2", kAllNumeric, {in_t("iny", 0), in_t("inx", 1)}, PMC_OP_ATAN2);
  def("magnitude", {"float"}, {in_any("in")}, PMC_OP_LENGTH).emit = Emit::WidthImm;
  def("crossproduct", {"vector3"}, {in_t("in1", 0), in_t("in2", 0)}, PMC_OP_CROSS);
  // Booleans are 0 or 1: and = min, or = max.
  def("and", {"boolean"}, {in_b("in1", false), in_b("in2", false)}, PMC_OP_MIN);
  def("or", {"boolean"}, {in_b("in1", false), in_b("in2", false)}, PMC_OP_MAX);
  def("not", {"boolean"}, {in_b("in", false)}, PMC_OP_NOT);
  def("ifequal", kAllNumeric, {in_f("value1", 0), in_f("value2", 0), in_t("in1", 0), in_t("in2", 0)},
      PMC_OP_IFEQUAL);
  struct Blend {
    const char* name;
    unsigned mode;
  };
  for (Blend b : {Blend{"plus", PMC_BLEND_PLUS}, Blend{"minus", PMC_BLEND_MINUS},
                  Blend{"difference", PMC_BLEND_DIFFERENCE}, Blend{"burn", PMC_BLEND_BURN},
                  Blend{"dodge", PMC_BLEND_DODGE}, Blend{"screen", PMC_BLEND_SCREEN}})
    def(b.name, {"float", "color3", "color4"}, {in_t("fg", 0), in_t("bg", 0), in_f("mix", 1)}, PMC_OP_BLEND,
        b.mode);
  // Merge nodes on color4 (pmc_compositing.h); the masking nodes on any width.
  struct Comp {
    const char* name;
    unsigned mode;
  };
  for (Comp c :
       {Comp{"disjointover", PMC_COMP_DISJOINTOVER}, Comp{"in", PMC_COMP_IN}, Comp{"mask", PMC_COMP_MASK},
        Comp{"matte", PMC_COMP_MATTE}, Comp{"out", PMC_COMP_OUT}, Comp{"over", PMC_COMP_OVER}})
    def(c.name, {"color4"}, {in_t("fg", 0), in_t("bg", 0), in_f("mix", 1)}, PMC_OP_COMPOSITE, c.mode);
  const InputDef opaque_black = {"in", "T", num(0, 0, 0, 1), GeomDefault::None};
  def("premult", {"color4"}, {opaque_black}, PMC_OP_PREMULT, 0);
  def("unpremult", {"color4"}, {opaque_black}, PMC_OP_PREMULT, 1);
  def("inside", {"float", "color3", "color4"}, {in_t("in", 0), in_f("mask", 1)}, PMC_OP_MUL);
  def("outside", {"float", "color3", "color4"}, {in_t("in", 0), in_f("mask", 0)}, PMC_OP_OUTSIDE);
  def("rotate2d", {"vector2"}, {in_t("in", 0), in_f("amount", 0)}, PMC_OP_ROTATE2D);
  def("rotate3d", {"vector3"},
      {in_t("in", 0), in_f("amount", 0), {"axis", "vector3", num(0, 1, 0), GeomDefault::None}},
      PMC_OP_ROTATE3D);
  // pmc has one space: object space is world space (no instance transforms),
  // so space transforms are the identity (a normal stays normalised).
  std::vector<InputDef> spaces = {in_s("fromspace", ""), in_s("tospace", "")};
  def("transformpoint", {"vector3"}, {in_t("in", 0), spaces[0], spaces[1]}, PMC_OP_MOVE);
  def("transformvector", {"vector3"}, {in_t("in", 0), spaces[0], spaces[1]}, PMC_OP_MOVE);
  def("transformnormal", {"vector3"},
      {{"in", "vector3", num(0, 0, 1), GeomDefault::None}, spaces[0], spaces[1]}, PMC_OP_NORMALIZE);
  // A still image of an OBJ: frame 1, time = frame / fps, no vertex colours or
  // primvars (geomcolor is white, geompropvalue its default).
  def("time", {"float"}, {not_operand(in_f("fps", 24))}, -1).lower = Lower::Time;
  def("frame", {"float"}, {}, -1).lower = Lower::Frame;
  def("geomcolor", {"float", "color3", "color4"}, {not_operand(in_i("index", 0))}, -1).lower =
      Lower::GeomColor;
  def("geompropvalue", kAllNumeric, {in_s("geomprop", ""), in_t("default", 0)}, -1).lower =
      Lower::GeomPropValue;
  // The shading point does not carry the ray direction: viewdirection is
  // approximated by -N (a head-on view), with a warning naming the node.
  def("viewdirection", {"vector3"}, {in_s("space", "world")}, -1).lower = Lower::ViewDirection;
  def("clamp", kAllNumeric, {in_t("in", 0), in_t("low", 0), in_t("high", 1)}, PMC_OP_CLAMP);
  def("smoothstep", kAllNumeric, {in_t("in", 0), in_t("low", 0), in_t("high", 1)}, PMC_OP_SMOOTHSTEP);
  def("remap", kAllNumeric,
      {in_t("in", 0), in_t("inlow", 0), in_t("inhigh", 1), in_t("outlow", 0), in_t("outhigh", 1)},
      PMC_OP_REMAP);
  def("dotproduct", {"float"}, {in_any("in1"), in_any("in2")}, PMC_OP_DOT).emit = Emit::WidthImm;
  Algebra& mix = def("mix", kAllNumeric, {in_t("fg", 0), in_t("bg", 0), in_t("mix", 0)}, PMC_OP_MIX).algebra;
  mix.selector = "mix";
  mix.select0 = "bg";
  mix.select1 = "fg";
  def("ifgreater", kAllNumeric, {in_f("value1", 1), in_f("value2", 0), in_t("in1", 0), in_t("in2", 0)},
      PMC_OP_IFGREATER);
  def("ifgreatereq", kAllNumeric, {in_f("value1", 1), in_f("value2", 0), in_t("in1", 0), in_t("in2", 0)},
      PMC_OP_IFGREATEREQ);
  def("invert", kAllNumeric, {in_t("in", 0), in_t("amount", 1)}, -1).lower = Lower::Invert;  // amount - in

  auto uv = in_geom("texcoord", "vector2", GeomDefault::UV0);
  def("ramplr", kAllNumeric, {in_t("valuel", 0), in_t("valuer", 0), uv}, PMC_OP_RAMPLR);
  def("ramptb", kAllNumeric, {in_t("valuet", 0), in_t("valueb", 0), uv}, PMC_OP_RAMPTB);
  def("ramp4", kAllNumeric,
      {in_t("valuetl", 0), in_t("valuetr", 0), in_t("valuebl", 0), in_t("valuebr", 0), uv}, PMC_OP_RAMP4);
  def("splitlr", kAllNumeric, {in_t("valuel", 0), in_t("valuer", 0), in_f("center", 0.5f), uv},
      PMC_OP_SPLITLR);
  def("splittb", kAllNumeric, {in_t("valuet", 0), in_t("valueb", 0), in_f("center", 0.5f), uv},
      PMC_OP_SPLITTB);

  def("rgbtohsv", {"color3", "color4"}, {in_t("in", 0)}, PMC_OP_RGBTOHSV);
  def("hsvtorgb", {"color3", "color4"}, {in_t("in", 0)}, PMC_OP_HSVTORGB);
  def("luminance", {"color3", "color4"},
      {in_t("in", 0), {"lumacoeffs", "color3", num(0.2722287f, 0.6740818f, 0.0536895f), GeomDefault::None}},
      PMC_OP_LUMINANCE);
  NodeDef& convert = def("convert", kAllNumeric, {in_any("in")}, PMC_OP_MOVE);
  convert.emit = Emit::Convert;
  convert.algebra.pass_through = "in";
  def("extract", {"float"}, {in_any("in"), in_i("index", 0)}, PMC_OP_SWIZZLE).emit = Emit::Extract;
  def("swizzle", kAllNumeric, {in_any("in"), in_s("channels", "")}, PMC_OP_SWIZZLE).emit = Emit::Swizzle;
  def("combine2", {"vector2", "color4", "vector4"}, {in_any("in1"), in_any("in2")}, PMC_OP_MOVE).emit =
      Emit::Combine2;
  def("combine3", {"vector3", "color3"}, {in_f("in1", 0), in_f("in2", 0), in_f("in3", 0)}, PMC_OP_COMBINE);
  def("combine4", {"vector4", "color4"}, {in_f("in1", 0), in_f("in2", 0), in_f("in3", 0), in_f("in4", 0)},
      PMC_OP_COMBINE);
  def("normalmap", {"vector3"},
      {{"in", "vector3", num(0.5f, 0.5f, 1.0f), GeomDefault::None},
       in_f("scale", 1),
       in_geom("normal", "vector3", GeomDefault::Nworld),
       in_geom("tangent", "vector3", GeomDefault::Tworld),
       not_operand(in_geom("bitangent", "vector3", GeomDefault::Bworld)),  // the opcode derives it
       in_s("space", "tangent")},
      PMC_OP_NORMALMAP)
      .folds = false;

  // Lowered to finite differences of shifted copies of the height sub-graph
  // (materials/height_normal.cpp); bump adds the normalmap.
  def("heighttonormal", {"vector3"}, {in_f("in", 0), in_f("scale", 1), uv}, -1).lower = Lower::HeightToNormal;
  def("bump", {"vector3"},
      {in_f("height", 0), in_f("scale", 1), in_geom("normal", "vector3", GeomDefault::Nworld),
       in_geom("tangent", "vector3", GeomDefault::Tworld),
       in_geom("bitangent", "vector3", GeomDefault::Bworld)},
      -1)
      .lower = Lower::Bump;

  std::vector<InputDef> shape = {uv, in_v2("uvtiling", 1, 1), in_v2("uvoffset", 0, 0), in_f("size", 0.5f),
                                 in_b("staggered", false)};
  def("tiledcircles", {"color3", "float"}, shape, PMC_OP_TILEDSHAPE, PMC_SHAPE_CIRCLES);
  def("tiledcloverleafs", {"color3", "float"}, shape, PMC_OP_TILEDSHAPE, PMC_SHAPE_CLOVERLEAFS);
  def("tiledhexagons", {"color3", "float"}, shape, PMC_OP_TILEDSHAPE, PMC_SHAPE_HEXAGONS);
  std::vector<InputDef> lines = {uv, in_v2("uvtiling", 1, 1), in_v2("uvoffset", 0, 0),
                                 in_f("thickness", 0.05f), in_b("staggered", false)};
  def("grid", {"color3", "float"}, lines, PMC_OP_LINEPATTERN, PMC_LINES_GRID);
  def("crosshatch", {"color3", "float"}, lines, PMC_OP_LINEPATTERN, PMC_LINES_CROSSHATCH);

  // Flakes (core/device/pmc_flake.h): four outputs, imm = PMC_FLAKE_* in this order.
  const std::vector<OutputDef> flake_outputs = {
      {"id", "integer"}, {"rand", "float"}, {"presence", "float"}, {"flakenormal", "vector3"}};
  const std::vector<InputDef> flake_frame = {in_geom("normal", "vector3", GeomDefault::Nworld),
                                             in_geom("tangent", "vector3", GeomDefault::Tworld),
                                             in_geom("bitangent", "vector3", GeomDefault::Bworld)};
  for (bool three : {false, true}) {
    std::vector<InputDef> ins = {in_f("size", 0.01f), in_f("roughness", 0.1f), in_f("coverage", 0.5f),
                                 three ? in_geom("position", "vector3", GeomDefault::Pobject) : uv};
    ins.insert(ins.end(), flake_frame.begin(), flake_frame.end());
    def(three ? "flake3d" : "flake2d", {}, ins, PMC_OP_FLAKE).outputs = flake_outputs;
  }
  // pbrlib data nodes (core/device/pmc_pbr_data.h).
  def("roughness_anisotropy", {"vector2"}, {in_f("roughness", 0), in_f("anisotropy", 0)},
      PMC_OP_ROUGHNESS_ANISO);
  def("roughness_dual", {"vector2"}, {in_v2("roughness", 0, 0)}, PMC_OP_ROUGHNESS_DUAL);
  def("artistic_ior", {},
      {{"reflectivity", "color3", num(0.944f, 0.776f, 0.373f), GeomDefault::None},
       {"edge_color", "color3", num(0.998f, 0.981f, 0.751f), GeomDefault::None}},
      PMC_OP_ARTISTIC_IOR)
      .outputs = {{"ior", "color3"}, {"extinction", "color3"}};
  def("blackbody", {"color3"}, {in_f("temperature", 5000)}, PMC_OP_BLACKBODY);
  // Hair data nodes (core/device/pmc_hair_data.h); outputs are vectors (MaterialX's types).
  def("chiang_hair_roughness", {},
      {in_f("longitudinal", 0.1f), in_f("azimuthal", 0.2f), in_f("scale_TT", 0.5f), in_f("scale_TRT", 2.0f)},
      PMC_OP_HAIR_ROUGHNESS)
      .outputs = {{"roughness_R", "vector2"}, {"roughness_TT", "vector2"}, {"roughness_TRT", "vector2"}};
  def("deon_hair_absorption_from_melanin", {"vector3"},
      {in_f("melanin_concentration", 0.25f),
       in_f("melanin_redness", 0.5f),
       {"eumelanin_color", "color3", num(0.657704f, 0.498077f, 0.254107f), GeomDefault::None},
       {"pheomelanin_color", "color3", num(0.829444f, 0.67032f, 0.349938f), GeomDefault::None}},
      PMC_OP_HAIR_MELANIN);
  def("chiang_hair_absorption_from_color", {"vector3"},
      {{"color", "color3", num(1, 1, 1), GeomDefault::None}, in_f("azimuthal_roughness", 0.2f)},
      PMC_OP_HAIR_COLOR);
  return m;
}

const std::map<std::string, NodeDef>& library() {
  static const std::map<std::string, NodeDef> m = build();
  return m;
}

}  // namespace

const NodeDef* find_node_def(const std::string& category) {
  auto it = library().find(category);
  return it == library().end() ? nullptr : &it->second;
}

const OutputDef* find_output(const NodeDef& def, const std::string& name, unsigned* index) {
  for (size_t i = 0; i < def.outputs.size(); ++i)
    if (def.outputs[i].name == name) {
      if (index) *index = unsigned(i);
      return &def.outputs[i];
    }
  return nullptr;
}

std::string output_names(const NodeDef& def) {
  std::string s;
  for (const OutputDef& o : def.outputs) s += (s.empty() ? "" : ", ") + o.name;
  return s;
}

ValueType resolve_input_type(const InputDef& def, ValueType node_type) {
  if (def.type == "T") return node_type;
  if (def.type == "any") return ValueType::None;
  return parse_type(def.type);
}

Input default_input(const InputDef& def, ValueType node_type) {
  const ValueType declared = resolve_input_type(def, node_type);
  Input in;
  in.name = def.name;
  in.value = def.value;
  in.type = declared == ValueType::None ? ValueType::Float : declared;
  in.value.type = in.type;
  if (def.type == "T")
    for (int i = 1; i < 4; ++i) in.value.f[size_t(i)] = in.value.f[0];
  return in;
}

std::vector<std::string> supported_categories() {
  std::vector<std::string> out;
  for (const auto& kv : library()) out.push_back(kv.first);
  return out;
}

std::vector<SurfaceParam> surface_params(const std::string& category) {
  if (category == "standard_surface") {
    // The defaults are the device's (PMC_STANDARD_SURFACE, pmc_bytecode.h).
    std::vector<SurfaceParam> out;
#define PMC_STANDARD_SURFACE_PARAM(input, param, width, x, y, z)                     \
  out.push_back({#input,                                                             \
                 param,                                                              \
                 width == 1 ? (param == PMC_P_THIN_WALLED ? VT::Boolean : VT::Float) \
                            : (param == PMC_P_NORMAL ? VT::Vector3 : VT::Color3),    \
                 {x, y, z}});
    PMC_STANDARD_SURFACE(PMC_STANDARD_SURFACE_PARAM)
#undef PMC_STANDARD_SURFACE_PARAM
    return out;
  }
  if (category == "UsdPreviewSurface")
    return {{"diffuseColor", PMC_P_BASE_COLOR, VT::Color3, {0.18f, 0.18f, 0.18f}},
            {"metallic", PMC_P_METALNESS, VT::Float, {0}},
            {"roughness", PMC_P_SPECULAR_ROUGHNESS, VT::Float, {0.5f}},
            {"emissiveColor", PMC_P_EMISSION_COLOR, VT::Color3, {0, 0, 0}},
            {"normal", PMC_P_NORMAL, VT::Vector3, {0, 0, 0}},
            {"opacity", PMC_P_OPACITY, VT::Float, {1}},
            {"ior", PMC_P_SPECULAR_IOR, VT::Float, {1.5f}},
            {"clearcoat", PMC_P_COAT, VT::Float, {0}},
            {"clearcoatRoughness", PMC_P_COAT_ROUGHNESS, VT::Float, {0.01f}},
            {"pmc_emission_weight", PMC_P_EMISSION, VT::Float, {1}},
            // opacity below 1 with opacityThreshold 0 is glass (the reader moves it here)
            {"pmc_transmission", PMC_P_TRANSMISSION, VT::Float, {0}},
            {"pmc_thin_walled", PMC_P_THIN_WALLED, VT::Boolean, {0}}};
  // OpenPBR: emission_luminance weights emission_color as standard_surface's
  // emission does (MaterialX's open_pbr_surface graph multiplies them).
  if (category == "open_pbr_surface")
    return {{"base_weight", PMC_P_BASE, VT::Float, {1}},
            {"base_color", PMC_P_BASE_COLOR, VT::Color3, {0.8f, 0.8f, 0.8f}},
            {"base_metalness", PMC_P_METALNESS, VT::Float, {0}},
            {"specular_weight", PMC_P_SPECULAR, VT::Float, {1}},
            {"specular_color", PMC_P_SPECULAR_COLOR, VT::Color3, {1, 1, 1}},
            {"specular_roughness", PMC_P_SPECULAR_ROUGHNESS, VT::Float, {0.3f}},
            {"specular_ior", PMC_P_SPECULAR_IOR, VT::Float, {1.5f}},
            {"emission_luminance", PMC_P_EMISSION, VT::Float, {0}},
            {"emission_color", PMC_P_EMISSION_COLOR, VT::Color3, {1, 1, 1}},
            {"geometry_normal", PMC_P_NORMAL, VT::Vector3, {0, 0, 0}},
            {"geometry_opacity", PMC_P_OPACITY, VT::Float, {1}},
            {"coat_weight", PMC_P_COAT, VT::Float, {0}},
            {"coat_color", PMC_P_COAT_COLOR, VT::Color3, {1, 1, 1}},
            {"coat_roughness", PMC_P_COAT_ROUGHNESS, VT::Float, {0}},
            {"coat_ior", PMC_P_COAT_IOR, VT::Float, {1.6f}},
            {"specular_roughness_anisotropy", PMC_P_SPECULAR_ANISOTROPY, VT::Float, {0}},
            {"transmission_weight", PMC_P_TRANSMISSION, VT::Float, {0}},
            {"transmission_color", PMC_P_TRANSMISSION_COLOR, VT::Color3, {1, 1, 1}},
            {"transmission_depth", PMC_P_TRANSMISSION_DEPTH, VT::Float, {0}},
            {"fuzz_weight", PMC_P_SHEEN, VT::Float, {0}},
            {"fuzz_color", PMC_P_SHEEN_COLOR, VT::Color3, {1, 1, 1}},
            {"fuzz_roughness", PMC_P_SHEEN_ROUGHNESS, VT::Float, {0.5f}},
            {"geometry_thin_walled", PMC_P_THIN_WALLED, VT::Boolean, {0}}};
  // glTF: emissive is a colour, emissive_strength its weight; alpha is the
  // opacity (ignored in alpha_mode OPAQUE, by the reader).
  if (category == "gltf_pbr")
    return {{"base_color", PMC_P_BASE_COLOR, VT::Color3, {1, 1, 1}},
            {"metallic", PMC_P_METALNESS, VT::Float, {1}},
            {"roughness", PMC_P_SPECULAR_ROUGHNESS, VT::Float, {1}},
            {"normal", PMC_P_NORMAL, VT::Vector3, {0, 0, 0}},
            {"specular", PMC_P_SPECULAR, VT::Float, {1}},
            {"specular_color", PMC_P_SPECULAR_COLOR, VT::Color3, {1, 1, 1}},
            {"ior", PMC_P_SPECULAR_IOR, VT::Float, {1.5f}},
            {"alpha", PMC_P_OPACITY, VT::Float, {1}},
            {"clearcoat", PMC_P_COAT, VT::Float, {0}},
            {"clearcoat_roughness", PMC_P_COAT_ROUGHNESS, VT::Float, {0}},
            {"emissive", PMC_P_EMISSION_COLOR, VT::Color3, {0, 0, 0}},
            {"emissive_strength", PMC_P_EMISSION, VT::Float, {1}},
            {"transmission", PMC_P_TRANSMISSION, VT::Float, {0}},
            {"sheen_color", PMC_P_SHEEN_COLOR, VT::Color3, {0, 0, 0}},
            {"sheen_roughness", PMC_P_SHEEN_ROUGHNESS, VT::Float, {0}},
            {"anisotropy_strength", PMC_P_SPECULAR_ANISOTROPY, VT::Float, {0}},
            // radians to turns
            {"anisotropy_rotation", PMC_P_SPECULAR_ROTATION, VT::Float, {0}, 0.15915494f, 0.0f},
            // sheen_color carries the weight; without the volume extension
            // (thickness 0) glTF transmission is thin-walled
            {"pmc_sheen_weight", PMC_P_SHEEN, VT::Float, {1}},
            {"pmc_thin_walled", PMC_P_THIN_WALLED, VT::Boolean, {1}}};
  // Disney: specular 0.5 is F0 = 0.04 (IOR 1.5), so it scales pmc's specular
  // weight by 2; a clearcoat gloss of 1 is a smooth coat (roughness 1 - gloss).
  if (category == "disney_principled")
    return {{"baseColor", PMC_P_BASE_COLOR, VT::Color3, {0.16f, 0.16f, 0.16f}},
            {"metallic", PMC_P_METALNESS, VT::Float, {0}},
            {"roughness", PMC_P_SPECULAR_ROUGHNESS, VT::Float, {0.5f}},
            {"specular", PMC_P_SPECULAR, VT::Float, {0.5f}, 2.0f, 0.0f},
            {"clearcoat", PMC_P_COAT, VT::Float, {0}},
            {"clearcoatGloss", PMC_P_COAT_ROUGHNESS, VT::Float, {1}, -1.0f, 1.0f},
            {"anisotropic", PMC_P_SPECULAR_ANISOTROPY, VT::Float, {0}},
            {"sheen", PMC_P_SHEEN, VT::Float, {0}}};
  // Unlit: emission only, no reflection.
  if (category == "surface_unlit")
    return {{"emission", PMC_P_EMISSION, VT::Float, {1}},
            {"emission_color", PMC_P_EMISSION_COLOR, VT::Color3, {1, 1, 1}},
            {"opacity", PMC_P_OPACITY, VT::Float, {1}},
            {"pmc_base", PMC_P_BASE, VT::Float, {0}},
            {"pmc_specular", PMC_P_SPECULAR, VT::Float, {0}}};
  if (category == "pmc_mtl_surface")
    return {{"model", PMC_P_MODEL, VT::Float, {1}},
            {"base_color", PMC_P_BASE_COLOR, VT::Color3, {0.5f, 0.5f, 0.5f}},
            {"specular_color", PMC_P_SPECULAR_COLOR, VT::Color3, {0, 0, 0}},
            {"specular_roughness", PMC_P_SPECULAR_ROUGHNESS, VT::Float, {1}},
            {"emission", PMC_P_EMISSION, VT::Float, {1}},
            {"emission_color", PMC_P_EMISSION_COLOR, VT::Color3, {0, 0, 0}},
            {"opacity", PMC_P_OPACITY, VT::Float, {1}},
            {"normal", PMC_P_NORMAL, VT::Vector3, {0, 0, 0}},
            {"transmission", PMC_P_TRANSMISSION, VT::Float, {0}},
            {"transmission_color", PMC_P_TRANSMISSION_COLOR, VT::Color3, {1, 1, 1}},
            {"specular_IOR", PMC_P_SPECULAR_IOR, VT::Float, {1.5f}}};
  return {};
}

}  // namespace pmc
