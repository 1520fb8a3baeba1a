// node_graph.cpp — type helpers for the node graph.
#include "materials/node_graph.h"

namespace pmc {

int type_width(ValueType t) {
  switch (t) {
    case ValueType::Float:
    case ValueType::Integer:
    case ValueType::Boolean:
      return 1;
    case ValueType::Vector2:
      return 2;
    case ValueType::Vector3:
    case ValueType::Color3:
      return 3;
    case ValueType::Vector4:
    case ValueType::Color4:
      return 4;
    default:
      return 0;
  }
}

bool is_numeric(ValueType t) { return type_width(t) > 0; }

Input Input::constant(const std::string& name, ValueType t, float a, float b, float c, float d) {
  Input in;
  in.name = name;
  in.type = t;
  in.value = Value::number(t, a, b, c, d);
  return in;
}

Input Input::link(const std::string& name, ValueType t, int node) {
  Input in;
  in.name = name;
  in.type = t;
  in.linked = true;
  in.node = node;
  return in;
}

const char* type_name(ValueType t) {
  switch (t) {
    case ValueType::Float:
      return "float";
    case ValueType::Integer:
      return "integer";
    case ValueType::Boolean:
      return "boolean";
    case ValueType::Vector2:
      return "vector2";
    case ValueType::Vector3:
      return "vector3";
    case ValueType::Vector4:
      return "vector4";
    case ValueType::Color3:
      return "color3";
    case ValueType::Color4:
      return "color4";
    case ValueType::String:
      return "string";
    case ValueType::Filename:
      return "filename";
    case ValueType::Surface:
      return "surfaceshader";
    case ValueType::Material:
      return "material";
    case ValueType::BSDF:
      return "BSDF";
    case ValueType::EDF:
      return "EDF";
    case ValueType::VDF:
      return "VDF";
    case ValueType::Matrix33:
      return "matrix33";
    case ValueType::Matrix44:
      return "matrix44";
    default:
      return "none";
  }
}

ValueType parse_type(const std::string& n) {
  for (ValueType t :
       {ValueType::Float, ValueType::Integer, ValueType::Boolean, ValueType::Vector2, ValueType::Vector3,
        ValueType::Vector4, ValueType::Color3, ValueType::Color4, ValueType::String, ValueType::Filename,
        ValueType::Surface, ValueType::Material, ValueType::Matrix33, ValueType::Matrix44, ValueType::BSDF,
        ValueType::EDF, ValueType::VDF})
    if (n == type_name(t)) return t;
  return ValueType::None;
}

Value Value::number(ValueType t, float a, float b, float c, float d) {
  Value v;
  v.type = t;
  v.f = {a, b, c, d};
  return v;
}

const Input* Node::input(const std::string& n) const {
  for (const Input& i : inputs)
    if (i.name == n) return &i;
  return nullptr;
}

Input* Node::input(const std::string& n) {
  for (Input& i : inputs)
    if (i.name == n) return &i;
  return nullptr;
}

size_t Graph::live_count() const {
  size_t n = 0;
  for (const Node& node : nodes) n += node.dead ? 0 : 1;
  return n;
}

}  // namespace pmc
