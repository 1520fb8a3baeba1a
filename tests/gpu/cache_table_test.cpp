// cache_table_test.cpp — the material cache's hash table (core/device/pmc_cache.h)
// under contention on a real OpenCL device (PoCL on CI), and its semantics
// single-threaded on the host (the same header compiled as C++).
//
// The race: 65536 work-items x 4 rounds insert colliding descriptors into a
// table, with lookups of the same and of another key before and after. Work
// takes its key from a global atomic clock (key = tick / W mod K), so the
// device's threads, whatever work-groups they run, work on the same fresh
// key at about the same time (a jittered delay between lookup and insert
// stands in for the material evaluation); the value is the tick, so the
// host knows which insert won. Tables: tiny ones where every or some cells overflow
// (K = 32 keys in 12, 32 or 1 entries), and a large one with 65536 fresh
// keys raced by W = 4 inserts each. Afterwards:
//  * every 64-bit word in the table is {fingerprint of a key whose cell it is
//    in, a value that a work-item inserting that key wrote}, and that
//    work-item's insert returned 1 (it won); no torn or mixed words;
//  * at most one entry per fingerprint per cell; entries fill from the front;
//  * per key: exactly one winner (1), every other insert 0 — or, if the key
//    is absent, its cell is full and every insert returned -1 (dropped);
//  * every value a lookup read during the race is the key's final value
//    (entries are immutable once published), and lookups after a successful
//    insert hit;
//  * a second run on the final table changes no bit and returns only 0 / -1.
// (Replacing the CAS by a plain store in pmc_cache_insert makes this fail
// when two inserts of a key coincide within a few nanoseconds: on PoCL with
// 2 loaded cores in about one run in four; a GPU races far more.)
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "core/device/pmc_cache.h"
#include "gpu/program.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

const char* kStressKernel = R"CL(
#include "pmc_cache.h"

/* Descriptor of key id k: distinct material/node/level/texels per key. */
static PmcCacheKey stress_key(uint k) {
  return pmc_cache_key((k & 7u) + 1u, 3u + ((k >> 3) & 3u), (k >> 3) & 3u, (int)(k % 7u) - 2, (long)k * 1000L - 7L,
                       -(long)k * 3L);
}

__kernel void cache_stress(__global volatile ulong* entries, ulong cells, uint ways, uint nkeys, uint w,
                           uint rounds, uint delay, __global volatile uint* clock, __global uint* tick, __global int* result,
                           __global uint* before, __global uint* after, __global uint* other, uint n) {
  uint gid = get_global_id(0);
  if (gid >= n) return;
  PmcCacheTable t;
  t.entries = entries;
  t.cells = cells;
  t.ways = ways;
  t.policy = PMC_CACHE_KEEP_FIRST;
  for (uint r = 0; r < rounds; ++r) {
    uint o = r * n + gid;
    uint now = atomic_inc(clock);
    uint k = (now / w) % nkeys;
    PmcCacheKey key = stress_key(k);
    uint v = 0xffffffffu;
    before[o] = pmc_cache_lookup(&t, key, &v) ? v : 0xffffffffu;
    /* Widen the window between lookup and insert (a material evaluation
     * sits there in the renderer) so that the other threads' inserts of
     * the same key land in it. */
    ulong spin = now;
    uint d = delay + (uint)(pmc_mix64(now) % 64u); /* jitter: some inserts of a key coincide */
    for (uint i = 0; i < d; ++i) spin = pmc_mix64(spin);
    tick[o] = spin == 1ul ? 0xfffffffeu : now; /* keeps the loop */
    result[o] = pmc_cache_insert(&t, key, now, 0u);
    v = 0xffffffffu;
    after[o] = pmc_cache_lookup(&t, key, &v) ? v : 0xffffffffu;
    v = 0xffffffffu;
    other[o] = pmc_cache_lookup(&t, stress_key((k + 1u) % nkeys), &v) ? v : 0xffffffffu;
  }
}
)CL";

