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

static inline float3 pmc_corner(__global const float* a, int k) {
  return make_float3(a[3 * k], a[3 * k + 1], a[3 * k + 2]);
}

/* The geometry of one ray's hit: what the material and pmc_shade_surface
 * need (computed for every hit of a batch before any material runs). */
typedef struct PmcHitPoint {
  float3 org, dir, pos, ng, ns, tangent; /* org: the ray's (the vertex that picked its light) */
  float2 uv, g1, g2;                     /* texture coordinates and their ray-cone gradients */
  float t, hit_scale, area2, cone_width;
  float cache_extra; /* the cache cone's width beyond cone_width at the hit (pmc_lobe_spread) */
  int prim, material;
  uint path;
  int surface;              /* 0: the ray escaped */
  int front;                /* the ray arrived on the side the surface's normals point to */
  float4 cache_jitter;      /* cache_filter bilinear: texel selection offsets (x, y); cells take
                               them in the tangent plane (pmc_cache_plane_jitter) */
  PmcCacheTexel texel;      /* ready when the material has uv-keyed cache points */
  PmcCacheTexel cell;       /* ready when it has position-keyed ones */
  uint cache_points;        /* how many (the cells to prefetch) */
  uint cache_position_mask; /* bit p: the p-th point is keyed on position */
  uint depth;               /* surface hits of the path before this one (0: camera ray) */
  uint past_last;           /* the hit is past its path's last one (PMC_PATH_EMISSION_ONLY) */
  uint pixel;               /* the path's pixel (its numbers' key, the lookup trace's) */
  int ellipse;              /* textures filter over the footprint's ellipse (pmc_texture_ellipse_needed) */
} PmcHitPoint;

/* The material cache's table as this frame sized it. */
static inline PmcCacheTable pmc_frame_cache_table(__constant PmcFrame* frame,
                                                  __global volatile ulong* entries) {
  PmcCacheTable t;
  t.entries = entries;
  t.cells = ((ulong)frame->cache_cells_hi << 32) | (ulong)frame->cache_cells_lo;
  t.ways = frame->cache_ways;
  t.policy = frame->cache_policy;
  return t;
}

/* What shading one ray asks the queues for. */
typedef struct PmcShadeOut {
  float3 next_org, next_dir;                 /* the continuation ray, if `next` */
  float3 shadow_org, shadow_dir, shadow_rgb; /* the light sample, if `shadow` */
  float shadow_tfar;
  int next, shadow;
} PmcShadeOut;

/* Light sample clamping (the clamp_direct and clamp_indirect settings): the
 * largest radiance one light sample may add to a path, chosen by the hit that
 * receives the light (`receiver`: 0 is the camera ray's hit, which also stands
 * for the camera when it sees an emitter itself; 1 and up: later hits). 0: no
 * limit. */
static inline float pmc_clamp_limit(__constant PmcFrame* frame, uint receiver) {
  return receiver == 0u ? frame->clamp_direct : frame->clamp_indirect;
}

/* Contribution c scaled so that its largest channel is at most `limit` (its
 * hue kept); c itself when limit is 0 or c is within it (or not finite: the
 * film counts that sample as bad). */
static inline float3 pmc_clamp_light(float3 c, float limit) {
  const float m = pmc_max3(c);
  return limit > 0.0f && m > limit ? c * (limit / m) : c;
}

/* radiance + a * b, the contribution a * b clamped to `limit`; unclamped, the
 * very expression of an unclamped renderer (which the compiler may fuse into
 * one multiply-add), so that images without clamping keep their bits. */
static inline float3 pmc_add_light(float3 radiance, float3 a, float3 b, float limit) {
  const float3 c = a * b;
  return limit > 0.0f && pmc_max3(c) > limit ? radiance + c * (limit / pmc_max3(c)) : radiance + a * b;
}

/* Pass 1a: what a ray's hit needs (its geometry: pmc_hit_geometry_lanes; the
 * lights it met: pmc_lights_seen_lanes), into lane k of `L` (an escaped
 * ray's lane holds its ray; pmc_hit_geometry_lanes zeroes the rest). */
static inline void pmc_hit_load(__constant PmcFrame* frame, const PmcSceneData* scene,
                                __global const PmcRay* rays, __global const PmcHit* hits,
                                __global PmcPathState* paths, uint i, PmcHitPoint* hp, PmcHitLanes* L,
                                int k) {
  PmcRay ray = rays[i];
  PmcHit hit = hits[i];
  hp->path = ray.id;
  __global PmcPathState* path = &paths[ray.id];
  hp->depth = path->depth;
  hp->past_last = (path->flags & PMC_PATH_EMISSION_ONLY) != 0u;
  hp->pixel = path->pixel;
  float3 dir = make_float3(ray.dir_x, ray.dir_y, ray.dir_z);
  hp->org = make_float3(ray.org_x, ray.org_y, ray.org_z);
  hp->surface = hit.prim >= 0;
  L->dx[k] = dir.x, L->dy[k] = dir.y, L->dz[k] = dir.z;
  L->ox[k] = ray.org_x, L->oy[k] = ray.org_y, L->oz[k] = ray.org_z, L->t_hit[k] = hit.t;
  L->escaped[k] = hp->surface ? 0 : -1;
  if (!hp->surface) return;
  __global const PmcTriangleRecord* tri = &scene->triangles[hit.prim];
  const float3 p0 = pmc_corner(tri->p, 0), p1 = pmc_corner(tri->p, 1), p2 = pmc_corner(tri->p, 2);
  L->b1[k] = hit.u, L->b2[k] = hit.v;
  L->p0x[k] = p0.x, L->p0y[k] = p0.y, L->p0z[k] = p0.z, L->p1x[k] = p1.x, L->p1y[k] = p1.y;
  L->p1z[k] = p1.z, L->p2x[k] = p2.x, L->p2y[k] = p2.y, L->p2z[k] = p2.z;
  const int normals = (tri->flags & PMC_TRI_NORMALS) != 0u;
  L->normals[k] = normals ? -1 : 0;
  L->n0x[k] = normals ? tri->n[0] : 0.0f, L->n0y[k] = normals ? tri->n[1] : 0.0f;
  L->n0z[k] = normals ? tri->n[2] : 0.0f, L->n1x[k] = normals ? tri->n[3] : 0.0f;
  L->n1y[k] = normals ? tri->n[4] : 0.0f, L->n1z[k] = normals ? tri->n[5] : 0.0f;
  L->n2x[k] = normals ? tri->n[6] : 0.0f, L->n2y[k] = normals ? tri->n[7] : 0.0f;
  L->n2z[k] = normals ? tri->n[8] : 0.0f;
  const int uvs = (tri->flags & PMC_TRI_UVS) != 0u;
  L->uvs[k] = uvs ? -1 : 0;
  L->t0u[k] = uvs ? tri->t[0] : 0.0f, L->t0v[k] = uvs ? tri->t[1] : 0.0f;
  L->t1u[k] = uvs ? tri->t[2] : 1.0f, L->t1v[k] = uvs ? tri->t[3] : 0.0f;
  L->t2u[k] = uvs ? tri->t[4] : 0.0f, L->t2v[k] = uvs ? tri->t[5] : 1.0f;
  const int tangents = (tri->flags & PMC_TRI_TANGENTS) != 0u;
  L->tangents[k] = tangents ? -1 : 0;
  const uint w0 = tangents ? tri->tangent[0] : 0u, w1 = tangents ? tri->tangent[1] : 0u;
  const uint w2 = tangents ? tri->tangent[2] : 0u;
  L->o0x[k] = pmc_snorm16(w0), L->o0y[k] = pmc_snorm16(w0 >> 16);
  L->o1x[k] = pmc_snorm16(w1), L->o1y[k] = pmc_snorm16(w1 >> 16);
  L->o2x[k] = pmc_snorm16(w2), L->o2y[k] = pmc_snorm16(w2 >> 16);
  /* Ray cone at the hit: uv gradients for texture LOD (and the material cache). */
  const float cone_width = path->cone_width + hit.t * frame->cam_spread;
  L->radius[k] = 0.5f * cone_width;
  hp->t = hit.t;
  hp->cone_width = cone_width;
  hp->ellipse = pmc_texture_ellipse_needed(path->cone_width, hit.t, frame->cam_spread, path->bsdf_pdf,
                                           (float)PMC_TEXTURE_MAX_TAPS);
  hp->prim = hit.prim;
  hp->material = tri->material;
  hp->cache_jitter = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
  hp->texel.ready = 0u;
  hp->cell.ready = 0u;
  hp->cache_points = 0u;
  hp->cache_position_mask = 0u;
  hp->cache_extra = 0.0f;
}

