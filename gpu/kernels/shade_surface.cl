/* shade_surface.cl — one hit after its material (part of pmc_kernels.cl).
 *
 * The shading frame, emission with MIS, the BSDF sample and Russian
 * roulette of one hit (pmc_shade_surface), which leaves what next-event
 * estimation needs in a PmcNeeInput; the prefetches of a batch's scene data
 * and the batch's random numbers drawn in one loop over its lanes.
 */

/* The local shading frame: the uv tangent (turned by `rotation` turns) for
 * anisotropic lobes, else any frame about ns. */
static inline void pmc_shading_frame(float3 ns, float3 tangent, const PmcBsdf* bsdf, float3* t, float3* b) {
  if (bsdf->ax != bsdf->ay) {
    float3 tt = tangent - ns * dot(ns, tangent);
    const float tl = length(tt);
    if (tl > 1e-12f && isfinite(tl)) {
      tt = tt * (1.0f / tl);
      float3 bb = cross(ns, tt);
      if (bsdf->rotation != 0.0f) {
        float sn, cs;
        pmc_sincos_turns(bsdf->rotation, &sn, &cs);
        tt = tt * cs + bb * sn;
        bb = cross(ns, tt);
      }
      *t = tt;
      *b = bb;
      return;
    }
  }
  pmc_basis(ns, t, b);
}

/* What next-event estimation needs of one hit (pmc_shade_surface fills it). */
typedef struct PmcNeeInput {
  PmcLobes lobes;             /* the BSDF prepared for wo */
  float3 t, b, ns, ng, wo;    /* the shading frame, the geometric normal, wo in the frame */
  float3 origin, pick_normal; /* where the shadow ray starts, the normal the pick uses */
  float3 throughput;          /* the path's, before this hit's BSDF sample */
  int active;                 /* the BSDF scatters */
  float clamp;                /* the light sample's largest radiance (pmc_clamp_light; 0: none) */
} PmcNeeInput;

/* After the material: emission, what next-event estimation needs (`nee`:
 * pmc_next_event_lanes takes the light sample) and the BSDF sample for the
 * next bounce of one hit. `shading_normal` is the material's normal
 * (normal maps) or the hit's.
 * Glass: light samples are taken on the side wo is on only (a shadow ray is
 * stopped by every surface, glass included, so a light behind glass is
 * reached by BSDF samples alone); a BSDF sample that crosses the surface is
 * therefore marked PMC_PATH_SPECULAR, and the emitter it meets takes full
 * weight. A ray that leaves a glass volume (a back-face hit on a material
 * with absorption) has its throughput multiplied by exp(-absorption t). */