// The same descriptors on the host.
PmcCacheKey stress_key(uint32_t k) {
  return pmc_cache_key((k & 7u) + 1u, 3u + ((k >> 3) & 3u), (k >> 3) & 3u, int(k % 7u) - 2,
                       long(k) * 1000L - 7L, -long(k) * 3L);
}

constexpr uint32_t kWorkItems = 65536;
constexpr uint32_t kRounds = 4;
constexpr uint32_t kMiss = 0xffffffffu;
constexpr uint32_t kDelay = 256;  // hash rounds between a lookup and its insert

struct Shape {
  uint64_t cells;
  uint32_t ways, keys, w;
};

struct RaceOutput {
  std::vector<uint64_t> table;
  std::vector<int32_t> result;
  std::vector<uint32_t> tick, before, after, other;
};

RaceOutput run_race(const ClContext& cl, ClProgram& prog, ClBuffer& entries, const Shape& s) {
  const size_t n = size_t(kWorkItems) * kRounds;
  uint32_t zero = 0;
  ClBuffer clock = cl.buffer(4, &zero), tick = cl.buffer(n * 4), result = cl.buffer(n * 4),
           before = cl.buffer(n * 4), after = cl.buffer(n * 4), other = cl.buffer(n * 4);
  cl_kernel k = prog.kernel("cache_stress");
  set_kernel_args(k, entries, cl_ulong(s.cells), cl_uint(s.ways), cl_uint(s.keys), cl_uint(s.w),
                  cl_uint(kRounds), cl_uint(kDelay), clock, tick, result, before, after, other,
                  cl_uint(kWorkItems));
  enqueue_1d(cl.queue(), k, kWorkItems);
  cl.finish();
  RaceOutput out;
  out.table.resize(size_t(s.cells) * s.ways);
  for (auto* v : {&out.tick, &out.before, &out.after, &out.other}) v->resize(n);
  out.result.resize(n);
  cl.read(entries, 0, out.table.size() * 8, out.table.data());
  cl.read(tick, 0, n * 4, out.tick.data());
  cl.read(result, 0, n * 4, out.result.data());
  cl.read(before, 0, n * 4, out.before.data());
  cl.read(after, 0, n * 4, out.after.data());
  cl.read(other, 0, n * 4, out.other.data());
  return out;
}