/* Pass 1b: the geometry of a batch's n hits (PMC_HIT_GEOMETRY), eight lanes
 * at a time in float8 where PMC_LANES allows, else hit by hit. */
#if PMC_LANES8
#define PMC_HIT_LD8(f) vload8(0, L->f + k)
#define PMC_HIT_ST8(f, x) vstore8((x), 0, L->f + k)
PMC_HIT_GEOMETRY(pmc_hit_geometry8, float8, int8, PMC_SEL_VECTOR, PMC_HIT_LD8, PMC_HIT_LD8, PMC_HIT_ST8)
#undef PMC_HIT_LD8
#undef PMC_HIT_ST8
#endif
static inline void pmc_hit_geometry_lanes(PmcHitLanes* L, int n) {
  for (int k = 0; k < n; ++k)
    if (L->escaped[k]) pmc_hit_lane_clear_surface(L, k);
#if PMC_LANES8
  for (int q = 0; q < n; q += 8) pmc_hit_geometry8(L, q);
#else
  for (int k = 0; k < n; ++k) pmc_hit_geometry_at(L, k);
#endif
}

/* Pass 1b': the radiance of the lights the batch's rays met (quads before
 * their hits; the environment and sun disks where they escaped), added to
 * their paths (pmc_lights_seen, the quads eight rays at a time in float8
 * where PMC_LANES allows: pmc_quad_seen8, the scalar form's twin). */
#if PMC_LANES8
PMC_QUAD_SEEN(pmc_quad_seen8, float8, int8, PMC_SEL_VECTOR)
#endif
/* pmc_infinity_seen for the escaped rays esc[0, m) of a batch, adding to
 * le[k]: for the environment map, the rays' texels first, in one loop over
 * them that PoCL vectorises (the direction's atan2 and acos polynomials; one
 * ray at a time, the lights at infinity were 8.7% of the samples of the
 * spider, whose camera rays mostly meet its sky), then each ray's radiance
 * and MIS weight, light by light in pmc_infinity_seen's order. */
static inline void pmc_infinity_seen_lanes(const PmcLightSet* ls, __global const PmcPathState* paths,
                                           const PmcHitPoint* hp, const PmcHitLanes* L, const int* esc, int m,
                                           float3* le) {
  for (int i = 0; i < ls->h.at_infinity; ++i) {
    const int map = pmc_infinity_is_map(ls, i);
    float mx[PMC_LANES], my[PMC_LANES], mz[PMC_LANES];
    int texel[PMC_LANES], row[PMC_LANES];
    if (map)
      for (int q = 0; q < m; ++q) {
        const int k = esc[q];
        const float3 md = pmc_env_to_map(&ls->h, make_float3(L->dx[k], L->dy[k], L->dz[k]));
        int r;
        texel[q] = pmc_env_texel_at(&ls->h, md, &r);
        row[q] = r;
        mx[q] = md.x, my[q] = md.y, mz[q] = md.z;
      }
    for (int q = 0; q < m; ++q) {
      const int k = esc[q];
      __global const PmcPathState* path = &paths[hp[k].path];
      const float3 md = map ? make_float3(mx[q], my[q], mz[q]) : make_float3(0.0f, 0.0f, 0.0f);
      float3 add;
      if (pmc_infinity_light_seen(ls, i, hp[k].org, make_float3(L->dx[k], L->dy[k], L->dz[k]), path->bsdf_pdf,
                                  pmc_load3(path->light_normal), path->flags & PMC_PATH_SPECULAR, md,
                                  map ? texel[q] : 0, map ? row[q] : 0, &add))
        le[k] += add;
    }
  }
}

static inline void pmc_lights_seen_lanes(__constant PmcFrame* frame, const PmcSceneData* scene,
                                         __global PmcPathState* paths, const PmcHitPoint* hp,
                                         const PmcHitLanes* L, int n) {
  const PmcLightSet* ls = &scene->light_set;
  if (ls->h.quad_end <= 0) return;
  float3 le[PMC_LANES];
  for (int k = 0; k < n; ++k) le[k] = make_float3(0.0f, 0.0f, 0.0f);
  for (int i = ls->h.distant_end; i < ls->h.quad_end; ++i) {
    __global const PmcLight* l = &ls->lights[i];
    int seen[PMC_LANES];
    float t[PMC_LANES], denom[PMC_LANES];
#if PMC_LANES8
    for (int q = 0; q < n; q += 8) {
      float8 t8, denom8;
      const int8 seen8 = pmc_quad_seen8(l, vload8(0, L->ox + q), vload8(0, L->oy + q), vload8(0, L->oz + q),
                                        vload8(0, L->dx + q), vload8(0, L->dy + q), vload8(0, L->dz + q),
                                        vload8(0, L->t_hit + q), vload8(0, L->escaped + q), &t8, &denom8);
      vstore8(seen8, 0, seen + q);
      vstore8(t8, 0, t + q);
      vstore8(denom8, 0, denom + q);
    }
#else
    for (int k = 0; k < n; ++k)
      seen[k] = pmc_quad_seen_at(l, L->ox[k], L->oy[k], L->oz[k], L->dx[k], L->dy[k], L->dz[k], L->t_hit[k],
                                 L->escaped[k], &t[k], &denom[k]);
#endif
    for (int k = 0; k < n; ++k)
      if (seen[k]) {
        __global const PmcPathState* path = &paths[hp[k].path];
        le[k] += pmc_quad_seen_radiance(ls, i, hp[k].org, t[k], denom[k], path->bsdf_pdf,
                                        pmc_load3(path->light_normal), path->flags & PMC_PATH_SPECULAR);
      }
  }
  int escaped[PMC_LANES], n_escaped = 0;
  for (int k = 0; k < n; ++k)
    if (!hp[k].surface) escaped[n_escaped++] = k;
  if (n_escaped > 0) pmc_infinity_seen_lanes(ls, paths, hp, L, escaped, n_escaped, le);
  for (int k = 0; k < n; ++k) {
    __global PmcPathState* path = &paths[hp[k].path];
    /* light met by a ray from hit depth - 1 (from the camera at depth 0) */
    const float limit = pmc_clamp_limit(frame, hp[k].depth > 0u ? hp[k].depth - 1u : 0u);
    const float3 radiance =
        pmc_add_light(pmc_load3(path->radiance), pmc_load3(path->throughput), le[k], limit);
    path->radiance[0] = radiance.x;
    path->radiance[1] = radiance.y;
    path->radiance[2] = radiance.z;
  }
}

/* Pass 1c: a hit's geometry from its lane (the smooth corner tangents of
 * core/vertex_tangents.h included: PMC_HIT_GEOMETRY). */
static inline void pmc_hit_store(const PmcHitLanes* L, int k, PmcHitPoint* hp) {
  if (!hp->surface) return;
  hp->dir = make_float3(L->dx[k], L->dy[k], L->dz[k]);
  hp->pos = make_float3(L->px[k], L->py[k], L->pz[k]);
  hp->ng = make_float3(L->nx[k], L->ny[k], L->nz[k]);
  hp->ns = make_float3(L->sx[k], L->sy[k], L->sz[k]);
  hp->tangent = make_float3(L->tx[k], L->ty[k], L->tz[k]);
  hp->uv = make_float2(L->u[k], L->v[k]);
  hp->area2 = L->area2[k];
  hp->hit_scale = L->scale[k]; /* for the ray offsets (pmc_geometry.h) */
  hp->front = L->front[k] != 0;
}

/* The uv gradients of a batch's n hits (their cones' footprints, from the
 * lanes pmc_hit_geometry_lanes filled) into hp[k].g1, g2: eight at a time in
 * float8 where PMC_LANES allows (pmc_ray_cone_gradients8, the scalar form's
 * twin), else hit by hit. */
