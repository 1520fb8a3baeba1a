// lights.cpp — power-proportional emissive triangle selection.
#include "core/lights.h"

#include <cmath>

namespace pmc {

LightTable build_light_table(const Scene& scene, const std::vector<float>& emission) {
  LightTable t;
  t.triangle_pmf.assign(scene.triangles.size(), 0.0f);
  std::vector<double> power;
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const PmcTriangle& tri = scene.triangles[i];
    const float* e = &emission[3 * size_t(tri.material)];
    double lum = 0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2];
    if (!(lum > 0.0) || !std::isfinite(lum)) continue;
    const float* p0 = &scene.positions[3 * size_t(tri.v[0])];
    const float* p1 = &scene.positions[3 * size_t(tri.v[1])];
    const float* p2 = &scene.positions[3 * size_t(tri.v[2])];
    double a[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    double b[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    double area = 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (!(area > 0.0) || !std::isfinite(area)) continue;  // zero-area emitters cannot be sampled
    t.triangles.push_back(int(i));
    power.push_back(area * lum);
  }
  double total = 0.0;
  for (double p : power) total += p;
  double running = 0.0;
  for (size_t k = 0; k < power.size(); ++k) {
    running += power[k];
    t.cdf.push_back(k + 1 == power.size() ? 1.0f : float(running / total));
    t.triangle_pmf[size_t(t.triangles[k])] = float(power[k] / total);
  }
  t.total_power = float(total);
  return t;
}

}  // namespace pmc