// Checks the table and every recorded outcome. `second`: the table was already
// final before this run, so nobody may win. Returns the lost races seen (a
// lookup missed, then the insert found the key: someone got in between).
size_t check_race(const RaceOutput& o, const Shape& s, bool second) {
  const size_t n = o.result.size();
  auto cell_of = [&](uint32_t k) { return stress_key(k).h1 % s.cells; };
  auto key_of_tick = [&](uint32_t t) { return (t / s.w) % s.keys; };
  // Keys by (cell, fingerprint): the identity the table itself uses.
  std::map<std::pair<uint64_t, uint32_t>, uint32_t> key_by_slot;
  for (uint32_t k = 0; k < s.keys; ++k) {
    PmcCacheKey key = stress_key(k);
    EXPECT_NE(key.fingerprint, 0u);
    EXPECT_TRUE(key_by_slot.emplace(std::make_pair(cell_of(k), key.fingerprint), k).second)
        << "test keys must differ in cell or fingerprint";
  }
  // Ticks are a permutation of 0..n-1: tick -> outcome index.
  std::vector<uint32_t> at_tick(n, kMiss);
  for (size_t i = 0; i < n; ++i) {
    EXPECT_LT(o.tick[i], n);
    if (o.tick[i] < n) at_tick[o.tick[i]] = uint32_t(i);
  }
  if (::testing::Test::HasFailure()) return 0;

  // The table, word by word.
  std::map<uint32_t, uint32_t> stored;  // key id -> value
  std::vector<uint32_t> used(s.cells, 0);
  for (uint64_t c = 0; c < s.cells; ++c) {
    bool empty_seen = false;
    std::set<uint32_t> fps;
    for (uint32_t i = 0; i < s.ways; ++i) {
      uint64_t w = o.table[size_t(c * s.ways + i)];
      if (w == 0) {
        empty_seen = true;
        continue;
      }
      EXPECT_FALSE(empty_seen) << "cell " << c << ": entries fill from the front";
      ++used[c];
      uint32_t fp = uint32_t(w >> 32), value = uint32_t(w);
      auto it = key_by_slot.find({c, fp});
      if (it == key_by_slot.end()) {
        ADD_FAILURE() << "cell " << c << " entry " << i << ": torn or foreign word " << std::hex << w;
        return 0;
      }
      uint32_t k = it->second;
      EXPECT_TRUE(fps.insert(fp).second) << "cell " << c << ": two entries for key " << k;
      if (value >= n || key_of_tick(value) != k) {
        ADD_FAILURE() << "cell " << c << ": value " << value << " was never inserted under key " << k
                      << " (mixed word " << std::hex << w << ")";
        return 0;
      }
      if (!second) EXPECT_EQ(o.result[at_tick[value]], 1) << "the work-item whose value is stored won";
      stored[k] = value;
    }
  }

  // Every outcome against the final table.
  std::vector<uint32_t> winners(s.keys, 0), drops(s.keys, 0);
  size_t lost_races = 0, bad = 0;
  for (size_t i = 0; i < n && bad < 10; ++i) {
    uint32_t k = key_of_tick(o.tick[i]);
    int res = o.result[i];
    auto it = stored.find(k);
    if (it == stored.end()) {
      bad += res != -1 || o.before[i] != kMiss || o.after[i] != kMiss;
      EXPECT_EQ(res, -1) << "key " << k << " is absent, so its insert must have been dropped";
      EXPECT_EQ(o.before[i], kMiss);
      EXPECT_EQ(o.after[i], kMiss);
      ++drops[k];
    } else {
      bool ok = (res == 0 || res == 1) && (o.before[i] == kMiss || o.before[i] == it->second) &&
                o.after[i] == it->second;
      bad += !ok;
      EXPECT_TRUE(res == 0 || res == 1) << "key " << k << " is stored; insert returned " << res;
      winners[k] += res == 1;
      lost_races += res == 0 && o.before[i] == kMiss;
      EXPECT_TRUE(o.before[i] == kMiss || o.before[i] == it->second)
          << "lookup during the race read " << o.before[i] << ", final " << it->second;
      EXPECT_EQ(o.after[i], it->second) << "a lookup after a successful insert hits the first value";
    }
    uint32_t k2 = (k + 1u) % s.keys;
    if (o.other[i] != kMiss) {
      auto it2 = stored.find(k2);
      bad += it2 == stored.end() || o.other[i] != it2->second;
      EXPECT_TRUE(it2 != stored.end() && o.other[i] == it2->second)
          << "lookup of key " << k2 << " read " << o.other[i] << ", a value not stored under it";
    }
  }
  for (uint32_t k = 0; k < s.keys && !::testing::Test::HasFailure(); ++k) {
    if (stored.count(k)) {
      EXPECT_EQ(winners[k], second ? 0u : 1u) << "key " << k << ": exactly one insert wins";
    } else {
      EXPECT_EQ(used[cell_of(k)], s.ways) << "key " << k << " was dropped, so its cell must be full";
      EXPECT_GT(drops[k], 0u);
    }
  }
  return lost_races;
}