#if PMC_LANES8
PMC_RAY_CONE_GRADIENTS(pmc_ray_cone_gradients8, float8, int8, PMC_SEL_VECTOR)
#endif
static inline void pmc_ray_cone_lanes(const PmcHitLanes* c, int n, PmcHitPoint* hp) {
  float g1u[PMC_LANES], g1v[PMC_LANES], g2u[PMC_LANES], g2v[PMC_LANES];
#if PMC_LANES8
  for (int q = 0; q < n; q += 8) {
    float8 a, b, d, e;
    pmc_ray_cone_gradients8(vload8(0, c->dx + q), vload8(0, c->dy + q), vload8(0, c->dz + q),
                            vload8(0, c->nx + q), vload8(0, c->ny + q), vload8(0, c->nz + q),
                            vload8(0, c->radius + q), vload8(0, c->e1x + q), vload8(0, c->e1y + q),
                            vload8(0, c->e1z + q), vload8(0, c->e2x + q), vload8(0, c->e2y + q),
                            vload8(0, c->e2z + q), vload8(0, c->d1u + q), vload8(0, c->d1v + q),
                            vload8(0, c->d2u + q), vload8(0, c->d2v + q), &a, &b, &d, &e);
    vstore8(a, 0, g1u + q);
    vstore8(b, 0, g1v + q);
    vstore8(d, 0, g2u + q);
    vstore8(e, 0, g2v + q);
  }
#else
  for (int k = 0; k < n; ++k)
    pmc_ray_cone_gradients_at(c->dx[k], c->dy[k], c->dz[k], c->nx[k], c->ny[k], c->nz[k], c->radius[k],
                              c->e1x[k], c->e1y[k], c->e1z[k], c->e2x[k], c->e2y[k], c->e2z[k], c->d1u[k],
                              c->d1v[k], c->d2u[k], c->d2v[k], &g1u[k], &g1v[k], &g2u[k], &g2v[k]);
#endif
  for (int k = 0; k < n; ++k) {
    hp[k].g1 = make_float2(g1u[k], g1v[k]);
    hp[k].g2 = make_float2(g2u[k], g2v[k]);
  }
}

/* What a batch's hits draw their numbers by (pmc_rng.h), one array each:
 * the pixel, the sample and the bounce (the hit's depth + 1: bounce 0 is
 * the camera ray's dimensions). */
static inline void pmc_hit_sample_ids(__constant PmcFrame* frame, const PmcHitPoint* hp, int n, uint* pixel,
                                      uint* sample, uint* bounce) {
  for (int k = 0; k < n; ++k) {
    pixel[k] = hp[k].pixel;
    sample[k] = pmc_path_sample(frame, hp[k].path);
    bounce[k] = hp[k].depth + 1u;
  }
}

/* The cache's bilinear texel jitter of a batch's hits (the set
 * PMC_SET_CACHE of their bounce, as pmc_rand2 draws it), in one loop over
 * the lanes for the frame's sampler, which PoCL's compiler vectorises as it
 * does pmc_draw_hit_numbers'. Every lane draws; a hit without cache points
 * does not read its pair. Drawn one hit at a time inside pmc_hit_cache_keys,
 * the pair cost a cached wall of the default room more than its lookup did. */
static inline void pmc_draw_cache_jitter(__constant PmcFrame* frame, const PmcHitPoint* hp, int n,
                                         float* jitter_u, float* jitter_v) {
  uint pixel[PMC_LANES], sample[PMC_LANES], bounce[PMC_LANES];
  pmc_hit_sample_ids(frame, hp, n, pixel, sample, bounce);
  const uint seed = frame->seed;
  if (frame->sampler == PMC_SAMPLER_RANDOM) {
    for (int k = 0; k < n; ++k) {
      const float2 j = pmc_cache_jitter_random(pmc_path_key(seed, pixel[k], sample[k]), bounce[k]);
      jitter_u[k] = j.x; /* two arrays: PoCL did not vectorise stores of float2 */
      jitter_v[k] = j.y;
    }
  } else {
    for (int k = 0; k < n; ++k) {
      const uint key = pmc_sampler(PMC_SAMPLER_SOBOL, seed, pixel[k], sample[k]).key;
      const float2 j = pmc_cache_jitter_sobol(key, sample[k], bounce[k]);
      jitter_u[k] = j.x;
      jitter_v[k] = j.y;
    }
  }
}

/* A hit whose cache points need no uv texel (pmc_hit_cache_keys). */
#define PMC_NO_TEXEL (-1000)

/* Pass 1's end, with the cache: the cell of a hit's position cache points
 * (after its gradients), and what its uv texel needs: the texel's level
 * floor, or PMC_NO_TEXEL when it has no uv point or evaluates them exactly
 * (pmc_cache_texels_lanes then computes the texels of the batch). `jitter`
 * is its pair of pmc_draw_cache_jitter. */
static inline int pmc_hit_cache_keys(__constant PmcFrame* frame, const PmcSceneData* scene,
                                     __global PmcPathState* paths, float2 jitter, PmcHitPoint* hp) {
  if (!hp->surface) return PMC_NO_TEXEL;
  __global PmcPathState* path = &paths[hp->path];
  const float3 pos = hp->pos, ng = hp->ng;
  const float cone_width = hp->cone_width;
  __global const PmcMaterialInfo* info = &scene->materials[hp->material];
  /* A hit past a path's last one (PMC_PATH_EMISSION_ONLY) needs its
   * material's emission alone: it runs without the cache (pmc_shade_batch
   * gives it a run of its own), so it neither counts nor inserts keys that no
   * shading uses. */
  if (hp->past_last) {
    hp->cache_points = 0u;
    return PMC_NO_TEXEL;
  }
  hp->cache_points = info->cache_points;
  /* A camera-ray hit after the pixel's first cache_camera_samples samples
   * evaluates its points exactly (docs/DESIGN.md, "The cache at camera hits"). */
  if (hp->depth == 0u && pmc_path_sample(frame, hp->path) >= frame->cache_camera_samples) {
    hp->texel.ready = hp->texel.bypass = hp->cell.ready = hp->cell.bypass = 1u;
    return PMC_NO_TEXEL;
  }
  /* The position cells' cone: wider than the texture's after rough bounces
   * (uv texels keep the texture's: docs/DESIGN.md, "The cache's cone"). */
  if (frame->cache_lobe_spread > 0.0f) {
    const uint cone = path->cache_cone;
    hp->cache_extra = fmin(pmc_cone_width(cone) + hp->t * pmc_cone_spread(cone), 1e30f);
  }
  hp->cache_position_mask = info->cache_position_mask;
  if (frame->cache_bilinear && hp->cache_points > 0u)
    hp->cache_jitter = make_float4(jitter.x - 0.5f, jitter.y - 0.5f, 0.0f, 0.0f);
  const uint all = hp->cache_points >= 32u ? 0xffffffffu : (1u << hp->cache_points) - 1u;
  /* level floors (none unless the cache_bandwidth setting computed them): at every hit,
   * or with `camera` at camera-ray hits only */
  const int floors = frame->cache_bandwidth != PMC_CACHE_FLOORS_CAMERA || hp->depth == 0u;
  const int floor_uv = floors ? info->cache_level_floor_uv : PMC_LEVEL_NO_FLOOR;
  const int floor_position = floors ? info->cache_level_floor_position : PMC_LEVEL_NO_FLOOR;
  if (hp->cache_position_mask != 0u) {
    /* Level floors (the cache_bandwidth setting) count from the texture cone's level:
     * the widening coarsens cells down to a floor at most, and a point is
     * bypassed exactly where it would be without the widening. */
    int max_refine = frame->cache_max_refine;
    if (hp->cache_extra > 0.0f)
      max_refine += pmc_cache_level(0.5f * cone_width, frame->mip_bias) -
                    pmc_cache_level(0.5f * (cone_width + hp->cache_extra), frame->mip_bias);
    hp->cell = pmc_cache_cell_floored(pos, 0.5f * (cone_width + hp->cache_extra), frame->mip_bias,
                                      pmc_cache_plane_jitter(ng, hp->cache_jitter.x, hp->cache_jitter.y),
                                      (uint)hp->material, floor_position, max_refine);
  }
  return (all & ~hp->cache_position_mask) != 0u ? floor_uv : PMC_NO_TEXEL;
}

