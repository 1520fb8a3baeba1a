// light_sampling_test.cpp — the light library (core/device/pmc_lights.h, run
// on the host) and the light table (core/lights.cpp) against answers computed
// independently here:
//   * the lat-long convention of the issue, direction by direction, and the
//     rotation's sense;
//   * the environment map's sampling density: it integrates to one, samples
//     land in texels as often as it says, and its pdf is the density the
//     sampler draws from;
//   * irradiance at a point, estimated exactly as the kernel combines light
//     sampling and cosine (BSDF) sampling with MIS (pmc_light_sample +
//     pmc_lights_seen + pmc_env_light_pdf), against closed forms: I cos/d^2
//     for points and spots, Lambert's polygon formula for quads and
//     triangles, E cos for a sun disk, pi L for a constant environment, and a
//     quadrature over the texels for a map — each light alone and all
//     together (picked by power);
//   * pick probabilities proportional to the documented power formulas.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/device/pmc_lights.h"
#include "core/env_map.h"
#include "core/lights.h"

namespace pmc {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Rng {
  std::mt19937 gen;
  explicit Rng(uint32_t seed) : gen(seed) {}
  float next() { return float(gen() >> 8) * (1.0f / 16777216.0f); }
};

struct D3 {
  double x, y, z;
};
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot3(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross3(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
D3 unit(D3 a) { return a * (1.0 / std::sqrt(dot3(a, a))); }
float3 f3(D3 a) { return make_float3(float(a.x), float(a.y), float(a.z)); }
D3 d3(float3 a) { return {a.x, a.y, a.z}; }
double lum(const float* c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

// Lambert's formula: irradiance at p (normal n) from a convex polygon of
// uniform radiance L wholly above p's horizon: E = L/2 |sum_i angle_i n.g_i|,
// g_i the unit normal of the plane through p and edge i.
double polygon_irradiance(const std::vector<D3>& poly, D3 p, D3 n, double L) {
  double sum = 0.0;
  for (size_t i = 0; i < poly.size(); ++i) {
    D3 a = unit(poly[i] - p), b = unit(poly[(i + 1) % poly.size()] - p);
    double angle = std::acos(std::max(-1.0, std::min(1.0, dot3(a, b))));
    sum += angle * dot3(n, unit(cross3(a, b)));
  }
  return 0.5 * L * std::fabs(sum);
}

PmcLightSet light_set(const LightTable& t) {
  PmcLightSet ls;
  ls.lights = t.lights.data();
  ls.tree = t.tree_nodes.data();
  ls.env = t.env_floats();
  ls.h = t.header;
  return ls;
}

// Irradiance at p (normal n) from every light of `t`, estimated the way the
// shade kernel does it: one light sample and one cosine-sampled direction per
// iteration, combined with the power heuristic. Returns the mean and its
// standard error (luminance).
struct Estimate {
  double mean, stderr_;
};
Estimate mis_irradiance(const LightTable& t, D3 p, D3 n, int samples, uint32_t seed) {
  PmcLightSet ls = light_set(t);
  Rng rng(seed);
  float3 nf = f3(n), tan, bit;
  pmc_basis(nf, &tan, &bit);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < samples; ++i) {
    double e = 0.0;
    PmcLightSample s;
    float u0 = rng.next(), u1 = rng.next(), u2 = rng.next();
    if (pmc_light_sample(&ls, f3(p), nf, u0, u1, u2, &s)) {
      float c = dot(s.wi, nf);
      if (c > 0.0f) {
        float bpdf = c * PMC_INV_PI;
        float w = s.pdf > 0.0f ? pmc_mis_power(s.pdf, bpdf) : 1.0f;
        e += pmc_luminance(s.weight) * c * w;
      }
    }
    float3 local = pmc_sample_cosine(rng.next(), rng.next());
    if (local.z > 0.0f) {
      float3 wi = pmc_to_world(local, tan, bit, nf);
      float bpdf = local.z * PMC_INV_PI;
      float3 seen = pmc_lights_seen(&ls, f3(p), wi, INFINITY, 1, bpdf, nf, 0);
      e += pmc_luminance(seen) * local.z / bpdf;
    }
    sum += e;
    sum2 += e * e;
  }
  double mean = sum / samples;
  double var = std::max(0.0, sum2 / samples - mean * mean);
  return {mean, std::sqrt(var / samples)};
}

Scene empty_scene() {
  Scene s;
  float lo[3] = {-1, -1, -1}, hi[3] = {1, 1, 1};
  s.bounds.extend(lo);
  s.bounds.extend(hi);
  return s;
}

LightTable table_of(const std::vector<LightSpec>& lights, EnvironmentSpec env = {},
                    LightSampler sampler = LightSampler::Tree) {
  SceneLights sl;
  sl.lights = lights;
  sl.environment = env;
  return build_light_table(empty_scene(), {}, sl, sampler);
}

LightSpec point_light(D3 pos, float i) {
  LightSpec l;
  l.type = LightSpec::Type::Point;
  l.position[0] = float(pos.x), l.position[1] = float(pos.y), l.position[2] = float(pos.z);
  l.rgb[0] = l.rgb[1] = l.rgb[2] = i;
  return l;
}

LightSpec quad_light(D3 corner, D3 eu, D3 ev, float radiance, bool two_sided) {
  LightSpec l;
  l.type = LightSpec::Type::Quad;
  for (int k = 0; k < 3; ++k) {
    l.corner[k] = float((&corner.x)[k]);
    l.edge_u[k] = float((&eu.x)[k]);
    l.edge_v[k] = float((&ev.x)[k]);
    l.rgb[k] = radiance;
  }
  l.two_sided = two_sided;
  return l;
}

// A 32 x 16 map: dim sky gradient plus one bright 2 x 1 "sun" patch.
EnvMap sun_map() {
  const int w = 32, h = 16;
  std::vector<float> rgb(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* c = &rgb[3 * (size_t(y) * w + x)];
      c[0] = 0.05f + 0.01f * float(x % 5);
      c[1] = 0.08f;
      c[2] = 0.10f + 0.02f * float(y) / float(h);
      if (y == 4 && (x == 20 || x == 21)) c[0] = 300.0f, c[1] = 250.0f, c[2] = 200.0f;
    }
  return env_map_from_rgb(w, h, rgb);
}

EnvironmentSpec map_environment(const EnvMap& m, float rotate_deg = 0.0f, float scale = 1.0f) {
  EnvironmentSpec e;
  e.present = true;
  e.map = std::make_shared<const EnvMap>(m);
  e.rotate_y_deg = rotate_deg;
  e.scale = scale;
  return e;
}

// Irradiance on a surface (normal n) from a map: each texel's radiance times
// the integral of max(0, n.w) over its solid angle, by a 12 x 12 midpoint
// rule per texel in (u, v) with dw = 2 pi^2 sin(theta) du dv. Independent of
// the library: the convention is written out here from the issue text.
double map_irradiance(const EnvMap& m, D3 n, double rotate_deg, double scale) {
  const double a = rotate_deg * kPi / 180.0;
  double total = 0.0;
  const int sub = 12;
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x) {
      double L = lum(&m.rgb()[3 * (size_t(y) * m.width + x)]) * scale;
      if (L == 0.0) continue;
      double acc = 0.0;
      for (int i = 0; i < sub; ++i)
        for (int j = 0; j < sub; ++j) {
          double u = (x + (j + 0.5) / sub) / m.width, v = (y + (i + 0.5) / sub) / m.height;
          double phi = (u - 0.5) * 2.0 * kPi, theta = v * kPi;
          D3 md{std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
          // world = R_y(a) map: counter-clockwise seen from +Y.
          D3 wd{std::cos(a) * md.x + std::sin(a) * md.z, md.y, -std::sin(a) * md.x + std::cos(a) * md.z};
          acc += std::max(0.0, dot3(n, wd)) * std::sin(theta);
        }
      total += L * acc * (2.0 * kPi * kPi) / (double(m.width) * m.height * sub * sub);
    }
  return total;
}

TEST(EnvMapConvention, DirectionsMapToTheDocumentedUv) {
  struct Case {
    D3 d;
    double u, v;
  };
  const Case cases[] = {
      {{0, 0, -1}, 0.5, 0.5},   // the image centre is seen looking along -Z
      {{1, 0, 0}, 0.75, 0.5},   // +X at u = 0.75
      {{-1, 0, 0}, 0.25, 0.5},  // -X at u = 0.25
      {{0, 1, 0}, 0.5, 0.0},    // +Y: the top row
      {{0, -1, 0}, 0.5, 1.0},   // -Y: the bottom row
      {{0, 0.5, -0.8660254}, 0.5, 1.0 / 3.0},
  };
  for (const Case& c : cases) {
    float2 uv = pmc_env_dir_to_uv(f3(unit(c.d)));
    if (std::fabs(c.d.y) < 0.999) EXPECT_NEAR(uv.x, c.u, 1e-6) << c.d.x << "," << c.d.y << "," << c.d.z;
    EXPECT_NEAR(uv.y, c.v, 1e-6) << c.d.x << "," << c.d.y << "," << c.d.z;
  }
  // +Z is the seam: u = 0 or 1.
  float u = pmc_env_dir_to_uv(make_float3(0, 0, 1)).x;
  EXPECT_TRUE(std::fabs(u) < 1e-6 || std::fabs(u - 1.0f) < 1e-6) << u;
  // uv -> direction -> uv round trip over the sphere.
  Rng rng(1);
  for (int i = 0; i < 1000; ++i) {
    float us = rng.next(), vs = 0.01f + 0.98f * rng.next();
    float3 d = pmc_env_uv_to_dir(us, vs);
    EXPECT_NEAR(length(d), 1.0f, 1e-5f);
    float2 back = pmc_env_dir_to_uv(d);
    EXPECT_NEAR(std::fmod(back.x - us + 1.5f, 1.0f) - 0.5f, 0.0f, 1e-5f);
    EXPECT_NEAR(back.y, vs, 1e-5f);
  }
}

// pmc_atan2 and pmc_acos (core/abi/pmc_vec.h: the map's polynomial atan2)
// against double precision over every octant, at the axes, and at the
// special values.
TEST(EnvMapConvention, Atan2AndAcosMatchDoublePrecision) {
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {  // directions around the circle, at several radii
    const double a = 2.0 * kPi * (double(i) + 0.5) / 200000.0 - kPi;
    const double r = std::ldexp(1.0, i % 41 - 20);
    const float y = float(r * std::sin(a)), x = float(r * std::cos(a));
    worst = std::max(worst, std::fabs(double(pmc_atan2(y, x)) - std::atan2(double(y), double(x))));
  }
  EXPECT_LT(worst, 4e-7);  // a float's spacing at pi is 2.4e-7
  const float axes[][3] = {{0, 1, 0},
                           {1, 0, float(kPi / 2)},
                           {0, -1, float(kPi)},
                           {-1, 0, float(-kPi / 2)},
                           {1, 1, float(kPi / 4)},
                           {-1, -1, float(-3 * kPi / 4)},
                           {0, 0, 0}};
  for (const auto& c : axes) EXPECT_NEAR(pmc_atan2(c[0], c[1]), c[2], 3e-7) << c[0] << "," << c[1];
  EXPECT_TRUE(std::isnan(pmc_atan2(NAN, 1.0f)));
  EXPECT_TRUE(std::isnan(pmc_atan2(1.0f, NAN)));
  worst = 0.0;
  for (int i = -100000; i <= 100000; ++i) {
    const float c = float(i) * 1e-5f;
    worst = std::max(worst, std::fabs(double(pmc_acos(c)) - std::acos(double(c))));
  }
  EXPECT_LT(worst, 4e-7);
  EXPECT_EQ(pmc_acos(1.0f), 0.0f);
  EXPECT_NEAR(pmc_acos(-1.0f), float(kPi), 3e-7);
  EXPECT_EQ(pmc_acos(2.0f), 0.0f);  // clamped
}

// pmc_cdf_search against the standard library's upper bound, on CDFs with
// flat runs (texels of zero weight) and at u equal to entries.
TEST(EnvMapSampling, CdfSearchFindsTheFirstEntryAboveU) {
  std::mt19937 gen(7);
  for (int n : {1, 2, 3, 7, 8, 64, 255, 256, 1000}) {
    std::vector<double> w(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) w[size_t(i)] = gen() % 3 == 0 ? 0.0 : double(gen() % 100);
    std::vector<float> cdf(static_cast<size_t>(n));
    double total = 0.0, running = 0.0;
    for (double x : w) total += x;
    for (int i = 0; i < n; ++i) {
      running += w[size_t(i)];
      cdf[size_t(i)] = total > 0.0 ? float(running / total) : float(double(i + 1) / n);
    }
    cdf[size_t(n - 1)] = 1.0f;
    std::vector<float> us = {0.0f, 0.99999994f, 1.0f};
    for (float c : cdf) us.push_back(c);  // exactly at entries: the next bin
    for (int i = 0; i < 2000; ++i) us.push_back(float(gen() >> 8) * (1.0f / 16777216.0f));
    for (float u : us) {
      const int want =
          int(std::min<ptrdiff_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin(), n - 1));
      ASSERT_EQ(pmc_cdf_search(cdf.data(), n, u), want) << "n " << n << " u " << u;
    }
    EXPECT_EQ(pmc_cdf_search(cdf.data(), n, NAN), n - 1);
  }
}

// pmc_cdf_search_guided gives pmc_cdf_search's index for every u, with the
// guide table from cdf_guide and with wrong tables (shifted, all zero, all
// last): the table only says where to start.
TEST(EnvMapSampling, GuidedCdfSearchFindsWhatTheFullSearchFinds) {
  std::mt19937 gen(11);
  int guided_hits = 0, total = 0;
  for (int n : {1, 2, 3, 7, 8, 64, 255, 256, 1000}) {
    std::vector<float> cdf(static_cast<size_t>(n));
    double sum = 0.0;
    std::vector<double> w(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
      sum += w[size_t(i)] = gen() % 4 == 0 ? 0.0 : std::pow(double(gen() % 1000), 3.0);
    double running = 0.0;
    for (int i = 0; i < n; ++i) {
      running += w[size_t(i)];
      cdf[size_t(i)] = sum > 0.0 ? float(running / sum) : float(double(i + 1) / n);
    }
    cdf[size_t(n - 1)] = 1.0f;
    const std::vector<float> guide = cdf_guide(cdf.data(), n);
    ASSERT_EQ(guide.size(), size_t(n) + 1);
    std::vector<float> shifted(guide), zeros(guide.size(), 0.0f), last(guide.size(), float(n - 1));
    for (float& g : shifted) g = std::min(g + 1.0f, float(n - 1));
    std::vector<float> us = {0.0f, 0.99999994f, 1.0f, -0.5f, 2.0f, NAN};
    for (float c : cdf) us.push_back(c);
    for (int k = 0; k <= n; ++k) us.push_back(float(k) / float(n));  // the buckets' edges
    for (int i = 0; i < 3000; ++i) us.push_back(float(gen() >> 8) * (1.0f / 16777216.0f));
    for (float u : us) {
      const int want = pmc_cdf_search(cdf.data(), n, u);
      ASSERT_EQ(pmc_cdf_search_guided(cdf.data(), guide.data(), n, u), want) << "n " << n << " u " << u;
      ASSERT_EQ(pmc_cdf_search_guided(cdf.data(), shifted.data(), n, u), want)
          << "shifted, n " << n << " u " << u;
      ASSERT_EQ(pmc_cdf_search_guided(cdf.data(), zeros.data(), n, u), want)
          << "zeros, n " << n << " u " << u;
      ASSERT_EQ(pmc_cdf_search_guided(cdf.data(), last.data(), n, u), want) << "last, n " << n << " u " << u;
      if (u >= 0.0f && u < 1.0f) {  // the right table's range holds the answer without the fallback
        const int k = std::min(int(u * float(n)), n - 1);
        guided_hits += want >= int(guide[size_t(k)]) && want <= int(guide[size_t(k) + 1]);
        ++total;
      }
    }
  }
  EXPECT_GT(guided_hits, total * 99 / 100);
}

TEST(EnvMapConvention, RotationTurnsTheMapCounterClockwiseSeenFromAbove) {
  PmcLightHeader h{};
  h.env_rot_cos = std::cos(float(kPi / 2));
  h.env_rot_sin = std::sin(float(kPi / 2));
  // +90 degrees: the map centre (-Z) moves to -X, and +X (u = 0.75) to -Z.
  float3 w = pmc_env_to_world(&h, make_float3(0, 0, -1));
  EXPECT_NEAR(w.x, -1.0f, 1e-6f);
  EXPECT_NEAR(w.z, 0.0f, 1e-6f);
  w = pmc_env_to_world(&h, make_float3(1, 0, 0));
  EXPECT_NEAR(w.z, -1.0f, 1e-6f);
  float3 m = pmc_env_to_map(&h, make_float3(-1, 0, 0));
  EXPECT_NEAR(m.z, -1.0f, 1e-6f);
  EXPECT_NEAR(pmc_env_dir_to_uv(m).x, 0.5f, 1e-6f);
}

TEST(EnvMapSampling, PdfIntegratesToOneAndSamplesFollowIt) {
  EnvMap map = sun_map();
  LightTable t = table_of({}, map_environment(map, 30.0f));
  PmcLightSet ls = light_set(t);
  // Integral of the pdf over the sphere (world directions; midpoint rule in
  // (theta, phi) with dw = sin(theta) dtheta dphi, fine enough to resolve
  // the sun's texels).
  double integral = 0.0;
  const int nt = 800, np = 1600;
  for (int i = 0; i < nt; ++i) {
    double theta = (i + 0.5) * kPi / nt, c = std::cos(theta), s = std::sin(theta);
    double row = 0.0;
    for (int j = 0; j < np; ++j) {
      double phi = (j + 0.5) * 2.0 * kPi / np;
      row += pmc_env_map_pdf(&ls, pmc_env_to_map(&ls.h, make_float3(float(s * std::cos(phi)), float(c),
                                                                    float(s * std::sin(phi)))));
    }
    integral += row * s;
  }
  integral *= (kPi / nt) * (2.0 * kPi / np);
  EXPECT_NEAR(integral, 1.0, 2e-3);

  // Sampled texels against each texel's probability f / sum f, with f =
  // luminance x sin(theta of the row centre), computed here from the map.
  std::vector<double> prob(size_t(map.width) * map.height);
  double total = 0.0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      size_t k = size_t(y) * map.width + x;
      prob[k] = lum(&map.rgb()[3 * k]) * std::sin((y + 0.5) * kPi / map.height);
      total += prob[k];
    }
  std::vector<double> counts(prob.size(), 0.0);
  Rng rng(7);
  const int n = 400000;
  int at_edges = 0;
  for (int i = 0; i < n; ++i) {
    float3 wi, le;
    float pdf = pmc_env_map_sample(&ls, rng.next(), rng.next(), &wi, &le);
    ASSERT_GT(pdf, 0.0f);
    // The reported pdf is the density at the sampled direction, and the
    // radiance is the texel there: the sampled texel's, which the direction
    // names again except within rounding of a texel's edge.
    float3 m = pmc_env_to_map(&ls.h, wi);
    int k = pmc_env_texel_index(&ls.h, m);
    counts[size_t(k)] += 1.0;
    if (std::fabs(pdf - pmc_env_map_pdf(&ls, m)) <= 1e-3f * pdf &&
        std::fabs(le.x - map.rgb()[3 * size_t(k)]) <= 1e-6f)
      continue;
    const float2 uv = pmc_env_dir_to_uv(m);
    const double du = uv.x * map.width - std::round(uv.x * map.width);
    const double dv = uv.y * map.height - std::round(uv.y * map.height);
    EXPECT_LT(std::min(std::fabs(du), std::fabs(dv)), 1e-4) << "sample " << i << " is inside its texel";
    ++at_edges;
  }
  EXPECT_LT(at_edges, n / 10000);
  int checked = 0;
  for (size_t k = 0; k < prob.size(); ++k) {
    double expected = n * prob[k] / total;
    if (expected < 25.0) continue;
    EXPECT_NEAR(counts[k], expected, 5.0 * std::sqrt(expected)) << "texel " << k;
    ++checked;
  }
  EXPECT_GT(checked, 100);
  // The sun texels (0.7% of the solid angle at most) get most samples.
  EXPECT_GT(counts[4 * 32 + 20] + counts[4 * 32 + 21], 0.5 * n);
}

TEST(LightSampling, PointAndSpotGiveIntensityCosOverDistanceSquared) {
  const D3 p{0.3, 0.0, -0.2}, n{0, 1, 0};
  const D3 lp{0.0, 2.0, 0.0};
  LightTable t = table_of({point_light(lp, 5.0f)});
  const D3 to = lp - p;
  const double d2 = dot3(to, to), cos_t = to.y / std::sqrt(d2);
  Estimate e = mis_irradiance(t, p, n, 64, 3);
  EXPECT_NEAR(e.mean, 5.0 * cos_t / d2, 1e-5 * 5.0 / d2);  // a delta light: no noise

  // A spot pointing down, cone 60 degrees, blend 0.5: full intensity within
  // 15 degrees of the axis, smoothstep in the angle to 0 at 30 degrees.
  LightSpec spot = point_light(lp, 5.0f);
  spot.type = LightSpec::Type::Spot;
  spot.direction[0] = 0, spot.direction[1] = -1, spot.direction[2] = 0;
  spot.cone_angle_deg = 60.0f;
  spot.blend = 0.5f;
  LightTable ts = table_of({spot});
  for (double deg : {0.0, 10.0, 14.9, 16.0, 20.0, 22.5, 25.0, 29.0, 31.0, 60.0}) {
    const double a = deg * kPi / 180.0;
    const D3 q{2.0 * std::tan(a), 0.0, 0.0};  // seen from the light at `deg` off the axis
    const D3 v = lp - q;
    const double dist2 = dot3(v, v), c = v.y / std::sqrt(dist2);
    double s = std::min(1.0, std::max(0.0, (30.0 - deg) / 15.0));
    const double falloff = s * s * (3.0 - 2.0 * s);
    Estimate es = mis_irradiance(ts, q, n, 4, 5);
    EXPECT_NEAR(es.mean, 5.0 * falloff * c / dist2, 1e-4 * 5.0 / dist2) << deg << " degrees";
  }
}

TEST(LightSampling, QuadMatchesLambertsFormulaAndEmitsFromOneSide) {
  const D3 corner{-0.5, 1.0, -0.25}, eu{1.0, 0.0, 0.0}, ev{0.0, 0.2, 0.5};
  const D3 p{0.4, 0.0, 0.3}, n{0, 1, 0};
  const std::vector<D3> poly = {corner, corner + eu, corner + eu + ev, corner + ev};
  const double exact = polygon_irradiance(poly, p, n, 2.0);
  // edge_u x edge_v = (0, -0.5, 0.2): it faces down toward p.
  Estimate down = mis_irradiance(table_of({quad_light(corner, eu, ev, 2.0f, false)}), p, n, 40000, 11);
  EXPECT_NEAR(down.mean, exact, 4.0 * down.stderr_ + 1e-3 * exact);
  EXPECT_LT(down.stderr_, 0.01 * exact);
  // Turned over (edges swapped): nothing reaches p, by either strategy.
  Estimate up = mis_irradiance(table_of({quad_light(corner, ev, eu, 2.0f, false)}), p, n, 4000, 12);
  EXPECT_EQ(up.mean, 0.0);
  // Two-sided: the same light from both sides.
  Estimate both = mis_irradiance(table_of({quad_light(corner, ev, eu, 2.0f, true)}), p, n, 40000, 13);
  EXPECT_NEAR(both.mean, exact, 4.0 * both.stderr_ + 1e-3 * exact);
}

TEST(LightSampling, QuadsNextToThePointMatchLambertsFormula) {
  // Close to the light, where rectangles are sampled by solid angle
  // (pmc_sph_rect_*) and a parallelogram by area: points under the quad's
  // middle, beside it, and nearly in its plane; both kinds against Lambert.
  const D3 corner{-0.5, 0.05, -0.4}, eu{1.0, 0.0, 0.0}, ev{0.0, 0.0, 0.8};  // 5 cm up, facing down
  const D3 skew{0.3, 0.0, 0.8};                                             // a parallelogram
  const D3 n{0, 1, 0};
  for (D3 p : {D3{0.0, 0.0, 0.0}, D3{0.9, 0.0, 0.1}, D3{0.2, 0.049, -0.6}}) {
    for (int parallelogram = 0; parallelogram < 2; ++parallelogram) {
      const D3 ev_k = parallelogram ? skew : ev;
      const std::vector<D3> poly = {corner, corner + eu, corner + eu + ev_k, corner + ev_k};
      const double exact = polygon_irradiance(poly, p, n, 3.0);
      Estimate e = mis_irradiance(table_of({quad_light(corner, eu, ev_k, 3.0f, false)}), p, n, 40000, 21);
      EXPECT_NEAR(e.mean, exact, 4.0 * e.stderr_ + 1e-3 * exact)
          << "p " << p.x << "," << p.y << "," << p.z << (parallelogram ? " parallelogram" : " rectangle");
    }
  }
}

TEST(LightSampling, SphericalRectangleHasTheExactSolidAngleAndMapsUniformly) {
  // A w x h rectangle at height d above p, one corner straight above it:
  // solid angle atan(w h / (d sqrt(d^2 + w^2 + h^2))).
  const double w = 0.7, h = 0.4, d = 0.3;
  PmcLight l{};
  l.type = PMC_LIGHT_QUAD;
  l.flags = PMC_LIGHT_RECTANGLE;
  l.pos[1] = float(d);
  l.axis[0] = float(w);
  l.edge_v[2] = float(h);
  const float3 p = make_float3(0.0f, 0.0f, 0.0f);
  PmcSphRect r;
  const float omega = pmc_sph_rect_init(&l, p, &r);
  const double exact = std::atan(w * h / (d * std::sqrt(d * d + w * w + h * h)));
  EXPECT_NEAR(omega, exact, 1e-5 * exact);
  // Area-preserving: each cell of a 16 x 16 grid of the unit square maps to
  // omega / 256 of solid angle (the cell's two spherical triangles, by Van
  // Oosterom and Strackee), and every sample lies on the rectangle.
  const int g = 16;
  auto dir = [&](double u, double v) {
    float3 q = pmc_sph_rect_sample(&r, p, float(u), float(v));
    EXPECT_NEAR(q.y, d, 1e-5);
    EXPECT_GE(q.x, -1e-5);
    EXPECT_LE(q.x, w + 1e-5);
    EXPECT_GE(q.z, -1e-5);
    EXPECT_LE(q.z, h + 1e-5);
    D3 a{q.x, q.y, q.z};
    double len = std::sqrt(dot3(a, a));
    return D3{a.x / len, a.y / len, a.z / len};
  };
  auto tri = [](D3 a, D3 b, D3 c) {
    D3 bc{b.y * c.z - b.z * c.y, b.z * c.x - b.x * c.z, b.x * c.y - b.y * c.x};
    return 2.0 * std::atan2(std::fabs(dot3(a, bc)), 1.0 + dot3(a, b) + dot3(a, c) + dot3(b, c));
  };
  double total = 0.0, worst = 0.0;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j) {
      D3 a = dir(double(i) / g, double(j) / g), b = dir(double(i + 1) / g, double(j) / g);
      D3 c = dir(double(i + 1) / g, double(j + 1) / g), e = dir(double(i) / g, double(j + 1) / g);
      const double cell = tri(a, b, c) + tri(a, c, e);
      total += cell;
      worst = std::max(worst, std::fabs(cell * g * g / exact - 1.0));
    }
  EXPECT_NEAR(total, exact, 1e-3 * exact);
  EXPECT_LT(worst, 0.02) << "cells of the unit square map to equal solid angles";
  // Not a rectangle, or p in its plane: no spherical rectangle.
  l.flags = 0u;
  EXPECT_EQ(pmc_sph_rect_init(&l, p, &r), 0.0f);
  l.flags = PMC_LIGHT_RECTANGLE;
  EXPECT_EQ(pmc_sph_rect_init(&l, make_float3(0.2f, float(d), 0.1f), &r), 0.0f);
}

TEST(LightSampling, EmissiveTriangleMatchesLambertsFormula) {
  Scene scene = empty_scene();
  scene.positions = {-0.5f, 1.0f, 0.0f, 0.7f, 1.2f, 0.1f, 0.0f, 0.9f, 0.8f};
  PmcTriangle tri{};
  tri.v[0] = 0, tri.v[1] = 1, tri.v[2] = 2;
  tri.n[0] = tri.n[1] = tri.n[2] = -1;
  tri.t[0] = tri.t[1] = tri.t[2] = -1;
  tri.material = 0;
  scene.triangles.push_back(tri);
  LightTable t = build_light_table(scene, {3.0f, 3.0f, 3.0f}, SceneLights{});
  ASSERT_EQ(t.lights.size(), 1u);
  EXPECT_EQ(t.triangle_light[0], 0);
  EXPECT_EQ(t.lights[0].pmf, 1.0f);
  const D3 p{0.1, 0.0, 0.2}, n{0, 1, 0};
  const double exact = polygon_irradiance({{-0.5, 1.0, 0.0}, {0.7, 1.2, 0.1}, {0.0, 0.9, 0.8}}, p, n, 3.0);
  // Light sampling alone: triangles are hit as surfaces, not by pmc_lights_seen,
  // so the estimate uses the light strategy with full weight.
  PmcLightSet ls = light_set(t);
  Rng rng(21);
  double sum = 0.0;
  const int samples = 40000;
  for (int i = 0; i < samples; ++i) {
    PmcLightSample s;
    if (pmc_light_sample(&ls, f3(p), f3(n), rng.next(), rng.next(), rng.next(), &s))
      sum += pmc_luminance(s.weight) * std::max(0.0f, s.wi.y);
  }
  EXPECT_NEAR(sum / samples, exact, 0.01 * exact);
}

TEST(LightSampling, SunDiskDeliversItsIrradianceAndStaysInsideTheDisk) {
  LightSpec sun;
  sun.type = LightSpec::Type::Directional;
  D3 dir = unit({0.3, -1.0, 0.2});  // the direction the light travels
  sun.direction[0] = float(dir.x), sun.direction[1] = float(dir.y), sun.direction[2] = float(dir.z);
  sun.rgb[0] = sun.rgb[1] = sun.rgb[2] = 4.0f;
  sun.angle_deg = 0.53f;
  LightTable t = table_of({sun});
  ASSERT_EQ(t.header.at_infinity, 1);
  const D3 n = unit({0.1, 1.0, -0.3});
  const double exact = 4.0 * dot3(n, dir * -1.0);
  Estimate e = mis_irradiance(t, {0, 0, 0}, n, 20000, 4);
  EXPECT_NEAR(e.mean, exact, 2e-3 * exact);
  PmcLightSet ls = light_set(t);
  Rng rng(9);
  const double cos_half = std::cos(0.265 * kPi / 180.0);
  for (int i = 0; i < 2000; ++i) {
    PmcLightSample s;
    ASSERT_TRUE(pmc_light_sample(&ls, make_float3(0, 0, 0), f3(n), rng.next(), rng.next(), rng.next(), &s));
    EXPECT_GE(dot3(d3(s.wi), dir * -1.0), cos_half - 1e-7);
    EXPECT_TRUE(pmc_sun_contains(&ls.lights[0], s.wi));
  }
  // Just outside the disk is outside.
  D3 axis = dir * -1.0, side = unit(cross3(axis, {0, 0, 1}));
  const double out = 0.27 * kPi / 180.0;
  EXPECT_FALSE(pmc_sun_contains(&ls.lights[0], f3(unit(axis * std::cos(out) + side * std::sin(out)))));
  // Without an angle it is a delta light: E cos exactly.
  sun.angle_deg = 0.0f;
  Estimate delta = mis_irradiance(table_of({sun}), {0, 0, 0}, n, 16, 4);
  EXPECT_NEAR(delta.mean, exact, 1e-5 * exact);
}

TEST(LightSampling, ConstantAndMapEnvironmentsMatchTheirIrradiance) {
  const D3 n = unit({0.2, 1.0, 0.4});
  float white[3] = {0.7f, 0.7f, 0.7f};
  Estimate c = mis_irradiance(table_of({}, constant_environment(white)), {0, 0, 0}, n, 1000, 2);
  // Cosine sampling on both sides with equal pdfs: every sample is exact.
  EXPECT_NEAR(c.mean, kPi * 0.7, 1e-4);
  EnvMap map = sun_map();
  for (float rotate : {0.0f, 75.0f}) {
    const double exact = map_irradiance(map, n, rotate, 2.0);
    Estimate e = mis_irradiance(table_of({}, map_environment(map, rotate, 2.0f)), {0, 0, 0}, n, 40000, 3);
    EXPECT_NEAR(e.mean, exact, 4.0 * e.stderr_ + 1e-3 * exact) << "rotate " << rotate;
    EXPECT_LT(e.stderr_, 0.01 * exact);
  }
}

// The map is kept once (core/env_map.h): every table built from it points at
// its data, whatever the scale, and the scale reaches the texels through the
// header. Each render builds a table; a copy per render is what this rules out.
TEST(LightSampling, TablesOfOneMapShareItsTexelsAndScaleThemInTheHeader) {
  EnvironmentSpec once = map_environment(sun_map(), 0.0f, 1.0f), thrice = once;
  thrice.scale = 3.0f;
  const LightTable a = table_of({}, once), b = table_of({}, thrice);
  EXPECT_EQ(a.env_floats(), once.map->data.data());
  EXPECT_EQ(b.env_floats(), once.map->data.data());
  EXPECT_EQ(a.env_float_count(), EnvMap::data_floats(once.map->width, once.map->height));
  const PmcLightSet la = light_set(a), lb = light_set(b);
  for (int i : {0, 7, 4 * once.map->width + 20}) {  // the sun's texel among them
    const float3 ta = pmc_env_texel(&la, i), tb = pmc_env_texel(&lb, i);
    EXPECT_EQ(ta.x, once.map->rgb()[3 * i]) << i;
    EXPECT_FLOAT_EQ(tb.x, 3.0f * ta.x) << i;
    EXPECT_FLOAT_EQ(tb.z, 3.0f * ta.z) << i;
  }
  // The density does not depend on the scale; the integral it divides by does.
  const float3 up = make_float3(0.0f, 1.0f, 0.0f);
  EXPECT_FLOAT_EQ(pmc_env_map_pdf(&la, up), pmc_env_map_pdf(&lb, up));
  // Without a map the buffer is one zero, never empty.
  const LightTable none = table_of({}, EnvironmentSpec{});
  EXPECT_EQ(none.env_float_count(), 1u);
  EXPECT_EQ(none.env_floats()[0], 0.0f);
}

TEST(LightSampling, EveryLightTogetherSumsTheirIrradiance) {
  const D3 p{0.2, 0.0, 0.1}, n{0, 1, 0};
  const D3 corner{-0.5, 1.5, -0.5}, eu{1.0, 0.0, 0.0}, ev{0.0, 0.0, 1.0};  // faces down
  LightSpec sun;
  sun.type = LightSpec::Type::Directional;
  D3 dir = unit({-0.2, -1.0, 0.1});
  sun.direction[0] = float(dir.x), sun.direction[1] = float(dir.y), sun.direction[2] = float(dir.z);
  sun.rgb[0] = sun.rgb[1] = sun.rgb[2] = 2.0f;
  sun.angle_deg = 3.0f;
  EnvMap map = sun_map();
  for (LightSampler sampler : {LightSampler::Tree, LightSampler::Power}) {
    const char* name = sampler == LightSampler::Tree ? "tree" : "power";
    LightTable t =
        table_of({point_light({1.0, 2.0, 0.0}, 3.0f), quad_light(corner, eu, ev, 1.5f, false), sun},
                 map_environment(map, 10.0f), sampler);
    EXPECT_EQ(t.header.env, PMC_ENV_MAP);
    EXPECT_EQ(t.header.at_infinity, 2);  // environment, sun
    EXPECT_EQ(t.header.distant_end, 2);
    EXPECT_EQ(t.header.quad_end, 3);
    EXPECT_EQ(t.header.tree_nodes, sampler == LightSampler::Tree ? 3 : 0) << name;
    const D3 lp{1.0, 2.0, 0.0};
    const double d2 = dot3(lp - p, lp - p);
    const double exact = 3.0 * (lp.y - p.y) / std::sqrt(d2) / d2 +
                         polygon_irradiance({corner, corner + eu, corner + eu + ev, corner + ev}, p, n, 1.5) +
                         2.0 * dot3(n, dir * -1.0) + map_irradiance(map, n, 10.0, 1.0);
    Estimate e = mis_irradiance(t, p, n, 80000, 17);
    EXPECT_NEAR(e.mean, exact, 4.0 * e.stderr_ + 1e-3 * exact) << name;
    EXPECT_LT(e.stderr_, 0.01 * exact) << name;
  }
}

TEST(LightTable, PicksLightsByPower) {
  // Scene bounds [-1, 1]^3: bounding-sphere radius sqrt(3).
  const double disk = kPi * 3.0;
  LightSpec spot = point_light({0, 1, 0}, 2.0f);
  spot.type = LightSpec::Type::Spot;
  spot.cone_angle_deg = 90.0f;
  spot.blend = 0.0f;
  LightSpec dir;
  dir.type = LightSpec::Type::Directional;
  dir.rgb[0] = dir.rgb[1] = dir.rgb[2] = 0.5f;
  float sky[3] = {0.25f, 0.25f, 0.25f};
  LightTable t = table_of(
      {point_light({0, 0, 0}, 1.0f), quad_light({0, 0, 0}, {2, 0, 0}, {0, 0, 1}, 1.0f, true), spot, dir},
      constant_environment(sky));
  // Kernel order: environment | directional | quad | point, spot.
  ASSERT_EQ(t.lights.size(), 5u);
  EXPECT_EQ(t.lights[0].type, PMC_LIGHT_ENV);
  EXPECT_EQ(t.lights[1].type, PMC_LIGHT_DIRECTIONAL);
  EXPECT_EQ(t.lights[2].type, PMC_LIGHT_QUAD);
  const double power[5] = {disk * 4.0 * kPi * 0.25,                       // environment
                           disk * 0.5,                                    // directional
                           2.0 * kPi * 2.0 * 1.0,                         // two-sided quad, area 2
                           4.0 * kPi * 1.0,                               // point
                           2.0 * kPi * (1.0 - std::cos(kPi / 4)) * 2.0};  // spot, 90 degree cone
  double total = 0.0;
  for (double p : power) total += p;
  double running = 0.0;
  for (int i = 0; i < 5; ++i) {
    running += power[i] / total;
    EXPECT_NEAR(t.lights[size_t(i)].pmf, power[i] / total, 1e-6) << i;
    EXPECT_NEAR(t.lights[size_t(i)].cdf, running, 1e-6) << i;
  }
  EXPECT_EQ(t.lights[4].cdf, 1.0f);
}

}  // namespace
}  // namespace pmc
