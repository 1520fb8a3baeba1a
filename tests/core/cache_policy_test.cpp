// cache_policy_test.cpp — the cache table's replacement policies
// (core/device/pmc_cache.h compiled as C++, one thread), and what the
// priority policy's depth tag costs in fingerprint bits.
//
//  * priority: a full cell takes a camera insert (depth 0) in place of its
//    deepest entry (the first of equal tags), written as {30-bit fingerprint,
//    tag, value}; deeper inserts never replace; camera entries are never
//    replaced; a key already present is not inserted twice; lookups of the
//    replaced key miss and all others still hit.
//  * keep-first (the paper's rule): the same sequence replaces nothing, and
//    entries keep the whole 32-bit fingerprint.
//  * False hits: over 2^22 distinct descriptors, the pairs whose 30-bit
//    fingerprints agree are counted against C(N, 2) * 2^-30, and the 32-bit
//    ones against 2^-32 (Poisson counts, 6 sigma bands). A lookup of an absent
//    key in a full cell of E entries then hits falsely with probability
//    about E * 2^-30 under priority, E * 2^-32 under keep-first (recorded as
//    test properties). And concretely: a key whose fingerprint differs from a
//    stored one only in the 2 low bits hits under priority, not under keep-first.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "core/device/pmc_cache.h"

