/* pmc_kernels.cl — the wavefront path tracer's device stages.
 *
 * One program holds every kernel; the host's wave loop
 * (gpu/wavefront_renderer.cpp) runs them in this order for each wave of paths:
 *   pmc_camera_rays     : pixel -> camera ray + fresh path state
 *   (host: Embree intersects the ray queue into PmcHit records)
 *   pmc_shade           : hit -> lights the ray met (pmc_lights.h), material
 *                         (bytecode against the cache), emission, light
 *                         sample (shadow ray), BSDF sample (next ray),
 *                         Russian roulette
 *   (host: Embree tests the shadow rays, one occlusion byte each)
 *   pmc_resolve_shadows : add unoccluded light samples to their paths
 *   pmc_film_accumulate : when the wave is done, add path radiance to the film
 *                         (and, with render passes, each path's passes to the
 *                         pass film: pmc_passes.h)
 * Kernels take the index range of their rays as arguments (never a global
 * offset), so one compiled variant per kernel serves every launch. Scene
 * buffers arrive as the PMC_SCENE_BUFFERS list (pmc_scene_args.h) and travel
 * through the device functions as one PmcSceneData.
 *
 * pmc_shade's device functions live in fragments this file includes, in the
 * order they build on each other: shade_hits.cl (a batch's hits up to their
 * material), shade_surface.cl (one hit after its material), samplers8.cl
 * (float8 twins of scalar samplers), light_pick_lanes.cl and
 * next_event_lanes.cl (next-event estimation for a batch's lanes); the
 * material itself is material_network.cl's.
 */
#include "pmc_bsdf.h"
#include "pmc_film.h"
#include "pmc_geometry.h"
#include "pmc_hit_geometry.h"
#include "pmc_interp.h"
#include "pmc_lights.h"
#include "pmc_octahedral.h"
#include "pmc_passes.h"
#include "pmc_raycone.h"
#include "pmc_rng.h"
#include "pmc_scene_args.h"
#include "pmc_types.h"

/* After the headers: it uses their types. */
#include "material_network.cl"

/* Batches whose lanes split into groups of eight run parts of their work in
 * float8, eight lanes at a time (PoCL does not vectorise those loops itself),
 * with the arithmetic written once for float and float8 where a scalar form
 * must agree bit for bit; SEL of those macros is this, OpenCL's select. */
#if PMC_LANES >= 8 && PMC_LANES % 8 == 0
#define PMC_LANES8 1
#else
#define PMC_LANES8 0
#endif
#define PMC_SEL_VECTOR(c, a, b) select((b), (a), (c))

/* A wave holds wave_samples samples of wave_pixels pixels of the window:
 * path i is sample frame->sample + i / wave_pixels of the window's pixel
 * frame->pixel_offset + i % wave_pixels (so the paths of one pixel are
 * wave_pixels apart, and pmc_film_accumulate walks them per pixel). */
static inline uint pmc_path_sample(__constant PmcFrame* frame, uint path) {
  return frame->sample + path / frame->wave_pixels;
}

/* Writes ray `slot` of queue q (a PmcRay, laid out as Embree's RTCRay). */
static inline void pmc_append_ray(__global PmcRay* q, uint slot, float3 o, float3 d, float tfar, uint id) {
  __global PmcRay* r = &q[slot];
  r->org_x = o.x;
  r->org_y = o.y;
  r->org_z = o.z;
  r->tnear = 0.0f;
  r->dir_x = d.x;
  r->dir_y = d.y;
  r->dir_z = d.z;
  r->time = 0.0f;
  r->tfar = tfar;
  r->mask = 0xffffffffu;
  r->id = id;
  r->flags = 0u;
}

