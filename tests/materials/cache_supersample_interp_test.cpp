// cache_supersample_interp_test.cpp — supersampled cache misses in the host
// interpreter (core/device/pmc_cache_supersample.h, core/device/pmc_interp.h).
//
// The material: stripes along u (or x), f = 0.5 + 0.5 sin(F u), a float
// (stored exactly) cache point with 6.3 periods per level-6 texel (1/64):
// patterns far finer than a texel, which the centre alone point-samples.
//  * the sub-sample offsets: in [-0.5, 0.5), one in each of K strata along
//    every axis, a function of the key alone, different for other texels;
//  * a miss stores (and delivers) the mean of the cacheless program run at the
//    K sub-sample points, computed here by the reference interpreter without a
//    cache, in double; a later hit in the texel reads the same value;
//  * K = 16 is within 0.07 of the stripes' analytic mean over the texel (cell)
//    on average over 64 texels, where K = 1 (the centre) is off by more than
//    0.15. The bounds: one point of f has a standard deviation of
//    sqrt(1/8) = 0.35 about the area mean (a mean absolute error of about
//    0.28); 16 stratified points, each in a stratum 0.39 periods wide, whose
//    own variance is (1/8)(1 - sinc^2(0.39)) = 0.051, have sqrt(16 x 0.051) / 16
//    = 0.056 (about 0.045 mean absolute); a centre-only cache fails the first
//    bound, and an unstratified or wrongly weighted mean the second;
//  * K = 1 compiles to the program of before and stores the centre's value.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "core/device/pmc_interp.h"
#include "core/texture.h"
#include "materials/compiler.h"
#include "tests/support/graph_builder.h"

