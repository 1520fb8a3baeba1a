// node_library.cpp — the table of supported nodes (MaterialX 1.39 stdlib defaults).
#include "materials/node_library.h"

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
InputDef in_any(const std::string& name) { return {name, "any", num(0), GeomDefault::None}; }

const std::vector<std::string> kAllNumeric = {"float", "vector2", "vector3", "vector4", "color3", "color4"};
const std::vector<std::string> kFloatVec = kAllNumeric;

std::map<std::string, NodeDef> build() {
  std::map<std::string, NodeDef> m;
  auto def = [&](const std::string& cat, std::vector<std::string> outs, std::vector<InputDef> ins, int op,
                 unsigned imm = 0) {
    m[cat] = NodeDef{cat, std::move(outs), std::move(ins), op, imm};
  };

  def("constant", kAllNumeric, {in_t("value", 0)}, PMC_OP_MOVE);
  def("dot", kAllNumeric, {in_t("in", 0)}, PMC_OP_MOVE);  // MaterialX "dot" is a pass-through
  def("texcoord", {"vector2", "vector3"}, {in_i("index", 0)}, PMC_OP_TEXCOORD);
  def("position", {"vector3"}, {in_s("space", "object")}, PMC_OP_POSITION);
  def("normal", {"vector3"}, {in_s("space", "object")}, PMC_OP_NORMAL);
  def("tangent", {"vector3"}, {in_s("space", "object"), in_i("index", 0)}, PMC_OP_TANGENT);
  def("bitangent", {"vector3"}, {in_s("space", "object"), in_i("index", 0)}, PMC_OP_BITANGENT);

  std::vector<InputDef> frame_inputs = {in_s("framerange", ""), in_i("frameoffset", 0),
                                        in_s("frameendaction", "constant")};
  std::vector<InputDef> image = {{"file", "filename", text(""), GeomDefault::None},
                                 in_s("layer", ""),
                                 in_t("default", 0),
                                 in_geom("texcoord", "vector2", GeomDefault::UV0),
                                 in_s("uaddressmode", "periodic"),
                                 in_s("vaddressmode", "periodic"),
                                 in_s("filtertype", "linear")};
  image.insert(image.end(), frame_inputs.begin(), frame_inputs.end());
  def("image", kAllNumeric, image, PMC_OP_IMAGE);
  std::vector<InputDef> tiled = {{"file", "filename", text(""), GeomDefault::None},
                                 in_t("default", 0),
                                 in_geom("texcoord", "vector2", GeomDefault::UV0),
                                 in_v2("uvtiling", 1, 1),
                                 in_v2("uvoffset", 0, 0),
                                 in_v2("realworldimagesize", 1, 1),
                                 in_v2("realworldtilesize", 1, 1),
                                 in_s("filtertype", "linear")};
  tiled.insert(tiled.end(), frame_inputs.begin(), frame_inputs.end());
  def("tiledimage", kAllNumeric, tiled, -1);  // lowered to place math + IMAGE
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

  struct Bin {
    const char* name;
    int op;
    float in2;
  };
  for (Bin b : {Bin{"add", PMC_OP_ADD, 0}, Bin{"subtract", PMC_OP_SUB, 0}, Bin{"multiply", PMC_OP_MUL, 1},
                Bin{"divide", PMC_OP_DIV, 1}, Bin{"modulo", PMC_OP_MOD, 1}, Bin{"power", PMC_OP_POW, 1},
                Bin{"min", PMC_OP_MIN, 0}, Bin{"max", PMC_OP_MAX, 0}})
    def(b.name, kAllNumeric, {in_t("in1", 0), in_t("in2", b.in2)}, b.op);
  struct Un {
    const char* name;
    int op;
  };
  for (Un u :
       {Un{"absval", PMC_OP_ABS}, Un{"floor", PMC_OP_FLOOR}, Un{"ceil", PMC_OP_CEIL}, Un{"sin", PMC_OP_SIN},
        Un{"cos", PMC_OP_COS}, Un{"sqrt", PMC_OP_SQRT}, Un{"normalize", PMC_OP_NORMALIZE}})
    def(u.name, kAllNumeric, {in_t("in", 0)}, u.op);
  def("clamp", kAllNumeric, {in_t("in", 0), in_t("low", 0), in_t("high", 1)}, PMC_OP_CLAMP);
  def("smoothstep", kAllNumeric, {in_t("in", 0), in_t("low", 0), in_t("high", 1)}, PMC_OP_SMOOTHSTEP);
  def("remap", kAllNumeric,
      {in_t("in", 0), in_t("inlow", 0), in_t("inhigh", 1), in_t("outlow", 0), in_t("outhigh", 1)},
      PMC_OP_REMAP);
  def("dotproduct", {"float"}, {in_any("in1"), in_any("in2")}, PMC_OP_DOT);
  def("mix", kAllNumeric, {in_t("fg", 0), in_t("bg", 0), in_t("mix", 0)}, PMC_OP_MIX);
  def("ifgreater", kAllNumeric, {in_f("value1", 1), in_f("value2", 0), in_t("in1", 0), in_t("in2", 0)},
      PMC_OP_IFGREATER);
  def("ifgreatereq", kAllNumeric, {in_f("value1", 1), in_f("value2", 0), in_t("in1", 0), in_t("in2", 0)},
      PMC_OP_IFGREATEREQ);
  def("invert", kAllNumeric, {in_t("in", 0), in_t("amount", 1)}, -1);  // lowered to amount - in

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
  def("convert", kAllNumeric, {in_any("in")}, -1);
  def("extract", {"float"}, {in_any("in"), in_i("index", 0)}, -1);
  def("swizzle", kAllNumeric, {in_any("in"), in_s("channels", "")}, -1);
  def("combine2", {"vector2", "color4", "vector4"}, {in_any("in1"), in_any("in2")}, -1);
  def("combine3", {"vector3", "color3"}, {in_f("in1", 0), in_f("in2", 0), in_f("in3", 0)}, PMC_OP_COMBINE);
  def("combine4", {"vector4", "color4"}, {in_f("in1", 0), in_f("in2", 0), in_f("in3", 0), in_f("in4", 0)},
      PMC_OP_COMBINE);
  def("normalmap", {"vector3"},
      {{"in", "vector3", num(0.5f, 0.5f, 1.0f), GeomDefault::None},
       in_f("scale", 1),
       in_geom("normal", "vector3", GeomDefault::Nworld),
       in_geom("tangent", "vector3", GeomDefault::Tworld),
       in_geom("bitangent", "vector3", GeomDefault::Bworld),
       in_s("space", "tangent")},
      PMC_OP_NORMALMAP);

  // Lowered to finite differences of shifted copies of the height sub-graph
  // (materials/height_normal.cpp); bump adds the normalmap.
  def("heighttonormal", {"vector3"}, {in_f("in", 0), in_f("scale", 1), uv}, -1);
  def("bump", {"vector3"},
      {in_f("height", 0), in_f("scale", 1), in_geom("normal", "vector3", GeomDefault::Nworld),
       in_geom("tangent", "vector3", GeomDefault::Tworld),
       in_geom("bitangent", "vector3", GeomDefault::Bworld)},
      -1);

  std::vector<InputDef> shape = {uv, in_v2("uvtiling", 1, 1), in_v2("uvoffset", 0, 0), in_f("size", 0.5f),
                                 in_b("staggered", false)};
  def("tiledcircles", {"color3", "float"}, shape, PMC_OP_TILEDSHAPE, PMC_SHAPE_CIRCLES);
  def("tiledcloverleafs", {"color3", "float"}, shape, PMC_OP_TILEDSHAPE, PMC_SHAPE_CLOVERLEAFS);
  def("tiledhexagons", {"color3", "float"}, shape, PMC_OP_TILEDSHAPE, PMC_SHAPE_HEXAGONS);
  std::vector<InputDef> lines = {uv, in_v2("uvtiling", 1, 1), in_v2("uvoffset", 0, 0),
                                 in_f("thickness", 0.05f), in_b("staggered", false)};
  def("grid", {"color3", "float"}, lines, PMC_OP_LINEPATTERN, PMC_LINES_GRID);
  def("crosshatch", {"color3", "float"}, lines, PMC_OP_LINEPATTERN, PMC_LINES_CROSSHATCH);
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

ValueType resolve_input_type(const InputDef& def, ValueType node_type) {
  if (def.type == "T") return node_type;
  if (def.type == "any") return ValueType::None;
  return parse_type(def.type);
}

std::vector<std::string> supported_categories() {
  std::vector<std::string> out;
  for (const auto& kv : library()) out.push_back(kv.first);
  return out;
}

std::vector<SurfaceParam> surface_params(const std::string& category) {
  if (category == "standard_surface")
    return {{"base", PMC_P_BASE, VT::Float, {1}},
            {"base_color", PMC_P_BASE_COLOR, VT::Color3, {0.8f, 0.8f, 0.8f}},
            {"metalness", PMC_P_METALNESS, VT::Float, {0}},
            {"specular", PMC_P_SPECULAR, VT::Float, {1}},
            {"specular_color", PMC_P_SPECULAR_COLOR, VT::Color3, {1, 1, 1}},
            {"specular_roughness", PMC_P_SPECULAR_ROUGHNESS, VT::Float, {0.2f}},
            {"specular_IOR", PMC_P_SPECULAR_IOR, VT::Float, {1.5f}},
            {"emission", PMC_P_EMISSION, VT::Float, {0}},
            {"emission_color", PMC_P_EMISSION_COLOR, VT::Color3, {1, 1, 1}},
            {"normal", PMC_P_NORMAL, VT::Vector3, {0, 0, 0}},
            {"opacity", PMC_P_OPACITY, VT::Color3, {1, 1, 1}},
            {"coat", PMC_P_COAT, VT::Float, {0}},
            {"coat_color", PMC_P_COAT_COLOR, VT::Color3, {1, 1, 1}},
            {"coat_roughness", PMC_P_COAT_ROUGHNESS, VT::Float, {0.1f}}};
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
            {"pmc_emission_weight", PMC_P_EMISSION, VT::Float, {1}}};
  if (category == "pmc_mtl_surface")
    return {{"model", PMC_P_MODEL, VT::Float, {1}},
            {"base_color", PMC_P_BASE_COLOR, VT::Color3, {0.5f, 0.5f, 0.5f}},
            {"specular_color", PMC_P_SPECULAR_COLOR, VT::Color3, {0, 0, 0}},
            {"specular_roughness", PMC_P_SPECULAR_ROUGHNESS, VT::Float, {1}},
            {"emission", PMC_P_EMISSION, VT::Float, {1}},
            {"emission_color", PMC_P_EMISSION_COLOR, VT::Color3, {0, 0, 0}},
            {"opacity", PMC_P_OPACITY, VT::Float, {1}},
            {"normal", PMC_P_NORMAL, VT::Vector3, {0, 0, 0}}};
  return {};
}

}  // namespace pmc
