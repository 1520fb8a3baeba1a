/* samplers8.cl — float8 twins of scalar samplers (part of pmc_kernels.cl).
 *
 * Sines and cosines in turns, the cosine-weighted hemisphere (the shade
 * batch's diffuse samples) and the spherical rectangle's point (the quads'
 * light samples, next_event_lanes.cl), eight lanes at a time. Each performs
 * its scalar twin's operations (core/abi/pmc_vec.h, core/device/pmc_bsdf.h,
 * core/device/pmc_lights.h) in the same order, so every lane's value is the
 * scalar form's bit for bit.
 */

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