static inline void pmc_shade_surface(__constant PmcFrame* frame, const PmcSceneData* scene,
                                     const PmcHitPoint* hp, const PmcBsdf* bsdf_in, float3 shading_normal,
                                     const PmcHitNumbers* u, const float3* cosine_wi,
                                     __global PmcPathState* paths, __global PmcPathPasses* passes,
                                     PmcShadeOut* out, PmcNeeInput* nee) {
  __global PmcPathState* path = &paths[hp->path];
  float3 throughput = pmc_load3(path->throughput);
  float3 radiance = pmc_load3(path->radiance);
  uint depth = path->depth;
  float3 dir = hp->dir, pos = hp->pos, ng = hp->ng, ns = hp->ns;
  float3 wo_world = -dir;
  const PmcBsdf* bsdf = bsdf_in;
  if (dot(shading_normal, wo_world) > 0.0f) ns = shading_normal; /* normal maps, unless they face away */
  if (!hp->front && !bsdf->thin && pmc_max3(bsdf->absorption) > 0.0f) {
    const float3 a = bsdf->absorption * (-hp->t);
    throughput *= make_float3(exp(a.x), exp(a.y), exp(a.z));
  }

  /* Emission reached by the path: MIS against light sampling. */
  if (pmc_max3(bsdf->emission) > 0.0f) {
    float w = 1.0f;
    if (!(path->flags & PMC_PATH_SPECULAR)) {
      /* the probability that the previous vertex (the ray's origin) picked this triangle */
      float pmf = pmc_light_pick_pmf(&scene->light_set, hp->org, pmc_load3(path->light_normal),
                                     scene->tri_light[hp->prim]);
      float light_pdf = pmc_area_light_pdf(pmf, hp->t, 0.5f * hp->area2, dot(ng, dir));
      w = pmc_mis_power(path->bsdf_pdf, light_pdf);
    }
    radiance = pmc_add_light(radiance, throughput * bsdf->emission, w,
                             pmc_clamp_limit(frame, depth > 0u ? depth - 1u : 0u));
  }
  /* Past the last hit (max_depth): the BSDF sample of the last hit met this
   * one only to weigh the emission it sees against that hit's light sample
   * (as pbrt-v4 ends a path); nothing more is sampled here. */
  if (path->flags & PMC_PATH_EMISSION_ONLY) {
    nee->active = 0;
    path->radiance[0] = radiance.x;
    path->radiance[1] = radiance.y;
    path->radiance[2] = radiance.z;
    return;
  }

  depth += 1u;
  float3 t, b;
  pmc_shading_frame(ns, hp->tangent, bsdf, &t, &b);
  float3 wo = pmc_to_local(wo_world, t, b, ns);
  const PmcLobes lobes = pmc_bsdf_prepare(bsdf, wo, hp->front);
  int has_lobes = pmc_lobes_any(&lobes);
  if (frame->passes_on)
    pmc_passes_record(&passes[hp->path], depth - 1u, pos, hp->t, hp->material, &lobes, wo, ns,
                      (int)depth >= frame->max_depth);

  /* Next-event estimation: one light, picked at `origin` with the shading
   * normal as the path stores it (pmc_lights.h), so that the next vertex can
   * recompute the pick's probability from its ray's origin and that normal;
   * taken for the batch's lanes together after this (pmc_next_event_lanes).
   * Always weighed by MIS against the BSDF sample: at the last hit that
   * sample is traced for the emission it meets alone (PMC_PATH_EMISSION_ONLY),
   * so a light sample close to an emitter never takes full weight there. */
  float3 origin = pmc_offset_ray(pos, ng, hp->hit_scale);
  nee->active = has_lobes;
  nee->origin = origin;
  nee->pick_normal = ns;
  nee->ng = ng;
  nee->t = t;
  nee->b = b;
  nee->ns = ns;
  nee->wo = wo;
  nee->throughput = throughput;
  nee->clamp = pmc_clamp_limit(frame, depth - 1u);
  nee->lobes = lobes;

  const int last = (int)depth >= frame->max_depth;
  int alive = has_lobes;
  if (alive) {
    float3 wi, weight;
    float pdf;
    alive = pmc_bsdf_sample_from(&lobes, wo, u->lobe, u->bsdf_u, u->bsdf_v, cosine_wi, &wi, &pdf, &weight);
    float3 wi_world = make_float3(0.0f, 0.0f, 1.0f);
    if (alive) {
      wi_world = pmc_to_world(wi, t, b, ns);
      /* the geometric side must agree with the lobe's (shading normals) */
      alive = (dot(wi_world, ng) > 0.0f) == (wi.z > 0.0f);
    }
    if (alive) {
      throughput *= weight;
      if (depth >= 3u) {
        float q = fmin(0.95f, pmc_max3(throughput));
        if (u->rr >= q)
          alive = 0;
        else
          throughput *= 1.0f / q;
      }
    }
    if (alive && isfinite(pmc_max3(throughput))) {
      const int crossed = wi.z < 0.0f;
      out->next = 1;
      out->next_org = crossed ? pmc_offset_ray(pos, -ng, hp->hit_scale) : origin; /* light samples' */
      out->next_dir = wi_world;
      path->bsdf_pdf = pdf;
      path->light_normal[0] = ns.x;
      path->light_normal[1] = ns.y;
      path->light_normal[2] = ns.z;
      path->flags = (crossed ? PMC_PATH_SPECULAR : 0u) | (last ? PMC_PATH_EMISSION_ONLY : 0u);
      path->cone_width = hp->cone_width;
      if (frame->cache_lobe_spread > 0.0f)
        path->cache_cone = pmc_pack_cone(
            hp->cache_extra,
            fmin(pmc_cone_spread(path->cache_cone) + pmc_lobe_spread(pdf, frame->cache_lobe_spread), 1e30f));
    }
  }
  path->depth = depth;
  path->throughput[0] = throughput.x;
  path->throughput[1] = throughput.y;
  path->throughput[2] = throughput.z;
  path->radiance[0] = radiance.x;
  path->radiance[1] = radiance.y;
  path->radiance[2] = radiance.z;
}

/* Starts the loads of a hit's triangle record (both of its cache lines) and
 * path state (the hit and ray records, which name them, should be on their
 * way already). */
