/* light_pick_lanes.cl — the light pick for a batch's lanes (part of pmc_kernels.cl).
 *
 * Next-event estimation's pick of one light per lane (pmc_light_pick_lanes):
 * the lights at infinity against the tree, then the light tree's levels,
 * two nodes' importances eight lanes at a time in float8. The float8 forms
 * compute what their scalar twins in core/device/pmc_lights.h compute, bit
 * for bit, so a lane picks what pmc_light_pick would.
 */

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
