// lights.h — the scene's lights: the lights file, the environment, and the
// table that next-event estimation samples.
//
// Data flow: read_lights_file() parses and checks a lights JSON file
// (the lights setting, or SCENE.lights.json beside the OBJ) into SceneLights and
// loads its environment map (core/env_map.h); the command line may replace
// the environment (the env and env_map settings). At render time build_light_table()
// turns SceneLights plus the scene's emissive triangles into one PmcLight
// array in the order the kernels expect (environment, sun disks, directional
// deltas, quads, the rest), each with its probability of being picked by
// power, the light tree over the finite lights (core/light_tree.h), each
// triangle's light (MIS when a path hits an emitter) and the map's device
// data. core/device/pmc_lights.h samples and evaluates it.
//
// Two samplers pick the light of next-event estimation (LightSampler):
//   Tree (the default): a light at infinity (environment, sun disk,
//     directional) or the light tree, in proportion to an irradiance
//     estimate at the shading point (p, n): its irradiance at normal
//     incidence times a bound of the cosine for lights at infinity, the root's
//     importance for the tree; inside the tree, each child by its importance
//     (pmc_lights.h). Nothing depends on the scene's extent: a far stray
//     object does not change any probability.
//   Power: one global pmf by power, lights at infinity weighted by the
//     scene's bounding sphere (the old selection, kept for comparisons).
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

// Whether two sets of lights give the same light table: the same lights in
// the same order with the same fields, and the same environment (a map by
// identity: the one loaded object). The source file's name does not count.
bool same_lights(const SceneLights& a, const SceneLights& b);

// Reads a lights file (and loads its environment map, resolved relative to
// the file). Any problem is a pmc::Error naming the file and the field.
SceneLights read_lights_file(const std::string& path);
// An environment from a map file (the env_map setting).
EnvironmentSpec environment_from_map(const std::string& path, float scale, float rotate_y_deg);
// An environment of constant radiance (the env setting); absent when black.
EnvironmentSpec constant_environment(const float radiance[3]);

enum class LightSampler { Tree, Power };

struct LightTable {
  std::vector<PmcLight> lights;              // kernel order, each with pmf and cdf (and its tree trail)
  std::vector<int32_t> triangle_light;       // per scene triangle: its light's index (-1: not a light)
  std::vector<PmcLightTreeNode> tree_nodes;  // the light tree (one blank node when there is none)
  // The sky map (its EnvMap::data: texels and CDFs, the scale in header.env_scale);
  // null when there is no map. CPU devices read the map's own memory.
  std::shared_ptr<const EnvMap> env_map;
  // What the kernel's env buffer holds: the map's data, or one 0 without a map.
  const float* env_floats() const;
  size_t env_float_count() const;
  PmcLightHeader header{};
  double total_power = 0.0;  // sum of the lights' power estimates (luminance, W)
  size_t emissive_triangles = 0;
  int tree_depth = 0;
  double tree_build_seconds = 0.0;
};

// `emission[m]` is the (constant) emitted radiance of material m, rgb.
// Lights are picked by power: pi A L for area lights (x2 two-sided), 4 pi I
// for points, 2 pi I (1 - cos) for spots, pi r^2 E for directional lights and
// pi r^2 x the radiance integrated over the sphere for the environment, r
// the radius of the scene's bounding sphere (the power sampler's pmf, kept
// with either sampler).
LightTable build_light_table(const Scene& scene, const std::vector<float>& emission,
                             const SceneLights& lights, LightSampler sampler = LightSampler::Tree);
// A table without lights (one blank entry per device buffer): what the scene
// buffers hold until a render uploads its own.
LightTable empty_light_table();

}  // namespace pmc
