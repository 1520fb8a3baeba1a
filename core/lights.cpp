// lights.cpp — reading lights files and building the light table (power pmf and light tree).
#include "core/lights.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/error.h"
#include "core/light_tree.h"

namespace pmc {
namespace {

constexpr double kPi = 3.14159265358979323846;

using Json = nlohmann::json;

// Reads one JSON object's fields, naming the file and the object in errors:
// "scene.lights.json: lights[2] (spot): 'blend' must be in [0, 1], got 2".
class FieldReader {
 public:
  FieldReader(const Json& obj, std::string where) : obj_(obj), where_(std::move(where)) {}

  [[noreturn]] void error(const std::string& field, const std::string& what) const {
    fail(where_, ": '", field, "' ", what);
  }
  bool has(const char* key) const { return obj_.contains(key); }

  void vec3(const char* key, float out[3], bool required = true) {
    seen_.insert(key);
    if (!obj_.contains(key)) {
      if (required) fail(where_, ": missing '", key, "' (an array of 3 numbers)");
      return;
    }
    const Json& v = obj_.at(key);
    if (!v.is_array() || v.size() != 3) error(key, "must be an array of 3 numbers, got " + describe(v));
    for (int i = 0; i < 3; ++i) {
      if (!v[size_t(i)].is_number()) error(key, "must be an array of 3 numbers, got " + describe(v));
      double x = v[size_t(i)].get<double>();
      if (!std::isfinite(x) || std::fabs(x) > 3.0e38)
        error(key, "holds a value that is not a finite float: " + v[size_t(i)].dump());
      out[i] = float(x);
    }
  }
  // A colour-like triple: every component >= 0.
  void rgb(const char* key, float out[3]) {
    vec3(key, out);
    for (int i = 0; i < 3; ++i)
      if (out[i] < 0.0f) error(key, "must not be negative, got " + obj_.at(key).dump());
  }
  // A direction: normalised, must not be zero.
  void direction(const char* key, float out[3]) {
    vec3(key, out);
    double l = std::sqrt(double(out[0]) * out[0] + double(out[1]) * out[1] + double(out[2]) * out[2]);
    if (!(l > 1e-20)) error(key, "must not be the zero vector");
    for (int i = 0; i < 3; ++i) out[i] = float(out[i] / l);
  }
  // An optional number in [lo, hi] (open ends when lo_open/hi_open).
  float number(const char* key, float fallback, double lo, double hi, bool lo_open, bool hi_open,
               const char* range) {
    seen_.insert(key);
    if (!obj_.contains(key)) return fallback;
    const Json& v = obj_.at(key);
    if (!v.is_number()) error(key, std::string("must be a number in ") + range + ", got " + describe(v));
    double x = v.get<double>();
    bool ok = std::isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
    if (!ok) error(key, std::string("must be in ") + range + ", got " + v.dump());
    return float(x);
  }
  bool boolean(const char* key, bool fallback) {
    seen_.insert(key);
    if (!obj_.contains(key)) return fallback;
    const Json& v = obj_.at(key);
    if (!v.is_boolean()) error(key, "must be true or false, got " + describe(v));
    return v.get<bool>();
  }
  std::string string(const char* key) {
    seen_.insert(key);
    const Json& v = obj_.at(key);
    if (!v.is_string() || v.get<std::string>().empty())
      error(key, "must be a non-empty string, got " + describe(v));
    return v.get<std::string>();
  }
  void allow(const char* key) { seen_.insert(key); }
  // Every field must have been read: a misspelt one is an error, not ignored.
  void no_others(const std::string& expected) const {
    for (auto it = obj_.begin(); it != obj_.end(); ++it)
      if (!seen_.count(it.key())) fail(where_, ": unknown field '", it.key(), "' (expected ", expected, ")");
  }

  static std::string describe(const Json& v) {
    std::string s = v.dump();
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
  }

