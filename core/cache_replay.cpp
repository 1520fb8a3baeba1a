// cache_replay.cpp — trace reading and the replayed policies (cache_replay.h).
#include "core/cache_replay.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <numeric>
#include <queue>
#include <unordered_map>

#include "core/error.h"

namespace pmc {

namespace {

template <typename T>
bool get(std::ifstream& in, T& v) {
  return bool(in.read(reinterpret_cast<char*>(&v), sizeof v));
}

void count(ReplayCounts& r, const TraceLookup& l, bool hit) {
  const bool camera = l.depth() == 0;
  r.lookups++;
  r.camera_lookups += camera;
  r.hits += hit;
  r.camera_hits += hit && camera;
}

uint64_t cell_of(uint64_t key, uint64_t cells) {
  return (cells & (cells - 1)) == 0 ? key & (cells - 1) : key % cells;
}

void check_table(uint64_t cells, uint32_t ways) {
  if (cells == 0 || ways == 0) fail("cache replay: a table needs at least one cell of at least one entry");
}

// Index of each lookup's next lookup of the same key (UINT64_MAX: none).
std::vector<uint64_t> next_uses(const std::vector<TraceLookup>& t) {
  std::vector<uint64_t> order(t.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](uint64_t a, uint64_t b) { return t[a].key < t[b].key; });
  std::vector<uint64_t> next(t.size(), UINT64_MAX);
  for (size_t j = 0; j + 1 < order.size(); ++j)
    if (t[order[j]].key == t[order[j + 1]].key) next[order[j]] = order[j + 1];
  return next;
}

}  // namespace

LookupTrace read_lookup_trace(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cache trace '", path, "': cannot open it");
  char magic[8];
  uint32_t version = 0;
  LookupTrace t;
  uint64_t kept = 0;
  if (!in.read(magic, 8) || std::memcmp(magic, "PMCTRACE", 8) != 0)
    fail("cache trace '", path, "': not a pmc cache trace (PMC_CACHE_TRACE writes them)");
  if (!get(in, version) || version != 1)
    fail("cache trace '", path, "': version ", version, " (this pmc reads 1)");
  if (!get(in, t.width) || !get(in, t.height) || !get(in, t.ways) || !get(in, t.cells) ||
      !get(in, t.lookups) || !get(in, kept))
    fail("cache trace '", path, "': its header is cut short");
  if (kept > t.lookups) fail("cache trace '", path, "': ", kept, " records kept of ", t.lookups, " lookups");
  in.seekg(0, std::ios::end);
  const uint64_t bytes = uint64_t(in.tellg()), header = 48;
  if (bytes != header + kept * 16)
    fail("cache trace '", path, "': ", bytes, " bytes where its header promises ", header + kept * 16,
         " (a trace cut short or with bytes after it)");
  in.seekg(std::streamoff(header));
  t.records.resize(size_t(kept));
  if (kept && !in.read(reinterpret_cast<char*>(t.records.data()), std::streamsize(kept * 16)))
    fail("cache trace '", path, "': its records could not be read");
  return t;
}

ReplayCounts replay_keep_first(const std::vector<TraceLookup>& trace, uint64_t cells, uint32_t ways) {
  check_table(cells, ways);
  ReplayCounts r;
  std::vector<uint64_t> keys(size_t(cells * ways));
  std::vector<uint8_t> used(size_t(cells * ways), 0);
  for (const TraceLookup& l : trace) {
    const size_t base = size_t(cell_of(l.key, cells) * ways);
    bool hit = false;
    for (uint32_t w = 0; w < ways; ++w) {
      if (!used[base + w]) {  // entries fill from the front: the first empty one ends the scan
        used[base + w] = 1;
        keys[base + w] = l.key;
        break;
      }
      if (keys[base + w] == l.key) {
        hit = true;
        break;
      }
    }
    count(r, l, hit);
  }
  return r;
}

