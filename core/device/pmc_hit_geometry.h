/* pmc_hit_geometry.h — a ray hit's geometry from its triangle, for a batch's
 * lanes: one source for the scalar form (a batch of 1 on GPUs, the host) and
 * the float8 form (eight lanes of a CPU batch at once).
 *
 * From the ray's unit direction, the hit's barycentrics and the triangle's
 * corners (positions, and where the mesh has them vertex normals and uvs):
 * the point, the unit geometric normal turned to face the ray, twice the
 * triangle's area, the shading normal (the interpolated vertex normal on the
 * geometric normal's side; the geometric normal where it would face away
 * from the viewer), whether the ray arrived on the side the normals point to,
 * the uv (the barycentrics without uvs), the triangle's edges and uv edges
 * (the ray cone's inputs, pmc_raycone.h), the corners' largest |coordinate|
 * (the ray offsets' scale, PMC_HIT_SCALE), and the unit tangent: the
 * mesh's smooth tangent where it has them (the corners' octahedral words,
 * decoded and interpolated), else dp/du, orthogonalised to the shading
 * normal (any tangent when uvs give none).
 *
 * PMC_HIT_GEOMETRY writes it once for two forms: F is float or float8, I its
 * integer type (a comparison's result), SEL(c, a, b) its select (pmc_vec.h);
 * LD/LDI read a float/integer field of the lanes, ST stores one. The dot and
 * cross products and lengths are written out and the code is straight-line,
 * so every lane of the float8 form equals the scalar form bit for bit: a
 * batch of 1 and a batch of 64 render the same image. Flags hold -1 (true)
 * or 0, which both forms' selects read alike.
 */
#ifndef PMC_HIT_GEOMETRY_H
#define PMC_HIT_GEOMETRY_H

#include "../abi/pmc_vec.h"
#include "pmc_geometry.h"

#ifndef PMC_LANES
#define PMC_LANES 1
#endif

/* A batch's hits, a field per array (lane k at [k]); the float8 form reads
 * eight lanes from each. The loader fills the inputs; an escaped ray's lane
 * holds zeros but for its ray (its outputs are not used, its cone radius 0
 * gives no gradients). pmc_ray_cone_lanes reads the direction, the normal,
 * the radius and the edges from here, the lights the rays met their rays. */
typedef struct PmcHitLanes {
  /* in */
  float dx[PMC_LANES], dy[PMC_LANES], dz[PMC_LANES]; /* unit ray direction */
  float b1[PMC_LANES], b2[PMC_LANES];                /* barycentrics of corners 1 and 2 */
  float p0x[PMC_LANES], p0y[PMC_LANES], p0z[PMC_LANES], p1x[PMC_LANES], p1y[PMC_LANES], p1z[PMC_LANES];
  float p2x[PMC_LANES], p2y[PMC_LANES], p2z[PMC_LANES];
  int normals[PMC_LANES]; /* -1: the corners' vertex normals follow */
  float n0x[PMC_LANES], n0y[PMC_LANES], n0z[PMC_LANES], n1x[PMC_LANES], n1y[PMC_LANES], n1z[PMC_LANES];
  float n2x[PMC_LANES], n2y[PMC_LANES], n2z[PMC_LANES];
  int uvs[PMC_LANES]; /* -1: the corners' uvs follow; else (0,0), (1,0), (0,1) */
  float t0u[PMC_LANES], t0v[PMC_LANES], t1u[PMC_LANES], t1v[PMC_LANES], t2u[PMC_LANES], t2v[PMC_LANES];
  int tangents[PMC_LANES]; /* -1: the corners' smooth tangents follow, as the octahedral */
  float o0x[PMC_LANES], o0y[PMC_LANES], o1x[PMC_LANES], o1y[PMC_LANES]; /* map's two snorms */
  float o2x[PMC_LANES], o2y[PMC_LANES];                                 /* (pmc_snorm16) */
  float radius[PMC_LANES]; /* the ray cone's at the hit (pmc_ray_cone_lanes) */
  /* in, for the lights the rays met (the shade kernel's pmc_lights_seen_lanes) */
  float ox[PMC_LANES], oy[PMC_LANES], oz[PMC_LANES], t_hit[PMC_LANES];
  int escaped[PMC_LANES]; /* -1: the ray met no surface */
  /* out */
  float px[PMC_LANES], py[PMC_LANES], pz[PMC_LANES];                   /* the point */
  float nx[PMC_LANES], ny[PMC_LANES], nz[PMC_LANES], area2[PMC_LANES]; /* geometric normal, 2 x area */
  float sx[PMC_LANES], sy[PMC_LANES], sz[PMC_LANES];                   /* shading normal */
  float tx[PMC_LANES], ty[PMC_LANES], tz[PMC_LANES];                   /* tangent */
  float u[PMC_LANES], v[PMC_LANES];
  int front[PMC_LANES];   /* -1: arrived on the normals' side */
  float scale[PMC_LANES]; /* the largest |coordinate| of the corners (PMC_HIT_SCALE) */
  float e1x[PMC_LANES], e1y[PMC_LANES], e1z[PMC_LANES], e2x[PMC_LANES], e2y[PMC_LANES], e2z[PMC_LANES];
  float d1u[PMC_LANES], d1v[PMC_LANES], d2u[PMC_LANES], d2v[PMC_LANES];
} PmcHitLanes;

