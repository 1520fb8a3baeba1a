// cache_supersample_device_test.cpp — supersampled cache misses in the
// lane-batched interpreter on the OpenCL device (PoCL on CI).
//
// One material with two cache points: stripes along u (a uv point, 4
// sub-samples) and stripes along x (a position point, 16 sub-samples), half
// of each added at the top (that sum reads uv and position, so it is not
// cached): the group replays 16 times, and the uv point stops summing after
// its 4. A kernel runs the program 8 points to a work-item (PMC_LANES 8, as
// the shade kernel batches on CPU devices) in cache_eval center, with points
// that share texels in one batch and across work-items, into one table. Each
// point's roughness must equal half the reference interpreter's mean of the
// uv stripes over the texel's 4 sub-sample points plus half its mean of the
// x stripes over the cell's 16, evaluated on the host without a cache (the
// independent answer), to float rounding and the device's sin. A group's
// packed lanes are padded to 8 with copies of its first point
// (PMC_LANE_PAD): a copy that stored would add that point's sub-sample twice.
//
// Bypassed keys (a level floor more than max_refine levels finer than the
// footprint) are evaluated at the point's own inputs once, in the group's
// last pass: a work-item whose odd lanes bypass their cells, and one whose
// every lane bypasses both keys (no lane needs the sub-samples: the group
// goes straight to its last pass), must give the reference at the point
// itself for what they bypass and the sub-samples' mean for the rest.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/device/pmc_interp.h"
#include "core/texture.h"
#include "gpu/program.h"
#include "materials/compiler.h"
#include "tests/support/graph_builder.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

using VT = ValueType;
using test::add;
using test::add_surface;
using test::link;
using test::new_graph;
using test::value;

constexpr float kTexel = 1.0f / 64.0f;
constexpr float kFreq = 2.0f * 3.14159265f * 6.3f / kTexel;  // 6.3 stripe periods per texel

// 0.5 + 0.5 sin(F x), x the u or the position's x; returns the node.
int stripes(Graph& g, bool by_position) {
  int key = by_position ? add(g, "p", "position", VT::Vector3) : add(g, "uv", "texcoord", VT::Vector2);
  int d = add(g, by_position ? "dp" : "du", "dotproduct", VT::Float,
              {{"in1", link(key, by_position ? VT::Vector3 : VT::Vector2)},
               {"in2", by_position ? value(VT::Vector3, kFreq, 0, 0) : value(VT::Vector2, kFreq, 0)}});
  int s = add(g, by_position ? "sp" : "su", "sin", VT::Float, {{"in", link(d)}});
  int m = add(g, by_position ? "mp" : "mu", "multiply", VT::Float,
              {{"in1", link(s)}, {"in2", value(VT::Float, 0.5f)}});
  return add(g, by_position ? "ap" : "au", "add", VT::Float,
             {{"in1", link(m)}, {"in2", value(VT::Float, 0.5f)}});
}

Graph one_kind(const std::string& name, bool by_position) {
  Graph g = new_graph(name);
  add_surface(g, {{"specular_roughness", link(stripes(g, by_position))}});
  return g;
}

Graph both_kinds(const std::string& name) {
  Graph g = new_graph(name);
  int hu = add(g, "hu", "multiply", VT::Float,
               {{"in1", link(stripes(g, false))}, {"in2", value(VT::Float, 0.5f)}});
  int hp =
      add(g, "hp", "multiply", VT::Float, {{"in1", link(stripes(g, true))}, {"in2", value(VT::Float, 0.5f)}});
  int sum = add(g, "sum", "add", VT::Float, {{"in1", link(hu)}, {"in2", link(hp)}});
  add_surface(g, {{"specular_roughness", link(sum)}});
  return g;
}

