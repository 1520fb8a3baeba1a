// cache_sizing.cpp — the sizing rule (see cache_sizing.h).
#include "core/cache_sizing.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace pmc {

double expected_keys_per_pixel_point(int spp) {
  return 1.0 + 3.0 * (1.0 - 1.0 / std::sqrt(double(std::max(spp, 1))));
}

double expected_entries(int width, int height, int spp, double points) {
  const double pixels = double(width) * double(height);
  return pixels * std::max(points, 1.0) * expected_keys_per_pixel_point(spp) * 2.0;  // load factor 1/2
}

float fit_levels(double expected, uint64_t table_entries) {
  if (table_entries == 0 || !(expected > double(table_entries))) return 0.0f;
  return float(0.5 * std::log2(expected / double(table_entries)));
}

CacheSize choose_cache_size(int width, int height, int spp, double points, uint64_t memory_limit_bytes,
                            uint32_t entries) {
  CacheSize s;
  s.entries = std::max<uint32_t>(entries, 1);
  const double factor = expected_keys_per_pixel_point(spp);
  const double slots = expected_entries(width, height, spp, points);
  const double keys = slots / 2.0;
  uint64_t cells = table_cells_at_least(uint64_t(std::ceil(slots / s.entries)));
  const uint64_t max_cells = std::max<uint64_t>(1024, memory_limit_bytes / (8ull * s.entries));
  bool capped = cells > max_cells;
  while (cells > max_cells && cells > 1024) cells >>= 1;
  s.cells = cells;
  std::ostringstream os;
  os.precision(3);
  os << width << "x" << height << " pixels x " << points << " cache points per material (position points twice) x "
     << factor
     << " (texels reached by " << spp << " spp: jitter, bilinear selection, bounces) = " << uint64_t(keys)
     << " expected keys at load factor 1/2 in cells of " << s.entries << " entries"
     << (capped ? ", capped by the memory limit" : "");
  s.reason = os.str();
  return s;
}

uint64_t table_cells_at_least(uint64_t cells) {
  uint64_t pow2 = 1024;
  while (pow2 < cells) pow2 <<= 1;
  return pow2;
}

uint64_t cells_for_total_entries(uint64_t total_entries, uint64_t entries) {
  entries = std::max<uint64_t>(entries, 1);
  return table_cells_at_least((total_entries + entries - 1) / entries);
}

uint64_t available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  uint64_t kb = 0;
  while (in >> key) {
    if (key == "MemAvailable:") {
      in >> kb;
      return kb * 1024;
    }
    std::string rest;
    std::getline(in, rest);
  }
  return uint64_t(8) << 30;
}

std::string table_memory_problem(uint64_t cells, uint64_t entries) {
  const double bytes = double(cells) * double(entries) * 8.0, avail = double(available_memory_bytes());
  if (bytes <= avail * 0.8) return "";
  std::ostringstream os;
  os << "a table of " << cells << " cells x " << entries << " entries (" << bytes / double(1 << 20)
     << " MiB) does not fit in the " << avail / double(1 << 20) << " MiB of free memory";
  return os.str();
}

}  // namespace pmc
