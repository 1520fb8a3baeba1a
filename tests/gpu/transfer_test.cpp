// transfer_test.cpp — the two ways hits reach the device give the same image.
//
// Zero-copy (mapped host-visible buffers, the CPU-device default) and explicit
// copies streamed in chunks (the discrete-GPU path, forced here on PoCL) must
// render bit-identical images with identical ray counts, with the material
// cache off and on (center mode is independent of who inserts first; the
// hit map is not: whether a lookup finds a texel depends on which work-items
// ran before it), and with a wave smaller than the image (several waves per
// sample).
#include <gtest/gtest.h>

#include "core/error.h"
#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

RenderOutput render_default_scene(bool cache, TransferMode mode, size_t chunk, size_t wave_paths) {
  RenderConfig c = test::default_scene_config(40, 24, 2);
  c.cache = cache;
  c.cache_cells = 4096;
  c.transfer = mode;
  c.chunk_rays = int64_t(chunk);
  RenderSession session(c, test::cl());
  RenderSettings s = session.settings();
  s.max_wave_paths = wave_paths;
  return session.render(s);
}

void expect_same(const RenderOutput& a, const RenderOutput& b) {
  ASSERT_EQ(a.image.pixels.size(), b.image.pixels.size());
  EXPECT_EQ(test::differing_values(a.image, b.image), 0u) << "of " << a.image.pixels.size() << " values";
  EXPECT_EQ(a.stats.rays, b.stats.rays);
  EXPECT_EQ(a.stats.shadow_rays, b.stats.shadow_rays);
}

TEST(Transfer, ZeroCopyAndChunkedCopiesRenderIdenticalImages) {
  for (bool cache : {false, true}) {
    SCOPED_TRACE(cache ? "cache on" : "cache off");
    RenderOutput zero = render_default_scene(cache, TransferMode::ZeroCopy, 0, 1 << 20);
    EXPECT_EQ(zero.stats.transfer, "zero-copy");
    EXPECT_GT(zero.stats.shadow_rays, 0u);
    EXPECT_GT(test::image_mean(zero.image), 0.0);
    RenderOutput chunked = render_default_scene(cache, TransferMode::Copy, 97, 1 << 20);
    EXPECT_EQ(chunked.stats.transfer, "copy");
    expect_same(zero, chunked);
    RenderOutput whole = render_default_scene(cache, TransferMode::Copy, 0, 1 << 20);
    expect_same(zero, whole);
    // 960 pixels in waves of 300: four waves per sample, the last one short.
    RenderOutput waves = render_default_scene(cache, TransferMode::ZeroCopy, 0, 300);
    expect_same(zero, waves);
  }
}

TEST(Transfer, ModeNamesParseAndUnknownOnesAreRefused) {
  EXPECT_EQ(parse_transfer_mode("auto"), TransferMode::Auto);
  EXPECT_EQ(parse_transfer_mode("zero-copy"), TransferMode::ZeroCopy);
  EXPECT_EQ(parse_transfer_mode("copy"), TransferMode::Copy);
  EXPECT_THROW(parse_transfer_mode("dma"), Error);
  // A CPU device (PoCL) resolves auto to zero-copy.
  HostLink link(test::cl(), TransferMode::Auto);
  EXPECT_EQ(link.zero_copy(), test::cl().info().is_cpu || test::cl().info().host_unified_memory);
}

}  // namespace
}  // namespace pmc
