// denoise_test.cpp — OIDN denoising (core/denoiser.h) of a render with its albedo and normal passes.
//
// The independent answer is a high-sample reference with another seed: the
// issue's goal, the denoised default scene at 16 spp has a relMSE at least
// 8x lower than the noisy image's. OIDN comes from scripts/setup (.venv), so
// this file is not part of pmc_device_tests.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/denoiser.h"
#include "core/image_metrics.h"
#include "core/render_passes.h"
#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

// The goal at a test's size: 96x54 (about 37 s on 2 shared cores,
// almost all of it the 4096-spp reference; measured 37x lower).
TEST(Denoise, DefaultSceneAt16SppIsAtLeast8xCloserToTheReference) {
  RenderConfig c = test::default_scene_config(96, 54, 16);
  c.passes = kPassAlbedo | kPassNormal;
  RenderSession session(c, test::cl());
  const RenderOutput noisy = session.render();
  RenderSettings ref_settings = session.settings();
  ref_settings.spp = 4096;
  ref_settings.seed = 7;  // independent of the noisy image's samples
  ref_settings.passes = 0;
  const RenderOutput reference = session.render(ref_settings);
  const DenoiseResult clean = denoise({&noisy.image, &noisy.passes.albedo, &noisy.passes.normal});
  const double noisy_err = compare_images(noisy.image, reference.image).relmse;
  const double clean_err = compare_images(clean.image, reference.image).relmse;
  std::printf("relMSE noisy %.5f, denoised %.5f (%.1fx) on %s\n", noisy_err, clean_err, noisy_err / clean_err,
              clean.device.c_str());
  EXPECT_GT(noisy_err, 0.0);
  EXPECT_LE(clean_err * 8.0, noisy_err);
}

}  // namespace
}  // namespace pmc
