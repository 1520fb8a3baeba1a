// host_threading_test.cpp — the host's concurrent code paths, without OpenCL,
// so that scripts/sanitize can run them under ThreadSanitizer.
//
//  * EmbreeTracer: intersect() and occluded() are const and run TBB
//    parallel_for inside; several application threads calling them at once
//    on one tracer (all three query styles, with and without a cut-out
//    filter that runs the CPU material interpreter inside Embree's callback)
//    must give exactly the single-caller answers.
//  * The material cache table (core/device/pmc_cache.h compiled as C++, 64-bit
//    CAS via __atomic): threads inserting colliding descriptors into a few
//    small cells must leave one value per key (the first inserted one),
//    entries that fill from the front and no torn words; lookups after a
//    successful insert must hit and return that value.
//
// Under ThreadSanitizer (scripts/sanitize tsan) TBB and OpenImageIO run their
// work on the calling thread: their task hand-off happens inside libtbb /
// libOpenImageIO_Util, which are not instrumented, so TSan would report the
// data of every task as racing with its spawner. The concurrency under test
// is then between this test's std::threads (several callers of one tracer,
// Embree's traversal and the cut-out callbacks), which TSan sees completely.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <thread>
#include <vector>

#include "core/device/pmc_cache.h"
#include "core/embree_tracer.h"
#include "core/obj_loader.h"
#include "core/sanitizers.h"
#include "materials/cutout.h"
#include "tests/hard_cases/hard_support.h"

namespace pmc {
namespace {

// See the header comment: uninstrumented thread pools run inline under TSan.
struct InlineThreadPoolsUnderTsan {
#ifdef PMC_UNDER_TSAN
  tbb::global_control one{tbb::global_control::max_allowed_parallelism, 1};
  InlineThreadPoolsUnderTsan() { OIIO::attribute("threads", 1); }
#endif
};

// A grid of quads over [-1,1]^2 at z = 0 plus a second layer at z = -0.5,
// `n` x `n` cells each; the front layer uses material `front`.
std::string layered_obj(int n, const std::string& front) {
  hard::ObjText o;
  o.line("mtllib scene.mtl\nusemtl " + front);
  for (int layer = 0; layer < 2; ++layer) {
    if (layer == 1) o.line("usemtl solid");
    double z = layer == 0 ? 0.0 : -0.5;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        double x0 = -1 + 2.0 * i / n, x1 = -1 + 2.0 * (i + 1) / n;
        double y0 = -1 + 2.0 * j / n, y1 = -1 + 2.0 * (j + 1) / n;
        const double q[4][3] = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
        o.quad(q, double(i) / n, double(j) / n, double(i + 1) / n, double(j + 1) / n);
      }
  }
  return o.str();
}

std::vector<PmcRay> random_rays(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.2f, 1.2f);
  std::vector<PmcRay> rays(n);
  for (size_t i = 0; i < n; ++i) {
    PmcRay& r = rays[i];
    std::memset(&r, 0, sizeof r);
    r.org_x = u(rng), r.org_y = u(rng), r.org_z = 2.0f;
    float dx = 0.3f * u(rng), dy = 0.3f * u(rng), dz = -1.0f;
    float l = std::sqrt(dx * dx + dy * dy + dz * dz);
    r.dir_x = dx / l, r.dir_y = dy / l, r.dir_z = dz / l;
    r.tnear = 0.0f;
    r.tfar = (i % 3 == 0) ? 2.2f : INFINITY;  // some shadow rays end between the layers
    r.mask = 0xffffffffu;
    r.id = uint32_t(i);
  }
  return rays;
}

