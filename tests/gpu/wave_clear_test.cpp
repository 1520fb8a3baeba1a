// wave_clear_test.cpp — WaveKernels::clear zeroes the film, the cache table
// and its counters on the device, whole, whatever the buffers held before:
// the film and the table are larger than the zeroing kernel's fixed grid
// (4096 groups of 64 work-items, each group zeroing a contiguous block), and
// their word counts are not multiples of the groups, so the blocks' rounding
// and the last, shorter block are exercised; the counters (26 words) take
// one group with work-items to spare. The buffers are filled with a pattern from the host first
// and read back after the clear.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "core/device/pmc_cache.h"
#include "gpu/host_link.h"
#include "gpu/wave_buffers.h"
#include "gpu/wave_kernels.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

size_t count_nonzero(const ClContext& cl, const ClBuffer& b, size_t bytes) {
  std::vector<uint32_t> words(bytes / sizeof(uint32_t));
  cl.read(b, 0, bytes, words.data());
  size_t n = 0;
  for (uint32_t w : words) n += w != 0 ? 1 : 0;
  return n;
}

void fill_pattern(const ClContext& cl, const ClBuffer& b, size_t bytes) {
  std::vector<uint32_t> words(bytes / sizeof(uint32_t));
  for (size_t i = 0; i < words.size(); ++i) words[i] = uint32_t(i * 2654435761u) | 1u;
  cl.write(b, 0, bytes, words.data(), true);
}

TEST(WaveClear, FilmTableAndCountersAreZeroedWhole) {
  const ClContext& cl = test::cl();
  MaterialSet no_materials;
  WaveKernels kernels(cl, no_materials, default_shade_lanes(cl, no_materials));
  HostLink link(cl, TransferMode::Copy);
  const size_t pixels = 300001;        // 64-byte film pixels: ~4.8M words
  const size_t cache_words = 1234567;  // 64-bit entries: ~2.5M words
  WaveBuffers wave(cl, link, 1024, 1024, pixels, cache_words);
  ASSERT_EQ(wave.film_bytes, pixels * sizeof(PmcFilmPixel));
  ASSERT_EQ(wave.cache_bytes, cache_words * sizeof(uint64_t));
  const size_t stats_bytes = PMC_CSTAT_COUNT * sizeof(uint64_t);
  fill_pattern(cl, wave.film, wave.film_bytes);
  fill_pattern(cl, wave.cache_entries, wave.cache_bytes);
  fill_pattern(cl, wave.cache_stats, stats_bytes);
  ASSERT_EQ(count_nonzero(cl, wave.film, wave.film_bytes), wave.film_bytes / 4);

  kernels.clear(wave);
  EXPECT_EQ(count_nonzero(cl, wave.film, wave.film_bytes), 0u);
  EXPECT_EQ(count_nonzero(cl, wave.cache_entries, wave.cache_bytes), 0u);
  EXPECT_EQ(count_nonzero(cl, wave.cache_stats, stats_bytes), 0u);
}

// The pass film (render passes: 176-byte pixels) is zeroed with the film; a
// render without passes keeps one pixel of it.
TEST(WaveClear, PassFilmIsZeroedWhole) {
  const ClContext& cl = test::cl();
  MaterialSet no_materials;
  WaveKernels kernels(cl, no_materials, default_shade_lanes(cl, no_materials));
  HostLink link(cl, TransferMode::Copy);
  const size_t pixels = 100003;
  WaveBuffers wave(cl, link, 1024, 1024, pixels, 1, true);
  ASSERT_EQ(wave.pass_film_bytes, pixels * sizeof(PmcPassPixel));
  fill_pattern(cl, wave.pass_film, wave.pass_film_bytes);
  ASSERT_EQ(count_nonzero(cl, wave.pass_film, wave.pass_film_bytes), wave.pass_film_bytes / 4);
  kernels.clear(wave);
  EXPECT_EQ(count_nonzero(cl, wave.pass_film, wave.pass_film_bytes), 0u);
  const WaveBuffers without(cl, link, 1024, 1024, pixels, 1);
  EXPECT_EQ(without.pass_film_bytes, sizeof(PmcPassPixel));
}

}  // namespace
}  // namespace pmc