TEST(CacheTable, ConcurrentCollidingInsertsNeverTearAndKeepTheFirstValue) {
  const ClContext& cl = test::cl();
  ClProgram prog = ClProgram::from_text(cl, "cache_table_test.cl", kStressKernel);
  // 32 keys in 12 entries (every cell overflows), in 32 entries of 16 cells
  // (some overflow, some stay partly empty), in a single entry; 65536 fresh
  // keys, 4 inserts each, in 2^16 cells of 4 entries.
  for (Shape s : {Shape{3, 4, 32, 1}, Shape{16, 2, 32, 1}, Shape{1, 1, 32, 1}, Shape{65536, 4, 65536, 4}}) {
    SCOPED_TRACE("cells " + std::to_string(s.cells) + " x " + std::to_string(s.ways) + " entries, " +
                 std::to_string(s.keys) + " keys");
    // Fresh keys raced by 4 inserts: with more than one compute unit some
    // lookups must miss a key another thread then inserts first (PoCL on 2
    // busy cores: from ~10 to ~20000 of 65536 keys), or the test is not
    // testing a race; a loaded machine may need another try.
    const bool want_race = s.keys == 65536 && cl.info().compute_units > 1;
    size_t lost = 0;
    for (int attempt = 0; attempt < (want_race ? 4 : 1) && !(want_race && lost > 0); ++attempt) {
      std::vector<uint64_t> zeros(size_t(s.cells) * s.ways, 0);
      ClBuffer entries = cl.buffer(zeros.size() * 8, zeros.data());
      RaceOutput first = run_race(cl, prog, entries, s);
      lost = check_race(first, s, false);
      if (HasFailure()) return;
      size_t dropped = 0, inserted = 0;
      for (int r : first.result) dropped += r<0, inserted += r> 0;
      std::printf("cache race: %llu cells x %u: %zu inserted, %zu dropped, %zu lost races\n",
                  (unsigned long long)s.cells, s.ways, inserted, dropped, lost);
      EXPECT_GT(inserted, 0u);
      if (s.keys > s.cells * s.ways) EXPECT_GT(dropped, 0u) << "more keys than entries: some must be dropped";
      // On the final table nothing changes: a second run finds or drops everything.
      RaceOutput again = run_race(cl, prog, entries, s);
      EXPECT_EQ(again.table, first.table) << "a final table must not change";
      check_race(again, s, true);
      for (int r : again.result) ASSERT_LE(r, 0) << "nothing can be inserted twice";
    }
    if (want_race) EXPECT_GT(lost, 0u) << "no concurrent inserts of one key observed";
  }
}

// ---- host, single thread -------------------------------------------------------

// Descriptors whose keys fall into cell `cell` of a `cells`-cell table.
std::vector<PmcCacheKey> keys_in_cell(uint64_t cells, uint64_t cell, size_t count) {
  std::vector<PmcCacheKey> out;
  for (long tx = 0; out.size() < count; ++tx) {
    PmcCacheKey k = pmc_cache_key(7u, 11u, 0u, 5, tx, 2);
    if (k.h1 % cells == cell) out.push_back(k);
  }
  return out;
}