const char* kKernel = R"CL(
#define PMC_LANES 8
#include "pmc_interp.h"
__kernel void shade(__global const uint* code, uint entry, __global const float* points,
                    __global ulong* table, ulong cells, float texel, __global float* out, uint n,
                    uint floors) {
  const uint first = get_global_id(0) * PMC_LANES;
  if (first >= n) return;
  const int m = (int)min((uint)PMC_LANES, n - first);
  PmcShadingInputs in[PMC_LANES];
  PmcCacheContext cache[PMC_LANES];
  float stack[PMC_STACK_SIZE * PMC_LANES];
  float params[PMC_LANES * PMC_P_COUNT];
  for (int k = 0; k < m; ++k) {
    __global const float* p = points + 5 * (first + (uint)k);
    in[k].uv = make_float2(p[0], p[1]);
    in[k].position = make_float3(p[2], p[3], p[4]);
    in[k].normal = make_float3(0.0f, 0.0f, 1.0f);
    in[k].tangent = make_float3(1.0f, 0.0f, 0.0f);
    in[k].bitangent = make_float3(0.0f, 1.0f, 0.0f);
    in[k].footprint = 2.0f * texel;
    in[k].footprint_axis = make_float2(0.0f, 0.0f);
    in[k].footprint_minor = 0.0f;
    PmcCacheContext* c = &cache[k];
    c->table.entries = (PMC_CACHE_PTR)table;
    c->table.cells = cells;
    c->table.ways = 8u;
    c->table.policy = PMC_CACHE_KEEP_FIRST;
    c->g1 = make_float2(texel, 0.0f);
    c->g2 = make_float2(0.0f, texel);
    c->bias = 0.0f;
    c->jitter = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
    c->radius = texel;
    /* floors 1: work-item w % 3 == 1 bypasses its odd lanes' cells, 2 every key */
    const uint mode = floors ? get_global_id(0) % 3u : 0u;
    c->floors = mode != 0u ? 1u : 0u;
    c->level_floor_uv = mode == 2u ? 9 : PMC_LEVEL_NO_FLOOR; /* the footprint's level is 6 */
    c->level_floor_position = mode == 2u || (mode == 1u && (k & 1)) ? 9 : PMC_LEVEL_NO_FLOOR;
    c->max_refine = 2;
    c->material = 1u;
    c->center = 1u;
    c->depth = 0u;
    c->texel.ready = 0u;
    c->cell.ready = 0u;
    c->hits = 0u;
    for (int i = 0; i < PMC_CSTAT_COUNT; ++i) c->counts[i] = 0u;
    pmc_surface_defaults(params + k * PMC_P_COUNT, in[k].normal);
  }
  PmcTextureSet ts;
  ts.textures = 0;
  ts.texels = 0;
  ts.srgb_lut = 0;
  ts.count = 0u;
  pmc_interp_lanes(code, entry, in, m, &ts, stack, params, cache);
  for (int k = 0; k < m; ++k) out[first + (uint)k] = params[k * PMC_P_COUNT + PMC_P_SPECULAR_ROUGHNESS];
}
)CL";

// The host reference: material `material` of `prog` without a cache at (uv, p).
float reference(const MaterialProgram& prog, int material, float2 uv, float3 p) {
  PmcShadingInputs in{};
  in.uv = uv;
  in.position = p;
  in.normal = make_float3(0, 0, 1);
  in.tangent = make_float3(1, 0, 0);
  in.bitangent = make_float3(0, 1, 0);
  in.footprint = 2.0f * kTexel;
  PmcTextureSet ts{};
  float stack[PMC_STACK_SIZE] = {0};
  float out[PMC_P_COUNT];
  pmc_surface_defaults(out, in.normal);
  pmc_interp_run(prog.code.data(), prog.materials[size_t(material)].entry, &in, &ts, stack, out, nullptr);
  return out[PMC_P_SPECULAR_ROUGHNESS];
}

