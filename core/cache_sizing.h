// cache_sizing.h — choosing the cache table's size from the scene.
//
// Without cache_cells the table is sized for the keys a render is expected
// to create: about one virtual texel per pixel and cache point for camera
// hits (the ray cone's footprint is about a pixel), times a factor for the
// samples: later samples' sub-pixel jitter, bilinear texel selection and
// secondary bounces (wider cones, coarser texels) reach texels the first
// missed. Measured on the default scene at 320x180 (1.75 points per
// material), keys / (pixels x points) = 1.12 at 1 spp, 2.14 at 4, 2.69 at
// 16, 2.90 at 64; the rule 1 + 3 (1 - 1/sqrt(spp)) (1, 2.5, 3.25, 3.6) stays
// above that from 4 spp on, and the load factor of one half absorbs the rest.
// A position-keyed point counts twice (a surface cuts about twice as many
// cells as it covers texels): on the heavy scene (13 uv and 12 position
// points) the table sized by the plain count dropped about 40% of its misses'
// inserts from full cells at 256 spp. Cells hold 8 entries (one 64-byte cache
// line) unless cache_entries says otherwise. The reason is kept for the log
// and stats.
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

// Keys per pixel and cache point after `spp` samples (see above).
double expected_keys_per_pixel_point(int spp);
// Entries a frame's expected keys need at load factor 1/2 (before rounding to cells).
double expected_entries(int width, int height, int spp, double cache_points_per_material);
// cache_fit: the levels to coarsen texels by so that `expected` entries' worth
// of keys fit in `table_entries`: half a level per halving (a level has 4x
// fewer texels, and cells cut by a surface scale like area); 0 when they fit.
float fit_levels(double expected, uint64_t table_entries);

// `entries` per cell (8 by default); the cell count is a power of two of at
// least 1024, halved while the table exceeds `memory_limit_bytes`.
CacheSize choose_cache_size(int width, int height, int spp, double cache_points_per_material,
                            uint64_t memory_limit_bytes, uint32_t entries = 8);

// Cell counts are powers of two (the cell index is a mask, not a 64-bit
// division) of at least 1024: the smallest such count >= `cells`.
uint64_t table_cells_at_least(uint64_t cells);
// The cells of `entries` each that hold `total_entries` (rounded up as above):
// how a table keeps its size when its cells get wider or narrower.
uint64_t cells_for_total_entries(uint64_t total_entries, uint64_t entries);

// MemAvailable from /proc/meminfo (8 GiB where it cannot be read).
uint64_t available_memory_bytes();
// "" if a table of cells x entries (8 bytes each) fits in 80% of the free
// memory, else what is wrong: "a table of C cells x E entries (X MiB) does
// not fit in the Y MiB of free memory".
std::string table_memory_problem(uint64_t cells, uint64_t entries);

}  // namespace pmc
