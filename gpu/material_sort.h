// material_sort.h — hits in batches of one material, for the shade kernel.
//
// The shade kernel evaluates materials for a batch of hits at once (a
// work-item runs the interpreter once for `lanes` hits of one material), so
// the host orders each queue of hits by material before shading: a counting
// sort over the triangles' materials (stable, so hits of one material keep
// their queue order), each material's run padded with PMC_NO_RAY up to a
// whole number of batches. Rays that escaped form a run of their own. On a
// GPU (lanes = 1) the order still groups work-items of one material, which
// keeps a SIMT unit on one instruction stream.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/abi/pmc_types.h"

namespace pmc {

class MaterialSorter {
 public:
  // `triangle_material[t]`: material of scene triangle t, in [0, material_count).
  MaterialSorter(std::vector<int32_t> triangle_material, int material_count, int lanes);

  // Most order entries a queue of `count` hits can need.
  size_t capacity(size_t count) const;
  // Writes the ray indices first_ray + i of hits[0, count) to `order`, grouped by
  // material and padded; returns the number of entries (a multiple of lanes).
  size_t sort(const PmcHit* hits, size_t count, uint32_t first_ray, uint32_t* order);

  int lanes() const { return lanes_; }
  // Hits sorted per material since reset_counts() (escaped rays not counted):
  // how often each material ran, for the cache's predicted savings.
  const std::vector<uint64_t>& material_hits() const { return hits_; }
  void reset_counts() { std::fill(hits_.begin(), hits_.end(), 0); }
  // Adds another sorter's counts (a second wave in flight's).
  void add_counts(const std::vector<uint64_t>& hits) {
    for (size_t i = 0; i < hits_.size() && i < hits.size(); ++i) hits_[i] += hits[i];
  }

 private:
  std::vector<int32_t> material_;
  int buckets_;  // materials + 1 (escaped rays)
  int lanes_;
  std::vector<uint32_t> start_;  // per bucket: count, then write position
  std::vector<uint64_t> hits_;   // per material
};

}  // namespace pmc
