// cache_plan.h — which nodes of a material the progressive cache stores.
//
// Bottom-up dependency bits (graph_analysis.h) say which shading-point inputs each
// node reads. A node is a cache point when its whole sub-graph depends on uv
// and nothing else, or on position and nothing else (and is not constant),
// no consumer of it has the same single dependency (it is the highest such
// node), its value has a 32-bit encoding (float,
// non-negative colour3/vector3 as RGB9E5, vector2 as two halves), and its
// sub-graph has at least `min_nodes` nodes: a smaller sub-graph costs less to
// evaluate than a lookup. When the highest such node cannot be encoded or
// is too cheap, its inputs of the same dependency are considered instead. A
// uv-only point is keyed on the uv texel, a position-only one on the position
// cell (pmc_cache.h). Sub-graphs that read uv and position together, or the
// normal or tangent frame, are not cached: their value is not a function of
// one key (a uv seam or a normal map would alias across the key's cell).
// With a cost model (materials/node_costs.h) the node count is a floor: a
// point must also pay on the device for the frame, h C > L + (1 - h) M, and
// the point carries the figures behind that decision for the plan dump. A
// point that does not pay is not replaced by its inputs (their sub-graphs
// cost less at the same hit rate, so they pay less).
// A material can have several cache points. Every other node gets a reason
// for the plan dump. Each point carries the level floor its pattern's
// bandwidth asks for (materials/bandwidth.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/device/pmc_cache.h"
#include "materials/node_costs.h"
#include "materials/node_graph.h"

namespace pmc {

enum class CacheKey { Uv, Position };

struct CachePoint {
  int node = -1;
  int subgraph_nodes = 0;  // nodes a hit skips
  uint32_t encoding = 0;   // PMC_ENC_*
  CacheKey key = CacheKey::Uv;
  // Bandwidth (materials/bandwidth.h): the sub-graph's smallest feature in
  // key units, the level floor it asks for (PMC_LEVEL_NO_FLOOR: none), and
  // why it has none when a pattern's coordinate has no bound.
  double feature = 1e300;
  int level_floor = PMC_LEVEL_NO_FLOOR;
  std::string bandwidth_note;
  // Sub-samples a miss evaluates and averages in cache_eval center
  // (core/device/pmc_cache_supersample.h): a power of two, 1..16.
  int supersample = 1;
  // The cost model's figures (modelled: a model decided; else the node count alone).
  bool modelled = false;
  PointEconomics economics;
};

const char* cache_key_name(CacheKey k);

struct CachePlan {
  std::vector<CachePoint> points;
  std::vector<std::pair<int, std::string>> not_cached;  // node, reason
};

// The sub-graph size threshold found by measurement; with the cost model on
// (the default) it stays the floor, so cheap sub-graphs of a few costly nodes
// (a 4-node fractal3d roughness) stay uncached: a cached roughness moves
// highlights and lobe choices (docs/BENCHMARKS.md, "Node costs"). The
// measurement behind 8 (scripts/bench-cache,
// "cache point threshold" in docs/BENCHMARKS.md): on PoCL a 3-node point
// costs the default scene a fifth of its speed-up, points of 4-16 nodes are
// within noise of each other, and dropping the 25-31-node points loses a
// quarter of it. 8 keeps clear of the losing end.
constexpr int kDefaultCacheMinNodes = 8;

// `position_keys`: position-only sub-graphs may become (position-keyed) points.
// `feature_texels` > 0: points get level floors from their patterns' feature
// sizes, this many texels across the smallest (materials/bandwidth.h); 0: none.
// `model`: each point must also pay (see above); nullptr: node counts alone.
// `supersample`: each point's sub-samples by its key kind (the model counts them).
CachePlan plan_cache(const Graph& g, int min_nodes, bool position_keys = true, double feature_texels = 0.0,
                     const CacheCostModel* model = nullptr, CacheSupersample supersample = {});

// A material's level floor for one key kind: the highest of its points' (the
// points of one evaluation share one texel or cell, so their sub-graphs run
// once, at its centre in cache_eval center); PMC_LEVEL_NO_FLOOR if none.
int material_level_floor(const CachePlan& plan, CacheKey key);
// Nodes of the sub-graph under `node` (itself included), inputs first.
std::vector<int> subgraph_order(const Graph& g, int node);

}  // namespace pmc
