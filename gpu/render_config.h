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
#include "gpu/wavefront_renderer.h"
#include "materials/cache_plan.h"

namespace pmc {

// --cache-lobe-spread's default: how much position cells widen per bounce, C
// of core/device/pmc_raycone.h's pmc_lobe_spread. 0 (the paper's cone): 1/32
// renders the solid room 3-7% faster at the same bias, but its paths part from
// the cacheless render's more often, so same-seed comparisons at low sample
// counts (scripts/ci-compare) lose up to 8 dB (docs/BENCHMARKS.md, "Coarser
// cells after rough bounces").
constexpr float kDefaultCacheLobeSpread = 0.0f;

using Vec3 = std::array<float, 3>;

// What a cache miss stores for a texel: the value at the inserting hit, or
// at the texel's centre (then the image does not depend on the table).
enum class CacheEval { Hit, Center };
// The texel a lookup reads: the one under the hit, or a neighbour picked at
// random with its bilinear weight (center mode only).
enum class CacheFilter { Nearest, Bilinear };
// When a cell is full: keep the first entries (the paper's rule), or let an
// insert from a camera-ray hit replace an entry from a deeper bounce
// (core/device/pmc_cache.h).
enum class CachePolicy { KeepFirst, Priority };

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

  // The image.
  int width = 640, height = 360;  // pixels
  int spp = 16;                   // samples per pixel
  // Part of the frame (a farm chunk; `pmc merge` adds parts up): the sample
  // indices [first, second) of the frame's spp, and the window x0, y0, x1, y1
  // (pixels [x0, x1) x [y0, y1)). Unset: all samples, the whole frame.
  std::optional<std::array<int, 2>> samples;
  std::optional<std::array<int, 4>> crop;
  int max_depth = 8;  // surface hits per path, 1..1024
  int64_t seed = 0;   // 0..2^32-1; equal seeds give identical images (cache: center mode)
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

  // The progressive material cache.
  bool cache = true;
  std::optional<int64_t> cache_cells;  // cells; unset: sized from the scene
  int64_t cache_entries = 8;           // entries per cell, 1..1024
  float mip_bias = 0.0f;               // added to the virtual mip level (higher: finer), -32..32
  CacheEval cache_eval = CacheEval::Center;
  std::optional<CacheFilter> cache_filter;  // unset: bilinear with center, nearest with hit
  CachePolicy cache_policy = CachePolicy::KeepFirst;
  int cache_min_nodes = kDefaultCacheMinNodes;  // smallest sub-graph worth a cache point
  bool cache_position_keys = true;              // --cache-keys uv+position (false: uv)
  bool cache_bandwidth = false;                 // --cache-bandwidth on: level floors from the patterns
  double cache_feature_texels = 2.0;            // --cache-feature-texels: texels across the smallest feature
  int cache_max_refine = 2;                     // --cache-max-refine: levels of refinement before bypass
  // --cache-lobe-spread: position cells' widening per bounce (pmc_lobe_spread)
  float cache_lobe_spread = kDefaultCacheLobeSpread;
  bool cache_fit = false;    // --cache-fit on: coarser texels for a table too small
  bool cache_audit = false;  // count occupied entries by reading the table (tests)

  // The machine.
  std::string device;          // OpenCL device or platform name substring ("": first GPU, else CPU)
  std::optional<int> threads;  // host and PoCL worker threads (unset: all cores)
  // stream: rtcIntersect1M over the queue; on Sponza 5-10% less render time
  // than single (docs/BENCHMARKS.md, Tracing), images identical.
  TraceMode trace_mode = TraceMode::Stream;
  int64_t chunk_rays = 65536;                  // copy transfers: rays per streamed chunk (0: the whole queue)
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

// The renderer's settings for `config` (validated) that need no scene: image,
// samples, seed, environment, chunking and the cache's mode (not its size).
RenderSettings base_render_settings(const RenderConfig& config);

}  // namespace pmc
