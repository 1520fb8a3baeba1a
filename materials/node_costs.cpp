// node_costs.cpp — node weights, the frame's expected hit rate and a cache
// point's economics (node_costs.h).
#include "materials/node_costs.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/cache_sizing.h"
#include "materials/cache_plan.h"

namespace pmc {
namespace {

// Unit nodes per node of each costly family: docs/BENCHMARKS.md "Node costs"
// (bench.node_costs, PoCL, 2026-11-27; images 2026-11-29: a bilinear read
// through a 1024x1024 texture's mip chain, RGB or grey; the Worley noises and
// the 3D Perlin noises 2026-11-30, once their batch loops vectorised, scaled by
// the median ratio of the unchanged families between that run and this table).
// A fractal's figure is per octave. Every other node costs one unit.
const std::map<std::string, double>& family_weights() {
  static const std::map<std::string, double> w = {
      {"noise2d", 1.0},       {"fractal2d", 1.5},     {"cellnoise2d", 0.8}, {"worleynoise2d", 2.5},
      {"tiledhexagons", 3.5}, {"tiledcircles", 2.3},  {"noise3d", 2.1},     {"fractal3d", 2.2},
      {"cellnoise3d", 0.8},   {"worleynoise3d", 8.1}, {"image", 30.0},
  };
  return w;
}

// Free nodes: the key inputs and constants the compiler folds into operands.
bool free_node(const std::string& category) {
  return category == "texcoord" || category == "position" || category == "constant";
}

// Lookups of one point per pixel and sample when camera hits look up: the
// camera hit and later ones. Measured on the default scene (max depth 8):
// hits 89.8% at 320x180, 16 spp with 2.69 keys per pixel and point, 97.2% at
// 64 spp with 2.90, i.e. 1.6 lookups per point and sample; a camera-only
// path makes one.
double lookups_per_sample(const CacheFrame& frame) { return frame.max_depth > 1 ? 1.6 : 1.0; }

}  // namespace

double node_cost(const Node& n) {
  if (free_node(n.category)) return 0.0;
  const auto& w = family_weights();
  auto it = w.find(n.category);
  double weight = it == w.end() ? 1.0 : it->second;
  if (n.category == "fractal2d" || n.category == "fractal3d") {
    const Input* octaves = n.input("octaves");
    const double count = octaves && !octaves->linked ? double(octaves->value.f[0]) : 3.0;
    weight *= std::clamp(count, 1.0, 16.0);
  }
  return weight;
}

double subgraph_cost(const Graph& g, int node) {
  double total = 0.0;
  for (int i : subgraph_order(g, node)) total += node_cost(g.nodes[size_t(i)]);
  return total;
}

CacheCosts default_cache_costs(bool gpu) {
  CacheCosts c;  // PoCL's CPU device (the struct's defaults)
  c.source = gpu ? "table (GPU estimate, not calibrated)" : "table (PoCL CPU, not calibrated)";
  if (gpu) c.miss_per_cost = 2.0;  // a warp waits for its missing lanes
  return c;
}

double lookups_per_pixel(const CacheFrame& frame) {
  const double spp = std::max(1, frame.spp);
  const double camera = std::min(spp, double(std::max(0, frame.camera_samples)));
  return camera + spp * (lookups_per_sample(frame) - 1.0);
}

double expected_hit_rate(const CacheFrame& frame, bool position_key) {
  const double spp = std::max(1, frame.spp);
  const double keys = expected_keys_per_pixel_point(int(spp)) * (position_key ? 2.0 : 1.0);
  const double lookups = lookups_per_pixel(frame);
  return lookups > 0.0 ? std::clamp(1.0 - keys / lookups, 0.0, 1.0) : 0.0;
}

double expected_lookups_per_key(const CacheFrame& frame, bool position_key) {
  const double spp = std::max(1, frame.spp);
  const double keys = expected_keys_per_pixel_point(int(spp)) * (position_key ? 2.0 : 1.0);
  return lookups_per_pixel(frame) / keys;
}

int auto_supersample(const CacheFrame& frame, bool position_key) {
  const double most = expected_lookups_per_key(frame, position_key) / 4.0;
  int k = 1;
  while (k < 16 && 2.0 * k <= most) k *= 2;
  return k;
}

CacheSupersample resolve_supersample(const CacheFrame& frame, int setting) {
  CacheSupersample s;
  if (setting > 0) {
    s.uv = s.position = setting;
  } else {
    s.uv = auto_supersample(frame, false);
    s.position = auto_supersample(frame, true);
  }
  return s;
}

PointEconomics point_economics(double cost, bool position_key, const CacheCosts& costs,
                               const CacheFrame& frame, int samples) {
  PointEconomics e;
  e.cost = cost;
  e.lookup = costs.lookup;
  e.samples = std::max(1, samples);
  // A miss evaluates the sub-graph K times at (1 + miss_per_cost) each; the
  // first C is what the render pays without the cache too.
  e.miss =
      costs.miss + costs.miss_per_cost * cost + double(e.samples - 1) * (1.0 + costs.miss_per_cost) * cost;
  e.hit_rate = expected_hit_rate(frame, position_key);
  e.gain = e.hit_rate * e.cost - e.lookup - (1.0 - e.hit_rate) * e.miss;
  const double lookups = double(frame.width) * double(frame.height) * lookups_per_pixel(frame);
  e.frame_seconds = e.gain * lookups * costs.unit_ns * 1e-9;
  return e;
}

}  // namespace pmc