// The roughness every point gets: half the uv stripes, half the x stripes,
// each the mean over its key's sub-samples or, where the point bypasses that
// key (`floors`: the kernel's pattern), their value at the point itself.
void expect_batched_means(bool floors) {
  TexturePool tex;
  MaterialProgram prog;
  CompileOptions on;
  on.cache = true;
  on.cache_min_nodes = 1;
  on.cache_supersample.uv = 4;
  on.cache_supersample.position = 16;
  Graph g = both_kinds("M_both");
  const CompiledMaterial& cm = compile_material(g, tex, prog, on);
  ASSERT_EQ(cm.cache_plan.points.size(), 2u);
  Graph u = one_kind("M_u", false), x = one_kind("M_x", true);
  compile_material(u, tex, prog);  // material 1: the uv stripes, uncached
  compile_material(x, tex, prog);  // material 2: the x stripes, uncached

  // 200 points; every third repeats an earlier point's texel and cell (hits
  // and same-batch misses of one key).
  std::vector<float> points;
  const uint32_t n = 200;
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = i % 3 == 2 ? i / 2 : i;
    const float jig = i % 3 == 2 ? 0.2f * kTexel : 0.0f;
    points.insert(points.end(), {0.05f + 0.0371f * float(j) + jig, 0.2f + 0.0113f * float(j),
                                 -0.7f + 0.0493f * float(j) + jig, 0.31f, 0.0217f * float(j)});
  }
  const ClContext& cl = test::cl();
  ClProgram kernel = ClProgram::from_text(cl, "cache_supersample_test.cl", kKernel);
  const uint64_t cells = 4096;
  std::vector<uint64_t> zeros(cells * 8, 0);
  ClBuffer code = cl.buffer(prog.code.size() * 4, prog.code.data()),
           in = cl.buffer(points.size() * 4, points.data()),
           table = cl.buffer(zeros.size() * 8, zeros.data()), out = cl.buffer(n * 4);
  cl_kernel k = kernel.kernel("shade");
  set_kernel_args(k, code, cl_uint(prog.materials[0].entry), in, table, cl_ulong(cells), kTexel, out,
                  cl_uint(n), cl_uint(floors ? 1 : 0));
  enqueue_1d(cl.queue(), k, (n + 7) / 8);
  std::vector<float> got(n);
  cl.read(out, 0, n * 4, got.data());

  for (uint32_t i = 0; i < n; ++i) {
    const float* p = &points[size_t(i) * 5];
    const float2 uv = make_float2(p[0], p[1]);
    const float3 pos = make_float3(p[2], p[3], p[4]);
    const PmcCacheTexel t =
        pmc_cache_texel_of(uv, make_float2(kTexel, 0), make_float2(0, kTexel), 0.0f, make_float2(0, 0), 1u);
    const PmcCacheTexel c = pmc_cache_cell_of(pos, kTexel, 0.0f, make_float4(0, 0, 0, 0), 1u);
    const float wt = std::ldexp(1.0f, -t.lambda), wc = std::ldexp(1.0f, -c.lambda);
    double mean_u = 0.0, mean_x = 0.0;
    for (pmc_u32 s = 0; s < 4; ++s) {
      const float4 o = pmc_cache_subsample(&t, 1u, s);
      mean_u += reference(
          prog, 1, make_float2((float(t.tx) + 0.5f) * wt + o.x * wt, (float(t.ty) + 0.5f) * wt + o.y * wt),
          pos);
    }
    for (pmc_u32 s = 0; s < 16; ++s) {
      const float4 o = pmc_cache_subsample(&c, 1u, s);
      mean_x += reference(
          prog, 2, uv,
          make_float3(float(c.tx) * wc + o.x * wc, float(c.ty) * wc + o.y * wc, float(c.tz) * wc + o.z * wc));
    }
    const uint32_t mode = floors ? (i / 8) % 3 : 0;
    const bool own_u = mode == 2, own_x = mode == 2 || (mode == 1 && i % 2 == 1);
    const double u = own_u ? double(reference(prog, 1, uv, pos)) : mean_u / 4.0;
    const double x = own_x ? double(reference(prog, 2, uv, pos)) : mean_x / 16.0;
    ASSERT_NEAR(got[i], 0.5 * u + 0.5 * x, 2e-5) << "point " << i << ", floors " << floors;
  }
}

TEST(CacheSupersampleDevice, BatchedMissesStoreTheMeanOfTheirSubSamples) { expect_batched_means(false); }

TEST(CacheSupersampleDevice, BypassedKeysAreEvaluatedAtThePointOnceInTheLastPass) {
  expect_batched_means(true);
}

}  // namespace
}  // namespace pmc