 private:
  const Json& obj_;
  std::string where_;
  std::set<std::string> seen_;
};

LightSpec read_light(const Json& j, const std::string& where_index) {
  if (!j.is_object()) fail(where_index, ": a light must be a JSON object, got ", FieldReader::describe(j));
  if (!j.contains("type")) fail(where_index, ": missing 'type' (point, spot, directional or quad)");
  if (!j.at("type").is_string())
    fail(where_index, ": 'type' must be a string (point, spot, directional or quad), got ",
         FieldReader::describe(j.at("type")));
  const std::string type = j.at("type").get<std::string>();
  FieldReader r(j, where_index + " (" + type + ")");
  r.allow("type");
  r.allow("name");
  LightSpec l;
  if (type == "point") {
    l.type = LightSpec::Type::Point;
    r.vec3("position", l.position);
    r.rgb("intensity", l.rgb);
    r.no_others("type, name, position, intensity");
  } else if (type == "spot") {
    l.type = LightSpec::Type::Spot;
    r.vec3("position", l.position);
    r.direction("direction", l.direction);
    r.rgb("intensity", l.rgb);
    l.cone_angle_deg = r.number("cone_angle_deg", 45.0f, 0.0, 180.0, true, false, "(0, 180] degrees");
    l.blend = r.number("blend", 0.15f, 0.0, 1.0, false, false, "[0, 1]");
    r.no_others("type, name, position, direction, intensity, cone_angle_deg, blend");
  } else if (type == "directional") {
    l.type = LightSpec::Type::Directional;
    r.direction("direction", l.direction);
    r.rgb("irradiance", l.rgb);
    l.angle_deg = r.number("angle_deg", 0.0f, 0.0, 180.0, false, true, "[0, 180) degrees");
    r.no_others("type, name, direction, irradiance, angle_deg");
  } else if (type == "quad") {
    l.type = LightSpec::Type::Quad;
    r.vec3("corner", l.corner);
    r.vec3("edge_u", l.edge_u);
    r.vec3("edge_v", l.edge_v);
    r.rgb("radiance", l.rgb);
    l.two_sided = r.boolean("two_sided", false);
    double u[3] = {l.edge_u[0], l.edge_u[1], l.edge_u[2]}, v[3] = {l.edge_v[0], l.edge_v[1], l.edge_v[2]};
    double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    if (!(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] > 0.0))
      fail(where_index, " (quad): 'edge_u' and 'edge_v' span no area (parallel or zero)");
    r.no_others("type, name, corner, edge_u, edge_v, radiance, two_sided");
  } else {
    fail(where_index, ": unknown light type '", type, "' (expected point, spot, directional or quad)");
  }
  return l;
}

EnvironmentSpec read_environment(const Json& j, const std::string& file) {
  const std::string where = file + ": environment";
  if (!j.is_object()) fail(where, ": must be a JSON object, got ", FieldReader::describe(j));
  FieldReader r(j, where);
  const bool has_map = j.contains("map"), has_radiance = j.contains("radiance");
  if (has_map == has_radiance)
    fail(where, has_map ? ": give either 'radiance' or 'map', not both" : ": needs 'radiance' or 'map'");
  float scale = r.number("scale", 1.0f, 0.0, 3.0e38, false, false, "[0, inf)");
  float rotate = r.number("rotate_y_deg", 0.0f, -3.0e38, 3.0e38, false, false, "degrees (a finite number)");
  EnvironmentSpec env;
  if (has_radiance) {
    r.rgb("radiance", env.radiance);
    r.no_others("radiance or map, scale, rotate_y_deg");
    env.present = true;
    env.scale = scale;
    env.rotate_y_deg = rotate;
    return env;
  }
  std::string map = r.string("map");
  r.no_others("radiance or map, scale, rotate_y_deg");
  std::filesystem::path p(map);
  if (p.is_relative()) p = std::filesystem::path(file).parent_path() / p;
  try {
    return environment_from_map(p.string(), scale, rotate);
  } catch (const Error& e) {
    fail(where, ".map: ", e.what());
  }
}

double luminance(const float* c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }
void put3(float* dst, const float* src) { std::copy(src, src + 3, dst); }
void put3(float* dst, double x, double y, double z) {
  dst[0] = float(x), dst[1] = float(y), dst[2] = float(z);
}

}  // namespace