/* Lane k's surface inputs, all zeros (an escaped ray's lane: its ray stays). */
PMC_FN void pmc_hit_lane_clear_surface(PmcHitLanes* L, int k) {
  L->b1[k] = L->b2[k] = 0.0f;
  L->p0x[k] = L->p0y[k] = L->p0z[k] = L->p1x[k] = L->p1y[k] = L->p1z[k] = 0.0f;
  L->p2x[k] = L->p2y[k] = L->p2z[k] = 0.0f;
  L->normals[k] = L->uvs[k] = 0;
  L->n0x[k] = L->n0y[k] = L->n0z[k] = L->n1x[k] = L->n1y[k] = L->n1z[k] = 0.0f;
  L->n2x[k] = L->n2y[k] = L->n2z[k] = 0.0f;
  L->t0u[k] = L->t0v[k] = L->t1u[k] = L->t1v[k] = L->t2u[k] = L->t2v[k] = 0.0f;
  L->tangents[k] = 0;
  L->o0x[k] = L->o0y[k] = L->o1x[k] = L->o1y[k] = L->o2x[k] = L->o2y[k] = 0.0f;
  L->radius[k] = 0.0f;
}

/* Lane k's inputs, all zeros (a spare lane). */
PMC_FN void pmc_hit_lane_clear(PmcHitLanes* L, int k) {
  pmc_hit_lane_clear_surface(L, k);
  L->dx[k] = L->dy[k] = L->dz[k] = 0.0f;
  L->ox[k] = L->oy[k] = L->oz[k] = L->t_hit[k] = 0.0f;
  L->escaped[k] = 0;
}

/* A corner's unit tangent from its octahedral snorms x, y (pmc_oct_decode's
 * arithmetic, its dot product written out) into vx, vy, vz. */
#define PMC_OCT_UNFOLD(F, I, SEL, x, y, vx, vy, vz)                      \
  {                                                                      \
    const F one_ = (F)(1.0f), z_ = one_ - fabs(x) - fabs(y);             \
    const I fold_ = z_ < (F)(0.0f);                                      \
    const F ox_ = (one_ - fabs(y)) * SEL((x) >= (F)(0.0f), one_, -one_); \
    const F oy_ = (one_ - fabs(x)) * SEL((y) >= (F)(0.0f), one_, -one_); \
    const F ux_ = SEL(fold_, ox_, x), uy_ = SEL(fold_, oy_, y);          \
    const F inv_ = one_ / sqrt(ux_ * ux_ + uy_ * uy_ + z_ * z_);         \
    vx = ux_ * inv_, vy = uy_ * inv_, vz = z_ * inv_;                    \
  }

