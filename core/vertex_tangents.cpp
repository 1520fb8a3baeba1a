// vertex_tangents.cpp — accumulate each triangle's dp/du at its corners.
#include "core/vertex_tangents.h"

#include <cmath>
#include <unordered_map>

namespace pmc {
namespace {

struct V3 {
  double x = 0, y = 0, z = 0;
};
V3 sub(const float* a, const float* b) {
  return {double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]};
}
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 scale(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }

// The corner's identity: position, normal and uv indices and the uv orientation.
uint64_t corner_key(int v, int n, int t, bool mirrored) {
  uint64_t h = uint64_t(uint32_t(v)) * 0x9E3779B97F4A7C15ull;
  h ^= (uint64_t(uint32_t(n)) + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2));
  h ^= (uint64_t(uint32_t(t)) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2));
  return h * 2 + (mirrored ? 1 : 0);
}

}  // namespace

VertexTangents vertex_tangents(const Scene& scene) {
  const size_t count = scene.triangles.size();
  VertexTangents out;
  out.corners.assign(count, {});
  out.valid.assign(count, false);
  std::vector<V3> face(count);
  std::vector<char> mirrored(count, 0), has(count, 0);
  std::unordered_map<uint64_t, V3> sums;
  sums.reserve(count * 2);
  for (size_t i = 0; i < count; ++i) {
    const PmcTriangle& t = scene.triangles[i];
    if (t.t[0] < 0) continue;
    const float* p0 = &scene.positions[3 * size_t(t.v[0])];
    const float* p1 = &scene.positions[3 * size_t(t.v[1])];
    const float* p2 = &scene.positions[3 * size_t(t.v[2])];
    const float* t0 = &scene.uvs[2 * size_t(t.t[0])];
    const float* t1 = &scene.uvs[2 * size_t(t.t[1])];
    const float* t2 = &scene.uvs[2 * size_t(t.t[2])];
    const double d1x = t1[0] - t0[0], d1y = t1[1] - t0[1], d2x = t2[0] - t0[0], d2y = t2[1] - t0[1];
    const double det = d1x * d2y - d1y * d2x;
    const V3 e1 = sub(p1, p0), e2 = sub(p2, p0);
    V3 dpdu = scale(sub(p1, p0), d2y);  // (p1 - p0) d2.y - (p2 - p0) d1.y, as the kernel's
    dpdu = {dpdu.x - e2.x * d1y, dpdu.y - e2.y * d1y, dpdu.z - e2.z * d1y};
    const double len = std::sqrt(dot(dpdu, dpdu));
    const V3 n = cross(e1, e2);
    const double area = 0.5 * std::sqrt(dot(n, n));
    if (!(std::fabs(det) > 1e-20) || !(len > 0) || !std::isfinite(len) || !(area > 0)) continue;
    face[i] = scale(dpdu, (det < 0 ? -1.0 : 1.0) * area / len);  // unit +u direction, weighted by area
    mirrored[i] = det < 0;
    has[i] = 1;
    for (int k = 0; k < 3; ++k) {
      V3& s = sums[corner_key(t.v[k], t.n[k], t.t[k], det < 0)];
      s = {s.x + face[i].x, s.y + face[i].y, s.z + face[i].z};
    }
  }
  for (size_t i = 0; i < count; ++i) {
    if (!has[i]) continue;
    const PmcTriangle& t = scene.triangles[i];
    const V3 e1 = sub(&scene.positions[3 * size_t(t.v[1])], &scene.positions[3 * size_t(t.v[0])]);
    const V3 e2 = sub(&scene.positions[3 * size_t(t.v[2])], &scene.positions[3 * size_t(t.v[0])]);
    const V3 ng = cross(e1, e2);
    bool ok = true;
    for (int k = 0; k < 3 && ok; ++k) {
      V3 tv = sums[corner_key(t.v[k], t.n[k], t.t[k], mirrored[i] != 0)];
      V3 n = ng;
      if (t.n[k] >= 0) {
        const float* vn = &scene.normals[3 * size_t(t.n[k])];
        n = {vn[0], vn[1], vn[2]};
      }
      const double nl = std::sqrt(dot(n, n));
      if (nl > 0 && std::isfinite(nl)) {
        n = scale(n, 1.0 / nl);
        tv = {tv.x - n.x * dot(n, tv), tv.y - n.y * dot(n, tv), tv.z - n.z * dot(n, tv)};
      }
      const double tl = std::sqrt(dot(tv, tv));
      // A corner whose tangents cancel (a pole, a fold) keeps the face's own.
      if (!(tl > 1e-12) || !std::isfinite(tl)) {
        ok = false;
        break;
      }
      for (int c = 0; c < 3; ++c) out.corners[i][size_t(3 * k + c)] = float((&tv.x)[c] / tl);
    }
    out.valid[i] = ok;
  }
  return out;
}

}  // namespace pmc