/* The uv texels of a batch's hits (pmc_cache_texel_floored; `level_floor`:
 * pmc_hit_cache_keys' answers), in loops over the lanes that PoCL's compiler
 * vectorises: the level from the gradients' exponent bits, the indices and
 * the four 64-bit hashes, for every lane, kept where a texel is needed.
 * Computed one hit at a time, they cost a cached wall of the default room
 * more than its lookup did. A bias that is not an integer (the level takes a log2)
 * goes one hit at a time. */
static inline void pmc_cache_texels_lanes(__constant PmcFrame* frame, PmcHitPoint* hp, const int* level_floor,
                                          int n) {
  const float bias = frame->mip_bias;
  const int max_refine = frame->cache_max_refine;
  if (!pmc_cache_bias_integral(bias)) {
    for (int k = 0; k < n; ++k)
      if (level_floor[k] != PMC_NO_TEXEL)
        hp[k].texel = pmc_cache_texel_floored(hp[k].uv, hp[k].g1, hp[k].g2, bias,
                                              make_float2(hp[k].cache_jitter.x, hp[k].cache_jitter.y),
                                              (uint)hp[k].material, level_floor[k], max_refine);
    return;
  }
  const int ib = (int)(isfinite(bias) ? bias : 0.0f);
  float m[PMC_LANES], u[PMC_LANES], v[PMC_LANES], ju[PMC_LANES], jv[PMC_LANES];
  uint material[PMC_LANES];
  for (int k = 0; k < n; ++k) {
    m[k] = pmc_cache_gradient_size(hp[k].g1, hp[k].g2);
    u[k] = hp[k].uv.x;
    v[k] = hp[k].uv.y;
    ju[k] = hp[k].cache_jitter.x;
    jv[k] = hp[k].cache_jitter.y;
    material[k] = (uint)hp[k].material;
  }
  int lambda[PMC_LANES], footprint_lambda[PMC_LANES];
  uint bypass[PMC_LANES];
  long tx[PMC_LANES], ty[PMC_LANES];
  ulong hash[PMC_LANES], base[PMC_LANES];
  for (int k = 0; k < n; ++k) {
    footprint_lambda[k] = pmc_cache_level_integral(m[k], ib);
    lambda[k] = pmc_cache_floored_level(footprint_lambda[k], level_floor[k], max_refine, &bypass[k]);
    tx[k] = pmc_cache_texel_jittered(u[k], lambda[k], ju[k]);
    ty[k] = pmc_cache_texel_jittered(v[k], lambda[k], jv[k]);
    hash[k] = pmc_cache_texel_hash(lambda[k], tx[k], ty[k]);
    base[k] = pmc_cache_group_base(hash[k], material[k]);
  }
  for (int k = 0; k < n; ++k)
    if (level_floor[k] != PMC_NO_TEXEL) {
      PmcCacheTexel* t = &hp[k].texel;
      t->footprint_lambda = footprint_lambda[k];
      t->lambda = lambda[k];
      t->bypass = bypass[k];
      t->tx = tx[k];
      t->ty = ty[k];
      t->tz = 0L;
      t->hash = hash[k];
      t->base = base[k];
      t->ready = 1u;
    }
}

/* The material's shading inputs and, with the cache, its cache context at
 * one hit. The footprint only for a material that filters images
 * (PMC_MAT_FOOTPRINT): no other instruction reads it. */
static inline void pmc_material_inputs(__constant PmcFrame* frame, const PmcHitPoint* hp, int footprint,
                                       __global volatile ulong* cache_entries, PmcShadingInputs* sp,
                                       PmcCacheContext* cache) {
  sp->uv = hp->uv;
  sp->position = hp->pos;
  sp->normal = hp->ns;
  sp->tangent = hp->tangent;
  sp->bitangent = cross(hp->ns, hp->tangent);
  if (footprint) {
    pmc_shading_footprint(sp, hp->g1, hp->g2, hp->ellipse); /* width, and ellipse where it shows */
  } else {
    sp->footprint = 0.0f;
    sp->footprint_axis = make_float2(0.0f, 0.0f);
    sp->footprint_minor = 0.0f;
  }
  if (cache) {
    cache->table = pmc_frame_cache_table(frame, cache_entries);
    cache->g1 = hp->g1;
    cache->g2 = hp->g2;
    cache->bias = frame->mip_bias;
    cache->material = (uint)hp->material;
    cache->center = frame->cache_center;
    cache->depth = hp->depth;
    cache->jitter = hp->cache_jitter;
    cache->radius = 0.5f * (hp->cone_width + hp->cache_extra);
    cache->floors = 0u; /* hp's texel and cell are ready, the floors applied */
    cache->level_floor_uv = PMC_LEVEL_NO_FLOOR;
    cache->level_floor_position = PMC_LEVEL_NO_FLOOR;
    cache->max_refine = frame->cache_max_refine;
    cache->texel = hp->texel;
    cache->cell = hp->cell;
    cache->hits = 0u;
#if PMC_CACHE_TRACE_RECORDS
    cache->trace_pixel = hp->pixel;
    cache->trace_sample = pmc_path_sample(frame, hp->path);
#endif
    for (int c = 0; c < PMC_CSTAT_COUNT; ++c) cache->counts[c] = 0u;
  }
}

static inline PmcMaterialData pmc_material_data(const PmcSceneData* scene) {
  PmcMaterialData md;
  md.code = scene->code;
  md.materials = scene->materials;
  md.textures.textures = scene->textures;
  md.textures.texels = scene->texels;
  md.textures.srgb_lut = scene->srgb_lut;
  md.textures.count = scene->texture_count;
  return md;
}

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

#if PMC_LANES >= 8
/* pmc_sincos_turns and pmc_sph_rect_sample_xy (core/abi/pmc_vec.h,
 * core/device/pmc_lights.h), eight lanes at a time: the same operations in
 * the same order on float8, so each lane's value is the scalar form's (the
 * images are bit-identical). PoCL's compiler did not vectorise the scalar
 * form's loop over the lanes; OpenCL's vector types say it outright. */
static inline void pmc_sincos_turns8(float8 t, float8* s, float8* c) {
  const float8 q = floor(t * 4.0f + 0.5f);
  const float8 x = (t - q * 0.25f) * (2.0f * 3.14159265358979323846f);
  const float8 z = x * x;
  const float8 sn = ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * x + x;
  const float8 cs =
      ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) * z * z - 0.5f * z +
      1.0f;
  const int8 k = convert_int8(q) & 3;
  *s = k == 0 ? sn : (k == 1 ? cs : (k == 2 ? -sn : -cs));
  *c = k == 0 ? cs : (k == 1 ? -sn : (k == 2 ? -cs : sn));
}

#if PMC_LANES8
/* pmc_sample_cosine (core/device/pmc_bsdf.h) for eight lanes: the same
 * operations in the same order, selects for its branches. */
static inline void pmc_sample_cosine8(float8 u1, float8 u2, float8* x_out, float8* y_out, float8* z_out) {
  const float8 a = 2.0f * u1 - 1.0f;
  const float8 c = 2.0f * u2 - 1.0f;
  const int8 wide = fabs(a) > fabs(c);
  const float8 r = select(c, a, wide);
  const float8 turns = select(0.25f - 0.125f * (a / c), 0.125f * (c / a), wide); /* the angle, in turns */
  float8 sin_phi, cos_phi;
  pmc_sincos_turns8(turns, &sin_phi, &cos_phi);
  const float8 x = r * cos_phi, y = r * sin_phi;
  const float8 z = sqrt(fmax((float8)(0.0f), 1.0f - x * x - y * y));
  const int8 centre = (a == 0.0f) & (c == 0.0f); /* the scalar form's (0, 0, 1) */
  *x_out = select(x, (float8)(0.0f), centre);
  *y_out = select(y, (float8)(0.0f), centre);
  *z_out = select(z, (float8)(1.0f), centre);
}
#endif

