// worley_lanes_test.cpp — the batch form of the Worley noises
// (pmc_worley_lanes, core/device/pmc_noise.h), which the interpreter runs for
// every worleynoise2d/3d node, against the single-point form
// (pmc_op_worley2d/3d, whose MaterialX semantics node_math_test checks):
// bit for bit, lane by lane, in batches of every size up to PMC_LANES, with
// per-point jitter (none, ordinary, huge) and style, every output width, and
// the inputs that take the early exit (NaN, infinities, huge coordinates).
#define PMC_LANES 16
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "core/device/pmc_noise.h"

namespace pmc {
namespace {

uint32_t bits(float x) {
  uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// A coordinate: mostly ordinary, sometimes on a cell boundary, huge, or not finite.
float coordinate(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float r = u(rng);
  if (r < 0.02f) return std::numeric_limits<float>::quiet_NaN();
  if (r < 0.03f) return -std::numeric_limits<float>::infinity();
  if (r < 0.05f) return (u(rng) < 0.5f ? -1.0f : 1.0f) * std::ldexp(1.0f + u(rng), 30 + int(u(rng) * 10));
  if (r < 0.15f) return std::floor(40.0f * u(rng) - 20.0f);  // on a cell boundary
  return 200.0f * u(rng) - 100.0f;
}

TEST(WorleyLanes, EveryLaneMatchesTheSinglePointForm) {
  std::mt19937 rng(20261130);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  long checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + trial % PMC_LANES;
    const int dims = 2 + trial % 2;
    const uint32_t width = 1u + uint32_t(trial / 2) % 3u;
    float px[PMC_LANES], py[PMC_LANES], pz[PMC_LANES], jitter[PMC_LANES];
    int style[PMC_LANES];
    for (int k = 0; k < n; ++k) {
      px[k] = coordinate(rng), py[k] = coordinate(rng), pz[k] = coordinate(rng);
      const float j = u(rng);
      // not finite; none; so large that candidates may all lie beyond the search's start (1e6); ordinary
      jitter[k] = j < 0.05f  ? std::numeric_limits<float>::infinity()
                  : j < 0.2f ? 0.0f
                  : j < 0.3f ? std::ldexp(1.0f, 10 + int(20.0f * u(rng)))
                             : 1.5f * j;
      style[k] = u(rng) < 0.5f ? 1 : 0;
    }
    float out[4][PMC_LANES];
    pmc_worley_lanes(dims, px, py, pz, jitter, style, width, n, out);
    for (int k = 0; k < n; ++k) {
      const float4 want = dims == 3
                              ? pmc_op_worley3d(make_float3(px[k], py[k], pz[k]), jitter[k], style[k], width)
                              : pmc_op_worley2d(make_float2(px[k], py[k]), jitter[k], style[k], width);
      const float w[4] = {want.x, want.y, want.z, want.w};
      for (int c = 0; c < 4; ++c)
        ASSERT_EQ(bits(out[c][k]), bits(w[c]))
            << "trial " << trial << " lane " << k << " of " << n << ", dims " << dims << ", width " << width
            << ", style " << style[k] << ", component " << c << ": " << out[c][k] << " against " << w[c]
            << " at (" << px[k] << ", " << py[k] << ", " << pz[k] << "), jitter " << jitter[k];
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000);
}

}  // namespace
}  // namespace pmc