SceneLights read_lights_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, ": cannot open the lights file");
  Json j;
  try {
    j = Json::parse(in);
  } catch (const Json::exception& e) {
    std::string what = e.what();
    size_t bracket = what.find("] ");  // drop nlohmann's "[json.exception.parse_error.101] "
    fail(path, ": malformed JSON: ", bracket == std::string::npos ? what : what.substr(bracket + 2));
  }
  if (!j.is_object()) fail(path, ": a lights file is a JSON object with 'lights' and/or 'environment'");
  SceneLights sl;
  sl.source = path;
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "lights" && it.key() != "environment")
      fail(path, ": unknown field '", it.key(), "' (expected lights, environment)");
  if (j.contains("lights")) {
    const Json& arr = j.at("lights");
    if (!arr.is_array()) fail(path, ": 'lights' must be an array, got ", FieldReader::describe(arr));
    for (size_t i = 0; i < arr.size(); ++i)
      sl.lights.push_back(read_light(arr[i], path + ": lights[" + std::to_string(i) + "]"));
  }
  if (j.contains("environment")) sl.environment = read_environment(j.at("environment"), path);
  return sl;
}

EnvironmentSpec environment_from_map(const std::string& path, float scale, float rotate_y_deg) {
  if (!std::isfinite(rotate_y_deg)) fail(path, ": the rotation must be a finite angle");
  EnvironmentSpec env;
  env.present = true;
  if (!(scale >= 0.0f) || !std::isfinite(scale))
    fail(path, ": the environment scale must be a finite number >= 0, got ", scale);
  env.map = std::make_shared<const EnvMap>(load_env_map(path));
  env.scale = scale;
  env.rotate_y_deg = rotate_y_deg;
  return env;
}

EnvironmentSpec constant_environment(const float radiance[3]) {
  EnvironmentSpec env;
  for (int i = 0; i < 3; ++i) env.radiance[i] = radiance[i] > 0.0f ? radiance[i] : 0.0f;  // NaN -> 0
  env.present = env.radiance[0] > 0.0f || env.radiance[1] > 0.0f || env.radiance[2] > 0.0f;
  return env;
}

namespace {

// What the light tree needs of a finite light of the table (core/light_tree.h).
LightBounds bounds_of(const PmcLight& l, uint32_t index) {
  LightBounds b;
  b.light = index;
  const float* p = l.pos;
  for (int k = 0; k < 3; ++k) b.lo[k] = b.hi[k] = p[k];
  auto extend = [&](double x, double y, double z) {
    const double q[3] = {x, y, z};
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = std::min(b.lo[k], std::nextafter(float(q[k]), -HUGE_VALF));
      b.hi[k] = std::max(b.hi[k], std::nextafter(float(q[k]), HUGE_VALF));
    }
  };
  const double u[3] = {l.axis[0], l.axis[1], l.axis[2]}, v[3] = {l.edge_v[0], l.edge_v[1], l.edge_v[2]};
  switch (l.type) {
    case PMC_LIGHT_QUAD:
    case PMC_LIGHT_TRIANGLE:
      extend(p[0] + u[0], p[1] + u[1], p[2] + u[2]);
      extend(p[0] + v[0], p[1] + v[1], p[2] + v[2]);
      if (l.type == PMC_LIGHT_QUAD) extend(p[0] + u[0] + v[0], p[1] + u[1] + v[1], p[2] + u[2] + v[2]);
      b.energy = float(luminance(l.rgb) * l.area);  // radiance x area: the intensity along the normal
      put3(b.axis, l.normal);
      b.cos_theta_o = 1.0f;  // one normal
      b.cos_theta_e = 0.0f;  // emits over the hemisphere around it
      b.two_sided = l.type == PMC_LIGHT_TRIANGLE || (l.flags & PMC_LIGHT_TWO_SIDED);
      break;
    case PMC_LIGHT_SPOT:
      b.energy = float(luminance(l.rgb));
      put3(b.axis, l.axis);
      b.cos_theta_o = std::cos(l.spot_inner);  // full intensity within the inner angle
      b.cos_theta_e = std::cos(l.spot_outer - l.spot_inner);
      break;
    default:  // point
      b.energy = float(luminance(l.rgb));
      b.cos_theta_o = -1.0f;  // every direction
      b.cos_theta_e = 0.0f;
      break;
  }
  return b;
}

}  // namespace

