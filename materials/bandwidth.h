// bandwidth.h — how fine a material's patterns are, for the cache's texel size.
//
// A cache point stores one value per virtual texel (uv) or cell (position).
// When the pattern under it has features smaller than the texel (grid lines,
// tile gaps, a noise's top octave), the texel's one value stands for an area
// the pattern changes inside: the cached image aliases where the cacheless
// one averages. This pass bounds, bottom-up, three quantities per node:
//  - rate: how fast the value runs per key unit (uv, or scene units for
//    position), for values used as coordinates: texcoord and position 1,
//    multiply by c |c| times, place2d 1 / scale, a noise its slope;
//    infinity where pmc has no bound;
//  - magnitude: a bound on |value| (infinity where none);
//  - features: (size in key units, amplitude in value units) pairs, kept on
//    their Pareto front (no pair both larger and fainter than another).
// Pattern nodes add a feature of their own period in their coordinate,
// divided by the coordinate's rate, with their output's range as amplitude:
//  - grid and crosshatch: min(thickness, 1 - thickness) / uvtiling;
//  - tiled shapes: min(size, 1 - size) / uvtiling (the gap between shapes);
//  - noise: half its lattice cell; fractal: that at its finest octave that
//    still has at least 1/8 of the first octave's amplitude;
//  - cellnoise: its cell; worley: half its cell;
//  - floor, ceil, round: 1; modulo: its divisor; sin, cos: pi;
//  - smoothstep: its transition width.
// A feature's amplitude follows the gains on its way up: a multiply by the
// other factor's magnitude, a mix's weight by |fg - bg|, remap and
// smoothstep by their slopes; never beyond twice the node's magnitude. A
// pattern turns its coordinate's features into features of its own range.
// A cache point's feature is its smallest one with amplitude at least
// kMinFeatureAmplitude: fainter ones (the default floor's scratches, 0.06)
// alias by less than resolving them would cost.
// Images are filtered to the footprint by their own mip map, so they add no
// feature (their uvtiling and resolution only scale how fast they change).
// Isolated edges (splitlr, ifgreater) are no periodic features and are not
// bounded. A pattern whose coordinate has no bound adds no feature (and the
// point gets a note saying so): no floor, the paper's behaviour.
//
// The cache plan turns a point's feature w into a level floor
// ceil(log2(n / w)): n texels across the feature, 2 by default
// (cache_feature_texels).
#pragma once

#include <string>
#include <vector>

#include "materials/node_graph.h"

namespace pmc {

struct Feature {
  double size = 0;       // key units
  double amplitude = 0;  // value units
};

constexpr double kNoFeature = 1e300;
constexpr double kDefaultFeatureTexels = 2.0;
constexpr double kMinFeatureAmplitude = 0.1;

struct NodeBandwidth {
  double rate = 0;                // |d value / d key| bound (infinity: unknown)
  double magnitude = 0;           // |value| bound (infinity: unknown)
  std::vector<Feature> features;  // Pareto front, by size
  std::string unbounded;          // a pattern below reads a coordinate without a bound: which
  // The smallest feature of at least `min_amplitude` (kNoFeature if none).
  double feature(double min_amplitude = kMinFeatureAmplitude) const;
};

// Per node (index as in g.nodes); dead nodes get the defaults.
std::vector<NodeBandwidth> node_bandwidths(const Graph& g);

// The level floor for a feature size w in key units: the smallest integer
// level whose texels (2^-level) are at most w / texels_per_feature, clamped
// to [no_floor, max_level]; `no_floor` when w is none (or not positive and
// finite) or texels_per_feature is not positive.
int level_floor_for_feature(double feature, double texels_per_feature, int no_floor, int max_level);

}  // namespace pmc