namespace pmc {
namespace {

// Distinct descriptors whose keys fall into cell `cell` of a `cells`-cell table.
std::vector<PmcCacheKey> keys_in_cell(uint64_t cells, uint64_t cell, size_t count) {
  std::vector<PmcCacheKey> out;
  for (long tx = 0; out.size() < count; ++tx) {
    PmcCacheKey k = pmc_cache_key(3u, 17u, 0u, 9, tx, -4);
    if (k.h1 % cells == cell) out.push_back(k);
  }
  return out;
}

uint64_t priority_word(PmcCacheKey k, uint32_t depth, uint32_t value) {
  return (uint64_t((pmc_cache_fp30(k.fingerprint) << 2) | std::min(depth, 3u)) << 32) | value;
}

struct Table {
  std::vector<uint64_t> words;
  PmcCacheTable t{};
  Table(uint64_t cells, uint32_t ways, uint32_t policy) : words(cells * ways, 0) {
    t.entries = words.data();
    t.cells = cells;
    t.ways = ways;
    t.policy = policy;
  }
  int insert(PmcCacheKey k, uint32_t value, uint32_t depth) { return pmc_cache_insert(&t, k, value, depth); }
  // The value stored under k, or -1.
  int64_t lookup(PmcCacheKey k) const {
    pmc_u32 v = 0;
    return pmc_cache_lookup(&t, k, &v) ? int64_t(v) : -1;
  }
};

TEST(CachePolicy, PriorityCameraInsertReplacesTheDeepestEntryOfAFullCell) {
  const uint64_t cells = 4, cell = 1;
  const uint32_t ways = 4;
  Table tb(cells, ways, PMC_CACHE_PRIORITY);
  std::vector<PmcCacheKey> k = keys_in_cell(cells, cell, 9);
  const size_t base = cell * ways;
  // Fill the cell: tags 2, 1, 3 (depth 7 clamps to 3), 0.
  EXPECT_EQ(tb.insert(k[0], 100, 2), 1);
  EXPECT_EQ(tb.insert(k[1], 101, 1), 1);
  EXPECT_EQ(tb.insert(k[2], 102, 7), 1);
  EXPECT_EQ(tb.insert(k[3], 103, 0), 1);
  EXPECT_EQ(tb.words[base + 0], priority_word(k[0], 2, 100));
  EXPECT_EQ(tb.words[base + 2], priority_word(k[2], 3, 102));
  EXPECT_EQ(tb.words[base + 3], priority_word(k[3], 0, 103));
  // Deeper inserts never replace.
  EXPECT_EQ(tb.insert(k[4], 104, 1), -1);
  EXPECT_EQ(tb.insert(k[4], 104, 5), -1);
  EXPECT_EQ(tb.lookup(k[4]), -1);
  // A present key (even a deeper entry) is found, not inserted again.
  EXPECT_EQ(tb.insert(k[0], 999, 0), 0);
  EXPECT_EQ(tb.lookup(k[0]), 100);
  // Camera inserts replace the deepest: tag 3 (k2), then 2 (k0), then 1 (k1).
  EXPECT_EQ(tb.insert(k[4], 104, 0), 2);
  EXPECT_EQ(tb.words[base + 2], priority_word(k[4], 0, 104));
  EXPECT_EQ(tb.lookup(k[2]), -1) << "the replaced key misses";
  EXPECT_EQ(tb.lookup(k[4]), 104);
  EXPECT_EQ(tb.insert(k[5], 105, 0), 2);
  EXPECT_EQ(tb.words[base + 0], priority_word(k[5], 0, 105));
  EXPECT_EQ(tb.insert(k[6], 106, 0), 2);
  EXPECT_EQ(tb.words[base + 1], priority_word(k[6], 0, 106));
  // Now every entry is a camera entry: nothing replaces them.
  EXPECT_EQ(tb.insert(k[7], 107, 0), -1);
  EXPECT_EQ(tb.insert(k[8], 108, 2), -1);
  for (int i : {3, 4, 5, 6}) EXPECT_EQ(tb.lookup(k[size_t(i)]), 100 + i) << "camera key " << i;
  for (int i : {0, 1, 2, 7, 8}) EXPECT_EQ(tb.lookup(k[size_t(i)]), -1) << "key " << i;
  // The other cells were never touched.
  for (size_t i = 0; i < tb.words.size(); ++i)
    if (i / ways != cell) {
      EXPECT_EQ(tb.words[i], 0u) << "word " << i;
    }
}

TEST(CachePolicy, PriorityReplacesTheFirstOfEquallyDeepEntries) {
  Table tb(1, 3, PMC_CACHE_PRIORITY);
  std::vector<PmcCacheKey> k = keys_in_cell(1, 0, 5);
  for (uint32_t i = 0; i < 3; ++i) EXPECT_EQ(tb.insert(k[i], 10 + i, 1), 1);
  EXPECT_EQ(tb.insert(k[3], 13, 0), 2);
  EXPECT_EQ(tb.words[0], priority_word(k[3], 0, 13));
  EXPECT_EQ(tb.insert(k[4], 14, 0), 2);
  EXPECT_EQ(tb.words[1], priority_word(k[4], 0, 14));
  EXPECT_EQ(tb.lookup(k[2]), 12);
}

TEST(CachePolicy, KeepFirstReplacesNothingAndKeepsTheWholeFingerprint) {
  const uint64_t cells = 4, cell = 1;
  const uint32_t ways = 4;
  Table tb(cells, ways, PMC_CACHE_KEEP_FIRST);
  std::vector<PmcCacheKey> k = keys_in_cell(cells, cell, 6);
  const uint32_t depths[4] = {2, 1, 7, 0};
  for (uint32_t i = 0; i < 4; ++i) EXPECT_EQ(tb.insert(k[i], 100 + i, depths[i]), 1);
  for (uint32_t i = 0; i < 4; ++i)
    EXPECT_EQ(tb.words[cell * ways + i], (uint64_t(k[i].fingerprint) << 32) | (100 + i));
  EXPECT_EQ(tb.insert(k[4], 104, 0), -1) << "keep-first: a full cell drops even camera inserts";
  EXPECT_EQ(tb.insert(k[5], 105, 3), -1);
  for (uint32_t i = 0; i < 4; ++i) EXPECT_EQ(tb.lookup(k[i]), 100 + i);
  EXPECT_EQ(tb.lookup(k[4]), -1);
}

TEST(CachePolicy, TheTwoLowFingerprintBitsNoLongerSeparateKeysUnderPriority) {
  // A key in the same cell whose fingerprint differs only in bit 0 or 1
  // (the bits the depth tag took) is a false hit under priority; bit 2 still
  // separates keys. Under keep-first all three are misses.
  PmcCacheKey k = keys_in_cell(1, 0, 1)[0];
  for (uint32_t policy : {PMC_CACHE_PRIORITY, PMC_CACHE_KEEP_FIRST}) {
    SCOPED_TRACE(policy == PMC_CACHE_PRIORITY ? "priority" : "keep-first");
    Table tb(1, 8, policy);
    ASSERT_EQ(tb.insert(k, 42, 1), 1);
    for (uint32_t flip : {1u, 2u, 4u}) {
      PmcCacheKey other = k;
      other.fingerprint ^= flip;
      const bool false_hit = policy == PMC_CACHE_PRIORITY && flip < 4u;
      EXPECT_EQ(tb.lookup(other), false_hit ? 42 : -1) << "fingerprint ^ " << flip;
    }
  }
}

TEST(CachePolicy, FingerprintCollisionRatesOfThe30And32BitFingerprints) {
  // 2^22 distinct descriptors of the renderer's shape: 4 materials, 8 nodes,
  // 4 levels, 1024 x 32 texels.
  const size_t n = size_t(1) << 22;
  std::vector<uint32_t> fp32(n), fp30(n);
  for (size_t i = 0; i < n; ++i) {
    const PmcCacheKey k = pmc_cache_key(1u + uint32_t(i & 3u), 3u + uint32_t((i >> 2) & 7u), 0u,
                                        10 + int((i >> 5) & 3u), long((i >> 7) & 1023u), long(i >> 17));
    fp32[i] = k.fingerprint;
    fp30[i] = pmc_cache_fp30(k.fingerprint);
  }
  auto equal_pairs = [](std::vector<uint32_t>& v) {
    std::sort(v.begin(), v.end());
    double pairs = 0;
    for (size_t i = 0; i < v.size();) {
      size_t j = i;
      while (j < v.size() && v[j] == v[i]) ++j;
      pairs += double(j - i) * double(j - i - 1) / 2.0;
      i = j;
    }
    return pairs;
  };
  const double all_pairs = double(n) * double(n - 1) / 2.0;
  const double p30 = equal_pairs(fp30), p32 = equal_pairs(fp32);
  const double want30 = all_pairs * std::ldexp(1.0, -30), want32 = all_pairs * std::ldexp(1.0, -32);
  EXPECT_NEAR(p30, want30, 6 * std::sqrt(want30)) << "30-bit fingerprints: pairs that agree";
  EXPECT_NEAR(p32, want32, 6 * std::sqrt(want32)) << "32-bit fingerprints: pairs that agree";
  const double rate30 = p30 / all_pairs, rate32 = p32 / all_pairs;
  // A lookup of an absent key compares it with every entry of its cell
  // (8 in a full default cell).
  RecordProperty("pair_collision_rate_30bit", std::to_string(rate30));
  RecordProperty("pair_collision_rate_32bit", std::to_string(rate32));
  RecordProperty("false_hit_per_lookup_full_8way_priority", std::to_string(8 * rate30));
  RecordProperty("false_hit_per_lookup_full_8way_keep_first", std::to_string(8 * rate32));
  std::printf(
      "fingerprint collisions over %zu keys: 30-bit %.0f pairs (%.3g per pair, expected %.3g), "
      "32-bit %.0f pairs (%.3g, expected %.3g); false hit per lookup in a full 8-entry cell: "
      "priority %.3g, keep-first %.3g\n",
      n, p30, rate30, std::ldexp(1.0, -30), p32, rate32, std::ldexp(1.0, -32), 8 * rate30, 8 * rate32);
}

}  // namespace
}  // namespace pmc
