// bandwidth.cpp — coordinate rates, magnitudes and features, bottom-up (bandwidth.h).
#include "materials/bandwidth.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "materials/graph_analysis.h"

namespace pmc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

// Largest / smallest |component| of a constant input (`fallback` when the
// node lacks it or it is linked).
double const_abs_max(const Node& n, const char* name, double fallback) {
  const Input* in = n.input(name);
  if (!in || in->linked) return fallback;
  double m = 0;
  for (int c = 0; c < std::max(1, type_width(in->value.type)) && c < 4; ++c)
    m = std::max(m, std::fabs(double(in->value.f[size_t(c)])));
  return m;
}

double const_abs_min(const Node& n, const char* name, double fallback) {
  const Input* in = n.input(name);
  if (!in || in->linked) return fallback;
  double m = kInf;
  for (int c = 0; c < std::max(1, type_width(in->value.type)) && c < 4; ++c)
    m = std::min(m, std::fabs(double(in->value.f[size_t(c)])));
  return m;
}

double const_value(const Node& n, const char* name, double fallback) {
  const Input* in = n.input(name);
  return in && !in->linked ? double(in->value.f[0]) : fallback;
}

// max |a - b| over components of two constant inputs (infinity if linked).
double const_abs_diff(const Node& n, const char* a, const char* b) {
  const Input* x = n.input(a);
  const Input* y = n.input(b);
  if (!x || !y || x->linked || y->linked) return kInf;
  double m = 0;
  for (size_t c = 0; c < 4; ++c) m = std::max(m, std::fabs(double(x->value.f[c]) - double(y->value.f[c])));
  return m;
}

bool is_linked(const Node& n, const char* name) {
  const Input* in = n.input(name);
  return in && in->linked;
}

bool one_of(const std::string& c, std::initializer_list<const char*> names) {
  for (const char* s : names)
    if (c == s) return true;
  return false;
}

void add_feature(std::vector<Feature>& front, Feature f) {
  if (!(f.amplitude > 0) || !(f.size > 0) || !std::isfinite(f.size)) return;
  for (const Feature& e : front)
    if (e.size <= f.size && e.amplitude >= f.amplitude) return;  // dominated
  front.erase(
      std::remove_if(front.begin(), front.end(),
                     [&](const Feature& e) { return e.size >= f.size && e.amplitude <= f.amplitude; }),
      front.end());
  front.push_back(f);
  std::sort(front.begin(), front.end(), [](const Feature& a, const Feature& b) { return a.size < b.size; });
}

// The node kinds whose value is a pattern of a coordinate input: a feature
// of the coordinate becomes one of the pattern's full range.
const char* pattern_coordinate(const std::string& c) {
  if (one_of(c, {"noise2d", "fractal2d", "cellnoise2d", "worleynoise2d", "tiledcircles", "tiledcloverleafs",
                 "tiledhexagons", "grid", "crosshatch", "image", "tiledimage", "hextiledimage",
                 "hextilednormalmap"}))
    return "texcoord";
  if (one_of(c, {"noise3d", "fractal3d", "cellnoise3d", "worleynoise3d"})) return "position";
  return nullptr;
}

}  // namespace

double NodeBandwidth::feature(double min_amplitude) const {
  for (const Feature& f : features)  // by size
    if (f.amplitude >= min_amplitude) return f.size;
  return kNoFeature;
}

int level_floor_for_feature(double feature, double texels_per_feature, int no_floor, int max_level) {
  if (!(feature > 0) || !std::isfinite(feature) || feature >= kNoFeature) return no_floor;
  if (!(texels_per_feature > 0) || !std::isfinite(texels_per_feature)) return no_floor;
  double level = std::ceil(std::log2(texels_per_feature / feature) - 1e-9);
  if (level > max_level) return max_level;
  if (level < no_floor) return no_floor;
  return int(level);
}