#define PMC_HIT_GEOMETRY(NAME, F, I, SEL, LD, LDI, ST)                                                \
  PMC_FN void NAME(PmcHitLanes* L, int k) {                                                           \
    const F zero = (F)(0.0f), one = (F)(1.0f);                                                        \
    const F dx = LD(dx), dy = LD(dy), dz = LD(dz), b1 = LD(b1), b2 = LD(b2);                          \
    const F b0 = one - b1 - b2;                                                                       \
    const F p0x = LD(p0x), p0y = LD(p0y), p0z = LD(p0z), p1x = LD(p1x), p1y = LD(p1y), p1z = LD(p1z); \
    const F p2x = LD(p2x), p2y = LD(p2y), p2z = LD(p2z);                                              \
    ST(scale, PMC_HIT_SCALE(p0x, p0y, p0z, p1x, p1y, p1z, p2x, p2y, p2z));                            \
    ST(px, (p0x * b0) + (p1x * b1) + (p2x * b2));                                                     \
    ST(py, (p0y * b0) + (p1y * b1) + (p2y * b2));                                                     \
    ST(pz, (p0z * b0) + (p1z * b1) + (p2z * b2));                                                     \
    const F e1x = p1x - p0x, e1y = p1y - p0y, e1z = p1z - p0z;                                        \
    const F e2x = p2x - p0x, e2y = p2y - p0y, e2z = p2z - p0z;                                        \
    F gx = e1y * e2z - e1z * e2y, gy = e1z * e2x - e1x * e2z, gz = e1x * e2y - e1y * e2x;             \
    const F area2 = sqrt(gx * gx + gy * gy + gz * gz);                                                \
    const I has_area = (area2 > zero) & isfinite(area2);                                              \
    const F inv_area2 = one / area2;                                                                  \
    gx = SEL(has_area, gx * inv_area2, -dx);                                                          \
    gy = SEL(has_area, gy * inv_area2, -dy);                                                          \
    gz = SEL(has_area, gz * inv_area2, -dz);                                                          \
    /* Outside is where the vertex normals point, else the winding's normal                           \
     * (glass knows from it whether a ray enters or leaves). */                                       \
    F outside = gx * dx + gy * dy + gz * dz;                                                          \
    const I flip = outside > zero; /* every surface is two-sided */                                   \
    gx = SEL(flip, -gx, gx);                                                                          \
    gy = SEL(flip, -gy, gy);                                                                          \
    gz = SEL(flip, -gz, gz);                                                                          \
    F nx = LD(n0x) * b0 + LD(n1x) * b1 + LD(n2x) * b2;                                                \
    F ny = LD(n0y) * b0 + LD(n1y) * b1 + LD(n2y) * b2;                                                \
    F nz = LD(n0z) * b0 + LD(n1z) * b1 + LD(n2z) * b2;                                                \
    const F nl = sqrt(nx * nx + ny * ny + nz * nz);                                                   \
    const I smooth = LDI(normals) & (nl > zero) & isfinite(nl);                                       \
    const F inv_nl = one / nl;                                                                        \
    nx = nx * inv_nl, ny = ny * inv_nl, nz = nz * inv_nl;                                             \
    outside = SEL(smooth, nx * dx + ny * dy + nz * dz, outside);                                      \
    const I turn = nx * gx + ny * gy + nz * gz < zero;                                                \
    F sx = SEL(smooth, SEL(turn, -nx, nx), gx);                                                       \
    F sy = SEL(smooth, SEL(turn, -ny, ny), gy);                                                       \
    F sz = SEL(smooth, SEL(turn, -nz, nz), gz);                                                       \
    ST(front, outside <= zero);                                                                       \
    const I uvs = LDI(uvs);                                                                           \
    const F t0u = LD(t0u), t0v = LD(t0v), t1u = LD(t1u), t1v = LD(t1v), t2u = LD(t2u), t2v = LD(t2v); \
    ST(u, SEL(uvs, t0u* b0 + t1u * b1 + t2u * b2, b1));                                               \
    ST(v, SEL(uvs, t0v* b0 + t1v * b1 + t2v * b2, b2));                                               \
    /* a shading normal facing away from the viewer: the geometric one */                             \
    const I away = sx * -dx + sy * -dy + sz * -dz <= zero;                                            \
    sx = SEL(away, gx, sx);                                                                           \
    sy = SEL(away, gy, sy);                                                                           \
    sz = SEL(away, gz, sz);                                                                           \
    /* Tangent frame from the uv parameterisation (dp/du), orthogonalised to                          \
     * the shading normal; any tangent (pmc_basis's) where it has none. */                            \
    const F d1u = t1u - t0u, d1v = t1v - t0v, d2u = t2u - t0u, d2v = t2v - t0v;                       \
    const F det = d1u * d2v - d1v * d2u;                                                              \
    F tx = e1x * d2v - e2x * d1v, ty = e1y * d2v - e2y * d1v, tz = e1z * d2v - e2z * d1v;             \
    const F st = sx * tx + sy * ty + sz * tz;                                                         \
    tx = tx - sx * st, ty = ty - sy * st, tz = tz - sz * st;                                          \
    const F tl = sqrt(tx * tx + ty * ty + tz * tz);                                                   \
    const I has_tangent = (fabs(det) > (F)(1e-20f)) & (tl > (F)(1e-20f)) & isfinite(tl);              \
    const F scale = SEL(det < zero, -one, one) / tl;                                                  \
    const F sign = SEL(sz >= zero, one, -one);                                                        \
    const F a = -one / (sign + sz);                                                                   \
    tx = SEL(has_tangent, tx * scale, one + sign * sx * sx * a);                                      \
    ty = SEL(has_tangent, ty * scale, sign * (sx * sy * a));                                          \
    tz = SEL(has_tangent, tz * scale, -sign * sx);                                                    \
    /* The mesh's smooth tangents where it has them (PMC_TRI_TANGENTS), the                           \
     * corners' interpolated and orthogonalised to the shading normal. */                             \
    F a0x, a0y, a0z, a1x, a1y, a1z, a2x, a2y, a2z;                                                    \
    PMC_OCT_UNFOLD(F, I, SEL, LD(o0x), LD(o0y), a0x, a0y, a0z)                                        \
    PMC_OCT_UNFOLD(F, I, SEL, LD(o1x), LD(o1y), a1x, a1y, a1z)                                        \
    PMC_OCT_UNFOLD(F, I, SEL, LD(o2x), LD(o2y), a2x, a2y, a2z)                                        \
    F vx = a0x * b0 + a1x * b1 + a2x * b2, vy = a0y * b0 + a1y * b1 + a2y * b2;                       \
    F vz = a0z * b0 + a1z * b1 + a2z * b2;                                                            \
    const F sv = sx * vx + sy * vy + sz * vz;                                                         \
    vx = vx - sx * sv, vy = vy - sy * sv, vz = vz - sz * sv;                                          \
    const F vl = sqrt(vx * vx + vy * vy + vz * vz);                                                   \
    const I smooth_tangent = LDI(tangents) & (vl > (F)(1e-6f)) & isfinite(vl);                        \
    const F inv_vl = one / vl;                                                                        \
    ST(tx, SEL(smooth_tangent, vx* inv_vl, tx));                                                      \
    ST(ty, SEL(smooth_tangent, vy* inv_vl, ty));                                                      \
    ST(tz, SEL(smooth_tangent, vz* inv_vl, tz));                                                      \
    ST(nx, gx);                                                                                       \
    ST(ny, gy);                                                                                       \
    ST(nz, gz);                                                                                       \
    ST(area2, area2);                                                                                 \
    ST(sx, sx);                                                                                       \
    ST(sy, sy);                                                                                       \
    ST(sz, sz);                                                                                       \
    ST(e1x, e1x);                                                                                     \
    ST(e1y, e1y);                                                                                     \
    ST(e1z, e1z);                                                                                     \
    ST(e2x, e2x);                                                                                     \
    ST(e2y, e2y);                                                                                     \
    ST(e2z, e2z);                                                                                     \
    ST(d1u, d1u);                                                                                     \
    ST(d1v, d1v);                                                                                     \
    ST(d2u, d2u);                                                                                     \
    ST(d2v, d2v);                                                                                     \
  }

/* The scalar form, lane k. */
#define PMC_HIT_LD1(f) (L->f[k])
#define PMC_HIT_ST1(f, x) (L->f[k] = (x))
PMC_HIT_GEOMETRY(pmc_hit_geometry_at, float, int, PMC_SEL_SCALAR, PMC_HIT_LD1, PMC_HIT_LD1, PMC_HIT_ST1)
#undef PMC_HIT_LD1
#undef PMC_HIT_ST1

#endif /* PMC_HIT_GEOMETRY_H */