TEST(CacheTable, HostLookupAndInsertSemantics) {
  const uint64_t cells = 4;
  const uint32_t ways = 3;
  std::vector<uint64_t> words(cells * ways, 0);
  PmcCacheTable t{words.data(), cells, ways, 0};
  std::vector<PmcCacheKey> same = keys_in_cell(cells, 1, ways + 2);
  PmcCacheKey elsewhere = keys_in_cell(cells, 2, 1)[0];
  pmc_u32 v = 0;

  EXPECT_EQ(pmc_cache_lookup(&t, same[0], &v), 0) << "empty table: miss";
  // A value of 0 (black in RGB9E5, 0.0f as float) is a real entry: the
  // fingerprint keeps the word non-zero.
  EXPECT_EQ(pmc_cache_insert(&t, same[0], 0u, 0u), 1);
  v = 123u;
  ASSERT_EQ(pmc_cache_lookup(&t, same[0], &v), 1);
  EXPECT_EQ(v, 0u);
  EXPECT_EQ(words[1 * ways + 0], uint64_t(same[0].fingerprint) << 32);
  // First value stays.
  EXPECT_EQ(pmc_cache_insert(&t, same[0], 77u, 0u), 0);
  ASSERT_EQ(pmc_cache_lookup(&t, same[0], &v), 1);
  EXPECT_EQ(v, 0u);
  // Fill the cell; the next distinct key is dropped, the others still work.
  for (uint32_t i = 1; i < ways; ++i) EXPECT_EQ(pmc_cache_insert(&t, same[i], 100u + i, 0u), 1);
  EXPECT_EQ(pmc_cache_insert(&t, same[ways], 999u, 0u), -1) << "full cell: dropped";
  EXPECT_EQ(pmc_cache_lookup(&t, same[ways], &v), 0) << "a dropped key stays a miss";
  EXPECT_EQ(pmc_cache_insert(&t, same[ways + 1], 998u, 0u), -1);
  for (uint32_t i = 1; i < ways; ++i) {
    ASSERT_EQ(pmc_cache_lookup(&t, same[i], &v), 1);
    EXPECT_EQ(v, 100u + i);
    EXPECT_EQ(pmc_cache_insert(&t, same[i], 5u, 0u), 0) << "present keys report 0 even in a full cell";
  }
  // Other cells are unaffected.
  EXPECT_EQ(pmc_cache_insert(&t, elsewhere, 42u, 0u), 1);
  ASSERT_EQ(pmc_cache_lookup(&t, elsewhere, &v), 1);
  EXPECT_EQ(v, 42u);
  // No word has a zero fingerprint, no cell holds a fingerprint twice.
  for (uint64_t c = 0; c < cells; ++c) {
    std::set<uint32_t> fps;
    for (uint32_t i = 0; i < ways; ++i) {
      uint64_t w = words[c * ways + i];
      if (!w) continue;
      EXPECT_NE(uint32_t(w >> 32), 0u);
      EXPECT_TRUE(fps.insert(uint32_t(w >> 32)).second);
    }
  }
  // Same fingerprint in another cell is a different entry (cell + fingerprint is the key).
  PmcCacheKey twin = same[0];
  twin.h1 = elsewhere.h1;
  EXPECT_EQ(pmc_cache_insert(&t, twin, 55u, 0u), 1);
  ASSERT_EQ(pmc_cache_lookup(&t, twin, &v), 1);
  EXPECT_EQ(v, 55u);
  ASSERT_EQ(pmc_cache_lookup(&t, same[0], &v), 1);
  EXPECT_EQ(v, 0u);
}

// Runs kernel `name` of `source` as name(in, out, n) over n work-items, each
// writing `per_item` values of T; returns them.
template <typename T>
std::vector<T> run_per_item(const char* source, const char* name, const std::vector<float>& in, uint32_t n,
                            size_t per_item) {
  const ClContext& cl = test::cl();
  ClProgram prog = ClProgram::from_text(cl, std::string(name) + "_test.cl", source);
  ClBuffer in_buf = cl.buffer(in.size() * 4, in.data()),
           out_buf = cl.buffer(size_t(n) * per_item * sizeof(T));
  cl_kernel k = prog.kernel(name);
  set_kernel_args(k, in_buf, out_buf, cl_uint(n));
  enqueue_1d(cl.queue(), k, n);
  std::vector<T> out(size_t(n) * per_item);
  cl.read(out_buf, 0, out.size() * sizeof(T), out.data());
  return out;
}