std::vector<NodeBandwidth> node_bandwidths(const Graph& g) {
  std::vector<NodeBandwidth> bw(g.nodes.size());
  for (int i : topological_order(g)) {
    const Node& n = g.nodes[size_t(i)];
    const std::string& c = n.category;
    NodeBandwidth& out = bw[size_t(i)];
    auto rate_of = [&](const char* name) {
      const Input* in = n.input(name);
      return in && in->linked ? bw[size_t(in->node)].rate : 0.0;
    };
    auto mag_of = [&](const char* name) {
      const Input* in = n.input(name);
      if (!in) return 0.0;
      return in->linked ? bw[size_t(in->node)].magnitude : const_abs_max(n, name, 0);
    };
    double sum_rate = 0, max_rate = 0, max_mag = 0;
    int linked = 0;
    for (const Input& in : n.inputs) {
      if (in.linked) {
        const NodeBandwidth& b = bw[size_t(in.node)];
        sum_rate += b.rate;
        max_rate = std::max(max_rate, b.rate);
        if (out.unbounded.empty()) out.unbounded = b.unbounded;
        ++linked;
      }
      if (is_numeric(in.type)) max_mag = std::max(max_mag, mag_of(in.name.c_str()));
    }

    // Rate and magnitude.
    const char* coord = pattern_coordinate(c);
    double own_size = 0, own_range = 0;  // a feature of the node's own
    const char* own_coord = nullptr;
    if (c == "texcoord" || c == "position") {
      out.rate = 1;
      out.magnitude = kInf;
    } else if (one_of(c, {"add", "subtract"})) {
      out.rate = sum_rate;
      out.magnitude = mag_of("in1") + mag_of("in2");
    } else if (one_of(c, {"combine2", "combine3", "combine4", "extract", "swizzle", "convert", "rotate2d",
                          "rotate3d", "absval", "min", "max", "luminance"})) {
      out.rate = max_rate;
      out.magnitude = max_mag;
    } else if (c == "multiply") {
      bool both = is_linked(n, "in1") && is_linked(n, "in2");
      out.rate = both ? kInf : max_rate * (is_linked(n, "in1") ? mag_of("in2") : mag_of("in1"));
      out.magnitude = mag_of("in1") * mag_of("in2");
    } else if (c == "divide") {
      double d = is_linked(n, "in2") ? 0 : const_abs_min(n, "in2", 1);
      out.rate = d > 0 ? rate_of("in1") / d : kInf;
      out.magnitude = d > 0 ? mag_of("in1") / d : kInf;
    } else if (c == "dotproduct") {
      bool both = is_linked(n, "in1") && is_linked(n, "in2");
      const Input* k = n.input(is_linked(n, "in1") ? "in2" : "in1");
      double s = 0;
      if (k && !k->linked)
        for (int j = 0; j < std::max(1, type_width(k->value.type)) && j < 4; ++j)
          s += std::fabs(double(k->value.f[size_t(j)]));
      out.rate = both ? kInf : max_rate * s;
      out.magnitude = both ? kInf : max_mag * s;
    } else if (c == "place2d") {
      double s = is_linked(n, "scale") ? 0 : const_abs_min(n, "scale", 1);
      out.rate = s > 0 ? rate_of("texcoord") / s : kInf;
      out.magnitude = kInf;
    } else if (one_of(c, {"floor", "ceil", "round"})) {
      out.rate = rate_of("in");
      out.magnitude = mag_of("in") + 1;
      own_coord = "in", own_size = 1, own_range = 1;
    } else if (c == "modulo") {
      double m = is_linked(n, "in2") ? 0 : const_abs_min(n, "in2", 1);
      out.rate = rate_of("in1");
      out.magnitude = m > 0 ? m : kInf;
      if (m > 0) own_coord = "in1", own_size = m, own_range = m;
    } else if (c == "sin" || c == "cos") {
      out.rate = rate_of("in");
      out.magnitude = 1;
      own_coord = "in", own_size = kPi, own_range = 2;
    } else if (c == "smoothstep") {
      double width = std::fabs(const_value(n, "high", 1) - const_value(n, "low", 0));
      bool fixed = !is_linked(n, "low") && !is_linked(n, "high") && width > 0;
      out.rate = fixed ? rate_of("in") / width : kInf;
      out.magnitude = 1;
      if (fixed) own_coord = "in", own_size = width, own_range = 1;
    } else if (c == "remap") {
      double in_w = std::fabs(const_value(n, "inhigh", 1) - const_value(n, "inlow", 0));
      double out_w = std::fabs(const_value(n, "outhigh", 1) - const_value(n, "outlow", 0));
      bool fixed = linked == 1 && is_linked(n, "in") && in_w > 0;
      out.rate = fixed ? rate_of("in") * out_w / in_w : kInf;
      out.magnitude = fixed ? std::fabs(const_value(n, "outlow", 0)) +
                                  out_w / in_w * (mag_of("in") + std::fabs(const_value(n, "inlow", 0)))
                            : kInf;
    } else if (c == "clamp") {
      out.rate = rate_of("in");
      out.magnitude = std::max(mag_of("low"), mag_of("high"));
    } else if (c == "mix") {
      out.rate = linked == 1 && is_linked(n, "mix") ? rate_of("mix") * const_abs_diff(n, "fg", "bg") : kInf;
      out.magnitude = std::max(mag_of("fg"), mag_of("bg"));
    } else if (c == "power") {
      double e = is_linked(n, "in2") ? kInf : const_abs_max(n, "in2", 1);
      double m = mag_of("in1");
      out.rate = rate_of("in1") * std::max(1.0, e);
      out.magnitude = m <= 1 ? 1 : std::pow(m, e);
    } else if (c == "noise2d" || c == "noise3d") {
      out.rate = 2.0 * rate_of(coord) * mag_of("amplitude");
      out.magnitude = mag_of("amplitude");
      own_coord = coord, own_size = 0.5, own_range = 2 * out.magnitude;
    } else if (c == "fractal2d" || c == "fractal3d") {
      double octaves = std::max(1.0, const_value(n, "octaves", 3));
      double lacunarity = std::max(1.0, const_value(n, "lacunarity", 2));
      double diminish = std::fabs(const_value(n, "diminish", 0.5));
      // Octaves with at least 1/8 of the first one's amplitude (diminish^k).
      double visible = octaves;
      if (diminish < 1 && diminish > 0)
        visible = std::min(octaves, 1 + std::floor(std::log(1.0 / 8.0) / std::log(diminish)));
      double slope = 0, sum = 0, a = 1, f = 1;
      for (int k = 0; k < int(octaves) && k < 16; ++k, a *= diminish, f *= lacunarity) {
        slope += a * f;
        sum += a;
      }
      out.rate = 2.0 * rate_of(coord) * mag_of("amplitude") * slope;
      out.magnitude = mag_of("amplitude") * sum;
      own_coord = coord, own_size = 0.5 / std::pow(lacunarity, visible - 1), own_range = 2 * out.magnitude;
    } else if (c == "cellnoise2d" || c == "cellnoise3d") {
      out.rate = 0;  // constant per cell
      out.magnitude = 1;
      own_coord = coord, own_size = 1, own_range = 1;
    } else if (c == "worleynoise2d" || c == "worleynoise3d") {
      out.rate = 2.0 * rate_of(coord);
      out.magnitude = 2;
      own_coord = coord, own_size = 0.5, own_range = 1;
    } else if (one_of(c, {"tiledcircles", "tiledcloverleafs", "tiledhexagons", "grid", "crosshatch"})) {
      bool lines = c == "grid" || c == "crosshatch";
      double tiling = is_linked(n, "uvtiling") ? 0 : const_abs_max(n, "uvtiling", 1);
      double t = std::clamp(const_value(n, lines ? "thickness" : "size", lines ? 0.05 : 0.5), 0.0, 1.0);
      out.rate = 0;
      out.magnitude = 1;
      if (tiling > 0)
        own_coord = coord, own_size = std::max(std::min(t, 1.0 - t), 1e-3) / tiling, own_range = 1;
    } else if (one_of(c, {"image", "tiledimage", "hextiledimage", "hextilednormalmap"})) {
      out.rate = kInf;
      out.magnitude = 1;  // an LDR texture (or a unit normal); HDR ones are not patterns anyway
    } else if (one_of(c, {"ramplr", "ramptb", "splitlr", "splittb"})) {
      out.rate = kInf;
      out.magnitude = std::max(mag_of("valuel"),
                               std::max(mag_of("valuer"), std::max(mag_of("valuet"), mag_of("valueb"))));
    } else if (one_of(c, {"ifgreater", "ifgreatereq", "ifequal"})) {
      out.rate = kInf;
      out.magnitude = std::max(mag_of("in1"), mag_of("in2"));
    } else {
      out.rate = max_rate > 0 ? kInf : 0;  // no bound on how fast it runs
      out.magnitude = max_mag;
    }

    // Features: the inputs' ones, through the node's gains, then its own.
    const double cap = 2 * out.magnitude;
    auto gain = [&](const std::string& input) -> double {
      if (coord && input == coord) return kInf;  // a pattern of it: its full range
      if (c == "multiply") return mag_of(input == "in1" ? "in2" : "in1");
      if (c == "divide") return input == "in1" ? 1.0 / std::max(const_abs_min(n, "in2", 0), 1e-30) : kInf;
      if (c == "mix") {
        if (input != "mix") return 1;
        double d = const_abs_diff(n, "fg", "bg");
        return std::isfinite(d) ? d : mag_of("fg") + mag_of("bg");
      }
      if (c == "remap" || c == "smoothstep" || c == "power") {
        const Input* in = n.input(input);
        double r = in && in->linked ? bw[size_t(in->node)].rate : 0;
        return r > 0 ? out.rate / r : kInf;
      }
      if (own_coord && input == own_coord) return kInf;
      return 1;
    };
    for (const Input& in : n.inputs) {
      if (!in.linked) continue;
      double k = gain(in.name);
      for (const Feature& f : bw[size_t(in.node)].features)
        add_feature(out.features, {f.size, std::min(f.amplitude * k, cap)});
    }
    if (own_coord && is_linked(n, own_coord) && own_size > 0) {
      double r = rate_of(own_coord);
      if (!std::isfinite(r)) {
        if (out.unbounded.empty())
          out.unbounded = c + (n.name.empty() ? std::string() : " '" + n.name + "'") +
                          " reads a coordinate pmc cannot bound";
      } else if (r > 0) {
        add_feature(out.features, {own_size / r, std::min(own_range, cap)});
      }
    }
  }
  return bw;
}

}  // namespace pmc