namespace {

bool same3(const float* a, const float* b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

bool same_light(const LightSpec& a, const LightSpec& b) {
  return a.type == b.type && same3(a.position, b.position) && same3(a.direction, b.direction) &&
         same3(a.rgb, b.rgb) && a.cone_angle_deg == b.cone_angle_deg && a.blend == b.blend &&
         a.angle_deg == b.angle_deg && same3(a.corner, b.corner) && same3(a.edge_u, b.edge_u) &&
         same3(a.edge_v, b.edge_v) && a.two_sided == b.two_sided;
}

}  // namespace

bool same_lights(const SceneLights& a, const SceneLights& b) {
  const EnvironmentSpec &ea = a.environment, &eb = b.environment;
  if (ea.present != eb.present || !same3(ea.radiance, eb.radiance) || ea.map != eb.map ||
      ea.scale != eb.scale || ea.rotate_y_deg != eb.rotate_y_deg || a.lights.size() != b.lights.size())
    return false;
  for (size_t i = 0; i < a.lights.size(); ++i)
    if (!same_light(a.lights[i], b.lights[i])) return false;
  return true;
}

LightTable empty_light_table() {
  LightTable t;
  t.lights.push_back(PmcLight{});
  t.triangle_light.push_back(-1);
  t.tree_nodes.push_back(PmcLightTreeNode{});
  return t;
}

namespace {
const float kNoEnvMap[1] = {0.0f};  // the env buffer without a map: never read, never empty
}  // namespace

const float* LightTable::env_floats() const { return env_map ? env_map->data.data() : kNoEnvMap; }

size_t LightTable::env_float_count() const { return env_map ? env_map->data.size() : 1; }

LightTable build_light_table(const Scene& scene, const std::vector<float>& emission, const SceneLights& sl,
                             LightSampler sampler) {
  LightTable t;
  // Power sampler: lights at infinity deliver pi r^2 x irradiance onto the scene's bounding sphere.
  double r = 1.0;
  if (!scene.bounds.empty()) {
    double d2 = 0.0;
    for (int i = 0; i < 3; ++i)
      d2 += double(scene.bounds.hi[i] - scene.bounds.lo[i]) * (scene.bounds.hi[i] - scene.bounds.lo[i]);
    if (std::sqrt(d2) > 0.0 && std::isfinite(d2)) r = 0.5 * std::sqrt(d2);
  }
  const double disk = kPi * r * r;

  // The kernel's order: environment, sun disks | directional deltas | quads | the rest.
  std::vector<PmcLight> infinite, directional, quads, rest;
  std::vector<double> p_infinite, p_directional, p_quads, p_rest;
  auto blank = [](uint32_t type) {
    PmcLight l{};
    l.type = type;
    return l;
  };

  const EnvironmentSpec& env = sl.environment;
  if (env.present) {
    PmcLight l = blank(PMC_LIGHT_ENV);
    double power;
    if (env.map) {
      const EnvMap& m = *env.map;
      t.header.env = PMC_ENV_MAP;
      t.header.env_width = m.width;
      t.header.env_height = m.height;
      const double integral = m.integral * double(env.scale);
      t.header.env_inv_integral = integral > 0.0 ? float(1.0 / integral) : 0.0f;
      t.env_map = env.map;
      t.header.env_scale = env.scale;
      power = disk * m.luminance_integral() * double(env.scale);
      // Irradiance of the sky's mean radiance: its integral over the sphere / 4pi, times pi.
      l.distant_weight = float(0.25 * m.luminance_integral() * double(env.scale));
    } else {
      t.header.env = PMC_ENV_CONSTANT;
      put3(l.rgb, env.radiance[0] * env.scale, env.radiance[1] * env.scale, env.radiance[2] * env.scale);
      power = disk * 4.0 * kPi * luminance(l.rgb);
      l.distant_weight = float(kPi * luminance(l.rgb));
    }
    const double a = double(env.rotate_y_deg) * kPi / 180.0;
    t.header.env_rot_cos = float(std::cos(a));
    t.header.env_rot_sin = float(std::sin(a));
    infinite.push_back(l);
    p_infinite.push_back(power);
  }
  for (const LightSpec& s : sl.lights) {
    switch (s.type) {
      case LightSpec::Type::Point: {
        PmcLight l = blank(PMC_LIGHT_POINT);
        put3(l.pos, s.position);
        put3(l.rgb, s.rgb);
        rest.push_back(l);
        p_rest.push_back(4.0 * kPi * luminance(s.rgb));
        break;
      }
      case LightSpec::Type::Spot: {
        PmcLight l = blank(PMC_LIGHT_SPOT);
        put3(l.pos, s.position);
        put3(l.axis, s.direction);
        put3(l.rgb, s.rgb);
        const double outer = 0.5 * double(s.cone_angle_deg) * kPi / 180.0;
        const double inner = outer * (1.0 - double(s.blend));
        l.spot_outer = float(outer);
        l.spot_inner = float(inner);
        l.cos_outer = float(std::cos(outer));
        rest.push_back(l);
        p_rest.push_back(2.0 * kPi * (1.0 - std::cos(0.5 * (inner + outer))) * luminance(s.rgb));
        break;
      }
      case LightSpec::Type::Directional: {
        const double half = 0.5 * double(s.angle_deg) * kPi / 180.0;
        PmcLight l = blank(half > 0.0 ? PMC_LIGHT_SUN : PMC_LIGHT_DIRECTIONAL);
        put3(l.axis, s.direction);
        l.distant_weight = float(luminance(s.rgb));
        if (half > 0.0) {
          // A disk of uniform radiance L gives irradiance pi L sin^2(half) at normal incidence.
          const double sin2 = std::sin(half) * std::sin(half);
          put3(l.rgb, s.rgb[0] / (kPi * sin2), s.rgb[1] / (kPi * sin2), s.rgb[2] / (kPi * sin2));
          l.cos_outer = float(std::cos(half));
          l.one_minus_cos = float(2.0 * std::sin(0.5 * half) * std::sin(0.5 * half));
          infinite.push_back(l);
          p_infinite.push_back(disk * luminance(s.rgb));
        } else {
          put3(l.rgb, s.rgb);
          directional.push_back(l);
          p_directional.push_back(disk * luminance(s.rgb));
        }
        break;
      }
      case LightSpec::Type::Quad: {
        PmcLight l = blank(PMC_LIGHT_QUAD);
        const float* u = s.edge_u;
        const float* v = s.edge_v;
        double c[3] = {double(u[1]) * v[2] - double(u[2]) * v[1], double(u[2]) * v[0] - double(u[0]) * v[2],
                       double(u[0]) * v[1] - double(u[1]) * v[0]};
        double area = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        put3(l.pos, s.corner);
        put3(l.axis, s.edge_u);
        put3(l.edge_v, s.edge_v);
        put3(l.normal, c[0] / area, c[1] / area, c[2] / area);
        put3(l.rgb, s.rgb);
        l.area = float(area);
        l.flags = s.two_sided ? PMC_LIGHT_TWO_SIDED : 0u;
        const double uu = double(u[0]) * u[0] + double(u[1]) * u[1] + double(u[2]) * u[2];
        const double vv = double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2];
        const double uv = double(u[0]) * v[0] + double(u[1]) * v[1] + double(u[2]) * v[2];
        if (uv * uv <= 1e-10 * uu * vv) l.flags |= PMC_LIGHT_RECTANGLE;  // within 1e-5 rad of square
        quads.push_back(l);
        p_quads.push_back((s.two_sided ? 2.0 : 1.0) * kPi * area * luminance(s.rgb));
        break;
      }
    }
  }
  // Emissive triangles (two-sided).
  std::vector<size_t> tri_of_rest(rest.size(), SIZE_MAX);
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const PmcTriangle& tri = scene.triangles[i];
    const float* e = &emission[3 * size_t(tri.material)];
    double lum = luminance(e);
    if (!(lum > 0.0) || !std::isfinite(lum)) continue;
    const float* p0 = &scene.positions[3 * size_t(tri.v[0])];
    const float* p1 = &scene.positions[3 * size_t(tri.v[1])];
    const float* p2 = &scene.positions[3 * size_t(tri.v[2])];
    double a[3] = {double(p1[0]) - p0[0], double(p1[1]) - p0[1], double(p1[2]) - p0[2]};
    double b[3] = {double(p2[0]) - p0[0], double(p2[1]) - p0[1], double(p2[2]) - p0[2]};
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    double area = 0.5 * len;
    if (!(area > 0.0) || !std::isfinite(area)) continue;  // zero-area emitters cannot be sampled
    PmcLight l = blank(PMC_LIGHT_TRIANGLE);
    put3(l.pos, p0);
    put3(l.axis, a[0], a[1], a[2]);
    put3(l.edge_v, b[0], b[1], b[2]);
    put3(l.normal, c[0] / len, c[1] / len, c[2] / len);
    put3(l.rgb, e);
    l.area = float(area);
    tri_of_rest.push_back(i);
    rest.push_back(l);
    p_rest.push_back(2.0 * kPi * area * lum);
    ++t.emissive_triangles;
  }

  t.header.at_infinity = int(infinite.size());
  t.header.distant_end = int(infinite.size() + directional.size());
  t.header.quad_end = int(t.header.distant_end + quads.size());
  std::vector<double> power;
  for (auto* group : {&infinite, &directional, &quads, &rest})
    t.lights.insert(t.lights.end(), group->begin(), group->end());
  for (auto* group : {&p_infinite, &p_directional, &p_quads, &p_rest})
    power.insert(power.end(), group->begin(), group->end());
  t.header.count = int(t.lights.size());
  double total = 0.0;
  for (double p : power) total += std::isfinite(p) ? p : 0.0;
  t.total_power = total;
  double running = 0.0;
  size_t last_positive = 0;
  for (size_t k = 0; k < t.lights.size(); ++k) {
    double p = total > 0.0 && std::isfinite(power[k]) ? power[k] / total : 0.0;
    running += p;
    t.lights[k].pmf = float(p);
    t.lights[k].cdf = float(std::min(1.0, running));
    if (p > 0.0) last_positive = k;
  }
  // Rounding must not leave a gap at the top that picks a light of no power.
  for (size_t k = last_positive; k < t.lights.size(); ++k) t.lights[k].cdf = 1.0f;
  t.triangle_light.assign(scene.triangles.size(), -1);
  const size_t rest_first = size_t(t.header.quad_end);
  for (size_t k = 0; k < tri_of_rest.size(); ++k)
    if (tri_of_rest[k] != SIZE_MAX) t.triangle_light[tri_of_rest[k]] = int32_t(rest_first + k);

  // The light tree over the finite lights (quads and the rest).
  t.header.sampler = sampler == LightSampler::Tree ? PMC_LIGHT_SAMPLER_TREE : PMC_LIGHT_SAMPLER_POWER;
  if (sampler == LightSampler::Tree) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<LightBounds> bounds;
    bounds.reserve(t.lights.size() - size_t(t.header.distant_end));
    for (size_t k = size_t(t.header.distant_end); k < t.lights.size(); ++k)
      bounds.push_back(bounds_of(t.lights[k], uint32_t(k)));
    LightTree tree = build_light_tree(bounds);
    for (size_t i = 0; i < bounds.size(); ++i) {
      PmcLight& l = t.lights[bounds[i].light];
      l.tree_trail[0] = uint32_t(tree.trails[i]);
      l.tree_trail[1] = uint32_t(tree.trails[i] >> 32);
    }
    t.tree_nodes = std::move(tree.nodes);
    t.tree_depth = tree.depth;
    t.header.tree_nodes = int(t.tree_nodes.size());
    t.tree_build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  if (t.tree_nodes.empty()) t.tree_nodes.push_back(PmcLightTreeNode{});  // no empty device buffers
  return t;
}

}  // namespace pmc