// The descriptor on the device: level, texel indices, texel hash and group
// base (and, with level floors, the footprint's level and the bypass flag)
// computed by an OpenCL kernel equal the host's bit for bit, on ordinary
// and hard inputs (grazing and degenerate gradients, negative, huge, infinite
// and NaN uvs, fractional and non-finite biases, jitter). A device whose
// log2/length or float-to-long conversion differed from the host's would
// split one texel into two keys across the host reference and the kernels.
const char* kDescriptorKernel = R"CL(
#include "pmc_cache.h"
__kernel void descriptors(__global const float* in, __global long* out, uint n) {
  uint i = get_global_id(0);
  if (i >= n) return;
  __global const float* p = in + 12 * i;
  PmcCacheTexel t = pmc_cache_texel_floored(make_float2(p[0], p[1]), make_float2(p[2], p[3]),
                                            make_float2(p[4], p[5]), p[6], make_float2(p[7], p[8]), (uint)p[9],
                                            (int)p[10], (int)p[11]);
  __global long* o = out + 7 * i;
  o[0] = t.lambda;
  o[1] = t.tx;
  o[2] = t.ty;
  o[3] = (long)t.hash;
  o[4] = (long)t.base;
  o[5] = t.footprint_lambda;
  o[6] = t.bypass;
}
)CL";

TEST(CacheTable, DeviceDescriptorsEqualTheHostsOnHardInputs) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> uvs = {0.0f, 0.25f, -0.3f, 0.999999f, 1.0f, -1.0f, 1e7f, -1e7f, 3e38f, inf, -inf, nan};
  std::vector<float> grads = {1e-3f, 0.01f, 0.37f, 1.0f, 3e-7f, 0.0f, 1e18f, 1e30f, inf, nan};
  std::vector<float> biases = {0.0f, 1.0f, -2.0f, 0.5f, -1.25f, 64.0f, 1e30f, nan};
  const std::vector<int> floors = {PMC_LEVEL_NO_FLOOR, -3, 5, 12, PMC_LAMBDA_MAX, PMC_LAMBDA_MAX + 20};
  const std::vector<int> refine = {0, 2, 5};
  std::mt19937 rng(71);
  std::uniform_real_distribution<float> jit(-0.5f, 0.5f);
  std::vector<float> in;
  for (float u : uvs)
    for (float g : grads)
      for (float bias : biases) {
        const float v = uvs[(in.size() / 10) % uvs.size()];
        const float g2 = grads[(in.size() / 10 + 3) % grads.size()];
        const size_t k = in.size() / 12;
        in.insert(in.end(), {u, v, g, 0.5f * g, -0.2f * g2, g2, bias, jit(rng), jit(rng), float(k % 7),
                             float(floors[k % floors.size()]), float(refine[(k / 3) % refine.size()])});
      }
  const uint32_t n = uint32_t(in.size() / 12);
  const std::vector<int64_t> out = run_per_item<int64_t>(kDescriptorKernel, "descriptors", in, n, 7);
  for (uint32_t i = 0; i < n; ++i) {
    const float* p = &in[size_t(i) * 12];
    PmcCacheTexel t =
        pmc_cache_texel_floored(make_float2(p[0], p[1]), make_float2(p[2], p[3]), make_float2(p[4], p[5]),
                                p[6], make_float2(p[7], p[8]), uint32_t(p[9]), int(p[10]), int(p[11]));
    if (int(p[10]) == PMC_LEVEL_NO_FLOOR) {  // without a floor: the paper's texel
      PmcCacheTexel plain =
          pmc_cache_texel_of(make_float2(p[0], p[1]), make_float2(p[2], p[3]), make_float2(p[4], p[5]), p[6],
                             make_float2(p[7], p[8]), uint32_t(p[9]));
      ASSERT_EQ(t.lambda, plain.lambda);
      ASSERT_EQ(t.hash, plain.hash);
      ASSERT_EQ(t.bypass, 0u);
    }
    const int64_t* o = &out[size_t(i) * 7];
    ASSERT_EQ(o[5], t.footprint_lambda);
    ASSERT_EQ(uint64_t(o[6]), uint64_t(t.bypass)) << "floor " << p[10] << " refine " << p[11];
    ASSERT_EQ(o[0], t.lambda) << "uv " << p[0] << "," << p[1] << " g " << p[2] << "," << p[3] << " / " << p[4]
                              << "," << p[5] << " bias " << p[6];
    ASSERT_EQ(o[1], t.tx) << "u " << p[0] << " level " << t.lambda << " jitter " << p[7];
    ASSERT_EQ(o[2], t.ty) << "v " << p[1] << " level " << t.lambda << " jitter " << p[8];
    ASSERT_EQ(uint64_t(o[3]), t.hash);
    ASSERT_EQ(uint64_t(o[4]), t.base);
  }
}

