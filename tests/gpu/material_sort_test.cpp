// material_sort_test.cpp — MaterialSorter (gpu/material_sort.h) against a
// reference written here: a stable sort of the ray indices by material
// (escaped rays and primitives outside the scene last), each material's run
// padded with PMC_NO_RAY to whole batches. Short and long queues, lanes 1,
// 4 and 16, materials that never occur, and a queue of escaped rays only.
#include "gpu/material_sort.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace pmc {
namespace {

std::vector<uint32_t> reference(const std::vector<int32_t>& tri_material, int materials, int lanes,
                                const std::vector<PmcHit>& hits, uint32_t first_ray) {
  auto bucket = [&](const PmcHit& h) {
    return h.prim >= 0 && size_t(h.prim) < tri_material.size() ? tri_material[size_t(h.prim)] : materials;
  };
  std::vector<uint32_t> out;
  for (int b = 0; b <= materials; ++b) {
    size_t n = 0;
    for (size_t i = 0; i < hits.size(); ++i)
      if (bucket(hits[i]) == b) {
        out.push_back(first_ray + uint32_t(i));
        ++n;
      }
    while (n % size_t(lanes) != 0) {
      out.push_back(PMC_NO_RAY);
      ++n;
    }
  }
  return out;
}

void check(size_t count, int lanes, int materials, double escaped_share, uint32_t seed) {
  std::mt19937 rng(seed);
  const int triangles = 1000;
  std::vector<int32_t> tri_material(triangles);
  // Materials 0..materials-1, the last ones rarer, one never used.
  for (int32_t& m : tri_material)
    m = int32_t(std::min<uint32_t>(rng() % 16, rng() % 16) % uint32_t(materials - 1));
  std::vector<PmcHit> hits(count);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (PmcHit& h : hits) {
    h = PmcHit{1.0f, 0.0f, 0.0f, int32_t(rng() % triangles)};
    if (u(rng) < escaped_share) h.prim = (rng() & 1) ? -1 : triangles + 5;  // a miss, or out of range
  }
  MaterialSorter sorter(tri_material, materials, lanes);
  std::vector<uint32_t> order(sorter.capacity(count), 0xdeadbeefu);
  const uint32_t first_ray = 7000;
  const size_t entries = sorter.sort(hits.data(), count, first_ray, order.data());
  order.resize(entries);
  EXPECT_EQ(entries % size_t(lanes), 0u);
  EXPECT_EQ(order, reference(tri_material, materials, lanes, hits, first_ray))
      << count << " hits, lanes " << lanes << ", " << materials << " materials";
}

TEST(MaterialSort, ShortQueuesMatchAStableSortPaddedToBatches) {
  for (int lanes : {1, 4, 16}) {
    check(1, lanes, 3, 0.0, 1);
    check(1000, lanes, 9, 0.1, 2);
    check((size_t(1) << 16) - 1, lanes, 9, 0.2, 3);
  }
}

TEST(MaterialSort, LongQueuesMatchAStableSortPaddedToBatches) {
  for (int lanes : {1, 4, 16}) {
    check(size_t(1) << 16, lanes, 9, 0.2, 4);
    check(1234567, lanes, 17, 0.05, 5);
  }
}

TEST(MaterialSort, AQueueOfEscapedRaysIsOneRun) {
  check(200000, 4, 5, 1.0, 6);
  check(0, 4, 5, 1.0, 7);
}

}  // namespace
}  // namespace pmc