static inline void pmc_touch_triangle(const PmcSceneData* scene, __global const PmcHit* hits,
                                      __global const PmcRay* rays, __global PmcPathState* paths, uint i) {
  int prim = hits[i].prim;
  if (prim >= 0) {
    __global const float* r = (__global const float*)&scene->triangles[prim];
    PMC_TOUCH(r); /* its two cache lines */
    PMC_TOUCH(r + 16);
  }
  /* a path state: one cache line (64 bytes, in a buffer aligned to them) */
  PMC_TOUCH(&paths[rays[i].id].throughput[0]);
}

/* The numbers of a batch's hits (PmcHitNumbers), one array per dimension. */
typedef struct PmcBatchNumbers {
  float light_pick[PMC_LANES], light_u[PMC_LANES], light_v[PMC_LANES], lobe[PMC_LANES];
  float bsdf_u[PMC_LANES], bsdf_v[PMC_LANES], rr[PMC_LANES];
} PmcBatchNumbers;

static inline void pmc_store_hit_numbers(PmcBatchNumbers* u, int k, PmcHitNumbers h) {
  u->light_pick[k] = h.light_pick;
  u->light_u[k] = h.light_u;
  u->light_v[k] = h.light_v;
  u->lobe[k] = h.lobe;
  u->bsdf_u[k] = h.bsdf_u;
  u->bsdf_v[k] = h.bsdf_v;
  u->rr[k] = h.rr;
}

static inline PmcHitNumbers pmc_load_hit_numbers(const PmcBatchNumbers* u, int k) {
  PmcHitNumbers h;
  h.light_pick = u->light_pick[k];
  h.light_u = u->light_u[k];
  h.light_v = u->light_v[k];
  h.lobe = u->lobe[k];
  h.bsdf_u = u->bsdf_u[k];
  h.bsdf_v = u->bsdf_v[k];
  h.rr = u->rr[k];
  return h;
}

/* Every hit's numbers of its bounce (pmc_rng.h's PmcHitNumbers; escaped
 * rays' lanes draw too, unread), in one loop over the lanes for the frame's
 * sampler: the loops are straight-line integer hashing over arrays, which
 * PoCL's compiler vectorises across the lanes, where drawing each number
 * in the per-hit code ran it one lane at a time. */
static inline void pmc_draw_hit_numbers(__constant PmcFrame* frame, const PmcHitPoint* hp, int n,
                                        PmcBatchNumbers* u) {
  uint pixel[PMC_LANES], sample[PMC_LANES], bounce[PMC_LANES];
  pmc_hit_sample_ids(frame, hp, n, pixel, sample, bounce);
  const uint seed = frame->seed;
  if (frame->sampler == PMC_SAMPLER_RANDOM) {
    for (int k = 0; k < n; ++k)
      pmc_store_hit_numbers(u, k, pmc_hit_numbers_random(pmc_path_key(seed, pixel[k], sample[k]), bounce[k]));
  } else {
    for (int k = 0; k < n; ++k) {
      const uint key = pmc_sampler(PMC_SAMPLER_SOBOL, seed, pixel[k], sample[k]).key;
      pmc_store_hit_numbers(u, k, pmc_hit_numbers_sobol(key, sample[k], bounce[k]));
    }
  }
}

#if PMC_CPU_PREFETCH
/* On CPU devices a thread runs consecutive work-groups, so batch b's
 * work-item starts the loads of the batches after it, in two steps a batch
 * apart: the hit and ray records of batch b + 2, and the triangle records
 * and path states of batch b + 1, whose hits and rays it can read without
 * waiting since batch b - 1 prefetched them. The loads a batch's own
 * prefetch starts (pmc_shade) arrive too late for its first hits: their
 * path states cost about a sixth of the kernel's own time in waits. */
static inline void pmc_prefetch_ahead(const PmcSceneData* scene, __global const PmcRay* rays,
                                      __global const PmcHit* hits, __global PmcPathState* paths,
                                      __global const uint* order, uint order_first, uint b,
                                      uint batch_count) {
  if (b + 2u < batch_count)
    for (uint k = 0u; k < (uint)PMC_LANES; ++k) {
      const uint i = order[order_first + (b + 2u) * PMC_LANES + k];
      if (i == PMC_NO_RAY) continue;
      PMC_TOUCH(&hits[i]);
      PMC_TOUCH(&rays[i].org_x);
      PMC_TOUCH(&rays[i].flags);
    }
  if (b + 1u < batch_count)
    for (uint k = 0u; k < (uint)PMC_LANES; ++k) {
      const uint i = order[order_first + (b + 1u) * PMC_LANES + k];
      if (i != PMC_NO_RAY) pmc_touch_triangle(scene, hits, rays, paths, i);
    }
}
#endif
