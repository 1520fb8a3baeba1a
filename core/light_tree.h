// light_tree.h — the light BVH that next-event estimation walks to pick a
// finite light in proportion to its importance at the shading point.
//
// Design (Conty Estevez & Kulla 2018, "Importance Sampling of Many Lights
// with Adaptive Tree Splitting"; the layout follows pbrt-v4's
// BVHLightSampler): every finite light (quad, emissive triangle, point,
// spot) is summarised by LightBounds — a box, an intensity bound and an
// orientation cone (axis, theta_o the spread of the normals or spot axis,
// theta_e how far emission reaches beyond them). build_light_tree() splits
// the lights top-down with binned SAH on the centroids, the cost of a side
// being energy x M_Omega(cone) x box area, times the node's aspect along
// the split axis (the orientation-aware cost of the paper, pbrt-v4's Kr),
// and writes the nodes depth first (PmcLightTreeNode: an interior node's
// first child follows it). Every leaf holds one light; the tree is at most
// kMaxLightTreeDepth deep (from depth kSahDepth on, the split halves by
// count), so a light's way
// from the root fits the 64 bits of PmcLight.tree_trail, which is how the
// kernel recomputes a pick's probability for MIS (core/device/pmc_lights.h).
// Build cost: O(n log n) time, 2n - 1 nodes of 64 bytes.
#pragma once

#include <cstdint>
#include <vector>

#include "core/abi/pmc_types.h"

namespace pmc {

constexpr int kMaxLightTreeDepth = 64;

// What the tree knows of one light.
struct LightBounds {
  float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  float energy = 0.0f;  // luminance intensity bound, W/sr (radiance x area for emitters)
  float axis[3] = {0, 0, 1};
  float cos_theta_o = 1.0f;  // normals / spot axes within theta_o of axis
  float cos_theta_e = 0.0f;  // emission at most theta_e beyond them
  bool two_sided = false;
  uint32_t light = 0;  // its index in the light table
};

struct LightTree {
  std::vector<PmcLightTreeNode> nodes;  // depth first, root at 0 (empty without lights)
  std::vector<uint64_t> trails;         // per input light: bit d = 1 where depth d goes to the second child
  int depth = 0;                        // of the deepest leaf (the root is depth 0)
};

// Builds the tree over `lights` (any order; zero-energy lights are kept and
// get zero importance). The nodes' leaves hold LightBounds::light.
LightTree build_light_tree(const std::vector<LightBounds>& lights);

}  // namespace pmc