/* `active`: with frame->active_list, the window indices of the pixels still
 * sampled (adaptive sampling, gpu/adaptive_sampling.h); the wave's pixels are
 * a run of that list instead of a run of the window. A work-item makes
 * PMC_LANES consecutive paths (the host launches path_count / PMC_LANES
 * items; one each on GPUs): their pixels one at a time (integer divisions),
 * then their pixel jitters in one loop over them (straight-line integer
 * hashing that a CPU compiler vectorises: one path at a time, the Sobol
 * point was 61% of this kernel on the spider), then rays and path states. */
__kernel void pmc_camera_rays(__constant PmcFrame* frame, __global PmcRay* rays, __global PmcPathState* paths,
                              __global PmcPathPasses* passes, __global const uint* active) {
  const uint first = (uint)get_global_id(0) * (uint)PMC_LANES;
  if (first >= frame->path_count) return;
  const int n = (int)min((uint)PMC_LANES, frame->path_count - first);
  uint xs[PMC_LANES], ys[PMC_LANES], pixel[PMC_LANES], sample[PMC_LANES];
  for (int j = 0; j < n; ++j) {
    const uint i = first + (uint)j;
    uint k = frame->pixel_offset + i % frame->wave_pixels; /* index into the window (crop), row by row */
    if (frame->active_list) k = active[k];
    xs[j] = frame->crop_x0 + k % frame->crop_width;
    ys[j] = frame->crop_y0 + k / frame->crop_width;
    pixel[j] =
        ys[j] * (uint)frame->width + xs[j]; /* in the full frame: the RNG key is the same in any window */
    sample[j] = pmc_path_sample(frame, i);
  }
  float jx[PMC_LANES], jy[PMC_LANES]; /* pmc_rand2(sampler, 0, PMC_DIM_PIXEL_X, PMC_DIM_PIXEL_Y) */
  const uint seed = frame->seed;
  if (frame->sampler == PMC_SAMPLER_RANDOM) {
    for (int j = 0; j < n; ++j) {
      const uint key = pmc_path_key(seed, pixel[j], sample[j]);
      jx[j] = pmc_rand_hashed(key, 0u, PMC_DIM_NUMBER(PMC_DIM_PIXEL_X));
      jy[j] = pmc_rand_hashed(key, 0u, PMC_DIM_NUMBER(PMC_DIM_PIXEL_Y));
    }
  } else {
    for (int j = 0; j < n; ++j) {
      const uint key = pmc_sampler(PMC_SAMPLER_SOBOL, seed, pixel[j], sample[j]).key;
      const float2 p = pmc_sobol_set2(key, sample[j], 0u, PMC_DIM_SET(PMC_DIM_PIXEL_X));
      jx[j] = p.x;
      jy[j] = p.y;
    }
  }
  for (int j = 0; j < n; ++j) {
    const uint i = first + (uint)j;
    float sx = ((float)xs[j] + jx[j]) / (float)frame->width * 2.0f - 1.0f;
    float sy = 1.0f - ((float)ys[j] + jy[j]) / (float)frame->height * 2.0f;
    float3 dir = normalize(pmc_load3(frame->cam_forward) + pmc_load3(frame->cam_right) * sx +
                           pmc_load3(frame->cam_up) * sy);
    pmc_append_ray(rays, i, pmc_load3(frame->cam_eye), dir, INFINITY, i);
    __global PmcPathState* p = &paths[i];
    for (int c = 0; c < 3; ++c) {
      p->throughput[c] = 1.0f;
      p->radiance[c] = 0.0f;
    }
    p->cone_width = 0.0f;
    p->cache_cone = 0u; /* bfloat16 zeros: no extra width or spread */
    p->bsdf_pdf = 0.0f;
    for (int c = 0; c < 3; ++c) p->light_normal[c] = 0.0f;
    p->pixel = pixel[j];
    p->depth = 0u;
    p->cache_hits = 0u;
    p->flags = PMC_PATH_SPECULAR; /* camera rays: emitters seen directly get full weight */
    if (frame->passes_on) pmc_passes_start(&passes[i]);
  }
}

