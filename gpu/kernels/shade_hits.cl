/* shade_hits.cl — a batch's hits up to their material (part of pmc_kernels.cl).
 *
 * What pmc_shade does for each batch before any material runs: the hit
 * point record (PmcHitPoint), the queues' outputs (PmcShadeOut) and light
 * sample clamping, loading the hits into lanes (pmc_hit_load), their
 * geometry eight lanes at a time, the lights the rays met, ray cones, the
 * cache's keys and texels, and the material's shading inputs. Included by
 * pmc_kernels.cl after its headers; it uses PMC_LANES8 and PMC_SEL_VECTOR
 * from there.
 */

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
 * spider, whose camera rays mostly meet its sky), and in a large map
 * (PMC_ENV_PREFETCHED) their loads started, then each ray's radiance and MIS
 * weight, light by light in pmc_infinity_seen's order. */
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
    if (map && PMC_ENV_PREFETCHED(&ls->h)) /* a large map: every lane's texel on its way at once */
      for (int q = 0; q < m; ++q) PMC_ENV_TEXEL_TOUCH(ls, texel[q]);
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
    /* width, and ellipse where it shows, its major axis as the pixel's samples so far stratify it */
    pmc_shading_footprint(sp, hp->g1, hp->g2, hp->ellipse,
                          pmc_footprint_major_scale(pmc_path_sample(frame, hp->path)));
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
