// node_costs.h — what a cache point's sub-graph costs, what a lookup and a
// miss cost, and whether the point pays for a frame.
//
// Costs are in "unit nodes": the time of an average node of the default
// scene's floor network on the device (docs/BENCHMARKS.md, "Node costs").
// node_cost() weighs each node by its family (a 3D Worley noise is about 70
// unit nodes, an add 1), from bench.node_costs on PoCL; a fractal's weight
// is per octave. CacheCosts holds a device's figures in those units: the
// lookup (hash, cell scan, decode) that every visit of a point pays, the
// miss's extra (the insert and store a miss adds to evaluating the sub-graph,
// plus `miss_per_cost` x the sub-graph: a miss evaluates it for the few lanes
// of a batch that missed, which costs more per lane than a full batch).
// default_cache_costs() is the table for a device no one has calibrated
// (measured on PoCL); gpu/device_calibration.h measures the unit, the lookup
// and the insert on a device once and stores them.
//
// The decision (cache_point_pays): with h the expected hit rate, C the
// sub-graph's cost, L the lookup's and M the miss's, a point pays when
// h C > L + (1 - h) M. The hit rate comes from the frame: keys are about one
// virtual texel per pixel and point for camera hits, times the samples'
// spread (core/cache_sizing.h's rule), position cells twice that (a surface
// cuts more cells than texels); lookups are the samples times the hits a path
// makes. The frame's pixel count cancels (texels follow the pixel footprint),
// so the samples per pixel, the path depth and the key kind decide it.
//
// Supersampled misses (core/device/pmc_cache_supersample.h): a miss may run
// the sub-graph at K points over its texel and store their mean. K
// multiplies what a miss evaluates, so M counts K (1 + miss_per_cost) C - C
// beyond the insert, and a point that no longer pays at that K is not cached.
// The automatic K (auto_supersample) keeps misses a small share of a key's
// lookups: the largest power of two of at most lookups per key / 4, 1..16
// (a key's sub-samples at most a quarter of its lookups).
#pragma once

#include <string>

#include "materials/node_graph.h"

namespace pmc {

// One node's cost in unit nodes (its family's weight; constants and the
// texcoord/position inputs cost nothing).
double node_cost(const Node& n);
// The sub-graph under `node`, itself included, each node once.
double subgraph_cost(const Graph& g, int node);

// A device's cache figures, in unit nodes (unit_ns converts them to time).
struct CacheCosts {
  double unit_ns = 1.55;       // one unit node, nanoseconds per hit of the whole device
  double lookup = 11.0;        // L: every visit of a point
  double miss = 12.0;          // the insert and store a miss adds
  double miss_per_cost = 1.0;  // a miss's extra per unit of its sub-graph (sparse batches)
  std::string source;          // "table (...)" or "calibrated (file)"
};

// The table for devices that were not calibrated (measured on PoCL's CPU
// device, docs/BENCHMARKS.md "Cache: off vs on"); a GPU's misses diverge
// (a warp waits for its missing lanes), so its miss_per_cost is higher.
CacheCosts default_cache_costs(bool gpu);

// The frame the plan is made for.
// camera_samples: a pixel's samples whose camera-ray hits use the cache (the
// cache_camera_samples setting); later samples look up at later hits only.
struct CacheFrame {
  int width = 640, height = 360, spp = 16, max_depth = 8, camera_samples = 16;
};

// Expected fraction of a point's lookups that hit (0..1).
double expected_hit_rate(const CacheFrame& frame, bool position_key);
// Lookups of one point per pixel over the frame's samples: the camera hit's
// in the first camera_samples samples, the later hits' in all of them.
double lookups_per_pixel(const CacheFrame& frame);

struct PointEconomics {
  double cost = 0;           // C, unit nodes
  double lookup = 0;         // L
  double miss = 0;           // M = miss + miss_per_cost x C + (K - 1)(1 + miss_per_cost) C
  int samples = 1;           // K, the sub-samples a miss evaluates
  double hit_rate = 0;       // h
  double gain = 0;           // h C - L - (1 - h) M, unit nodes per lookup (> 0: it pays)
  double frame_seconds = 0;  // gain x the frame's lookups x unit_ns: seconds the point saves
};

// Expected lookups of one key (texel or cell) in the frame: 1 / (1 - h) before the clamp.
double expected_lookups_per_key(const CacheFrame& frame, bool position_key);

// Sub-samples per supersampled miss, per key kind (1: the texel's centre alone).
struct CacheSupersample {
  int uv = 1, position = 1;
  int of(bool position_key) const { return position_key ? position : uv; }
};
// The automatic K for a key kind in the frame (see above).
int auto_supersample(const CacheFrame& frame, bool position_key);
// The cache_supersample setting: 0 is auto (per key kind), else that K for both kinds.
CacheSupersample resolve_supersample(const CacheFrame& frame, int setting);

// `samples`: the sub-samples a miss evaluates (M counts them).
PointEconomics point_economics(double cost, bool position_key, const CacheCosts& costs,
                               const CacheFrame& frame, int samples = 1);
inline bool cache_point_pays(const PointEconomics& e) { return e.gain > 0; }

// What the plan needs to decide by cost (CompileOptions::cache_model).
struct CacheCostModel {
  CacheCosts costs;
  CacheFrame frame;
};

}  // namespace pmc