static inline void pmc_sph_rect_sample_xy8(float8 omega, float8 k, float8 b0, float8 b1, float8 z0, float8 x0,
                                           float8 x1, float8 y0, float8 y1, float8 u, float8 v,
                                           float8* xu_out, float8* yv_out) {
  const float8 au = u * omega + k;
  float8 sin_au, cos_au;
  pmc_sincos_turns8(au * (0.5f * PMC_INV_PI), &sin_au, &cos_au);
  const float8 fu = (cos_au * b0 - b1) / sin_au;
  float8 cu = select((float8)(-1.0f), (float8)(1.0f), fu >= 0.0f) / sqrt(fu * fu + b0 * b0);
  cu = clamp(cu, -1.0f, 1.0f);
  float8 xu = -(cu * z0) / sqrt(fmax(1e-30f, 1.0f - cu * cu));
  xu = clamp(xu, x0, x1);
  const float8 dd = sqrt(xu * xu + z0 * z0);
  const float8 h0 = y0 / sqrt(dd * dd + y0 * y0);
  const float8 h1 = y1 / sqrt(dd * dd + y1 * y1);
  const float8 hv = h0 + v * (h1 - h0), hv2 = hv * hv;
  const float8 yv = hv2 < 1.0f - 1e-6f ? hv * dd / sqrt(1.0f - hv2) : y1;
  *xu_out = xu;
  *yv_out = clamp(yv, y0, y1);
}
#endif

#if PMC_LANES8
/* The light tree's importance eight lanes at a time: the scalar form's
 * arithmetic (PMC_TREE_IMPORTANCE, core/device/pmc_lights.h) on float8, so
 * each lane's value is pmc_tree_importance's bit for bit. */
PMC_TREE_IMPORTANCE(pmc_tree_importance8, float8, int8, PMC_SEL_VECTOR)

/* The points and pick normals of a batch's lanes, one array per component. */
typedef struct PmcPickLanes {
  float px[PMC_LANES], py[PMC_LANES], pz[PMC_LANES], nx[PMC_LANES], ny[PMC_LANES], nz[PMC_LANES];
} PmcPickLanes;

/* The points and normals of lanes act[0, count) packed to the front of cp,
 * padded to a multiple of eight with the first one's: each tree level's
 * importances then read them as vectors instead of gathering them through
 * act[] once per node. */
static inline void pmc_pick_lanes_pack(const PmcPickLanes* pl, const int* act, int count, PmcPickLanes* cp) {
  for (int q = 0; q < ((count + 7) & ~7); ++q) {
    const int j = act[q < count ? q : 0];
    cp->px[q] = pl->px[j], cp->py[q] = pl->py[j], cp->pz[q] = pl->pz[j];
    cp->nx[q] = pl->nx[j], cp->ny[q] = pl->ny[j], cp->nz[q] = pl->nz[j];
  }
}

/* The fields pmc_tree_importance8 reads of eight lanes' tree nodes. */
typedef struct PmcTreeNodes8 {
  float8 lox, loy, loz, hix, hiy, hiz, ax, ay, az, energy, cos_o, cos_e;
  int8 two_sided;
} PmcTreeNodes8;

/* Node n's fields in all eight lanes. */
PMC_FN_INLINE PmcTreeNodes8 pmc_tree_node_broadcast8(const PmcLightSet* ls, int n) {
  __global const float* t = (__global const float*)&ls->tree[n];
  const float4 b = vload4(0, t), h = vload4(1, t),
               x = vload4(2, t); /* lo + energy, hi + cos_o, axis + cos_e */
  PmcTreeNodes8 v;
  v.lox = (float8)(b.x), v.loy = (float8)(b.y), v.loz = (float8)(b.z), v.energy = (float8)(b.w);
  v.hix = (float8)(h.x), v.hiy = (float8)(h.y), v.hiz = (float8)(h.z), v.cos_o = (float8)(h.w);
  v.ax = (float8)(x.x), v.ay = (float8)(x.y), v.az = (float8)(x.z), v.cos_e = (float8)(x.w);
  v.two_sided = (int8)((ls->tree[n].flags & PMC_TREE_TWO_SIDED) != 0u ? -1 : 0);
  return v;
}

/* The fields of nodes node[q + i], i < 8, each read as three float4 loads
 * (PmcLightTreeNode's first 48 bytes) and turned into float8 fields by
 * shuffles (a loop that gathered field by field into arrays spent three
 * quarters of the importances' time in its gathers on Sponza's 960 emissive
 * triangles); lanes at or past `count` repeat node[0]. */
PMC_FN_INLINE PmcTreeNodes8 pmc_tree_node_gather8(const PmcLightSet* ls, const int* node, int q, int count) {
  float4 b[8], h[8], x[8];
  int two_sided[8];
  for (int i = 0; i < 8; ++i) {
    const int n = node[q + i < count ? q + i : 0];
    __global const float* t = (__global const float*)&ls->tree[n];
    b[i] = vload4(0, t);
    h[i] = vload4(1, t);
    x[i] = vload4(2, t);
    two_sided[i] = (ls->tree[n].flags & PMC_TREE_TWO_SIDED) != 0u ? -1 : 0;
  }
#define PMC_FIELD8(v, c) (float8)(v[0].c, v[1].c, v[2].c, v[3].c, v[4].c, v[5].c, v[6].c, v[7].c)
  PmcTreeNodes8 v;
  v.lox = PMC_FIELD8(b, x), v.loy = PMC_FIELD8(b, y), v.loz = PMC_FIELD8(b, z), v.energy = PMC_FIELD8(b, w);
  v.hix = PMC_FIELD8(h, x), v.hiy = PMC_FIELD8(h, y), v.hiz = PMC_FIELD8(h, z), v.cos_o = PMC_FIELD8(h, w);
  v.ax = PMC_FIELD8(x, x), v.ay = PMC_FIELD8(x, y), v.az = PMC_FIELD8(x, z), v.cos_e = PMC_FIELD8(x, w);
#undef PMC_FIELD8
  v.two_sided = vload8(0, two_sided);
  return v;
}

/* Whether node[0, count) are all one node. */
static inline int pmc_tree_nodes_uniform(const int* node, int count) {
  int uniform = 1;
  for (int q = 1; q < count; ++q) uniform &= node[q] == node[0];
  return uniform;
}

/* pmc_tree_importance8 for nodes v and packed lanes [q, q + 8) of cp. */
PMC_FN_INLINE float8 pmc_tree_importance_at8(const PmcTreeNodes8* v, const PmcPickLanes* cp, int q) {
  return pmc_tree_importance8(v->lox, v->loy, v->loz, v->hix, v->hiy, v->hiz, v->ax, v->ay, v->az, v->energy,
                              v->cos_o, v->cos_e, v->two_sided, vload8(0, cp->px + q), vload8(0, cp->py + q),
                              vload8(0, cp->pz + q), vload8(0, cp->nx + q), vload8(0, cp->ny + q),
                              vload8(0, cp->nz + q));
}

/* out[q] = the importance of tree node node[q] for packed lane q of cp
 * (pmc_pick_lanes_pack), q < count, eight at a time. When every lane reads
 * one node (the root, the root's children, all of a small tree's levels) it
 * is read once and broadcast. */
static inline void pmc_tree_importance_lanes(const PmcLightSet* ls, const PmcPickLanes* cp, const int* node,
                                             int count, float* out) {
  if (count <= 0) return;
  if (pmc_tree_nodes_uniform(node, count)) {
    const PmcTreeNodes8 b = pmc_tree_node_broadcast8(ls, node[0]);
    for (int q = 0; q < count; q += 8) vstore8(pmc_tree_importance_at8(&b, cp, q), 0, out + q);
    return;
  }
  for (int q = 0; q < count; q += 8) {
    const PmcTreeNodes8 v = pmc_tree_node_gather8(ls, node, q, count);
    vstore8(pmc_tree_importance_at8(&v, cp, q), 0, out + q);
  }
}

/* The importances of a level's two children at once (pmc_tree_importance_lanes
 * for node0 into out0 and node1 into out1): the two are independent chains of
 * square roots and divisions, which one loop interleaves. */
