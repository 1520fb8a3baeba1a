// bsdf_furnace_test.cpp — the whole layer stack (pmc_surface.h's reading of
// the parameter block, then pmc_bsdf_prepare) in a white furnace: the mean
// sample weight over reflection and transmission is the directional albedo,
// which must never pass 1 and must be 1 where nothing is absorbed. Also the
// albedo tables against the lobes they were integrated from, glass against
// Fresnel's closed forms, and total internal reflection.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include "core/device/pmc_interp.h"

namespace pmc {
namespace {

constexpr double kPi = 3.14159265358979323846;

float3 view(double deg) {
  const double t = deg * kPi / 180.0;
  return make_float3(float(std::sin(t) * std::cos(0.3)), float(std::sin(t) * std::sin(0.3)),
                     float(std::cos(t)));
}

struct Albedo {
  double mean, sd, transmitted;
};

// Monte Carlo directional albedo (luminance) of a prepared stack at wo, in
// energy: radiance refracted into a medium of relative IOR eta is divided by
// eta^2 (pmc_bsdf.h), so a transmitted weight is multiplied back by eta^2.
Albedo albedo(const PmcLobes& l, float3 wo, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  double s = 0, s2 = 0, st = 0;
  for (int k = 0; k < n; ++k) {
    float3 wi, w;
    float pdf;
    if (!pmc_bsdf_sample(&l, wo, u(rng), u(rng), u(rng), &wi, &pdf, &w)) continue;
    const double v = pmc_luminance(w) * (wi.z < 0.0f && !l.thin ? double(l.eta) * l.eta : 1.0);
    s += v;
    s2 += v * v;
    if (wi.z < 0.0f) st += v;
  }
  const double mean = s / n;
  return {mean, std::sqrt(std::max(0.0, s2 / n - mean * mean) / n), st / n};
}

// A standard_surface parameter block with white base and the given inputs.
struct Params {
  float p[PMC_P_COUNT];
  Params() {
    pmc_surface_defaults(p, make_float3(0, 0, 1));
    for (int c = 0; c < 3; ++c) p[PMC_P_BASE_COLOR + c] = 1.0f;
  }
};

std::string describe(const float* p, double deg) {
  std::ostringstream os;
  os << "rough " << p[PMC_P_SPECULAR_ROUGHNESS] << " metal " << p[PMC_P_METALNESS] << " spec "
     << p[PMC_P_SPECULAR] << " coat " << p[PMC_P_COAT] << " sheen " << p[PMC_P_SHEEN] << " trans "
     << p[PMC_P_TRANSMISSION] << " thin " << p[PMC_P_THIN_WALLED] << " ior " << p[PMC_P_SPECULAR_IOR]
     << " aniso " << p[PMC_P_SPECULAR_ANISOTROPY] << " at " << deg << " deg";
  return os.str();
}

TEST(BsdfFurnace, NoStandardSurfaceStackReflectsMoreThanItReceives) {
  uint32_t seed = 1;
  int cases = 0;
  for (float rough : {0.0f, 0.3f, 0.7f, 1.0f})
    for (float metal : {0.0f, 1.0f})
      for (float spec : {0.5f, 1.0f})
        for (float coat : {0.0f, 1.0f})
          for (float sheen : {0.0f, 1.0f})
            for (float trans : {0.0f, 1.0f})
              for (float ior : {1.0f, 1.5f, 3.0f})
                for (double deg : {0.0, 45.0, 75.0, 85.0, 89.0}) {
                  Params q;
                  float* p = q.p;
                  p[PMC_P_SPECULAR_ROUGHNESS] = rough;
                  p[PMC_P_METALNESS] = metal;
                  p[PMC_P_SPECULAR] = spec;
                  p[PMC_P_COAT] = coat;
                  p[PMC_P_COAT_ROUGHNESS] = rough;
                  p[PMC_P_SHEEN] = sheen;
                  p[PMC_P_SHEEN_ROUGHNESS] = rough;
                  p[PMC_P_TRANSMISSION] = trans;
                  p[PMC_P_SPECULAR_IOR] = ior;
                  p[PMC_P_THIN_WALLED] = (cases % 3 == 0) ? 1.0f : 0.0f;
                  p[PMC_P_SPECULAR_ANISOTROPY] = (cases % 4 == 1) ? 0.8f : 0.0f;
                  const PmcBsdf b = pmc_surface_to_bsdf(p);
                  const float3 wo = view(deg);
                  const PmcLobes l = pmc_bsdf_prepare(&b, wo, (cases & 1) == 0);
                  const Albedo a = albedo(l, wo, 3000, seed++);
                  EXPECT_LE(a.mean, 1.0 + 4.0 * a.sd + 5e-3) << describe(p, deg);
                  ++cases;
                }
  EXPECT_EQ(cases, 4 * 2 * 2 * 2 * 2 * 2 * 3 * 5);
}

TEST(BsdfFurnace, WhereNothingIsAbsorbedTheAlbedoIsOne) {
  uint32_t seed = 100;
  for (double deg : {0.0, 30.0, 60.0, 75.0, 85.0}) {
    const float3 wo = view(deg);
    // White Lambert (no specular layer): exactly 1.
    {
      Params q;
      q.p[PMC_P_SPECULAR] = 0.0f;
      PmcBsdf b = pmc_surface_to_bsdf(q.p);
      Albedo a = albedo(pmc_bsdf_prepare(&b, wo, 1), wo, 20000, seed++);
      EXPECT_NEAR(a.mean, 1.0, 1e-4) << "white diffuse at " << deg;
    }
    // White plastic: what the specular layer does not reflect, the diffuse does.
    for (float rough : {0.0f, 0.3f, 0.7f, 1.0f}) {
      Params q;
      q.p[PMC_P_SPECULAR_ROUGHNESS] = rough;
      PmcBsdf b = pmc_surface_to_bsdf(q.p);
      Albedo a = albedo(pmc_bsdf_prepare(&b, wo, 1), wo, 40000, seed++);
      EXPECT_NEAR(a.mean, 1.0, 0.01 + 4.0 * a.sd) << "white plastic rough " << rough << " at " << deg;
    }
    // White rough conductor with multiple-scattering compensation.
    for (float rough : {0.0f, 0.3f, 0.6f, 1.0f}) {
      Params q;
      q.p[PMC_P_METALNESS] = 1.0f;
      q.p[PMC_P_SPECULAR_ROUGHNESS] = rough;
      PmcBsdf b = pmc_surface_to_bsdf(q.p);
      Albedo a = albedo(pmc_bsdf_prepare(&b, wo, 1), wo, 40000, seed++);
      EXPECT_NEAR(a.mean, 1.0, 0.01 + 4.0 * a.sd) << "white conductor rough " << rough << " at " << deg;
    }
    // Clear smooth glass, thick (both sides) and thin: reflected + transmitted = 1.
    for (int thin = 0; thin < 2; ++thin)
      for (int entering = 0; entering < 2; ++entering) {
        Params q;
        q.p[PMC_P_TRANSMISSION] = 1.0f;
        q.p[PMC_P_SPECULAR_ROUGHNESS] = 0.0f;
        q.p[PMC_P_THIN_WALLED] = float(thin);
        PmcBsdf b = pmc_surface_to_bsdf(q.p);
        const PmcLobes l = pmc_bsdf_prepare(&b, wo, entering);
        EXPECT_NEAR(albedo(l, wo, 20000, seed++).mean, 1.0, 0.01)
            << "clear glass thin " << thin << " entering " << entering << " at " << deg;
      }
  }
}

TEST(BsdfFurnace, MtlKdOneKsOneNeverPassesOne) {
  // MTL's Kd 1, Ks 1 (docs/MTL.md): base colour 1, specular 1, F0 = 2 x 0.04.
  const float f0 = 0.08f, ior = (1.0f + std::sqrt(f0)) / (1.0f - std::sqrt(f0));
  uint32_t seed = 500;
  for (float rough : {0.0f, 0.2f, 0.5f, 1.0f})
    for (double deg = 0.0; deg <= 89.0; deg += 4.0) {
      Params q;
      q.p[PMC_P_SPECULAR_IOR] = ior;
      q.p[PMC_P_SPECULAR_ROUGHNESS] = rough;
      PmcBsdf b = pmc_surface_to_bsdf(q.p);
      const float3 wo = view(deg);
      Albedo a = albedo(pmc_bsdf_prepare(&b, wo, 1), wo, 8000, seed++);
      EXPECT_LE(a.mean, 1.0 + 4.0 * a.sd + 5e-3) << "rough " << rough << " at " << deg;
    }
  // A flattened closure graph with diffuse 1 and F0 1 (model 1).
  for (double deg = 0.0; deg <= 89.0; deg += 8.0) {
    Params q;
    q.p[PMC_P_MODEL] = 1.0f;
    for (int c = 0; c < 3; ++c) q.p[PMC_P_SPECULAR_COLOR + c] = 1.0f;
    PmcBsdf b = pmc_surface_to_bsdf(q.p);
    const float3 wo = view(deg);
    Albedo a = albedo(pmc_bsdf_prepare(&b, wo, 1), wo, 8000, seed++);
    EXPECT_LE(a.mean, 1.0 + 4.0 * a.sd + 5e-3) << "flattened at " << deg;
  }
}

// Glass at normal incidence against Fresnel's closed forms: one interface
// reflects R = ((n - 1) / (n + 1))^2; a thin pane (two interfaces, light
// bouncing between them) passes (1 - R)^2 / (1 - R^2) and reflects
// R + R (1 - R)^2 / (1 - R^2).
TEST(BsdfGlass, NormalIncidenceMatchesFresnel) {
  for (float n : {1.33f, 1.5f, 2.4f}) {
    const double r = std::pow((n - 1.0) / (n + 1.0), 2.0);
    for (int thin = 0; thin < 2; ++thin) {
      Params q;
      q.p[PMC_P_TRANSMISSION] = 1.0f;
      q.p[PMC_P_SPECULAR_ROUGHNESS] = 0.0f;
      q.p[PMC_P_SPECULAR_IOR] = n;
      q.p[PMC_P_THIN_WALLED] = float(thin);
      PmcBsdf b = pmc_surface_to_bsdf(q.p);
      const float3 wo = make_float3(0.0f, 0.0f, 1.0f);
      const PmcLobes l = pmc_bsdf_prepare(&b, wo, 1);
      Albedo a = albedo(l, wo, 40000, 7u + uint32_t(thin));
      const double trans = a.transmitted;
      const double want_t = thin ? (1 - r) * (1 - r) / (1 - r * r) : 1 - r;
      const double want_r = thin ? r + r * (1 - r) * (1 - r) / (1 - r * r) : r;
      EXPECT_NEAR(trans, want_t, 0.01 * want_t) << "n " << n << " thin " << thin;
      EXPECT_NEAR(a.mean - a.transmitted, want_r, 0.01 + 4.0 * a.sd) << "n " << n << " thin " << thin;
    }
  }
}

TEST(BsdfGlass, TotalInternalReflectionBeyondTheCriticalAngle) {
  // Inside glass of IOR 1.5 the critical angle is asin(1 / 1.5) = 41.8 degrees.
  Params q;
  q.p[PMC_P_TRANSMISSION] = 1.0f;
  q.p[PMC_P_SPECULAR_ROUGHNESS] = 0.0f;
  PmcBsdf b = pmc_surface_to_bsdf(q.p);
  for (double deg : {45.0, 60.0, 80.0}) {
    const float3 wo = view(deg);
    const PmcLobes l = pmc_bsdf_prepare(&b, wo, 0);
    Albedo a = albedo(l, wo, 5000, 3u);
    EXPECT_EQ(a.transmitted, 0.0) << deg;
    EXPECT_NEAR(a.mean, 1.0, 0.01) << deg;
  }
  // Below it, some light leaves.
  const float3 wo = view(20.0);
  EXPECT_GT(albedo(pmc_bsdf_prepare(&b, wo, 0), wo, 5000, 4u).transmitted, 0.5);
}

// The committed tables against the lobes: cells recomputed here with other
// strata (a different estimator of the same integrals).
TEST(BsdfTables, AlbedoTablesMatchTheLobes) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i : {3, 10, 20, 40, 63})
    for (int j : {0, 6, 12, 20, 31}) {
      const float x = float(i) / (PMC_BSDF_TABLE_MU - 1), mu = std::max(x * x, 1e-4f);
      const float y = float(j) / (PMC_BSDF_TABLE_N - 1), r = y * y;
      const float alpha = std::max(r * r, PMC_MIN_ALPHA);
      const float3 wo = make_float3(std::sqrt(1.0f - mu * mu), 0.0f, mu);
      double e1 = 0, e5 = 0, es = 0;
      const int n = 200000;
      for (int k = 0; k < n; ++k) {
        const float3 h = pmc_ggx_sample_vndf(wo, alpha, u(rng), u(rng));
        const float3 wi = h * (2.0f * dot(wo, h)) - wo;
        if (wi.z > 0.0f) {
          const double w = (1.0 + pmc_ggx_lambda(wo, alpha)) /
                           (1.0 + pmc_ggx_lambda(wo, alpha) + pmc_ggx_lambda(wi, alpha));
          e1 += w;
          e5 += w * pmc_schlick_m5(dot(wo, h));
        }
        const float3 wc = pmc_sample_cosine(u(rng), u(rng));
        es += pmc_sheen_brdf(wo, wc, r) * kPi;
      }
      const int cell = i * PMC_BSDF_TABLE_N + j;
      EXPECT_NEAR(pmc_ggx_e1_table[cell], e1 / n, 4e-3) << i << "," << j;
      EXPECT_NEAR(pmc_ggx_e5_table[cell], e5 / n, 4e-3) << i << "," << j;
      // (sheen of roughness 0 is a spike at grazing that neither estimate resolves)
      if (j > 0) EXPECT_NEAR(pmc_sheen_e_table[cell], es / n, 0.06 * std::max(1.0, es / n)) << i << "," << j;
    }
}

}  // namespace
}  // namespace pmc
