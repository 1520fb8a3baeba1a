// material_sort.cpp — counting sort of hits by material, padded to batches.
#include "gpu/material_sort.h"

#include <algorithm>

#include "core/error.h"

namespace pmc {

MaterialSorter::MaterialSorter(std::vector<int32_t> triangle_material, int material_count, int lanes)
    : material_(std::move(triangle_material)), buckets_(material_count + 1), lanes_(std::max(1, lanes)) {
  PMC_CHECK(material_count >= 0, "material count");
  for (int32_t& m : material_)
    if (m < 0 || m >= material_count) m = material_count;  // never: a triangle without a valid material
  start_.assign(size_t(buckets_) + 1, 0);
  hits_.assign(size_t(material_count), 0);
}

size_t MaterialSorter::capacity(size_t count) const { return count + size_t(buckets_) * size_t(lanes_ - 1); }

size_t MaterialSorter::sort(const PmcHit* hits, size_t count, uint32_t first_ray, uint32_t* order) {
  const uint32_t escaped = uint32_t(buckets_ - 1);
  auto bucket = [&](const PmcHit& h) {
    return h.prim >= 0 && size_t(h.prim) < material_.size() ? uint32_t(material_[size_t(h.prim)]) : escaped;
  };
  std::fill(start_.begin(), start_.end(), 0u);
  for (size_t i = 0; i < count; ++i) ++start_[bucket(hits[i]) + 1];
  // Runs padded to whole batches: start_[b] becomes the first entry of run b.
  const uint32_t lanes = uint32_t(lanes_);
  uint32_t at = 0;
  for (int b = 0; b < buckets_; ++b) {
    const uint32_t n = start_[size_t(b) + 1];
    const uint32_t padded = (n + lanes - 1) / lanes * lanes;
    if (b < buckets_ - 1) hits_[size_t(b)] += n;
    start_[size_t(b)] = at;
    std::fill(order + at + n, order + at + padded, PMC_NO_RAY);
    at += padded;
  }
  for (size_t i = 0; i < count; ++i) order[start_[bucket(hits[i])]++] = first_ray + uint32_t(i);
  return at;
}

}  // namespace pmc