static inline void pmc_tree_importance2_lanes(const PmcLightSet* ls, const PmcPickLanes* cp, const int* node0,
                                              const int* node1, int count, float* out0, float* out1) {
  if (count <= 0) return;
  const int uniform0 = pmc_tree_nodes_uniform(node0, count), uniform1 = pmc_tree_nodes_uniform(node1, count);
  const PmcTreeNodes8 b0 = pmc_tree_node_broadcast8(ls, node0[0]),
                      b1 = pmc_tree_node_broadcast8(ls, node1[0]);
  if (uniform0 && uniform1) { /* every lane at one node: its children read once, one after the other (their
                                 broadcast fields together would not fit the vector registers) */
    for (int q = 0; q < count; q += 8) vstore8(pmc_tree_importance_at8(&b0, cp, q), 0, out0 + q);
    for (int q = 0; q < count; q += 8) vstore8(pmc_tree_importance_at8(&b1, cp, q), 0, out1 + q);
    return;
  }
  for (int q = 0; q < count; q += 8) {
    const PmcTreeNodes8 v0 = uniform0 ? b0 : pmc_tree_node_gather8(ls, node0, q, count);
    const PmcTreeNodes8 v1 = uniform1 ? b1 : pmc_tree_node_gather8(ls, node1, q, count);
    vstore8(pmc_tree_importance_at8(&v0, cp, q), 0, out0 + q);
    vstore8(pmc_tree_importance_at8(&v1, cp, q), 0, out1 + q);
  }
}

/* pmc_pick_distant for lanes act[0, count) (their normals packed in cp by
 * pmc_pick_lanes_pack) with the tree's weights
 * tree_weight[q]: every light at infinity's weight for all lanes in one loop
 * over them (its fields the same for every lane; the first PMC_DISTANT_KEPT
 * weights kept for the choice), the total, then the choice in a second such
 * loop, each with pmc_pick_distant's arithmetic in its order (pmc_distant_weight_at; the next vertex's
 * pmc_light_pick_pmf adds the same sums). Lanes that fall on a light at infinity get it in picked[j] and its
 * probability in pmf[j], none (-1) when nothing lights them; the lanes that go on into the tree stay in
 * act[], rescaled as pmc_pick_distant leaves them. Returns how many stay. perf had the pick one lane at a
 * time at 4% of the default room's samples (a sun and a sky). */
static inline int pmc_pick_distant_lanes(const PmcLightSet* ls, const PmcPickLanes* cp, int* act, int count,
                                         const float* tree_weight, float* u, float* share, float* pmf,
                                         int* picked) {
  float total[PMC_LANES], x[PMC_LANES], below[PMC_LANES], weight[PMC_DISTANT_KEPT][PMC_LANES];
  int chosen[PMC_LANES];
  const float *nx = cp->nx, *ny = cp->ny, *nz = cp->nz;
  for (int q = 0; q < count; ++q) total[q] = 0.0f;
  const int lights = ls->h.distant_end;
  for (int i = 0; i < lights; ++i) {
    __global const PmcLight* l = &ls->lights[i];
    for (int q = 0; q < count; ++q) {
      const float w = pmc_distant_weight(l, make_float3(nx[q], ny[q], nz[q]));
      if (i < PMC_DISTANT_KEPT) weight[i][q] = w;
      total[q] += w;
    }
  }
  for (int q = 0; q < count; ++q) {
    total[q] += tree_weight[q];
    x[q] = u[act[q]] * total[q];
    below[q] = 0.0f;
    chosen[q] = total[q] > 0.0f ? PMC_PICK_TREE : -1;
  }
  for (int i = 0; i < lights; ++i) {
    __global const PmcLight* l = &ls->lights[i];
    for (int q = 0; q < count; ++q) {
      const float w =
          i < PMC_DISTANT_KEPT ? weight[i][q] : pmc_distant_weight(l, make_float3(nx[q], ny[q], nz[q]));
      if (chosen[q] == PMC_PICK_TREE && x[q] < below[q] + w) {
        chosen[q] = i;
        pmf[act[q]] = w / total[q];
      }
      below[q] += w;
    }
  }
  int kept = 0;
  for (int q = 0; q < count; ++q) {
    const int j = act[q];
    int d = chosen[q];
    if (d == PMC_PICK_TREE) {
      if (!(tree_weight[q] > 0.0f)) {
        d = -1; /* rounding ran past the last light at infinity */
      } else {
        share[j] = tree_weight[q] / total[q];
        u[j] = pmc_below_one((x[q] - below[q]) / tree_weight[q]);
      }
    }
    if (d == PMC_PICK_TREE)
      act[kept++] = j;
    else
      picked[j] = d;
  }
  return kept;
}

/* One level of the tree walk (pmc_tree_descend after pmc_first_share_of)
 * for packed lanes q of [0, count), eight at a time: lane q at interior node
 * a[q] with children node0[q] and node1[q] of importances i0[q] and i1[q]
 * moves to the child its u[q] falls in, u[q] rescaled to it and share[q]
 * multiplied by its probability. The scalar functions' operations in their
 * order, selects for their branches, so every lane matches them bit for bit
 * (the next vertex recomputes the pick's probability with them). One lane
 * at a time this loop was a division, a coin-toss branch and a dependent
 * rescale per lane and level. */
static inline void pmc_tree_descend_lanes(const PmcLightSet* ls, const int* node0, const int* node1,
                                          const float* i0, const float* i1, int count, int* a, float* u,
                                          float* share) {
  for (int q = 0; q < count; q += 8) {
    float e0[8], e1[8];
    for (int i = 0; i < 8; ++i) { /* the last group's spare lanes repeat the first */
      const int r = q + i < count ? q + i : 0;
      e0[i] = ls->tree[node0[r]].energy;
      e1[i] = ls->tree[node1[r]].energy;
    }
    float8 w0 = vload8(0, i0 + q), w1 = vload8(0, i1 + q);
    const int8 neither = !(w0 + w1 > (float8)(0.0f)); /* pmc_first_share_of: then by energy */
    w0 = PMC_SEL_VECTOR(neither, vload8(0, e0), w0);
    w1 = PMC_SEL_VECTOR(neither, vload8(0, e1), w1);
    const float8 sum = w0 + w1;
    const float8 first = PMC_SEL_VECTOR(sum > (float8)(0.0f), w0 / sum, (float8)(0.5f));
    const float8 x = vload8(0, u + q);
    const int8 take_first = x < first;
    const float8 second_share = (float8)(1.0f) - first;
    vstore8(vload8(0, share + q) * PMC_SEL_VECTOR(take_first, first, second_share), 0, share + q);
    const float8 rescaled = PMC_SEL_VECTOR(take_first, x / first, (x - first) / second_share);
    vstore8(fmin(fmax(rescaled, (float8)(0.0f)), (float8)(0x1.fffffep-1f)), 0, u + q); /* pmc_below_one */
    vstore8(PMC_SEL_VECTOR(take_first, vload8(0, node0 + q), vload8(0, node1 + q)), 0, a + q);
  }
}

/* pmc_light_pick for lanes lane[0, m) of a batch (those with nee[j].active),
 * the same picks and probabilities: with the light tree, the lanes descend
 * it level by level together, their walks' state packed (lane act[q] at
 * node a[q], its point and normal in cp), each level's importances and
 * choices eight lanes at a time; the lanes that reach a leaf leave the
 * packed arrays, which close up in place. Without the tree, lane by lane.
 * picked[j] = -1: none. */
