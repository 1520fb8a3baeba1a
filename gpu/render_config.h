// render_config.h — every choice a user makes about one render, as plain data.
//
// `pmc render`, `compare` and `sweep` fill a RenderConfig from their flags;
// tests and other programs fill one directly. RenderSession
// (gpu/render_session.h) turns it into a prepared render. validate() checks
// each field for what it says (ranges, combinations, an explicit cache table
// against free memory) without reading the scene or opening a device, and
// throws ConfigError naming the fields by their names here ("spp: samples
// per pixel must be at least 1, got 0"); app/ shows them as flags. What needs
// the scene is resolved by the session: the camera when none is given (a
// SCENE.camera file beside the OBJ, else framing the scene's bounds) and the
// cache table's size when none is given (core/cache_sizing.h).
//
// Units: pixels, samples per pixel, surface hits per path, degrees (vertical
// field of view, env_rotate), linear radiance (env, W/(m^2 sr)), floats
// (kernel stack), rays.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/embree_tracer.h"
#include "gpu/render_settings_table.h"
#include "gpu/wavefront_renderer.h"
#include "materials/cache_plan.h"

namespace pmc {

using Vec3 = std::array<float, 3>;

struct RenderConfig {
  // The scene and its materials.
  std::string scene;              // OBJ file
  std::vector<std::string> mtlx;  // MaterialX documents: `usemtl NAME` binds to their material NAME
  std::string material;           // one MaterialX material for every triangle ("": the OBJ's own)
  std::string mtlx_library;       // MaterialX data libraries ("": $PMC_MTLX_LIBRARY or the build's default)
  std::vector<std::string> mtlx_search_paths;  // where MaterialX filenames are looked up last
  // Decoded textures kept between runs (core/texture_cache.h): a folder, "off",
  // or "" for $PMC_TEXTURE_CACHE, else the user's cache folder.
  std::string texture_cache;

  // The plain settings, each with its default, flag, range and help
  // (gpu/render_settings_table.h): width, height, spp, max_depth, seed, the
  // cache's switch, entries, mip bias, eval mode, policy, keys, min nodes,
  // bandwidth, feature texels, fit, lobe spread and max refine, chunk_rays.
#define PMC_CONFIG_FIELD(field, name, flag, type, dflt, ...) type field = dflt;
  PMC_RENDER_SETTINGS(PMC_CONFIG_FIELD)
#undef PMC_CONFIG_FIELD

  // Part of the frame (a farm chunk; `pmc merge` adds parts up): the sample
  // indices [first, second) of the frame's spp, and the window x0, y0, x1, y1
  // (pixels [x0, x1) x [y0, y1)). Unset: all samples, the whole frame.
  std::optional<std::array<int, 2>> samples;
  std::optional<std::array<int, 4>> crop;
  // Render passes (AOVs) written beside the beauty, PassBit bits of
  // core/render_passes.h (0: none; the kernels then skip them).
  uint32_t passes = 0;
  Vec3 env = {0.0f, 0.0f,
              0.0f};  // constant environment radiance; when not black it replaces the lights file's

  // Lights (core/lights.h; README "Lights"): a lights file ("": SCENE.lights.json
  // beside the OBJ when there is one; "none": not even that), an environment
  // map that replaces the file's environment, and changes to whichever
  // environment applies (env_map's, the file's, or env).
  std::string lights;
  std::string env_map;              // lat-long EXR or Radiance HDR
  std::optional<float> env_scale;   // multiplies the environment, >= 0
  std::optional<float> env_rotate;  // degrees about +Y, counter-clockwise seen from above

  // The camera: camera_from and camera_at together (camera_up, fov), else a
  // SCENE.camera file beside the OBJ (fov overrides its fov), else framing
  // the scene's bounds (camera_up, fov).
  std::optional<Vec3> camera_from, camera_at, camera_up;  // up: 0,1,0 when not given
  std::optional<float> fov;                               // vertical, degrees, (0, 180); 45 when not given

  // The progressive material cache (its plain settings are in the table).
  std::optional<int64_t> cache_cells;       // cells; unset: sized from the scene
  std::optional<CacheFilter> cache_filter;  // unset: bilinear with center, nearest with hit
  bool cache_audit = false;                 // count occupied entries by reading the table (tests)

  // The machine.
  std::string device;          // OpenCL device or platform name substring ("": first GPU, else CPU)
  std::optional<int> threads;  // host and PoCL worker threads (unset: all cores)
  // stream: rtcIntersect1M over the queue; on Sponza 5-10% less render time
  // than single (docs/BENCHMARKS.md, Tracing), images identical.
  TraceMode trace_mode = TraceMode::Stream;
  TransferMode transfer = TransferMode::Auto;  // how hits reach the device (gpu/host_link.h)
  int shade_lanes = 0;  // hits per shade work-item: 1, 2, 4 ... 64 (0: 64 on CPU devices, fewer for large
                        // material stacks; 1 on GPUs)
  uint32_t min_kernel_stack = 0;  // floats; kernels get at least this stack (0: the materials' peak),
                                  // so renders of different scenes can share one kernel build

  // Throws ConfigError naming the first field that is out of range or
  // contradicts another.
  void validate() const;
  CacheFilter effective_cache_filter() const;
};

// Throws ConfigError when `settings`, made or edited without a RenderConfig
// (`pmc sweep`'s rows, tests) or resolved from one, cannot be rendered: the
// table's settings out of their ranges (gpu/render_settings_table.h), an
// empty image, sample range, window or cache table. The renderer checks
// every render with it.
void validate_render_settings(const RenderSettings& settings);

// The renderer's settings for `config` (validated) that need no scene: image,
// samples, seed, environment, chunking and the cache's mode (not its size).
RenderSettings base_render_settings(const RenderConfig& config);

}  // namespace pmc