namespace pmc {
namespace {

using VT = ValueType;
using test::add;
using test::add_surface;
using test::link;
using test::new_graph;
using test::value;

constexpr int kLevel = 6;                             // the footprint's level: texels of 1/64
constexpr double kTexel = 1.0 / 64.0;                 // their width
constexpr double kPeriods = 6.3;                      // stripe periods per texel
const double kFreq = 2.0 * M_PI * kPeriods / kTexel;  // F

// f = 0.5 + 0.5 sin(F x), x the uv's u or the position's x.
Graph stripes(const std::string& name, bool by_position) {
  Graph g = new_graph(name);
  int key = by_position ? add(g, "p", "position", VT::Vector3) : add(g, "uv", "texcoord", VT::Vector2);
  int d = add(
      g, "d", "dotproduct", VT::Float,
      {{"in1", link(key, by_position ? VT::Vector3 : VT::Vector2)},
       {"in2", by_position ? value(VT::Vector3, float(kFreq), 0, 0) : value(VT::Vector2, float(kFreq), 0)}});
  int s = add(g, "s", "sin", VT::Float, {{"in", link(d)}});
  int m = add(g, "m", "multiply", VT::Float, {{"in1", link(s)}, {"in2", value(VT::Float, 0.5f)}});
  int a = add(g, "a", "add", VT::Float, {{"in1", link(m)}, {"in2", value(VT::Float, 0.5f)}});
  add_surface(g, {{"specular_roughness", link(a)}});
  return g;
}

// The analytic mean of f over [lo, lo + w].
double stripe_mean(double lo, double w) {
  return 0.5 + 0.5 * (std::cos(kFreq * lo) - std::cos(kFreq * (lo + w))) / (kFreq * w);
}

struct Fixture {
  TexturePool tex;
  MaterialProgram prog;
  std::vector<uint64_t> words = std::vector<uint64_t>(size_t(1) << 14, 0);
  PmcCacheContext cx{};
  bool by_position;
  Fixture(int samples, bool position) : by_position(position) {
    CompileOptions on;
    on.cache = true;
    on.cache_min_nodes = 1;
    on.cache_supersample.uv = on.cache_supersample.position = samples;
    Graph off_g = stripes("M_off", position), on_g = stripes("M_on", position);
    compile_material(off_g, tex, prog);
    const CompiledMaterial& cm = compile_material(on_g, tex, prog, on);
    EXPECT_EQ(cm.cache_plan.points.size(), 1u);
    cx.table.entries = words.data();
    cx.table.cells = words.size() / 8;
    cx.table.ways = 8;
    cx.g1 = make_float2(float(kTexel), 0.0f);  // footprint level 6
    cx.g2 = make_float2(0.0f, float(kTexel));
    cx.radius = float(kTexel);  // cells of level 6 too
    cx.material = 1;
    cx.center = 1;
  }
  // The roughness at (uv or position) x: material 0 uncached, 1 cached.
  float eval(int material, float2 uv, float3 p, bool cached) {
    PmcShadingInputs in{};
    in.uv = uv;
    in.position = p;
    in.normal = make_float3(0, 0, 1);
    in.tangent = make_float3(1, 0, 0);
    in.bitangent = make_float3(0, 1, 0);
    in.footprint = float(2 * kTexel);
    PmcTextureSet ts{};
    float stack[PMC_STACK_SIZE] = {0};
    float out[PMC_P_COUNT];
    pmc_surface_defaults(out, in.normal);
    cx.hits = 0;
    cx.texel.ready = 0u;
    cx.cell.ready = 0u;
    pmc_interp_run(prog.code.data(), prog.materials[size_t(material)].entry, &in, &ts, stack, out,
                   cached ? &cx : nullptr);
    return out[PMC_P_SPECULAR_ROUGHNESS];
  }
  // The key the shading point at (uv, p) looks up.
  PmcCacheTexel key(float2 uv, float3 p) const {
    return by_position ? pmc_cache_cell_of(p, cx.radius, 0.0f, make_float4(0, 0, 0, 0), cx.material)
                       : pmc_cache_texel_of(uv, cx.g1, cx.g2, 0.0f, make_float2(0, 0), cx.material);
  }
};

float2 uv_at(int i) { return make_float2(0.1f + 0.0371f * float(i), 0.2f + 0.0113f * float(i)); }
float3 p_at(int i) { return make_float3(-0.7f + 0.0493f * float(i), 0.31f, 0.0217f * float(i)); }

TEST(CacheSupersample, OffsetsAreStratifiedAndFollowTheKey) {
  const PmcCacheTexel a = pmc_cache_texel_of(make_float2(0.3f, 0.7f), make_float2(float(kTexel), 0),
                                             make_float2(0, float(kTexel)), 0.0f, make_float2(0, 0), 2u);
  const PmcCacheTexel b = pmc_cache_texel_of(make_float2(0.5f, 0.7f), make_float2(float(kTexel), 0),
                                             make_float2(0, float(kTexel)), 0.0f, make_float2(0, 0), 2u);
  ASSERT_NE(a.hash, b.hash);
  for (pmc_u32 k = 2; k <= PMC_CACHE_SAMPLES_MAX; k *= 2) {
    std::set<int> xs, ys, zs;
    bool differs = false;
    for (pmc_u32 s = 0; s < k; ++s) {
      const float4 o = pmc_cache_subsample(&a, 2u, s);
      for (float c : {o.x, o.y, o.z}) {
        ASSERT_GE(c, -0.5f);
        ASSERT_LT(c, 0.5f);
      }
      xs.insert(int(std::floor((o.x + 0.5f) * float(k))));
      ys.insert(int(std::floor((o.y + 0.5f) * float(k))));
      zs.insert(int(std::floor((o.z + 0.5f) * float(k))));
      const float4 again = pmc_cache_subsample(&a, 2u, s);
      EXPECT_EQ(o.x, again.x);
      EXPECT_EQ(o.y, again.y);
      const float4 other = pmc_cache_subsample(&b, 2u, s);
      differs = differs || other.x != o.x || other.y != o.y;
    }
    EXPECT_EQ(xs.size(), size_t(k)) << "one point per column, K " << k;
    EXPECT_EQ(ys.size(), size_t(k)) << "one point per row, K " << k;
    EXPECT_EQ(zs.size(), size_t(k)) << "one point per layer, K " << k;
    EXPECT_TRUE(differs) << "another texel scrambles its points otherwise, K " << k;
  }
  EXPECT_EQ(pmc_cache_samples_of(0u), 1u);
  EXPECT_EQ(pmc_cache_samples_of(PMC_CACHE_KEY_POSITION | (3u << PMC_CACHE_SAMPLES_SHIFT) | 17u), 8u);
}

// The stored value is the reference interpreter's mean over the K points.
void expect_mean_of_subsamples(bool by_position) {
  for (int k : {1, 4, 16}) {
    Fixture f(k, by_position);
    for (int i = 0; i < 12; ++i) {
      const float2 uv = uv_at(i);
      const float3 p = p_at(i);
      const float cached = f.eval(1, uv, p, true);
      ASSERT_EQ(f.cx.hits, 0u) << "a fresh texel misses";
      const PmcCacheTexel t = f.key(uv, p);
      const double w = std::ldexp(1.0, -t.lambda);
      double sum = 0.0;
      for (int s = 0; s < k; ++s) {
        const float4 o =
            k == 1 ? make_float4(0, 0, 0, 0) : pmc_cache_subsample(&t, f.cx.material, pmc_u32(s));
        // The points as the kernel places them: the centre plus the offset, in float.
        const float wf = float(w);
        float2 q = make_float2((float(t.tx) + 0.5f) * wf + o.x * wf, (float(t.ty) + 0.5f) * wf + o.y * wf);
        float3 r = make_float3(float(t.tx) * wf + o.x * wf, float(t.ty) * wf + o.y * wf,
                               float(t.tz) * wf + o.z * wf);
        sum += f.eval(0, q, r, false);
      }
      EXPECT_NEAR(cached, sum / k, 2e-6) << "K " << k << " point " << i;
      EXPECT_EQ(f.eval(1, uv, p, true), cached) << "a hit reads the stored mean";
      EXPECT_EQ(f.cx.hits, 1u);
    }
  }
}

TEST(CacheSupersample, AMissStoresTheMeanOfItsSubSamplesUv) { expect_mean_of_subsamples(false); }
TEST(CacheSupersample, AMissStoresTheMeanOfItsSubSamplesPosition) { expect_mean_of_subsamples(true); }

// Mean |cached - the stripes' mean over the key's area| over 64 texels.
double area_error(int k, bool by_position) {
  Fixture f(k, by_position);
  double err = 0.0;
  const int n = 64;
  for (int i = 0; i < n; ++i) {
    const float2 uv = uv_at(i);
    const float3 p = p_at(i);
    const PmcCacheTexel t = f.key(uv, p);
    const double w = std::ldexp(1.0, -t.lambda);
    const double lo = by_position ? (double(t.tx) - 0.5) * w : double(t.tx) * w;
    err += std::fabs(f.eval(1, uv, p, true) - stripe_mean(lo, w));
  }
  return err / n;
}

TEST(CacheSupersample, SixteenSubSamplesAverageSubTexelStripes) {
  for (bool by_position : {false, true}) {
    const double one = area_error(1, by_position), sixteen = area_error(16, by_position);
    EXPECT_GT(one, 0.15) << "the centre point-samples the stripes (position " << by_position << ")";
    EXPECT_LT(sixteen, 0.07) << "16 sub-samples average them (position " << by_position << ")";
  }
}

// A key bypassed by a level floor beyond the refinement limit has no texel
// to average: with K = 16 sub-samples the point still gets its own value
// (the group's last pass, run once, at the point's inputs), and nothing is
// inserted. Batches of 1, as on GPUs and in this host build.
TEST(CacheSupersample, ABypassedKeyGetsThePointsOwnValueOnce) {
  for (bool by_position : {false, true}) {
    Fixture f(16, by_position);
    f.cx.floors = 1u;
    f.cx.max_refine = 2;
    f.cx.level_floor_uv = f.cx.level_floor_position = kLevel + 3;  // 3 levels finer: bypassed
    for (int i = 0; i < 12; ++i) {
      const float2 uv = uv_at(i);
      const float3 p = p_at(i);
      EXPECT_NEAR(f.eval(1, uv, p, true), f.eval(0, uv, p, false), 1e-6)
          << "point " << i << ", position " << by_position;
      EXPECT_EQ(f.cx.hits, 0u);
    }
    EXPECT_EQ(f.cx.counts[PMC_CSTAT_BYPASSED], 12u);
    EXPECT_EQ(f.cx.counts[PMC_CSTAT_INSERTS], 0u);
  }
}

TEST(CacheSupersample, OneSubSampleIsTheProgramAndValueOfBefore) {
  TexturePool tex;
  MaterialProgram before, one;
  CompileOptions on;
  on.cache = true;
  on.cache_min_nodes = 1;
  Graph a = stripes("M", false), b = stripes("M", false);
  compile_material(a, tex, before, on);
  on.cache_supersample.uv = on.cache_supersample.position = 1;
  compile_material(b, tex, one, on);
  EXPECT_EQ(before.code, one.code);

  Fixture f(1, false);
  const float2 uv = uv_at(3);
  const PmcCacheTexel t = f.key(uv, make_float3(0, 0, 0));
  const float2 centre =
      make_float2(pmc_cache_texel_center(t.tx, t.lambda), pmc_cache_texel_center(t.ty, t.lambda));
  EXPECT_EQ(f.eval(1, uv, make_float3(0, 0, 0), true), f.eval(0, centre, make_float3(0, 0, 0), false))
      << "K = 1 stores the centre's value, bit for bit";
  EXPECT_EQ(t.lambda, kLevel);
}

}  // namespace
}  // namespace pmc