static inline void pmc_light_pick_lanes(const PmcLightSet* ls, const PmcNeeInput* nee, const int* lane, int m,
                                        const PmcBatchNumbers* numbers, int* picked, float* pmf) {
  if (ls->h.sampler != PMC_LIGHT_SAMPLER_TREE || ls->h.tree_nodes <= 0 || ls->h.count <= 0) {
    for (int j = 0; j < m; ++j) {
      pmf[j] = 0.0f;
      picked[j] = nee[j].active ? pmc_light_pick(ls, nee[j].origin, nee[j].pick_normal,
                                                 numbers->light_pick[lane[j]], &pmf[j])
                                : -1;
    }
    return;
  }
  PmcPickLanes pl, cp; /* the active lanes' points: by lane, and packed (pmc_pick_lanes_pack) */
  float u[PMC_LANES], share[PMC_LANES], i0[PMC_LANES], i1[PMC_LANES];
  int act[PMC_LANES], node0[PMC_LANES], node1[PMC_LANES];
  int count = 0;
  for (int j = 0; j < m; ++j) {
    picked[j] = -1;
    pmf[j] = 0.0f;
    if (!nee[j].active) continue;
    pl.px[j] = nee[j].origin.x, pl.py[j] = nee[j].origin.y, pl.pz[j] = nee[j].origin.z;
    pl.nx[j] = nee[j].pick_normal.x, pl.ny[j] = nee[j].pick_normal.y, pl.nz[j] = nee[j].pick_normal.z;
    u[j] = numbers->light_pick[lane[j]];
    share[j] = 1.0f;
    act[count++] = j;
  }
  if (ls->h.distant_end > 0 && count > 0) { /* the root's importance weighs the tree among the strategies */
    for (int q = 0; q < count; ++q) node0[q] = 0;
    pmc_pick_lanes_pack(&pl, act, count, &cp);
    pmc_tree_importance_lanes(ls, &cp, node0, count, i0);
    count = pmc_pick_distant_lanes(ls, &cp, act, count, i0, u, share, pmf, picked);
  }
  if (count == 0) return;
  /* the walks, packed from here on: lane act[q] at node a[q] with wu[q], ws[q] */
  float wu[PMC_LANES], ws[PMC_LANES];
  int a[PMC_LANES];
  pmc_pick_lanes_pack(&pl, act, count, &cp);
  for (int q = 0; q < count; ++q) {
    wu[q] = u[act[q]];
    ws[q] = share[act[q]];
    a[q] = 0;
  }
  for (;;) {
    int kept = 0;
    for (int q = 0; q < count; ++q) {
      __global const PmcLightTreeNode* t = &ls->tree[a[q]];
      const int j = act[q];
      if (t->flags & PMC_TREE_LEAF) {
        picked[j] = (int)t->second;
        pmf[j] = ws[q];
        continue;
      }
      act[kept] = j, a[kept] = a[q], wu[kept] = wu[q], ws[kept] = ws[q];
      cp.px[kept] = cp.px[q], cp.py[kept] = cp.py[q], cp.pz[kept] = cp.pz[q];
      cp.nx[kept] = cp.nx[q], cp.ny[kept] = cp.ny[q], cp.nz[kept] = cp.nz[q];
      node0[kept] = a[q] + 1;
      node1[kept] = (int)t->second;
      ++kept;
    }
    count = kept;
    if (count == 0) return;
    for (int q = count; q < ((count + 7) & ~7); ++q) { /* spare lanes: copies of the first */
      cp.px[q] = cp.px[0], cp.py[q] = cp.py[0], cp.pz[q] = cp.pz[0];
      cp.nx[q] = cp.nx[0], cp.ny[q] = cp.ny[0], cp.nz[q] = cp.nz[0];
      a[q] = a[0], wu[q] = wu[0], ws[q] = ws[0], node0[q] = node0[0], node1[q] = node1[0];
    }
    pmc_tree_importance2_lanes(ls, &cp, node0, node1, count, i0, i1);
    pmc_tree_descend_lanes(ls, node0, node1, i0, i1, count, a, wu, ws);
  }
}
#endif

#if PMC_LANES8
/* The samples of the rectangle quads that lanes at[0, count) picked (light
 * index light[j], pick probability pmf[j]), eight at a time in float8 from the set-up to
 * the sample's direction and weight: PMC_SPH_RECT_SETUP, the point
 * (pmc_sph_rect_sample_xy8) and PMC_RECT_SAMPLE_END (core/device/pmc_lights.h),
 * the twins of the scalar pmc_sph_rect_init, pmc_sph_rect_sample_xy and
 * pmc_light_sample_rect_end bit for bit. The lanes' inputs are packed to
 * the front first (a light's fields gathered per lane, or read once where
 * every lane picked the same quad: the Cornell box, most of an interior's
 * batches); each lane's sample lands in ls[j] with its state 1 (a sample)
 * or 0 (none), and below PMC_SPH_RECT_MIN_SOLID_ANGLE it is sampled by area
 * there and then. Set up here and ended lane by lane, the rectangles were
 * a tenth of the Cornell box's shade samples. */
#define PMC_ACOS4_VECTOR(a, b, c, d, ga, gb, gc, gd) (ga = acos(a), gb = acos(b), gc = acos(c), gd = acos(d))
/* The packed inputs: the light's edges, normal and radiance, d = corner - p,
 * the random numbers and the pick's probability. */
enum {
  PMC_RI_EUX,
  PMC_RI_EUY,
  PMC_RI_EUZ,
  PMC_RI_EVX,
  PMC_RI_EVY,
  PMC_RI_EVZ,
  PMC_RI_NX,
  PMC_RI_NY,
  PMC_RI_NZ,
  PMC_RI_R,
  PMC_RI_G,
  PMC_RI_B,
  PMC_RI_DX,
  PMC_RI_DY,
  PMC_RI_DZ,
  PMC_RI_U,
  PMC_RI_V,
  PMC_RI_PMF,
  PMC_RI_COUNT
};
/* The packed outputs. */
enum {
  PMC_RO_WX,
  PMC_RO_WY,
  PMC_RO_WZ,
  PMC_RO_DIST,
  PMC_RO_COS,
  PMC_RO_PDF,
  PMC_RO_R,
  PMC_RO_G,
  PMC_RO_B,
  PMC_RO_OMEGA,
  PMC_RO_COUNT
};
static inline void pmc_rect_lights_lanes(const PmcLightSet* lights, const PmcNeeInput* nee, const int* at,
                                         int count, const PmcBatchNumbers* numbers, const int* lane,
                                         int* state, const int* light, const float* pmf, PmcLightSample* ls) {
  if (count == 0) return;
  const int padded = (count + 7) & ~7; /* the last group's spare lanes repeat the first */
  int uniform = 1;
  for (int q = 1; q < count; ++q) uniform &= light[at[q]] == light[at[0]];
  float in[PMC_RI_COUNT][PMC_LANES];
  if (uniform) {
    __global const PmcLight* l = &lights->lights[light[at[0]]];
    const float fields[12] = {l->axis[0],   l->axis[1],   l->axis[2],   l->edge_v[0],
                              l->edge_v[1], l->edge_v[2], l->normal[0], l->normal[1],
                              l->normal[2], l->rgb[0],    l->rgb[1],    l->rgb[2]};
    for (int f = 0; f < 12; ++f)
      for (int q = 0; q < padded; ++q) in[f][q] = fields[f];
    const float3 corner = pmc_load3(l->pos);
    for (int q = 0; q < padded; ++q) {
      const int j = at[q < count ? q : 0];
      const float3 d = corner - nee[j].origin;
      in[PMC_RI_DX][q] = d.x, in[PMC_RI_DY][q] = d.y, in[PMC_RI_DZ][q] = d.z;
    }
  } else {
    for (int q = 0; q < padded; ++q) {
      const int j = at[q < count ? q : 0];
      __global const PmcLight* l = &lights->lights[light[j]];
      const float3 d = pmc_load3(l->pos) - nee[j].origin;
      in[PMC_RI_EUX][q] = l->axis[0], in[PMC_RI_EUY][q] = l->axis[1], in[PMC_RI_EUZ][q] = l->axis[2];
      in[PMC_RI_EVX][q] = l->edge_v[0], in[PMC_RI_EVY][q] = l->edge_v[1], in[PMC_RI_EVZ][q] = l->edge_v[2];
      in[PMC_RI_NX][q] = l->normal[0], in[PMC_RI_NY][q] = l->normal[1], in[PMC_RI_NZ][q] = l->normal[2];
      in[PMC_RI_R][q] = l->rgb[0], in[PMC_RI_G][q] = l->rgb[1], in[PMC_RI_B][q] = l->rgb[2];
      in[PMC_RI_DX][q] = d.x, in[PMC_RI_DY][q] = d.y, in[PMC_RI_DZ][q] = d.z;
    }
  }
  for (int q = 0; q < padded; ++q) {
    const int j = at[q < count ? q : 0];
    in[PMC_RI_U][q] = numbers->light_u[lane[j]];
    in[PMC_RI_V][q] = numbers->light_v[lane[j]];
    in[PMC_RI_PMF][q] = pmf[j];
  }
  float o[PMC_RO_COUNT][PMC_LANES];
  for (int q = 0; q < count; q += 8) {
#define PMC_IN8(f) vload8(0, in[f] + q)
    PMC_SPH_RECT_SETUP(float8, int8, PMC_SEL_VECTOR, PMC_ACOS4_VECTOR, PMC_IN8(PMC_RI_EUX),
                       PMC_IN8(PMC_RI_EUY), PMC_IN8(PMC_RI_EUZ), PMC_IN8(PMC_RI_EVX), PMC_IN8(PMC_RI_EVY),
                       PMC_IN8(PMC_RI_EVZ), PMC_IN8(PMC_RI_DX), PMC_IN8(PMC_RI_DY), PMC_IN8(PMC_RI_DZ))
    float8 xu, yv;
    pmc_sph_rect_sample_xy8(omega, k, b0, b1, z0, x0, x1, y0, y1, PMC_IN8(PMC_RI_U), PMC_IN8(PMC_RI_V), &xu,
                            &yv);
    PMC_RECT_SAMPLE_END(float8, xx, xy, xz, yx, yy, yz, zx, zy, zz, z0, xu, yv, PMC_IN8(PMC_RI_NX),
                        PMC_IN8(PMC_RI_NY), PMC_IN8(PMC_RI_NZ))
    const float8 pdf = PMC_IN8(PMC_RI_PMF) / omega, inv_pdf = 1.0f / pdf;
    const float8 values[PMC_RO_COUNT] = {wx,
                                         wy,
                                         wz,
                                         dist,
                                         cos_light,
                                         pdf,
                                         PMC_IN8(PMC_RI_R) * inv_pdf,
                                         PMC_IN8(PMC_RI_G) * inv_pdf,
                                         PMC_IN8(PMC_RI_B) * inv_pdf,
                                         omega};
#undef PMC_IN8
    for (int v = 0; v < PMC_RO_COUNT; ++v) vstore8(values[v], 0, o[v] + q);
  }
  for (int q = 0; q < count; ++q) { /* pmc_light_sample_rect_end's tests, on its values */
    const int j = at[q];
    __global const PmcLight* l = &lights->lights[light[j]];
    if (!(o[PMC_RO_OMEGA][q] >= PMC_SPH_RECT_MIN_SOLID_ANGLE)) {
      const int k = lane[j];
      state[j] = pmc_quad_sample_by_area(l, pmf[j], o[PMC_RO_OMEGA][q], nee[j].origin, numbers->light_u[k],
                                         numbers->light_v[k], &ls[j]);
      continue;
    }
    const float dist = o[PMC_RO_DIST][q], pdf = o[PMC_RO_PDF][q];
    const float3 weight = make_float3(o[PMC_RO_R][q], o[PMC_RO_G][q], o[PMC_RO_B][q]);
    state[j] = dist > 0.0f && ((l->flags & PMC_LIGHT_TWO_SIDED) || !(o[PMC_RO_COS][q] <= 0.0f)) &&
               pdf > 0.0f && pmc_max3(weight) > 0.0f && isfinite(pmc_max3(weight));
    ls[j].wi = make_float3(o[PMC_RO_WX][q], o[PMC_RO_WY][q], o[PMC_RO_WZ][q]);
    ls[j].dist = dist;
    ls[j].pdf = pdf;
    ls[j].weight = weight;
  }
}
#endif

