// cache_sizing.cpp — the sizing rule (see cache_sizing.h).
#include "core/cache_sizing.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pmc {

double expected_keys_per_pixel_point(int spp) {
  return 1.0 + 3.0 * (1.0 - 1.0 / std::sqrt(double(std::max(spp, 1))));
}

CacheSize choose_cache_size(int width, int height, int spp, double points, uint64_t memory_limit_bytes,
                            uint32_t entries) {
  CacheSize s;
  s.entries = std::max<uint32_t>(entries, 1);
  const double pixels = double(width) * double(height);
  const double factor = expected_keys_per_pixel_point(spp);
  const double keys = pixels * std::max(points, 1.0) * factor;
  const double slots = keys * 2.0;  // load factor 1/2
  uint64_t cells = uint64_t(std::ceil(slots / s.entries));
  cells = std::max<uint64_t>(cells, 1024);
  uint64_t pow2 = 1;  // a power of two: the cell index is a mask, not a 64-bit division
  while (pow2 < cells) pow2 <<= 1;
  cells = pow2;
  const uint64_t max_cells = std::max<uint64_t>(1024, memory_limit_bytes / (8ull * s.entries));
  bool capped = cells > max_cells;
  while (cells > max_cells && cells > 1024) cells >>= 1;
  s.cells = cells;
  std::ostringstream os;
  os.precision(3);
  os << width << "x" << height << " pixels x " << points << " cache points per material x " << factor
     << " (texels reached by " << spp << " spp: jitter, bilinear selection, bounces) = " << uint64_t(keys)
     << " expected keys at load factor 1/2 in cells of " << s.entries << " entries"
     << (capped ? ", capped by the memory limit" : "");
  s.reason = os.str();
  return s;
}

}  // namespace pmc