#ifndef PMC_CPU_PREFETCH
#define PMC_CPU_PREFETCH 0
#endif
/* Starts loading the cache line that holds `p` without using its value. On
 * CPU devices (PMC_CPU_PREFETCH=1, set by the host) a prefetch instruction,
 * which nothing waits for: the loop that touches a batch's lines finishes at
 * once and the lines arrive while the work after it runs (OpenCL's own
 * prefetch() compiles to nothing on PoCL). Elsewhere a volatile load (the
 * compiler keeps it although its value is unused), which starts the
 * transfer too but holds the core until the line arrives. */
#if PMC_CPU_PREFETCH
#define PMC_TOUCH(p) __builtin_prefetch((__global const void*)(p))
#else
#define PMC_TOUCH(p) ((void)*(__global volatile const uchar*)(p))
#endif

/* Environment maps from this many texels on (512 x 256: about 2.6 MB of
 * texels, CDFs and guide tables, beyond a core's L2 cache) have the reads
 * of a batch's map lookups started for all its lanes at once, before the
 * lane-by-lane code that waits on them (pmc_infinity_seen_lanes,
 * pmc_env_sample_prefetch_lanes); smaller maps stay cached. */
#define PMC_ENV_PREFETCH_MIN_TEXELS 131072
#define PMC_ENV_PREFETCHED(h) \
  (PMC_CPU_PREFETCH && (h)->env == PMC_ENV_MAP && !(h)->env_uniform && \
   (h)->env_width * (h)->env_height >= PMC_ENV_PREFETCH_MIN_TEXELS)
/* Both ends of map texel i (12 bytes, which may straddle two lines). */
#define PMC_ENV_TEXEL_TOUCH(ls, i) (PMC_TOUCH((ls)->env + 3 * (i)), PMC_TOUCH((ls)->env + 3 * (i) + 2))

/* The shade kernel's parts, in the order they build on each other. */
/* clang-format off */
#include "shade_hits.cl"
#include "shade_surface.cl"
#include "samplers8.cl"
#include "light_pick_lanes.cl"
#include "next_event_lanes.cl"
/* clang-format on */

/* The materials of one batch of hits, then the rest of their shading. The
 * host sorts hits by material, so a batch normally holds one material; any
 * mix still works: each run of one material is evaluated together. */