/* Next-event estimation for lanes lane[0, m) of a batch (their
 * pmc_shade_surface filled nee[0, m)), in three loops over the lanes: the
 * light pick (with the light tree, its levels' importances eight lanes at
 * a time where PMC_LANES allows: pmc_light_pick_lanes) and the light's
 * sample (pmc_light_sample_picked: scalar and branchy) but for the quads
 * sampled by solid angle; those quads' samples (spherical rectangles: about
 * ten dependent square roots and divisions, and four arc cosines), eight
 * lanes at a time in float8 where PMC_LANES allows (pmc_rect_lights_lanes),
 * else lane by lane; then the BSDF's value for the sample's direction,
 * light sample clamping (pmc_clamp_light), MIS and the shadow ray. */
static inline void pmc_next_event_lanes(__constant PmcFrame* frame, const PmcSceneData* scene,
                                        const PmcNeeInput* nee, const int* lane, int m,
                                        const PmcBatchNumbers* numbers, PmcShadeOut* out) {
  const PmcLightSet* lights = &scene->light_set;
  PmcLightSample ls[PMC_LANES];
  int state[PMC_LANES];
#if PMC_LANES8
  int picked[PMC_LANES], light[PMC_LANES];
  float pick_pmf[PMC_LANES], pmf[PMC_LANES];
  pmc_light_pick_lanes(lights, nee, lane, m, numbers, picked, pick_pmf);
  /* The lanes that picked a rectangle quad (pmc_rect_lights_lanes samples
   * them together) apart from the rest, as pmc_light_sample_picked would
   * tell them apart but without a branch on the light's type: where lanes
   * pick different kinds of light (the Cornell box's quad and point) that
   * branch is a coin toss the predictor loses half the time. */
  int rect_at[PMC_LANES], rects = 0, other_at[PMC_LANES], others = 0;
  for (int j = 0; j < m; ++j) {
    state[j] = 0;
    light[j] = picked[j];
    pmf[j] = pick_pmf[j];
    if (!nee[j].active || picked[j] < 0 || !(pick_pmf[j] > 0.0f)) continue;
    const int rect = pmc_light_is_rectangle(&lights->lights[picked[j]]);
    rect_at[rects] = j;
    other_at[others] = j;
    rects += rect;
    others += !rect;
  }
  for (int i = 0; i < others; ++i) {
    const int j = other_at[i], k = lane[j];
    PmcSphRect unused; /* set up for rectangles alone, which these are not */
    state[j] = pmc_light_sample_picked(lights, picked[j], pick_pmf[j], nee[j].origin, nee[j].pick_normal,
                                       numbers->light_u[k], numbers->light_v[k], &ls[j], &unused, &light[j],
                                       &pmf[j]);
  }
  pmc_rect_lights_lanes(lights, nee, rect_at, rects, numbers, lane, state, light, pmf, ls);
#else
  for (int j = 0; j < m; ++j) {
    const int k = lane[j];
    PmcSphRect rect;
    int light = 0;
    float pmf = 0.0f;
    state[j] = nee[j].active ? pmc_light_sample_begin(lights, nee[j].origin, nee[j].pick_normal,
                                                      numbers->light_pick[k], numbers->light_u[k],
                                                      numbers->light_v[k], &ls[j], &rect, &light, &pmf)
                             : 0;
    if (state[j] == PMC_LIGHT_SAMPLE_RECT)
      state[j] = pmc_light_sample_rect_end(
          lights, light, pmf, &rect,
          pmc_sph_rect_sample_xy(rect.solid_angle, rect.k, rect.b0, rect.b1, rect.z0, rect.x0, rect.x1,
                                 rect.y0, rect.y1, numbers->light_u[k], numbers->light_v[k]),
          &ls[j]);
  }
#endif
  for (int j = 0; j < m; ++j) {
    const PmcNeeInput* in = &nee[j];
    if (!state[j] || !(dot(ls[j].wi, in->ng) > 0.0f)) continue;
    float3 wi = pmc_to_local(ls[j].wi, in->t, in->b, in->ns);
    if (!(wi.z > 0.0f)) continue;
    float bsdf_pdf;
    float3 f = pmc_bsdf_eval_pdf(&in->lobes, in->wo, wi, &bsdf_pdf);
    /* MIS against the BSDF sample (traced at every hit, the last one's for
     * emission alone: pmc_shade_surface) */
    float w = ls[j].pdf > 0.0f ? pmc_mis_power(ls[j].pdf, bsdf_pdf) : 1.0f;
    float3 c = pmc_clamp_light(in->throughput * f * ls[j].weight * (wi.z * w), in->clamp);
    if (pmc_max3(c) > 0.0f && isfinite(pmc_max3(c))) {
      PmcShadeOut* o = &out[lane[j]];
      o->shadow = 1;
      o->shadow_org = in->origin;
      o->shadow_dir = ls[j].wi;
      o->shadow_tfar = isinf(ls[j].dist) ? INFINITY : ls[j].dist * (1.0f - 1e-4f);
      o->shadow_rgb = c;
    }
  }
}

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
