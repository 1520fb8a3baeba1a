// cache_replay.h — replays a render's cache lookups under other replacement
// policies, table sizes and orders (the trace: gpu/cache_trace.h).
//
// The material cache keeps the first entries of a full cell (keep-first, the
// paper's rule) or lets camera-ray hits replace deeper ones (priority). How
// much better could any policy do? A trace of every lookup answers that
// offline: replaying it under keep-first and priority reproduces the
// renderer's own hit rates (up to the order of lookups within a launch), and
// Belady's MIN, which evicts the entry used again farthest in the future (or
// does not insert at all when the new key comes back later than everything
// held), gives the most hits any policy can get from a table of that many
// entries in that order, whatever its cells. Region-major order replays the
// same lookups as if each wave held all samples of one region of the frame
// (depth by depth) instead of one sample of the whole frame. A replay counts
// lookups only: a key's value and the work a miss costs are the renderer's.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pmc {

struct TraceLookup {
  uint64_t key = 0;   // the key's 64-bit hash (its cell: key mod cells)
  uint64_t info = 0;  // pixel | depth << 32 | sample << 40 | position << 60
  uint32_t pixel() const { return uint32_t(info); }
  uint32_t depth() const { return uint32_t(info >> 32) & 0xffu; }
  uint32_t sample() const { return uint32_t(info >> 40) & 0xfffffu; }
};

struct LookupTrace {
  uint32_t width = 0, height = 0, ways = 0;
  uint64_t cells = 0;    // the render's table
  uint64_t lookups = 0;  // all lookups of the render (records past the capacity were not kept)
  std::vector<TraceLookup> records;
};

// Reads a trace file; a file that is not one, or is cut short, fails with an
// error that names it.
LookupTrace read_lookup_trace(const std::string& path);

struct ReplayCounts {
  uint64_t lookups = 0, hits = 0, camera_lookups = 0, camera_hits = 0;
  double hit_rate() const { return lookups ? double(hits) / double(lookups) : 0.0; }
  double camera_hit_rate() const {
    return camera_lookups ? double(camera_hits) / double(camera_lookups) : 0.0;
  }
};

// The renderer's policies in cells of `ways` entries (a key's cell: key mod cells).
ReplayCounts replay_keep_first(const std::vector<TraceLookup>& trace, uint64_t cells, uint32_t ways);
ReplayCounts replay_priority(const std::vector<TraceLookup>& trace, uint64_t cells, uint32_t ways);
// Least recently used in cells of `ways` entries: for comparison.
ReplayCounts replay_lru(const std::vector<TraceLookup>& trace, uint64_t cells, uint32_t ways);
// Belady's MIN with `entries` entries in one fully associative table: the
// bound on every policy's hits for a table that size.
ReplayCounts replay_belady(const std::vector<TraceLookup>& trace, uint64_t entries);

// The lookups reordered region-major: the frame cut into regions x regions
// rectangles; region by region (rows of regions top to bottom), and within a
// region depth by depth, each in trace order.
std::vector<TraceLookup> region_major(const std::vector<TraceLookup>& trace, uint32_t width, uint32_t height,
                                      uint32_t regions);

}  // namespace pmc