static inline void pmc_shade_batch(__constant PmcFrame* frame, const PmcSceneData* scene, PmcHitPoint* hp,
                                   const PmcBatchNumbers* numbers, int n, __global PmcPathState* paths,
                                   __global volatile ulong* cache_entries, __global PmcPathPasses* passes,
                                   PmcShadeOut* out, uint* cache_counts) {
  PmcMaterialData md = pmc_material_data(scene);
  int done[PMC_LANES];
  for (int k = 0; k < n; ++k) done[k] = !hp[k].surface;
#if PMC_LANES8
  /* every lane's cosine-weighted direction, in case its BSDF sample takes
   * the diffuse lobe: eight lanes cost about what one does */
  float3 cosine_wi[PMC_LANES];
  for (int k = 0; k < n; k += 8) {
    float8 x, y, z;
    pmc_sample_cosine8(vload8(0, numbers->bsdf_u + k), vload8(0, numbers->bsdf_v + k), &x, &y, &z);
    float xs[8], ys[8], zs[8];
    vstore8(x, 0, xs);
    vstore8(y, 0, ys);
    vstore8(z, 0, zs);
    for (int i = 0; i < 8 && k + i < n; ++i) cosine_wi[k + i] = make_float3(xs[i], ys[i], zs[i]);
  }
#endif
  for (int first = 0; first < n; ++first) {
    if (done[first]) continue;
    /* a run: one material's hits, those past their path's last one apart
     * (they need its emission alone, without the cache: pmc_hit_cache_keys) */
    const int material = hp[first].material;
    const uint past_last = hp[first].past_last;
    int lane[PMC_LANES], m = 0;
    for (int k = first; k < n; ++k)
      if (!done[k] && hp[k].material == material && hp[k].past_last == past_last) {
        lane[m++] = k;
        done[k] = 1;
      }
    if (past_last && !(md.materials[material].flags & PMC_MAT_EMITS)) continue; /* they add nothing */
    PmcShadingInputs sp[PMC_LANES];
    PmcCacheContext cache[PMC_LANES];
    const int cached = frame->cache_on && hp[first].cache_points > 0u;
    const int footprint = (md.materials[material].flags & PMC_MAT_FOOTPRINT) != 0u;
    for (int j = 0; j < m; ++j)
      pmc_material_inputs(frame, &hp[lane[j]], footprint, cache_entries, &sp[j], cached ? &cache[j] : 0);
    PmcBsdf bsdf[PMC_LANES];
    pmc_eval_material_lanes(&md, material, sp, m, cached ? cache : 0, bsdf);
    PmcNeeInput nee[PMC_LANES];
    for (int j = 0; j < m; ++j) {
      const int k = lane[j];
      if (cached) {
        paths[hp[k].path].cache_hits += cache[j].hits;
        for (int c = 0; c < PMC_CSTAT_COUNT; ++c) cache_counts[c] += cache[j].counts[c];
      }
      const PmcHitNumbers u = pmc_load_hit_numbers(numbers, k);
#if PMC_LANES8
      const float3* cosine = &cosine_wi[k];
#else
      const float3* cosine = 0;
#endif
      pmc_shade_surface(frame, scene, &hp[k], &bsdf[j], sp[j].normal, &u, cosine, paths, passes, &out[k],
                        &nee[j]);
    }
    pmc_next_event_lanes(frame, scene, nee, lane, m, numbers, out);
  }
}

/* Shades one queue of hits. Each work-item takes one batch of up to
 * PMC_LANES hits from the host's material-sorted order (order[first + b *
 * PMC_LANES + lane], PMC_NO_RAY for padding), in passes over its lanes:
 *   1. prefetch its scene data: the triangle records (corners inline, two
 *      cache lines each) and path states its hits name. A hit's data sits
 *      at random addresses; this short loop has the batch's misses in
 *      flight at once instead of waiting for each in turn;
 *   2. geometry and the cache texel of every hit (pmc_hit_load, then
 *      pmc_hit_geometry_lanes eight lanes at a time, pmc_hit_store);
 *   3. the same prefetch for the cache cells its material will look up
 *      (and, on CPU devices, the next batches' records: pmc_prefetch_ahead);
 *   4. every hit's random numbers for the work after the material, in one
 *      vectorisable loop over the lanes (pmc_draw_hit_numbers);
 *   5. the material for the whole batch (one interpreter pass over all its
 *      lanes), then lights and the next bounce per hit (pmc_shade_batch);
 *   6. queue compaction: each work-item takes a range in local memory for
 *      its rays, one work-item reserves the group's range with one global
 *      atomic, then everyone writes its rays. The cache's event counts are
 *      summed the same way.
 * PMC_LANES is 1 on GPUs (a work-item per hit, as SIMT wants) and larger on
 * CPU devices, where one pass of the interpreter then serves many hits. */