void concurrent_trace_matches_serial(const Scene& scene, const AlphaTester* alpha) {
  [[maybe_unused]] InlineThreadPoolsUnderTsan inline_pools;
  const std::vector<PmcRay> rays = random_rays(20000, 3);
  for (TraceMode mode : {TraceMode::Single, TraceMode::Stream, TraceMode::Packet16}) {
    SCOPED_TRACE(trace_mode_name(mode));
    EmbreeTracer tracer(scene, mode, alpha);
    std::vector<PmcHit> ref_hits(rays.size());
    std::vector<uint8_t> ref_occ(rays.size());
    tracer.intersect(rays.data(), ref_hits.data(), rays.size(), false);
    tracer.occluded(rays.data(), ref_occ.data(), rays.size());
    size_t hits = 0;
    for (const PmcHit& h : ref_hits) hits += h.prim >= 0 ? 1 : 0;
    ASSERT_GT(hits, rays.size() / 4);
    ASSERT_LT(hits, rays.size());

    const int kThreads = 4;
    std::vector<std::vector<PmcHit>> got(kThreads, std::vector<PmcHit>(rays.size()));
    std::vector<std::vector<uint8_t>> occ(kThreads, std::vector<uint8_t>(rays.size()));
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
      threads.emplace_back([&, t] {
        for (int round = 0; round < 2; ++round) {
          tracer.intersect(rays.data(), got[size_t(t)].data(), rays.size(), round == 0);
          tracer.occluded(rays.data(), occ[size_t(t)].data(), rays.size());
        }
      });
    for (std::thread& th : threads) th.join();
    for (int t = 0; t < kThreads; ++t) {
      size_t mismatches = 0;
      for (size_t i = 0; i < rays.size(); ++i) {
        const PmcHit& a = got[size_t(t)][i];
        const PmcHit& b = ref_hits[i];
        if (a.prim != b.prim || (a.prim >= 0 && (a.t != b.t || a.u != b.u || a.v != b.v))) ++mismatches;
        if (occ[size_t(t)][i] != ref_occ[i]) ++mismatches;
      }
      EXPECT_EQ(mismatches, 0u) << "thread " << t;
    }
  }
}

TEST(HostThreading, EmbreeTracerAnswersConcurrentCallersLikeOne) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/scene.mtl", "newmtl solid\nKd 0.5 0.5 0.5\n");
  test::write_file(dir + "/scene.obj", layered_obj(24, "solid"));
  Scene scene = load_obj(dir + "/scene.obj");
  concurrent_trace_matches_serial(scene, nullptr);
}

TEST(HostThreading, CutoutFilterRunsConcurrentlyInsideEmbree) {
  // The front layer is cut out by a checker mask (map_d): Embree's filter
  // callbacks evaluate the material with the CPU interpreter on TBB threads.
  [[maybe_unused]] InlineThreadPoolsUnderTsan inline_pools;
  const std::string dir = test::temp_dir();
  std::vector<float> px;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) px.push_back(((x + y) % 2) ? 1.0f : 0.0f);
  hard::write_image(dir + "/mask.png", 8, 8, 1, px);
  test::write_file(dir + "/scene.mtl",
                   "newmtl solid\nKd 0.5 0.5 0.5\nnewmtl leaf\nKd 0.2 0.8 0.2\nmap_d mask.png\n");
  test::write_file(dir + "/scene.obj", layered_obj(24, "leaf"));
  ObjLoadOptions load;
  load.load_textures = false;
  Scene scene = load_obj(dir + "/scene.obj", load);
  MaterialSet set = build_material_set(scene, {});
  CutoutTester cutout(scene, set);
  ASSERT_TRUE(cutout.any());
  concurrent_trace_matches_serial(scene, &cutout);
}

// Descriptors of key k (the same scheme as the OpenCL stress test).
PmcCacheKey key_of(uint32_t k) {
  return pmc_cache_key(k + 1u, 3u + (k & 3u), k & 3u, int(k % 7u) - 2, long(k) * 1000L - 7L, -long(k) * 3L);
}

