// cache_sizing.h — choosing the cache table's size from the scene.
//
// Without --cache-cells/--cache-entries the table is sized for the keys a
// render is expected to create: about one virtual texel per pixel and cache
// point for camera hits (the ray cone's footprint is about a pixel), doubled
// for sub-pixel jitter crossing texel borders and again for secondary bounces
// (wider cones, coarser texels), at a load factor of one half. Cells hold 8
// entries (one 64-byte cache line). The reason is kept for the log and stats.
#pragma once

#include <cstdint>
#include <string>

namespace pmc {

struct CacheSize {
  uint64_t cells = 0;
  uint32_t entries = 0;  // per cell
  std::string reason;
  uint64_t bytes() const { return cells * entries * 8; }
};

CacheSize choose_cache_size(int width, int height, double cache_points_per_material,
                            uint64_t memory_limit_bytes);

}  // namespace pmc
