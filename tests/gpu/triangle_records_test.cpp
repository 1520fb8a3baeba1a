// triangle_records_test.cpp — triangle_records_of (gpu/scene_buffers.h): each
// record holds the corners its indexed triangle names, copied out of the
// scene's position, normal and uv arrays, with flags for what it has.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "gpu/scene_buffers.h"

namespace pmc {
namespace {

// A scene of `count` triangles over shared, shuffled vertex arrays; every
// third triangle lacks normals and every fifth lacks uvs.
Scene indexed_scene(int count) {
  Scene s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-10.0f, 10.0f);
  const int vertices = 97;
  for (int i = 0; i < 3 * vertices; ++i) s.positions.push_back(value(rng));
  for (int i = 0; i < 3 * (vertices + 3); ++i) s.normals.push_back(value(rng));
  for (int i = 0; i < 2 * (vertices + 5); ++i) s.uvs.push_back(value(rng));
  std::uniform_int_distribution<int> vertex(0, vertices - 1), normal(0, vertices + 2), uv(0, vertices + 4);
  for (int i = 0; i < count; ++i) {
    PmcTriangle t{};
    for (int k = 0; k < 3; ++k) {
      t.v[k] = vertex(rng);
      t.n[k] = i % 3 == 0 ? -1 : normal(rng);
      t.t[k] = i % 5 == 0 ? -1 : uv(rng);
    }
    t.material = i % 11;
    s.triangles.push_back(t);
  }
  return s;
}

TEST(TriangleRecords, HoldTheCornersTheirIndexedTriangleNames) {
  const Scene s = indexed_scene(5000);  // enough to split across threads
  const std::vector<PmcTriangleRecord> records = triangle_records_of(s);
  ASSERT_EQ(records.size(), s.triangles.size());
  for (size_t i = 0; i < records.size(); ++i) {
    const PmcTriangle& t = s.triangles[i];
    const PmcTriangleRecord& r = records[i];
    SCOPED_TRACE(i);
    EXPECT_EQ(r.material, t.material);
    EXPECT_EQ((r.flags & PMC_TRI_NORMALS) != 0, t.n[0] >= 0);
    EXPECT_EQ((r.flags & PMC_TRI_UVS) != 0, t.t[0] >= 0);
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(r.p[3 * k + c], s.positions[3 * t.v[k] + c]);
        EXPECT_EQ(r.n[3 * k + c], t.n[0] >= 0 ? s.normals[3 * t.n[k] + c] : 0.0f);
      }
      for (int c = 0; c < 2; ++c) EXPECT_EQ(r.t[2 * k + c], t.t[0] >= 0 ? s.uvs[2 * t.t[k] + c] : 0.0f);
    }
    if (::testing::Test::HasFailure()) break;
  }
}

TEST(TriangleRecords, FillWholeCacheLines) {
  static_assert(sizeof(PmcTriangleRecord) == 128, "two 64-byte lines per record");
  const std::vector<PmcTriangleRecord> records = triangle_records_of(indexed_scene(3));
  EXPECT_EQ(reinterpret_cast<uintptr_t>(records.data()) % 64, 0u);
  EXPECT_TRUE(triangle_records_of(Scene{}).empty());
}

}  // namespace
}  // namespace pmc
