// cache_sizing.cpp — the sizing rule (see cache_sizing.h).
#include "core/cache_sizing.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pmc {

CacheSize choose_cache_size(int width, int height, double points, uint64_t memory_limit_bytes) {
  CacheSize s;
  s.entries = 8;
  const double pixels = double(width) * double(height);
  const double keys = pixels * std::max(points, 1.0) * 2.0 * 2.0;  // jitter, secondary bounces
  const double slots = keys * 2.0;                                 // load factor 1/2
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
  os << width << "x" << height << " pixels x " << points
     << " cache points per material x 4 (jitter, bounces) = " << uint64_t(keys)
     << " expected keys at load factor 1/2" << (capped ? ", capped by the memory limit" : "");
  s.reason = os.str();
  return s;
}

}  // namespace pmc
