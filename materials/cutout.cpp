// cutout.cpp — opacity at a candidate hit, via the CPU interpreter.
#include "materials/cutout.h"

#include "materials/cpu_interpreter.h"

namespace pmc {

CutoutTester::CutoutTester(const Scene& scene, const MaterialSet& materials)
    : scene_(scene), materials_(materials), textures_(host_texture_set(scene, materials)) {
  flags_.assign(scene.triangles.size(), 0);
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    int m = scene.triangles[i].material;
    if (size_t(m) < materials.cutout_entry.size() && materials.cutout_entry[size_t(m)] >= 0) {
      flags_[i] = 1;
      ++count_;
    }
  }
}

PmcShadingInputs cutout_shading_inputs(const Scene& scene, uint32_t prim, float u, float v) {
  const PmcTriangle& t = scene.triangles[prim];
  const float w = 1.0f - u - v;
  PmcShadingInputs in{};
  if (t.t[0] >= 0) {
    const float* t0 = &scene.uvs[2 * size_t(t.t[0])];
    const float* t1 = &scene.uvs[2 * size_t(t.t[1])];
    const float* t2 = &scene.uvs[2 * size_t(t.t[2])];
    in.uv = make_float2(w * t0[0] + u * t1[0] + v * t2[0], w * t0[1] + u * t1[1] + v * t2[1]);
  } else {
    in.uv = make_float2(u, v);
  }
  const float* p0 = &scene.positions[3 * size_t(t.v[0])];
  const float* p1 = &scene.positions[3 * size_t(t.v[1])];
  const float* p2 = &scene.positions[3 * size_t(t.v[2])];
  in.position = make_float3(w * p0[0] + u * p1[0] + v * p2[0], w * p0[1] + u * p1[1] + v * p2[1],
                            w * p0[2] + u * p1[2] + v * p2[2]);
  in.normal = make_float3(0, 0, 1);
  in.tangent = make_float3(1, 0, 0);
  in.bitangent = make_float3(0, 1, 0);
  in.footprint = 0.0f;  // the finest mip: masks keep their edges
  return in;
}

bool CutoutTester::transparent(uint32_t prim, float u, float v) const {
  const PmcTriangle& t = scene_.triangles[prim];
  const PmcShadingInputs in = cutout_shading_inputs(scene_, prim, u, v);
  float params[PMC_P_COUNT];
  float stack[PMC_STACK_SIZE];
  pmc_surface_defaults(params, in.normal);
  pmc_interp_run(materials_.cutout_program.code.data(), uint32_t(materials_.cutout_entry[size_t(t.material)]),
                 &in, &textures_, stack, params, nullptr);
  float opacity =
      (params[PMC_P_OPACITY] + params[PMC_P_OPACITY + 1] + params[PMC_P_OPACITY + 2]) * (1.0f / 3.0f);
  return !(opacity >= 0.5f);
}

}  // namespace pmc
