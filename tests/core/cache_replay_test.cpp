// cache_replay_test.cpp — the replayed policies against answers worked out
// independently (core/cache_replay.h).
//  * The textbook reference string 7 0 1 2 0 3 0 4 2 3 0 3 2 1 2 0 1 7 0 1
//    with three frames (one cell of three entries): LRU faults 12 times
//    (8 hits); keep-first holds 7, 0, 1 for good: their 9 later lookups hit.
//  * Belady's MIN (with the choice not to insert) on random short traces:
//    as many hits as an exhaustive search over every eviction and
//    non-insertion finds, and never fewer than LRU, keep-first or priority.
//  * Priority: a camera lookup replaces the deepest non-camera entry of a
//    full cell, never a camera entry.
//  * Region-major order: regions row by row, depth by depth within one, the
//    trace's order among equals.
//  * A file that is not a trace, or is cut short, is refused, naming it.
#include "core/cache_replay.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

TraceLookup at(uint64_t key, uint32_t depth = 1, uint32_t pixel = 0, uint32_t sample = 0) {
  return {key, uint64_t(pixel) | uint64_t(depth) << 32 | uint64_t(sample) << 40};
}

std::vector<TraceLookup> textbook() {
  std::vector<TraceLookup> t;
  for (uint64_t k : {7, 0, 1, 2, 0, 3, 0, 4, 2, 3, 0, 3, 2, 1, 2, 0, 1, 7, 0, 1}) t.push_back(at(k + 100));
  return t;
}

TEST(CacheReplay, TextbookStringUnderLruAndKeepFirst) {
  EXPECT_EQ(replay_lru(textbook(), 1, 3).hits, 8u);         // 12 faults
  EXPECT_EQ(replay_keep_first(textbook(), 1, 3).hits, 9u);  // 7, 0, 1 stay: their 9 repeats hit
  EXPECT_EQ(replay_lru(textbook(), 1, 3).lookups, 20u);
}

// The most hits any policy gets: every choice at every miss (not inserting,
// or inserting in place of any held key), searched exhaustively.
uint64_t best_hits(const std::vector<TraceLookup>& t, size_t i, std::set<uint64_t> held, size_t cap,
                   std::map<std::pair<size_t, std::set<uint64_t>>, uint64_t>& memo) {
  if (i == t.size()) return 0;
  auto key = std::make_pair(i, held);
  if (auto f = memo.find(key); f != memo.end()) return f->second;
  uint64_t best;
  if (held.count(t[i].key)) {
    best = 1 + best_hits(t, i + 1, held, cap, memo);
  } else {
    best = best_hits(t, i + 1, held, cap, memo);  // not inserted
    if (held.size() < cap) {
      std::set<uint64_t> h = held;
      h.insert(t[i].key);
      best = std::max(best, best_hits(t, i + 1, h, cap, memo));
    } else {
      for (uint64_t out : held) {
        std::set<uint64_t> h = held;
        h.erase(out);
        h.insert(t[i].key);
        best = std::max(best, best_hits(t, i + 1, h, cap, memo));
      }
    }
  }
  memo[key] = best;
  return best;
}

TEST(CacheReplay, BeladyFindsTheMostHitsAnyPolicyCan) {
  std::map<std::pair<size_t, std::set<uint64_t>>, uint64_t> memo;
  EXPECT_EQ(replay_belady(textbook(), 3).hits, best_hits(textbook(), 0, {}, 3, memo));
  EXPECT_GE(replay_belady(textbook(), 3).hits, 11u);  // OPT without the choice not to insert: 9 faults
  std::mt19937 rng(5);
  for (int round = 0; round < 40; ++round) {
    std::vector<TraceLookup> t;
    const int keys = 3 + int(rng() % 6), n = 10 + int(rng() % 10);
    for (int i = 0; i < n; ++i) t.push_back(at(rng() % uint64_t(keys), rng() % 3));
    const size_t cap = 1 + rng() % 3;
    memo.clear();
    const uint64_t best = best_hits(t, 0, {}, cap, memo);
    SCOPED_TRACE("round " + std::to_string(round));
    EXPECT_EQ(replay_belady(t, cap).hits, best);
    EXPECT_LE(replay_lru(t, 1, uint32_t(cap)).hits, best);
    EXPECT_LE(replay_keep_first(t, 1, uint32_t(cap)).hits, best);
    EXPECT_LE(replay_priority(t, 1, uint32_t(cap)).hits, best);
  }
}