TEST(HostThreading, CacheTableConcurrentInsertsKeepTheFirstValue) {
  const uint64_t cells = 5;  // not a power of two: the modulo path
  const uint32_t ways = 4;
  const uint32_t keys = 24, threads_n = 4, rounds = 2000;
  std::vector<uint64_t> entries(cells * ways, 0);
  uint64_t stats[PMC_CSTAT_COUNT] = {0};
  PmcCacheTable table{};
  table.entries = entries.data();
  table.cells = cells;
  table.ways = ways;
  std::vector<std::vector<int>> results(threads_n);
  std::vector<std::vector<uint32_t>> after(threads_n);
  std::atomic<int> ready{0};
  std::vector<std::thread> threads;
  for (uint32_t t = 0; t < threads_n; ++t)
    threads.emplace_back([&, t] {
      ready.fetch_add(1);
      while (ready.load() < int(threads_n)) {
      }
      for (uint32_t r = 0; r < rounds; ++r) {
        uint32_t k = (t * 7u + r) % keys;
        uint32_t value = (k << 16) | (t << 12) | (r & 0xfffu);
        int res = pmc_cache_insert(&table, key_of(k), value, 0u);
        pmc_stat_add(stats, res > 0 ? PMC_CSTAT_INSERTS : res < 0 ? PMC_CSTAT_DROPPED_FULL : PMC_CSTAT_HITS);
        uint32_t v = 0xffffffffu;
        after[t].push_back(pmc_cache_lookup(&table, key_of(k), &v) ? v : 0xffffffffu);
        results[t].push_back(res);
      }
    });
  for (std::thread& th : threads) th.join();

  std::map<uint32_t, uint32_t> by_fp;
  for (uint32_t k = 0; k < keys; ++k) ASSERT_TRUE(by_fp.emplace(key_of(k).fingerprint, k).second);
  std::map<uint32_t, uint32_t> stored;
  for (uint64_t c = 0; c < cells; ++c) {
    bool empty = false;
    std::set<uint32_t> fps;
    for (uint32_t i = 0; i < ways; ++i) {
      uint64_t w = entries[c * ways + i];
      if (w == 0) {
        empty = true;
        continue;
      }
      ASSERT_FALSE(empty) << "entries fill from the front";
      auto it = by_fp.find(uint32_t(w >> 32));
      ASSERT_NE(it, by_fp.end()) << "torn or foreign word";
      ASSERT_EQ(key_of(it->second).h1 % cells, c) << "key stored in the wrong cell";
      ASSERT_TRUE(fps.insert(uint32_t(w >> 32)).second) << "two entries for one key";
      ASSERT_EQ(uint32_t(w) >> 16, it->second) << "value of another key";
      stored[it->second] = uint32_t(w);
    }
  }
  // Per key: exactly one successful insert if stored (its value is the one
  // stored), none if its cell filled up first; lookups after a successful or
  // "already present" insert return the stored value.
  std::map<uint32_t, int> winners;
  for (uint32_t t = 0; t < threads_n; ++t)
    for (uint32_t r = 0; r < rounds; ++r) {
      uint32_t k = (t * 7u + r) % keys;
      int res = results[t][r];
      if (res == 1) {
        ++winners[k];
        ASSERT_EQ(stored.count(k), 1u);
        EXPECT_EQ(stored[k], (k << 16) | (t << 12) | (r & 0xfffu)) << "the first value stays";
      }
      if (res >= 0) {
        ASSERT_EQ(stored.count(k), 1u);
        EXPECT_EQ(after[t][r], stored[k]);
      } else {
        EXPECT_EQ(stored.count(k), 0u) << "a drop means the key never got in";
      }
    }
  for (uint32_t k = 0; k < keys; ++k) EXPECT_EQ(winners[k], stored.count(k) ? 1 : 0) << "key " << k;
  EXPECT_EQ(stats[PMC_CSTAT_INSERTS], stored.size());
  EXPECT_GT(stats[PMC_CSTAT_DROPPED_FULL], 0u) << "24 keys in 5 cells x 4 entries: some must be dropped";
}

}  // namespace
}  // namespace pmc