// Position cells (position-keyed cache points) on the device: level, three
// indices, hash and group base equal the host's on hard positions, radii
// and biases.
const char* kCellKernel = R"CL(
#include "pmc_cache.h"
__kernel void cells(__global const float* in, __global long* out, uint n) {
  uint i = get_global_id(0);
  if (i >= n) return;
  __global const float* p = in + 9 * i;
  PmcCacheTexel t = pmc_cache_cell_of(make_float3(p[0], p[1], p[2]), p[3], p[4],
                                      make_float4(p[5], p[6], p[7], 0.0f), (uint)p[8]);
  __global long* o = out + 6 * i;
  o[0] = t.lambda;
  o[1] = t.tx;
  o[2] = t.ty;
  o[3] = t.tz;
  o[4] = (long)t.hash;
  o[5] = (long)t.base;
}
)CL";

TEST(CacheTable, DevicePositionCellsEqualTheHostsOnHardInputs) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> coords = {0.0f, 0.25f, -0.3f, 1.0f, -1.0f, 123.456f, 1e7f, -1e7f, 3e38f, inf, -inf, nan};
  std::vector<float> radii = {1e-3f, 0.01f, 0.37f, 1.0f, 3e-7f, 0.0f, 1e18f, 1e30f, inf, nan, -1.0f};
  std::vector<float> biases = {0.0f, 1.0f, -2.0f, 0.5f, 64.0f, nan};
  std::mt19937 rng(73);
  std::uniform_real_distribution<float> jit(-0.5f, 0.5f);
  std::vector<float> in;
  for (float x : coords)
    for (float r : radii)
      for (float bias : biases) {
        const size_t k = in.size() / 9;
        in.insert(in.end(), {x, coords[(k / 5) % coords.size()], -coords[(k / 3) % coords.size()], r, bias,
                             jit(rng), jit(rng), jit(rng), float(k % 7)});
      }
  const uint32_t n = uint32_t(in.size() / 9);
  const std::vector<int64_t> out = run_per_item<int64_t>(kCellKernel, "cells", in, n, 6);
  for (uint32_t i = 0; i < n; ++i) {
    const float* p = &in[size_t(i) * 9];
    PmcCacheTexel t = pmc_cache_cell_of(make_float3(p[0], p[1], p[2]), p[3], p[4],
                                        make_float4(p[5], p[6], p[7], 0.0f), uint32_t(p[8]));
    const int64_t* o = &out[size_t(i) * 6];
    ASSERT_EQ(o[0], t.lambda) << "radius " << p[3] << " bias " << p[4];
    ASSERT_EQ(o[1], t.tx) << "x " << p[0] << " level " << t.lambda;
    ASSERT_EQ(o[2], t.ty) << "y " << p[1] << " level " << t.lambda;
    ASSERT_EQ(o[3], t.tz) << "z " << p[2] << " level " << t.lambda;
    ASSERT_EQ(uint64_t(o[4]), t.hash);
    ASSERT_EQ(uint64_t(o[5]), t.base);
  }
}

