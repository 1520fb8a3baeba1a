// bsdf_albedo_test.cpp — the BSDF's albedo estimate and specular-only test for the render passes
// (pmc_lobes_albedo, pmc_lobes_specular_only in core/device/pmc_bsdf.h).
//
// Independent answers: a Lambert-only stack's albedo is its diffuse colour;
// the estimate of any stack agrees with a Monte Carlo integral of
// f cos over the sphere (sampled with the BSDF's own importance sampling,
// weight = f cos / pdf) within its noise and the tables' interpolation;
// a smooth mirror and smooth glass are specular-only, a rough or diffuse
// layer is not.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/device/pmc_bsdf.h"

namespace pmc {
namespace {

float3 mc_albedo(const PmcLobes& l, float3 wo, int n) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  float3 sum = make_float3(0.0f, 0.0f, 0.0f);
  for (int i = 0; i < n; ++i) {
    float3 wi, weight;
    float pdf;
    if (pmc_bsdf_sample(&l, wo, u(rng), u(rng), u(rng), &wi, &pdf, &weight)) sum += weight;
  }
  return sum * (1.0f / float(n));
}

TEST(BsdfAlbedo, LambertAlbedoIsTheDiffuseColour) {
  PmcBsdf b = pmc_bsdf_zero();
  b.diffuse = make_float3(0.6f, 0.3f, 0.2f);
  const float3 wo = normalize(make_float3(0.3f, 0.1f, 0.8f));
  const PmcLobes l = pmc_bsdf_prepare(&b, wo, 1);
  const float3 a = pmc_lobes_albedo(&l, wo);
  EXPECT_NEAR(a.x, 0.6f, 1e-6f);
  EXPECT_NEAR(a.y, 0.3f, 1e-6f);
  EXPECT_NEAR(a.z, 0.2f, 1e-6f);
  EXPECT_FALSE(pmc_lobes_specular_only(&l));
}

TEST(BsdfAlbedo, LayeredEstimateMatchesAMonteCarloIntegral) {
  PmcBsdf b = pmc_bsdf_zero();
  b.diffuse = make_float3(0.5f, 0.4f, 0.3f);
  b.spec_f0 = make_float3(0.04f, 0.04f, 0.04f);
  b.spec_tint = make_float3(1.0f, 1.0f, 1.0f);
  b.ax = b.ay = 0.2f;
  b.coat = 0.5f;
  b.coat_f0 = 0.04f;
  b.coat_alpha = 0.05f;
  b.coat_color = make_float3(1.0f, 1.0f, 1.0f);
  for (float mu : {0.9f, 0.5f, 0.2f}) {
    const float3 wo = make_float3(std::sqrt(1.0f - mu * mu), 0.0f, mu);
    const PmcLobes l = pmc_bsdf_prepare(&b, wo, 1);
    const float3 est = pmc_lobes_albedo(&l, wo), mc = mc_albedo(l, wo, 200000);
    EXPECT_NEAR(est.x, mc.x, 0.02f) << "mu " << mu;
    EXPECT_NEAR(est.y, mc.y, 0.02f) << "mu " << mu;
    EXPECT_NEAR(est.z, mc.z, 0.02f) << "mu " << mu;
    EXPECT_FALSE(pmc_lobes_specular_only(&l));
  }
}

TEST(BsdfAlbedo, SmoothMirrorAndGlassAreSpecularOnlyRoughOnesAreNot) {
  const float3 wo = normalize(make_float3(0.2f, 0.0f, 0.9f));
  PmcBsdf mirror = pmc_bsdf_zero();
  mirror.metal = 1.0f;
  mirror.metal_f0 = make_float3(0.9f, 0.9f, 0.9f);
  mirror.ax = mirror.ay = 0.0f;
  PmcLobes l = pmc_bsdf_prepare(&mirror, wo, 1);
  EXPECT_TRUE(pmc_lobes_specular_only(&l));
  const float3 a = pmc_lobes_albedo(&l, wo);
  EXPECT_GT(a.x, 0.85f);
  EXPECT_LE(a.x, 1.0f);

  PmcBsdf glass = pmc_bsdf_zero();
  glass.transmission = 1.0f;
  glass.transmission_tint = make_float3(1.0f, 1.0f, 1.0f);
  glass.spec_tint = make_float3(1.0f, 1.0f, 1.0f);
  glass.ax = glass.ay = 0.0f;
  l = pmc_bsdf_prepare(&glass, wo, 1);
  EXPECT_TRUE(pmc_lobes_specular_only(&l));
  EXPECT_NEAR(pmc_lobes_albedo(&l, wo).y, 1.0f, 1e-5f);  // reflection + refraction of a clear interface

  PmcBsdf rough = mirror;
  rough.ax = rough.ay = 0.09f;  // roughness 0.3
  l = pmc_bsdf_prepare(&rough, wo, 1);
  EXPECT_FALSE(pmc_lobes_specular_only(&l));
  PmcBsdf coated = mirror;  // a smooth coat over diffuse: the diffuse is seen
  coated.metal = 0.0f;
  coated.diffuse = make_float3(0.5f, 0.5f, 0.5f);
  coated.coat = 1.0f;
  coated.coat_f0 = 0.04f;
  coated.coat_alpha = 0.0f;
  coated.coat_color = make_float3(1.0f, 1.0f, 1.0f);
  l = pmc_bsdf_prepare(&coated, wo, 1);
  EXPECT_FALSE(pmc_lobes_specular_only(&l));
  PmcBsdf black = pmc_bsdf_zero();  // scatters nothing: not specular
  l = pmc_bsdf_prepare(&black, wo, 1);
  EXPECT_FALSE(pmc_lobes_specular_only(&l));
}

}  // namespace
}  // namespace pmc
