// mtl_graph.cpp — MTL parameters into standard_surface networks (docs/MTL.md has the table).
#include "materials/mtl_graph.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/error.h"
#include "core/image_backend.h"
#include "materials/geom_default.h"
#include "materials/node_table.h"

namespace pmc {

float mtl_ns_roughness(float ns) {
  const float n = std::isfinite(ns) ? std::min(std::max(ns, 0.0f), 1000.0f) : 0.0f;
  return 1.0f - std::sqrt(n / 1000.0f);
}

float mtl_ior(float ni) { return std::isfinite(ni) && ni > 1.0f ? ni : 1.5f; }

float mtl_level_ior(float n, float level) {
  const float r = (n - 1.0f) / (n + 1.0f);
  const float f0 = std::min(0.999f, 2.0f * level * r * r);
  const float s = std::sqrt(std::max(f0, 0.0f));
  return (1.0f + s) / (1.0f - s);
}

namespace {

// A value of the PBR extension: [0, 1], non-finite read as 0.
float unit(float x) { return std::isfinite(x) ? std::min(std::max(x, 0.0f), 1.0f) : 0.0f; }

// A -bm value: non-finite reads as 1 (not given).
float multiplier(float x) { return std::isfinite(x) ? x : 1.0f; }

bool is_glass(int illum) { return illum == 4 || illum == 6 || illum == 7 || illum == 9; }

// Nodes the way the MaterialX reader makes them: every input of the node's
// definition, the given ones replacing defaults, geometric defaults linked to
// one shared geometric node each.
class Builder {
 public:
  Builder(Graph& g, std::string origin) : g_(g), origin_(std::move(origin)) {}

  int node(const std::string& category, ValueType type, const std::vector<Input>& given,
           const std::string& what) {
    const NodeDef* def = find_node_def(category);
    PMC_CHECK(def != nullptr, "MTL network node category");
    Node n;
    n.category = category;
    n.type = type;
    n.origin = origin_ + " " + what;
    for (const InputDef& d : def->inputs) {
      Input in;
      bool found = false;
      for (const Input& x : given)
        if (x.name == d.name) in = x, found = true;
      const ValueType declared = resolve_input_type(d, type);
      if (!found && d.geom != GeomDefault::None) {
        in = Input::link(d.name, declared, geom(d.geom));
      } else if (!found) {
        in = default_input(d, type);
      } else if (in.type == ValueType::None) {
        in.type = declared;
      }
      n.inputs.push_back(in);
    }
    return g_.add(n);
  }

  // An image node reading `file` (sRGB-decoded when `srgb` and a colour).
  int image(const std::string& file, ValueType type, bool srgb, const std::string& what) {
    Input f;
    f.name = "file";
    f.type = ValueType::Filename;
    f.value.type = ValueType::Filename;
    f.value.text = file;
    f.value.f[0] = srgb ? 1.0f : 0.0f;
    return node("image", type, {f, Input::constant("default", type, 0, 0, 0)}, what);
  }

  int multiply(ValueType t, Input a, Input b, const std::string& what) {
    a.name = "in1";
    b.name = "in2";
    return node("multiply", t, {a, b}, what);
  }

 private:
  int geom(GeomDefault d) { return geom_default_in(g_, geom_, d, origin_ + " (geometric default)"); }