__kernel void pmc_shade(__constant PmcFrame* frame,
                        PMC_SCENE_BUFFERS(PMC_SCENE_PARAM) __global const PmcRay* rays,
                        __global const PmcHit* hits, __global PmcPathState* paths, __global PmcRay* next_rays,
                        __global PmcRay* shadow_rays, __global PmcShadowLoad* shadow_loads,
                        __global PmcCounters* counters, __global volatile ulong* cache_entries,
                        __global volatile ulong* cache_stats, __global const uint* order, uint order_first,
                        uint batch_count, __global PmcPathPasses* passes) {
  PmcSceneData s;
  PMC_SCENE_BUFFERS(PMC_SCENE_INIT)
  s.texture_count = frame->texture_count;
  s.light_set.lights = s.lights;
  s.light_set.tree = s.light_tree;
  s.light_set.env = s.env;
  s.light_set.h = frame->lights;
  const PmcSceneData* scene = &s;
  __local uint group_count[2 + PMC_CSTAT_COUNT];
  __local uint group_base[2];
  uint lid = (uint)get_local_id(0);
  if (lid == 0u)
    for (int c = 0; c < 2 + PMC_CSTAT_COUNT; ++c) group_count[c] = 0u;
  barrier(CLK_LOCAL_MEM_FENCE);

  /* Batches start at `order_first` (an argument, not a global offset: PoCL
   * would compile a second work-group function for non-zero offsets). */
  uint b = (uint)get_global_id(0);
  uint idx[PMC_LANES];
  int n = 0;
  if (b < batch_count)
    for (int k = 0; k < PMC_LANES; ++k) {
      uint i = order[order_first + b * PMC_LANES + (uint)k];
      if (i != PMC_NO_RAY) idx[n++] = i;
    }
#if PMC_CPU_PREFETCH
  for (int k = 0; k < n; ++k) { /* the hit and ray records first: the next loop reads them */
    PMC_TOUCH(&hits[idx[k]]);
    PMC_TOUCH(&rays[idx[k]].org_x); /* a ray's first and last word (48 bytes) */
    PMC_TOUCH(&rays[idx[k]].flags);
  }
  pmc_prefetch_ahead(scene, rays, hits, paths, order, order_first, b, batch_count);
#endif
  for (int k = 0; k < n; ++k) pmc_touch_triangle(scene, hits, rays, paths, idx[k]);
  PmcHitPoint hp[PMC_LANES];
  PmcHitLanes lanes;
  int surfaces = 0;
  for (int k = 0; k < n; ++k) {
    pmc_hit_load(frame, scene, rays, hits, paths, idx[k], &hp[k], &lanes, k);
    surfaces += hp[k].surface;
  }
#if PMC_LANES8
  for (int k = n; k < ((n + 7) & ~7); ++k) pmc_hit_lane_clear(&lanes, k); /* the last group's spare lanes */
#endif
  /* A batch of escaped rays (the host's sort gives them batches of their
   * own) only adds the lights they met: the surface passes are skipped. */
  if (surfaces) pmc_hit_geometry_lanes(&lanes, n);
  pmc_lights_seen_lanes(frame, scene, paths, hp, &lanes, n);

  PmcShadeOut out[PMC_LANES];
  for (int k = 0; k < n; ++k) out[k].next = out[k].shadow = 0;
  uint counts[PMC_CSTAT_COUNT];
  for (int c = 0; c < PMC_CSTAT_COUNT; ++c) counts[c] = 0u;
  if (surfaces) {
    for (int k = 0; k < n; ++k) pmc_hit_store(&lanes, k, &hp[k]);
    pmc_ray_cone_lanes(&lanes, n, hp);
    if (frame->cache_on) {
      float jitter_u[PMC_LANES], jitter_v[PMC_LANES];
      pmc_draw_cache_jitter(frame, hp, n, jitter_u, jitter_v);
      int level_floor[PMC_LANES];
      for (int k = 0; k < n; ++k)
        level_floor[k] =
            pmc_hit_cache_keys(frame, scene, paths, make_float2(jitter_u[k], jitter_v[k]), &hp[k]);
      pmc_cache_texels_lanes(frame, hp, level_floor, n);
      const PmcCacheTable table = pmc_frame_cache_table(frame, cache_entries);
      for (int k = 0; k < n; ++k)
        if (hp[k].surface && hp[k].cache_points > 0u) {
          uint points = min(hp[k].cache_points, 8u);
          for (uint p = 0u; p < points; ++p) { /* cell of the p-th point (pmc_cache_key_at) */
            const PmcCacheTexel* t = ((hp[k].cache_position_mask >> p) & 1u) ? &hp[k].cell : &hp[k].texel;
            if (!t->bypass)
              PMC_TOUCH(&cache_entries[pmc_cache_cell(&table, t->base + (ulong)p) * (ulong)table.ways]);
          }
        }
    }
    PmcBatchNumbers numbers;
    pmc_draw_hit_numbers(frame, hp, n, &numbers);
    pmc_shade_batch(frame, scene, hp, &numbers, n, paths, cache_entries, passes, out, counts);
  }

  uint n_next = 0u, n_shadow = 0u;
  for (int k = 0; k < n; ++k) {
    n_next += out[k].next ? 1u : 0u;
    n_shadow += out[k].shadow ? 1u : 0u;
  }
  uint next_slot = n_next ? atomic_add(&group_count[0], n_next) : 0u;
  uint shadow_slot = n_shadow ? atomic_add(&group_count[1], n_shadow) : 0u;
  if (frame->cache_on)
    for (int c = 0; c < PMC_CSTAT_COUNT; ++c)
      if (counts[c]) atomic_add(&group_count[2 + c], counts[c]);
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid == 0u) {
    group_base[0] = group_count[0] ? atomic_add(&counters->next_rays, group_count[0]) : 0u;
    group_base[1] = group_count[1] ? atomic_add(&counters->shadow_rays, group_count[1]) : 0u;
    if (frame->cache_on)
      for (int c = 0; c < PMC_CSTAT_COUNT; ++c)
        if (group_count[2 + c]) atom_add(&cache_stats[c], (ulong)group_count[2 + c]);
  }
  barrier(CLK_LOCAL_MEM_FENCE);

  next_slot += group_base[0];
  shadow_slot += group_base[1];
  for (int k = 0; k < n; ++k) {
    if (out[k].next)
      pmc_append_ray(next_rays, next_slot++, out[k].next_org, out[k].next_dir, INFINITY, hp[k].path);
    if (out[k].shadow) {
      uint slot = shadow_slot++;
      pmc_append_ray(shadow_rays, slot, out[k].shadow_org, out[k].shadow_dir, out[k].shadow_tfar, hp[k].path);
      __global PmcShadowLoad* sl = &shadow_loads[slot];
      sl->rgb[0] = out[k].shadow_rgb.x;
      sl->rgb[1] = out[k].shadow_rgb.y;
      sl->rgb[2] = out[k].shadow_rgb.z;
      sl->path = hp[k].path;
    }
  }
}