ReplayCounts replay_priority(const std::vector<TraceLookup>& trace, uint64_t cells, uint32_t ways) {
  check_table(cells, ways);
  ReplayCounts r;
  std::vector<uint64_t> keys(size_t(cells * ways));
  std::vector<uint8_t> tag(size_t(cells * ways), 0);  // 0: empty, else min(depth, 3) + 1
  for (const TraceLookup& l : trace) {
    const size_t base = size_t(cell_of(l.key, cells) * ways);
    const uint8_t mine = uint8_t(std::min(l.depth(), 3u) + 1);
    bool hit = false, placed = false;
    size_t victim = SIZE_MAX;
    for (uint32_t w = 0; w < ways && !hit && !placed; ++w) {
      const size_t e = base + w;
      if (!tag[e]) {
        tag[e] = mine;
        keys[e] = l.key;
        placed = true;
      } else if (keys[e] == l.key) {
        hit = true;
      } else if (tag[e] > 1 && (victim == SIZE_MAX || tag[e] > tag[victim])) {
        victim = e;  // the deepest non-camera entry (the first of equals)
      }
    }
    if (!hit && !placed && mine == 1 && victim != SIZE_MAX) {  // a camera insert into a full cell
      tag[victim] = mine;
      keys[victim] = l.key;
    }
    count(r, l, hit);
  }
  return r;
}

ReplayCounts replay_lru(const std::vector<TraceLookup>& trace, uint64_t cells, uint32_t ways) {
  check_table(cells, ways);
  ReplayCounts r;
  std::vector<uint64_t> keys(size_t(cells * ways));
  std::vector<uint8_t> used(size_t(cells * ways), 0);
  for (const TraceLookup& l : trace) {  // a cell in recency order, most recent first
    uint64_t* k = &keys[size_t(cell_of(l.key, cells) * ways)];
    uint8_t* u = &used[size_t(cell_of(l.key, cells) * ways)];
    uint32_t at = ways - 1;
    bool hit = false;
    for (uint32_t w = 0; w < ways; ++w)
      if (!u[w] || k[w] == l.key) {
        hit = u[w] != 0;
        at = w;
        break;
      }
    for (uint32_t w = at; w > 0; --w) k[w] = k[w - 1], u[w] = u[w - 1];
    k[0] = l.key;
    u[0] = 1;
    count(r, l, hit);
  }
  return r;
}

ReplayCounts replay_belady(const std::vector<TraceLookup>& trace, uint64_t entries) {
  if (entries == 0) fail("cache replay: a table needs at least one entry");
  const std::vector<uint64_t> next = next_uses(trace);
  ReplayCounts r;
  std::unordered_map<uint64_t, uint64_t> held;  // key -> the index of its next lookup
  held.reserve(size_t(std::min<uint64_t>(entries, trace.size())) * 2);
  std::priority_queue<std::pair<uint64_t, uint64_t>> farthest;  // (next lookup, key), stale pairs skipped
  for (size_t i = 0; i < trace.size(); ++i) {
    const uint64_t key = trace[i].key, n = next[i];
    auto it = held.find(key);
    count(r, trace[i], it != held.end());
    if (it != held.end()) {
      if (n == UINT64_MAX) {
        held.erase(it);
      } else {
        it->second = n;
        farthest.push({n, key});
      }
      continue;
    }
    if (n == UINT64_MAX) continue;  // never looked up again: not worth an entry
    if (held.size() >= entries) {
      while (true) {
        const auto top = farthest.top();
        auto f = held.find(top.second);
        if (f == held.end() || f->second != top.first) {
          farthest.pop();
          continue;
        }
        if (top.first < n) break;  // everything held comes back sooner: do not insert
        farthest.pop();
        held.erase(f);
        break;
      }
      if (held.size() >= entries) continue;
    }
    held[key] = n;
    farthest.push({n, key});
  }
  return r;
}

std::vector<TraceLookup> region_major(const std::vector<TraceLookup>& trace, uint32_t width, uint32_t height,
                                      uint32_t regions) {
  if (width == 0 || height == 0 || regions == 0)
    fail("cache replay: region-major order needs a frame and regions");
  auto region = [&](const TraceLookup& l) {
    const uint64_t x = l.pixel() % width, y = std::min<uint64_t>(l.pixel() / width, height - 1);
    return (y * regions / height) * regions + x * regions / width;
  };
  std::vector<TraceLookup> out = trace;
  std::stable_sort(out.begin(), out.end(), [&](const TraceLookup& a, const TraceLookup& b) {
    const uint64_t ra = region(a), rb = region(b);
    return ra != rb ? ra < rb : a.depth() < b.depth();
  });
  return out;
}

}  // namespace pmc