  Graph& g_;
  std::string origin_;
  std::map<int, int> geom_;
};

// Channels of an image file's first subimage; 0 when it cannot be opened
// (the compiler then refuses the missing texture, as for map_Kd).
int channels_of(const std::string& path) {
  std::string why;
  auto in = image_backend().open(path, false, why);
  return in ? in->header().channels : 0;
}

std::string number(float x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", double(x));
  return buf;
}

}  // namespace

Graph mtl_to_graph(const MtlMaterial& m, const std::string& mtl_file) {
  Graph g;
  g.material = m.name;
  g.file = mtl_file;
  const std::string origin = mtl_file + ": material '" + m.name + "'";
  Builder b(g, origin);
  Node surface;
  surface.category = "standard_surface";
  surface.type = ValueType::Surface;
  surface.origin = origin;
  for (const SurfaceParam& p : surface_params("standard_surface"))
    surface.inputs.push_back(Input::constant(p.input, p.type, p.def[0], p.def[1], p.def[2]));
  auto set = [&](const char* name, ValueType t, float x, float y = 0, float z = 0) {
    *surface.input(name) = Input::constant(name, t, x, y, z);
  };
  auto link = [&](const char* name, ValueType t, int node) {
    *surface.input(name) = Input::link(name, t, node);
  };
  auto first_channel = [&](const std::string& file, const std::string& what) {
    return b.image(file, ValueType::Float, false, what);
  };
  const ValueType F = ValueType::Float, C3 = ValueType::Color3, V3 = ValueType::Vector3;
  std::vector<std::string> dropped;

  // Base: Kd (times map_Kd).
  set("base", F, 1.0f);
  // A colour statement times its (sRGB) map, when it has one.
  auto textured_color = [&](const char* input, const float* rgb, const std::string& map, const char* what) {
    set(input, C3, rgb[0], rgb[1], rgb[2]);
    if (map.empty()) return;
    const int img = b.image(map, C3, true, std::string("map_") + what);
    link(input, C3,
         b.multiply(C3, Input::link("", C3, img), Input::constant("", C3, rgb[0], rgb[1], rgb[2]),
                    std::string(what) + "*map_" + what));
  };
  textured_color("base_color", m.kd, m.map_kd, "Kd");

  // The PBR extension: a material that uses any of it takes its roughness
  // from Pr (0 when absent), every other material from Ns.
  const bool pbr = m.pr != 0.0f || m.pm != 0.0f || m.ps != 0.0f || m.pc != 0.0f || m.pcr != 0.0f ||
                   m.aniso != 0.0f || m.anisor != 0.0f || !m.map_pr.empty() || !m.map_pm.empty() ||
                   !m.map_ps.empty();
  if (!m.map_pr.empty())
    link("specular_roughness", F, first_channel(m.map_pr, "map_Pr"));
  else
    set("specular_roughness", F, pbr ? unit(m.pr) : mtl_ns_roughness(m.ns));
  if (!m.map_pm.empty())
    link("metalness", F, first_channel(m.map_pm, "map_Pm"));
  else
    set("metalness", F, unit(m.pm));
  if (!m.map_ps.empty())
    link("sheen", F, first_channel(m.map_ps, "map_Ps"));
  else
    set("sheen", F, unit(m.ps));
  set("sheen_color", C3, 1, 1, 1);
  set("coat", F, unit(m.pc));
  set("coat_roughness", F, unit(m.pcr));
  set("specular_anisotropy", F, unit(m.aniso));
  set("specular_rotation", F, unit(m.anisor));

  // Dielectric specular: level L = mean(Ks) scales F0(n) by 2L (Blender's
  // "Specular IOR Level"); pmc folds it into the IOR. Glass keeps n.
  const float n = mtl_ior(m.ni);
  const bool glass = is_glass(m.illum);
  float level = (m.ks[0] + m.ks[1] + m.ks[2]) / 3.0f;
  if (!std::isfinite(level) || level < 0.0f) level = 0.0f;
  const float specular = glass || level > 0.0f ? 1.0f : 0.0f;
  set("specular", F, specular);
  set("specular_color", C3, 1, 1, 1);
  set("specular_IOR", F, glass ? n : level > 0.0f ? mtl_level_ior(n, level) : n);
  if (!m.map_ks.empty() && specular > 0.0f) link("specular", F, first_channel(m.map_ks, "map_Ks"));

  // Glass: illum 4, 6, 7, 9.
  const bool tf_zero = m.tf[0] == 0.0f && m.tf[1] == 0.0f && m.tf[2] == 0.0f;
  const bool tf_white = m.tf[0] == 1.0f && m.tf[1] == 1.0f && m.tf[2] == 1.0f;
  if (glass) {
    set("transmission", F, 1.0f);
    if (tf_zero)
      set("transmission_color", C3, 1, 1, 1);
    else
      set("transmission_color", C3, m.tf[0], m.tf[1], m.tf[2]);
  } else if (!tf_zero && !(tf_white && m.illum == 0)) {
    dropped.push_back("transmission filter (Tf " + number(m.tf[0]) + " " + number(m.tf[1]) + " " +
                      number(m.tf[2]) + ") with illum " + std::to_string(m.illum) +
                      " (transmission only with illum 4, 6, 7 or 9)");
  }
  if (m.illum == 10 || m.illum > 10 || m.illum < 0)
    dropped.push_back("illum " + std::to_string(m.illum) + " (no such shading model in pmc)");

  // Emission: Ke (times map_Ke).
  set("emission", F, 1.0f);
  textured_color("emission_color", m.ke, m.map_ke, "Ke");

  // Cut-out: d, or map_d's alpha channel (its first channel without one).
  *surface.input("opacity") = Input::constant("opacity", F, m.dissolve);
  if (!m.map_d.empty()) {
    bool alpha_channel = channels_of(m.map_d) == 4;
    int img = b.image(m.map_d, ValueType::Color4, false, "map_d");
    int e = b.node("extract", F,
                   {Input::link("in", ValueType::Color4, img),
                    Input::constant("index", ValueType::Integer, alpha_channel ? 3.0f : 0.0f)},
                   "map_d channel");
    link("opacity", F, e);
  }

  // Normals: norm is a tangent-space normal map; bump is a height map when
  // it has one or two channels or a -bm, else (Blender's exporter writes
  // normal maps as map_Bump) a tangent-space normal map too.
  auto normal_map = [&](const std::string& file, float scale, const std::string& what) {
    int img = b.image(file, V3, false, what);
    return b.node("normalmap", V3, {Input::link("in", V3, img), Input::constant("scale", F, scale)},
                  what + " normalmap");
  };
  if (!m.map_norm.empty()) {
    link("normal", V3, normal_map(m.map_norm, multiplier(m.norm_multiplier), "norm"));
    if (!m.map_bump.empty()) dropped.push_back("bump map (" + m.map_bump + ") besides norm");
  } else if (!m.map_bump.empty()) {
    const float bm = multiplier(m.bump_multiplier);
    const bool bm_given = bm != 1.0f;
    const int channels = channels_of(m.map_bump);
    if (bm_given || channels == 1 || channels == 2) {
      int h = first_channel(m.map_bump, "bump");
      link("normal", V3,
           b.node("bump", V3, {Input::link("height", F, h), Input::constant("scale", F, bm)}, "bump height"));
    } else {
      link("normal", V3, normal_map(m.map_bump, 1.0f, "bump (a normal map)"));
    }
  }

  dropped.insert(dropped.end(), m.not_modelled.begin(), m.not_modelled.end());
  std::string list;
  for (const std::string& what : dropped) list += (list.empty() ? " " : ", ") + what;
  if (!list.empty()) warn(origin + ": not modelled:" + list);
  g.surface = g.add(surface);
  return g;
}

}  // namespace pmc
