// camera.cpp — camera files, bounding-box framing, frame fields.
#include "core/camera.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace pmc {
namespace {

float3 load(const float* p) { return make_float3(p[0], p[1], p[2]); }
void store(float3 v, float* p) { p[0] = v.x, p[1] = v.y, p[2] = v.z; }
constexpr float kDegrees = 3.14159265358979f / 180.0f;

}  // namespace

std::optional<Camera> read_camera_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  Camera cam;
  std::string line;
  int line_no = 0;
  bool has_from = false, has_at = false;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string key;
    if (!(ls >> key) || key[0] == '#') continue;
    float* dst = key == "from" ? cam.from : key == "at" ? cam.at : key == "up" ? cam.up : nullptr;
    if (dst) {
      if (!(ls >> dst[0] >> dst[1] >> dst[2]))
        fail(path, ": line ", line_no, ": '", key, "' needs three numbers");
      has_from |= key == "from";
      has_at |= key == "at";
    } else if (key == "fov") {
      if (!(ls >> cam.fov_degrees) || !(cam.fov_degrees > 0.0f && cam.fov_degrees < 180.0f))
        fail(path, ": line ", line_no, ": 'fov' needs a number of degrees in (0, 180)");
    } else {
      fail(path, ": line ", line_no, ": unknown key '", key, "' (expected from, at, up, fov)");
    }
  }
  if (!has_from || !has_at) fail(path, ": a camera file needs both 'from' and 'at'");
  return cam;
}

Camera frame_bounds(const Bounds& bounds, float fov_degrees, float aspect) {
  Camera cam;
  cam.fov_degrees = fov_degrees;
  float3 lo = load(bounds.lo), hi = load(bounds.hi);
  float3 center = (lo + hi) * 0.5f;
  float3 half = (hi - lo) * 0.5f;
  float radius = std::fmax(length(half), 1e-6f);
  float half_fov = 0.5f * fov_degrees * kDegrees;
  float half_fov_x = std::atan(std::tan(half_fov) * std::fmin(aspect, 1.0f));
  float distance = radius / std::sin(std::fmin(half_fov, half_fov_x));
  store(center, cam.at);
  store(center + make_float3(0.0f, 0.0f, distance), cam.from);
  return cam;
}

void fill_frame_camera(const Camera& camera, PmcFrame& frame) {
  float3 from = load(camera.from), at = load(camera.at), up = load(camera.up);
  float3 forward = at - from;
  if (!(length(forward) > 0.0f)) fail("camera: 'from' and 'at' are the same point");
  forward = normalize(forward);
  float3 right = cross(forward, up);
  if (!(length(right) > 1e-6f)) {  // up parallel to the view: pick any perpendicular
    float3 t, b;
    pmc_basis(forward, &t, &b);
    right = t;
  }
  right = normalize(right);
  float3 true_up = cross(right, forward);
  float tan_half = std::tan(0.5f * camera.fov_degrees * kDegrees);
  float aspect = float(frame.width) / float(frame.height);
  store(from, frame.cam_eye);
  store(forward, frame.cam_forward);
  store(right * (tan_half * aspect), frame.cam_right);
  store(true_up * tan_half, frame.cam_up);
  // Spread angle of one pixel (Akenine-Möller et al. 2021, eq. 30).
  frame.cam_spread = std::atan(2.0f * tan_half / float(frame.height));
}

}  // namespace pmc
