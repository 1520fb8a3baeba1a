// cache_counters_test.cpp — the cache counters are one list
// (PMC_CACHE_COUNTERS, core/device/pmc_cache.h): each is a CacheStats field
// and a key of the stats JSON's cache object, and the list's order is the
// device buffer's layout.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "app/stats_json.h"
#include "core/device/pmc_cache.h"

namespace pmc {
namespace {

TEST(CacheCounters, EachCounterIsAFieldAndAStatsKey) {
  CacheStats st;
  uint64_t v = 1000;
  for (const CacheCounter& k : kCacheCounters) st.*k.field = v++;
  const nlohmann::json c = cache_json(RenderSettings{}, st);
  std::set<std::string> keys;
  v = 1000;
  for (int i = 0; i < PMC_CSTAT_COUNT; ++i) {
    const CacheCounter& k = kCacheCounters[i];
    EXPECT_EQ(k.index, i) << k.key;
    EXPECT_TRUE(keys.insert(k.key).second) << "two counters named " << k.key;
    EXPECT_FALSE(std::string(k.meaning).empty()) << k.key;
    ASSERT_TRUE(c.contains(k.key)) << k.key;
    EXPECT_EQ(c[k.key].get<uint64_t>(), v++) << k.key;
  }
  EXPECT_EQ(c["hit_rate"].get<double>(), double(st.hits) / double(st.lookups));
}

// The buffer layout the kernels sum into: the list's order must not change.
TEST(CacheCounters, IndicesAreTheBufferLayout) {
  const int expected[] = {
      PMC_CSTAT_LOOKUPS,        PMC_CSTAT_HITS,        PMC_CSTAT_INSERTS,          PMC_CSTAT_DROPPED_FULL,
      PMC_CSTAT_NOT_ENCODABLE,  PMC_CSTAT_MISSES,      PMC_CSTAT_ALREADY_PRESENT,  PMC_CSTAT_REPLACED,
      PMC_CSTAT_CAMERA_LOOKUPS, PMC_CSTAT_CAMERA_HITS, PMC_CSTAT_POSITION_LOOKUPS, PMC_CSTAT_POSITION_HITS,
      PMC_CSTAT_BYPASSED};
  ASSERT_EQ(int(sizeof(expected) / sizeof(expected[0])), int(PMC_CSTAT_COUNT));
  for (int i = 0; i < PMC_CSTAT_COUNT; ++i) EXPECT_EQ(expected[i], i);
  EXPECT_STREQ(kCacheCounters[PMC_CSTAT_ALREADY_PRESENT].key, "already_present");
  EXPECT_STREQ(kCacheCounters[PMC_CSTAT_BYPASSED].key, "bypassed");
}

}  // namespace
}  // namespace pmc
