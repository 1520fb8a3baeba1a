/* next_event_lanes.cl — light samples for a batch's lanes (part of pmc_kernels.cl).
 *
 * The samples of the picked lights: rectangle quads by solid angle eight
 * lanes at a time (pmc_rect_lights_lanes), the others lane by lane (a
 * large environment map's reads started for all its lanes first:
 * pmc_env_sample_prefetch_lanes); then each sample's BSDF value, MIS
 * weight, clamp and shadow ray (pmc_next_event_lanes).
 */

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

#if PMC_LANES8 && PMC_CPU_PREFETCH
/* The lanes at[0, count) that picked the environment map (light index
 * picked[j]) sample it by two guided CDF searches (pmc_env_map_sample), each
 * a chain of dependent reads: the row's guide bucket, then the row's CDF
 * around it, then the texel and the row's sine. In a large map each read is
 * a cache miss that the lane waits for, and the next lane's misses start
 * only after it. So the reads are started here for all of them, one link of
 * the chain a loop, each index computed as the sampler will compute it
 * (pmc_cdf_search_guided reads the same entries): the lanes' misses overlap,
 * and the sampler then finds its lines cached. The marginal CDF and its
 * guide (a few KB) stay cached. Same samples, same image. */
static inline void pmc_env_sample_prefetch_lanes(const PmcLightSet* ls, const int* at, int count,
                                                 const int* picked, const int* lane,
                                                 const PmcBatchNumbers* numbers) {
  const PmcLightHeader* h = &ls->h;
  const int w = h->env_width, hh = h->env_height;
  if (!PMC_ENV_PREFETCHED(h)) return;
  PMC_GLOBAL const float* marginal = pmc_env_marginal(ls);
  PMC_GLOBAL const float* marginal_guide = pmc_env_marginal_guide(ls);
  int env_at[PMC_LANES], row[PMC_LANES], bucket[PMC_LANES], n = 0;
  for (int i = 0; i < count; ++i) {
    const int j = at[i];
    env_at[n] = j;
    n += ls->lights[picked[j]].type == PMC_LIGHT_ENV;
  }
  if (n < 2) return;            /* a lone lane's chain has nothing to overlap with */
  for (int q = 0; q < n; ++q) { /* the row, then its guide's bucket */
    const int k = lane[env_at[q]];
    row[q] = pmc_cdf_search_guided(marginal, marginal_guide, hh, numbers->light_u[k]);
    const int b = (int)(numbers->light_v[k] * (float)w);
    bucket[q] = b < 0 ? 0 : (b < w ? b : w - 1);
    PMC_TOUCH(pmc_env_row_guide(ls, row[q]) + bucket[q]);
  }
  for (int q = 0; q < n; ++q) { /* the row's CDF entries the search compares first */
    PMC_GLOBAL const float* guide = pmc_env_row_guide(ls, row[q]);
    PMC_GLOBAL const float* conditional = pmc_env_row_cdf(ls, row[q]);
    const int lo = (int)guide[bucket[q]], hi = (int)guide[bucket[q] + 1];
    PMC_TOUCH(conditional + (lo > 0 ? lo - 1 : 0));
    PMC_TOUCH(conditional + (hi < w ? hi : w - 1));
  }
  for (int q = 0; q < n; ++q) { /* the texel and the row's sine */
    PMC_GLOBAL const float* conditional = pmc_env_row_cdf(ls, row[q]);
    const int col = pmc_cdf_search_guided(conditional, pmc_env_row_guide(ls, row[q]), w,
                                          numbers->light_v[lane[env_at[q]]]);
    PMC_ENV_TEXEL_TOUCH(ls, row[q] * w + col);
    PMC_TOUCH(pmc_env_row_sines(ls) + row[q]);
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
#if PMC_CPU_PREFETCH
  pmc_env_sample_prefetch_lanes(lights, other_at, others, picked, lane, numbers);
#endif
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
