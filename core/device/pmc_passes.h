/* pmc_passes.h — render passes (AOVs): what a path leaves for them, and their exact film.
 *
 * A path records, in its PmcPathPasses slot:
 *   - at its camera ray's hit: the world position, the distance from the
 *     camera along the ray (Z: Euclidean distance from the eye, not the
 *     depth along the view axis) and the material;
 *   - at its first hit whose BSDF is not specular-only (pmc_lobes_specular_only:
 *     mirrors and clear glass are looked through, as OIDN wants its albedo):
 *     the BSDF's directional albedo estimate at wo (pmc_lobes_albedo) and the
 *     world-space shading normal. A path that escapes or ends before such a
 *     hit leaves albedo and normal 0; the last hit a path may make records
 *     itself even when specular.
 * pmc_film_add_passes adds a finished path to its pixel's PmcPassPixel with
 * the beauty's exact fixed-point sums (pmc_film.h), so pass films of sample
 * ranges merge bit for bit like the beauty's; the material is a minimum
 * (kept as the maximum of its complement, so a zeroed film holds none),
 * which merges exactly too. core/film_sum.h resolves the sums on the host.
 */
#ifndef PMC_PASSES_H
#define PMC_PASSES_H

#include "../abi/pmc_types.h"
#include "pmc_bsdf.h"
#include "pmc_film.h"

/* A fresh path: nothing recorded. */
PMC_FN void pmc_passes_start(PMC_GLOBAL PmcPathPasses* p) {
  for (int c = 0; c < 3; ++c) p->albedo[c] = p->normal[c] = p->position[c] = 0.0f;
  p->depth = 0.0f;
  p->material = PMC_PASS_NO_MATERIAL;
  p->state = 0u;
}

/* One surface hit of a path: `hits_before` surface hits came before it (0:
 * the camera ray's), at distance `t` along a unit-length ray; `lobes` the
 * BSDF prepared for `wo` (local), `ns` the world shading normal; `last`: the
 * path may not continue beyond it. */
PMC_FN void pmc_passes_record(PMC_GLOBAL PmcPathPasses* p, uint hits_before, float3 pos, float t,
                              int material, const PmcLobes* lobes, float3 wo, float3 ns, int last) {
  if (hits_before == 0u) {
    p->position[0] = pos.x;
    p->position[1] = pos.y;
    p->position[2] = pos.z;
    p->depth = t;
    p->material = (pmc_u32)material;
  }
  if (p->state == PMC_PASS_FOUND || (pmc_lobes_specular_only(lobes) && !last)) return;
  const float3 a = pmc_lobes_albedo(lobes, wo);
  p->albedo[0] = a.x;
  p->albedo[1] = a.y;
  p->albedo[2] = a.z;
  p->normal[0] = ns.x;
  p->normal[1] = ns.y;
  p->normal[2] = ns.z;
  p->state = PMC_PASS_FOUND;
}

/* Adds a finished path's passes to its pixel (exact; a value that is not
 * finite or too large for the fixed point adds 0). */
PMC_FN void pmc_film_add_passes(PMC_GLOBAL PmcPassPixel* px, PMC_GLOBAL const PmcPathPasses* p) {
  float v[PMC_PASS_CHANNELS];
  for (int c = 0; c < 3; ++c) {
    v[PMC_PASS_ALBEDO + c] = p->albedo[c];
    v[PMC_PASS_NORMAL + c] = p->normal[c];
    v[PMC_PASS_POSITION + c] = p->position[c];
  }
  v[PMC_PASS_DEPTH] = p->depth;
  for (uint c = 0; c < PMC_PASS_CHANNELS; ++c) {
    pmc_u32 x[PMC_FIXED_WORDS], acc[PMC_FIXED_WORDS];
    if (!pmc_fixed_of_float(v[c], x)) continue;
    for (uint w = 0; w < PMC_FIXED_WORDS; ++w) acc[w] = px->sum[4u * c + w];
    pmc_fixed_add(acc, x);
    for (uint w = 0; w < PMC_FIXED_WORDS; ++w) px->sum[4u * c + w] = acc[w];
  }
  if (p->material != PMC_PASS_NO_MATERIAL) {
    px->hit_samples += 1u;
    const pmc_u32 inv = ~p->material;
    if (inv > px->material_inv) px->material_inv = inv;
  }
}

#endif /* PMC_PASSES_H */
