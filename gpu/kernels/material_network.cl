/* material_network.cl — the one entry point that turns a hit into a BSDF.
 *
 * pmc_eval_material() runs the material's bytecode (core/abi/pmc_interp.h)
 * from its entry offset in the shared program buffer, starting from the
 * standard_surface defaults, and converts the resulting surface parameters
 * into a BSDF. A normal written by the program (normal maps) replaces the
 * shading normal. `cache` is the progressive material cache (null when the
 * cache is off: those programs contain no cache instructions). Every material of every scene goes through this function:
 * there are no per-material kernels.
 */

typedef struct PmcMaterialData {
  __global const pmc_u32* code;
  __global const PmcMaterialInfo* materials;
  PmcTextureSet textures;
} PmcMaterialData;

static inline PmcBsdf pmc_eval_material(const PmcMaterialData* md, int material, PmcShadingInputs* sp,
                                        PmcCacheContext* cache) {
  float stack[PMC_STACK_SIZE];
  float params[PMC_P_COUNT];
  pmc_surface_defaults(params, sp->normal);
  pmc_interp_run(md->code, md->materials[material].entry, sp, &md->textures, stack, params, cache);
  float3 n = make_float3(params[PMC_P_NORMAL], params[PMC_P_NORMAL + 1], params[PMC_P_NORMAL + 2]);
  float nl = length(n);
  if (nl > 0.0f && isfinite(nl)) sp->normal = n * (1.0f / nl);
  return pmc_surface_to_bsdf(params);
}

/* Emitted radiance of a material, for light sampling (its constant part). */
static inline float3 pmc_material_emission(const PmcMaterialData* md, int material) {
  __global const PmcMaterialInfo* m = &md->materials[material];
  return make_float3(m->emission[0], m->emission[1], m->emission[2]);
}
