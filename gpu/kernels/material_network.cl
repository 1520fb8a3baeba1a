/* material_network.cl — the entry point that turns hits into BSDFs.
 *
 * pmc_eval_material_lanes() runs one material's bytecode
 * (core/device/pmc_interp.h) from its entry offset in the shared program
 * buffer for a batch of shading points of that material at once (PMC_LANES
 * of them at most), each starting from the standard_surface defaults, and
 * converts each point's surface parameters into a BSDF. A normal written by
 * the program (normal maps) replaces the point's shading normal. A uniform
 * program (PMC_MAT_UNIFORM: it reads nothing of the point, e.g. a constant
 * MTL material) runs for the batch's first point, and every point gets its
 * BSDF: what each would have computed alike. `cache`
 * holds one context per point (null when the cache is off: those programs
 * contain no cache instructions). Every material of every scene goes through
 * this function: there are no per-material kernels.
 */

typedef struct PmcMaterialData {
  __global const pmc_u32* code;
  __global const PmcMaterialInfo* materials;
  PmcTextureSet textures;
} PmcMaterialData;

static inline void pmc_eval_material_lanes(const PmcMaterialData* md, int material, PmcShadingInputs* sp,
                                           int n, PmcCacheContext* cache, PmcBsdf* bsdf) {
  float stack[PMC_STACK_SIZE * PMC_LANES];
  float params[PMC_P_COUNT * PMC_LANES];
  const int uniform = (md->materials[material].flags & PMC_MAT_UNIFORM) != 0u;
  const int runs = uniform && n > 0 ? 1 : n;
  for (int k = 0; k < runs; ++k) pmc_surface_defaults(&params[k * PMC_P_COUNT], sp[k].normal);
  pmc_interp_lanes(md->code, md->materials[material].entry, sp, runs, &md->textures, stack, params, cache);
  if (uniform && n > 0) bsdf[0] = pmc_surface_to_bsdf(params);
  for (int k = 0; k < n; ++k) {
    /* a uniform program keeps the default normal: the point's own */
    const float* p = &params[(uniform ? 0 : k) * PMC_P_COUNT];
    float3 nrm =
        uniform ? sp[k].normal : make_float3(p[PMC_P_NORMAL], p[PMC_P_NORMAL + 1], p[PMC_P_NORMAL + 2]);
    float nl = length(nrm);
    if (nl > 0.0f && isfinite(nl)) sp[k].normal = nrm * (1.0f / nl);
    bsdf[k] = uniform ? bsdf[0] : pmc_surface_to_bsdf(p);
  }
}
