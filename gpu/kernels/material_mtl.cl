/* material_mtl.cl — the one entry point that turns a hit into a BSDF.
 *
 * pmc_eval_material() is the single function the shade kernel calls to learn
 * what a surface looks like. Today it reads the MTL model (Kd/map_Kd, Ks/Ns,
 * Ke); the material-network interpreter replaces its body, not its callers.
 */

typedef struct PmcShadingPoint {
  float3 position;
  float3 normal; /* shading normal, facing the incoming ray */
  float2 uv;
  int material;
} PmcShadingPoint;

typedef struct PmcMaterialData {
  __global const PmcMtlMaterial* materials;
  __global const PmcTexture* textures;
  __global const uchar4* texels;
  __constant float* srgb_lut;
} PmcMaterialData;

static inline PmcBsdf pmc_eval_material(const PmcMaterialData* md, const PmcShadingPoint* sp) {
  __global const PmcMtlMaterial* m = &md->materials[sp->material];
  PmcBsdf b;
  b.diffuse = make_float3(m->kd[0], m->kd[1], m->kd[2]);
  if (m->kd_tex >= 0) {
    float4 t = pmc_texture_level(&md->textures[m->kd_tex], md->texels, md->srgb_lut, sp->uv, 0);
    b.diffuse *= t.xyz;
  }
  b.specular = make_float3(m->ks[0], m->ks[1], m->ks[2]);
  b.alpha = m->roughness;
  b.emission = make_float3(m->ke[0], m->ke[1], m->ke[2]);
  return b;
}

/* Emitted radiance of a material (for light sampling). */
static inline float3 pmc_material_emission(const PmcMaterialData* md, int material) {
  __global const PmcMtlMaterial* m = &md->materials[material];
  return make_float3(m->ke[0], m->ke[1], m->ke[2]);
}
