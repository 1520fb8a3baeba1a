/* pmc_bsdf_tables_grid.h — the grid of the albedo tables (pmc_bsdf_tables.h)
 * and their bilinear lookup: PMC_BSDF_TABLE_MU x PMC_BSDF_TABLE_N cells, [sqrt(mu)][sqrt(r)],
 * each axis sampled at i / (N - 1) over [0, 1] (mu = cos theta_o, r the
 * perceptual roughness; square roots give grazing angles and smooth lobes,
 * where albedos change fastest, finer steps). Program-scope constant data on the
 * device, static const arrays on the host (PMC_TABLE). */
#ifndef PMC_BSDF_TABLES_GRID_H
#define PMC_BSDF_TABLES_GRID_H

#include "../abi/pmc_vec.h"

#define PMC_BSDF_TABLE_MU 64 /* rows: sqrt(cos theta_o) */
#define PMC_BSDF_TABLE_N 32  /* columns: sqrt(roughness) */

#ifdef __OPENCL_VERSION__
#define PMC_TABLE __constant
#else
#define PMC_TABLE static const
#endif

PMC_FN float pmc_table_lookup(PMC_CONSTANT const float* t, float mu, float r) {
  const float x = sqrt(clamp(mu, 0.0f, 1.0f)) * (float)(PMC_BSDF_TABLE_MU - 1);
  const float y = sqrt(clamp(r, 0.0f, 1.0f)) * (float)(PMC_BSDF_TABLE_N - 1);
  int i = (int)x, j = (int)y;
  i = i < PMC_BSDF_TABLE_MU - 2 ? i : PMC_BSDF_TABLE_MU - 2;
  j = j < PMC_BSDF_TABLE_N - 2 ? j : PMC_BSDF_TABLE_N - 2;
  const float fx = x - (float)i, fy = y - (float)j;
  const int k = i * PMC_BSDF_TABLE_N + j;
  const float a = t[k] + (t[k + 1] - t[k]) * fy;
  const float b = t[k + PMC_BSDF_TABLE_N] + (t[k + PMC_BSDF_TABLE_N + 1] - t[k + PMC_BSDF_TABLE_N]) * fy;
  return a + (b - a) * fx;
}

#endif /* PMC_BSDF_TABLES_GRID_H */
