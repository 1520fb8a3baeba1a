// lights.h — the scene's lights: the lights file, the environment, and the
// table that next-event estimation samples.
//
// Data flow: read_lights_file() parses and checks a lights JSON file
// (the lights setting, or SCENE.lights.json beside the OBJ) into SceneLights and
// loads its environment map (core/env_map.h); the command line may replace
// the environment (the env and env_map settings). At render time build_light_table()
// turns SceneLights plus the scene's emissive triangles into one PmcLight
// array in the order the kernels expect (environment, sun disks, quads, the
// rest), each with its probability of being picked (proportional to power),
// the per-triangle pick probabilities (MIS when a path hits an emitter) and
// the map's device data. core/device/pmc_lights.h samples and evaluates it.
//
// Units and conventions (README "Lights"): distances in scene units,
// intensity W/sr, irradiance W/m^2 at normal incidence, radiance W/(m^2 sr);
// `direction` of a directional light is the direction the light travels, of
// a spot where it points; a quad emits toward edge_u x edge_v.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/abi/pmc_types.h"
#include "core/env_map.h"
#include "core/scene.h"

namespace pmc {

// One entry of a lights file's "lights" array, checked.
struct LightSpec {
  enum class Type { Point, Spot, Directional, Quad };
  Type type = Type::Point;
  float position[3] = {0, 0, 0};
  float direction[3] = {0, 0, -1};  // unit (normalised when read)
  float rgb[3] = {0, 0, 0};         // intensity, irradiance or radiance by type
  float cone_angle_deg = 45.0f;     // spot: full opening angle
  float blend = 0.15f;              // spot: fraction of the cone over which it fades
  float angle_deg = 0.0f;           // directional: apparent diameter (0: a delta light)
  float corner[3] = {0, 0, 0}, edge_u[3] = {1, 0, 0}, edge_v[3] = {0, 0, 1};
  bool two_sided = false;
};

// The environment: a constant radiance, or a map (loaded), scaled and turned.
struct EnvironmentSpec {
  bool present = false;
  float radiance[3] = {0, 0, 0};  // when no map
  std::shared_ptr<const EnvMap> map;
  float scale = 1.0f;  // multiplies the radiance or the map
  float rotate_y_deg = 0.0f;
};

struct SceneLights {
  std::string source;  // the lights file ("" when none)
  std::vector<LightSpec> lights;
  EnvironmentSpec environment;
};

// Reads a lights file (and loads its environment map, resolved relative to
// the file). Any problem is a pmc::Error naming the file and the field.
SceneLights read_lights_file(const std::string& path);
// An environment from a map file (the env_map setting).
EnvironmentSpec environment_from_map(const std::string& path, float scale, float rotate_y_deg);
// An environment of constant radiance (the env setting); absent when black.
EnvironmentSpec constant_environment(const float radiance[3]);

struct LightTable {
  std::vector<PmcLight> lights;     // kernel order, each with pmf and cdf
  std::vector<float> triangle_pmf;  // per scene triangle: pick probability (0: not a light)
  std::vector<float> env_data;      // the map's texels and CDFs (one 0 when there is no map)
  PmcLightHeader header{};
  double total_power = 0.0;  // sum of the lights' power estimates (luminance, W)
  size_t emissive_triangles = 0;
};

// `emission[m]` is the (constant) emitted radiance of material m, rgb.
// Lights are picked by power: pi A L for area lights (x2 two-sided), 4 pi I
// for points, 2 pi I (1 - cos) for spots, pi r^2 E for directional lights and
// pi r^2 x the radiance integrated over the sphere for the environment, r
// the radius of the scene's bounding sphere.
LightTable build_light_table(const Scene& scene, const std::vector<float>& emission,
                             const SceneLights& lights);

}  // namespace pmc