TEST(CacheReplay, PriorityReplacesTheDeepestNonCameraEntry) {
  // One cell of two entries: keys 1 (depth 2) and 2 (depth 1) fill it; camera
  // key 3 replaces key 1 (the deeper); camera key 4 then replaces key 2; a
  // third camera key finds only camera entries and is dropped.
  std::vector<TraceLookup> t = {at(1, 2), at(2, 1), at(3, 0), at(1, 2), at(2, 1), at(4, 0),
                                at(2, 1), at(5, 0), at(3, 0), at(4, 0), at(5, 0)};
  const ReplayCounts r = replay_priority(t, 1, 2);
  // hits: key 2 at index 4; key 3 and key 4 at indices 8 and 9
  EXPECT_EQ(r.hits, 3u);
  EXPECT_EQ(r.camera_hits, 2u);
  EXPECT_EQ(r.camera_lookups, 6u);
  // keep-first keeps keys 1 and 2: hits at indices 3, 4 and 6
  EXPECT_EQ(replay_keep_first(t, 1, 2).hits, 3u);
  EXPECT_EQ(replay_keep_first(t, 1, 2).camera_hits, 0u);
}

TEST(CacheReplay, CellsAreTheKeyModuloTheirCount) {
  // Keys 0 and 4 share cell 0 of 4 one-entry cells; key 1 has its own.
  std::vector<TraceLookup> t = {at(0), at(4), at(1), at(0), at(4), at(1)};
  EXPECT_EQ(replay_keep_first(t, 4, 1).hits, 2u);  // 0 and 1 again; 4 was dropped
  EXPECT_EQ(replay_keep_first(t, 3, 1).hits, 2u);  // cells 0, 1, 1 (mod 3): 0 and 4 kept
  EXPECT_EQ(replay_lru(t, 4, 1).hits, 1u);         // 0 and 4 evict each other
}

TEST(CacheReplay, RegionMajorOrder) {
  // A 4x2 frame cut 2x2: regions 0 and 1 are pixels 0-1 and 2-3 of the
  // first row, regions 2 and 3 pixels 4-5 and 6-7 of the second.
  std::vector<TraceLookup> t = {at(10, 1, 2), at(11, 0, 6), at(12, 1, 0), at(13, 0, 5), at(14, 0, 0)};
  std::vector<TraceLookup> r = region_major(t, 4, 2, 2);
  std::vector<uint64_t> keys;
  for (const TraceLookup& l : r) keys.push_back(l.key);
  EXPECT_EQ(keys, (std::vector<uint64_t>{14, 12, 10, 13, 11}));
}

TEST(CacheReplay, RefusesFilesThatAreNotTraces) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/x.trace", "not a trace at all, but long enough for a header.....");
  try {
    read_lookup_trace(dir + "/x.trace");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x.trace"), std::string::npos) << e.what();
  }
  // A real header that promises two records, with one.
  std::string text = "PMCTRACE";
  auto put = [&](auto v) { text.append(reinterpret_cast<const char*>(&v), sizeof v); };
  for (uint32_t v : {1u, 4u, 2u, 8u}) put(v);
  for (uint64_t v : {uint64_t(16), uint64_t(2), uint64_t(2)}) put(v);
  put(uint64_t(7));
  put(uint64_t(0));
  test::write_file(dir + "/short.trace", text);
  try {
    read_lookup_trace(dir + "/short.trace");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("short.trace"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cut short"), std::string::npos) << e.what();
  }
  put(uint64_t(9));
  put(uint64_t(1) << 32);
  test::write_file(dir + "/ok.trace", text);
  const LookupTrace ok = read_lookup_trace(dir + "/ok.trace");
  ASSERT_EQ(ok.records.size(), 2u);
  EXPECT_EQ(ok.records[1].key, 9u);
  EXPECT_EQ(ok.records[1].depth(), 1u);
  EXPECT_EQ(ok.cells, 16u);
  EXPECT_EQ(ok.ways, 8u);
}

}  // namespace
}  // namespace pmc