// Value encodings on the device: encodability, the 32-bit word and the
// decoded value equal the host's bit for bit for random and extreme values
// (0, -0, denormals, powers of two and their neighbours, 65408 and above,
// negatives, NaN, Inf).
const char* kEncodingKernel = R"CL(
#include "pmc_cache.h"
__kernel void encodings(__global const float* in, __global uint* out, uint n) {
  uint i = get_global_id(0);
  if (i >= n) return;
  __global const float* p = in + 4 * i;
  float4 v = make_float4(p[0], p[1], p[2], p[3]);
  __global uint* o = out + 3 * 6 * i;
  for (uint enc = 0u; enc < 3u; ++enc) {
    uint bits = 0xdeadbeefu;
    int ok = pmc_cache_encode(v, enc, &bits);
    float4 d = pmc_cache_decode(bits, enc);
    o[6 * enc + 0] = (uint)ok;
    o[6 * enc + 1] = bits;
    o[6 * enc + 2] = as_uint(d.x);
    o[6 * enc + 3] = as_uint(d.y);
    o[6 * enc + 4] = as_uint(d.z);
    o[6 * enc + 5] = as_uint(d.w);
  }
}
)CL";

TEST(CacheTable, DeviceEncodingsEqualTheHostsBitForBit) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> special = {0.0f,     -0.0f, 1e-45f, 1e-40f,   1.2e-38f, 2.9e-8f,  1.5e-5f,  0.001f,
                                0.5f,     1.0f,  2.0f,   3.14159f, 1000.0f,  65408.0f, 65409.0f, 65504.0f,
                                65520.0f, 1e30f, -1.0f,  -1e-30f,  inf,      -inf,     nan};
  for (int e = -26; e <= 17; ++e) {
    float p = std::ldexp(1.0f, e);
    special.insert(special.end(), {p, std::nextafter(p, 0.0f), std::nextafter(p, inf), 1.5f * p});
  }
  std::vector<float> in;
  std::mt19937 rng(123);
  std::uniform_int_distribution<size_t> pick(0, special.size() - 1);
  std::uniform_real_distribution<float> expo(-30.0f, 17.0f);
  for (float a : special) in.insert(in.end(), {a, a, a, a});
  for (int i = 0; i < 4000; ++i) {
    auto value = [&] { return i % 2 ? special[pick(rng)] : std::exp2(expo(rng)); };
    in.insert(in.end(), {value(), value(), value(), value()});
  }
  const uint32_t n = uint32_t(in.size() / 4);
  const std::vector<uint32_t> out = run_per_item<uint32_t>(kEncodingKernel, "encodings", in, n, 18);
  size_t encoded = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const float* p = &in[size_t(i) * 4];
    float4 v = make_float4(p[0], p[1], p[2], p[3]);
    for (uint32_t enc = 0; enc < 3; ++enc) {
      uint32_t bits = 0xdeadbeefu;
      int ok = pmc_cache_encode(v, enc, &bits);
      float4 d = pmc_cache_decode(bits, enc);
      const uint32_t* o = &out[size_t(i) * 18 + 6 * enc];
      SCOPED_TRACE("value " + std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " +
                   std::to_string(p[2]) + " encoding " + std::to_string(enc));
      ASSERT_EQ(int(o[0]), ok);
      ASSERT_EQ(o[1], bits);
      ASSERT_EQ(o[2], pmc_float_bits(d.x));
      ASSERT_EQ(o[3], pmc_float_bits(d.y));
      ASSERT_EQ(o[4], pmc_float_bits(d.z));
      ASSERT_EQ(o[5], pmc_float_bits(d.w));
      encoded += ok;
    }
  }
  EXPECT_GT(encoded, size_t(n)) << "most values must be encodable in some format";
}

TEST(CacheTable, FingerprintIsNeverZero) {
  // 2^-32 per descriptor: not reachable by search, so check the mapping on a
  // large sample and that the key function never yields 0.
  for (uint32_t m = 0; m < 8; ++m)
    for (long tx = -20000; tx < 20000; ++tx) {
      PmcCacheKey k =
          pmc_cache_key(m, uint32_t(tx & 15), uint32_t(tx & 3), int(((tx % 57) + 57) % 57) - 16, tx, -tx * 7);
      ASSERT_NE(k.fingerprint, 0u);
    }
}

}  // namespace
}  // namespace pmc