__kernel void pmc_resolve_shadows(__global const PmcShadowLoad* loads, __global const uchar* occluded,
                                  __global PmcPathState* paths, uint first, uint end) {
  uint i = first + (uint)get_global_id(0);
  if (i >= end || occluded[i]) return;
  __global PmcPathState* p = &paths[loads[i].path];
  p->radiance[0] += loads[i].rgb[0];
  p->radiance[1] += loads[i].rgb[1];
  p->radiance[2] += loads[i].rgb[2];
}

/* One work-item per pixel of the wave: it adds that pixel's wave_samples
 * paths (pmc_path_sample's layout), so no two work-items touch one pixel.
 * Each finished path adds its radiance as exact fixed-point sums (pmc_film.h:
 * the film does not depend on the order or the split of the samples), or a
 * bad sample, and its cache hits. */
__kernel void pmc_film_accumulate(__constant PmcFrame* frame, __global const PmcPathState* paths,
                                  __global PmcFilmPixel* film, __global const PmcPathPasses* passes,
                                  __global PmcPassPixel* pass_film) {
  uint i = get_global_id(0);
  if (i >= frame->wave_pixels || frame->path_count == 0u) return;
  /* the film holds the window only (crop) */
  const uint pixel = paths[i].pixel;
  uint x = pixel % (uint)frame->width - frame->crop_x0;
  uint y = pixel / (uint)frame->width - frame->crop_y0;
  const uint at = y * frame->crop_width + x;
  /* The pixel's sums stay in registers over its samples of the wave, added
   * in the samples' order as one at a time would (the same bits). */
  __global PmcFilmPixel* px = &film[at];
  pmc_u64 lo[3], hi[3];
  for (int c = 0; c < 3; ++c) {
    lo[c] = (pmc_u64)px->sum[4 * c] | ((pmc_u64)px->sum[4 * c + 1] << 32);
    hi[c] = (pmc_u64)px->sum[4 * c + 2] | ((pmc_u64)px->sum[4 * c + 3] << 32);
  }
#if PMC_CPU_PREFETCH
  /* On CPU devices a work-group's items run one after another on one
   * thread: start the loads of the item 16 ahead (its path states, one line
   * each, and about its film pixel), which perf found this loop waiting on
   * (a fifth of the kernel's samples on a path state's first read). */
  if (i + 16u < frame->wave_pixels)
    for (uint s = 0u; s < frame->wave_samples; ++s) PMC_TOUCH(&paths[s * frame->wave_pixels + i + 16u]);
  PMC_TOUCH(&film[at + 16u]); /* a prefetch past the film's end reads nothing */
#endif
  pmc_u32 cache_hits = px->cache_hits, bad = px->bad_samples;
  float grey_sq = px->grey_sq_sum;
  for (uint s = 0u; s < frame->wave_samples; ++s) {
    const uint path = s * frame->wave_pixels + i;
    __global const PmcPathState* p = &paths[path];
    cache_hits += p->cache_hits;
    pmc_u64 vl[3], vh[3];
    if (pmc_fixed2_of_float(p->radiance[0], &vl[0], &vh[0]) &&
        pmc_fixed2_of_float(p->radiance[1], &vl[1], &vh[1]) &&
        pmc_fixed2_of_float(p->radiance[2], &vl[2], &vh[2])) {
      const float grey = (p->radiance[0] + p->radiance[1] + p->radiance[2]) * (1.0f / 3.0f);
      grey_sq += grey * grey;
      for (int c = 0; c < 3; ++c) pmc_fixed2_add(&lo[c], &hi[c], vl[c], vh[c]);
    } else {
      bad += 1u;
    }
    if (frame->passes_on) pmc_film_add_passes(&pass_film[at], &passes[path]);
  }
  for (int c = 0; c < 3; ++c) {
    px->sum[4 * c] = (pmc_u32)lo[c];
    px->sum[4 * c + 1] = (pmc_u32)(lo[c] >> 32);
    px->sum[4 * c + 2] = (pmc_u32)hi[c];
    px->sum[4 * c + 3] = (pmc_u32)(hi[c] >> 32);
  }
  px->cache_hits = cache_hits;
  px->bad_samples = bad;
  px->grey_sq_sum = grey_sq;
}

/* Zeroes words [0, count) of a buffer: each work-group a contiguous block,
 * its work-items interleaved within the block (consecutive items write
 * consecutive words, which GPUs coalesce; on CPU devices, where a work-item
 * runs its whole loop before the next starts, a block spans a few pages, where
 * a stride of the whole grid made every item touch every page of a 128 MiB
 * table: 0.3 s of CPU). The film and the cache table are cleared here, on the
 * device: from the host they took a copy of zeros as large as the table. */
__kernel void pmc_zero_words(__global uint* words, ulong count) {
  const ulong groups = (ulong)get_num_groups(0), items = (ulong)get_local_size(0);
  const ulong block = (count + groups - 1ul) / groups;
  const ulong begin = (ulong)get_group_id(0) * block, end = min(count, begin + block);
  for (ulong i = begin + (ulong)get_local_id(0); i < end; i += items) words[i] = 0u;
}
