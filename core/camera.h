// camera.h — the pinhole camera: where it comes from and what kernels get.
//
// A camera is from/at/up/vertical fov. It comes from the command line, else
// from a SCENE.camera file next to the OBJ (lines "from x y z", "at x y z",
// "up x y z", "fov deg"), else it frames the scene's bounding box. The frame
// fields the camera kernel reads are filled by fill_frame_camera().
#pragma once

#include <optional>
#include <string>

#include "core/abi/pmc_types.h"
#include "core/scene.h"

namespace pmc {

struct Camera {
  float from[3] = {0, 0, 1};
  float at[3] = {0, 0, 0};
  float up[3] = {0, 1, 0};
  float fov_degrees = 45.0f;
};

// Reads a .camera file; returns nothing if the file does not exist.
std::optional<Camera> read_camera_file(const std::string& path);
// A camera looking at the bounds' centre from +z, far enough to see all of it.
Camera frame_bounds(const Bounds& bounds, float fov_degrees, float aspect);
// Fills the camera fields of `frame` (width/height must be set already).
void fill_frame_camera(const Camera& camera, PmcFrame& frame);

}  // namespace pmc
