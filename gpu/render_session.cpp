// render_session.cpp — scene, materials, camera, cache size, BVH and renderer in one place.
#include "gpu/render_session.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <sstream>

#include "core/background.h"
#include "core/cache_sizing.h"
#include "core/camera.h"
#include "core/error.h"
#include "core/obj_loader.h"
#include "core/texture_cache.h"
#include "gpu/device_calibration.h"
#include "gpu/wave_kernels.h"

namespace pmc {
namespace {

using Clock = std::chrono::steady_clock;

// The cache table for a program compiled with cache instructions: the
// config's size, else one sized from the scene's cache points; none (the
// cacheless program runs) when no material has a cache point.
void size_cache(const RenderConfig& config, const MaterialSet& materials, CacheSettings& cache, int width,
                int height, int spp) {
  // Position points count twice toward the table's size: a surface cuts about twice as many
  // cells as it covers texels (the cost model's hit rates assume the same, materials/node_costs.h).
  size_t points = 0, with_points = 0, key_weight = 0;
  for (const CompiledMaterial& m : materials.program.materials) {
    points += m.cache_plan.points.size();
    with_points += m.cache_plan.points.empty() ? 0 : 1;
    for (const CachePoint& p : m.cache_plan.points) key_weight += p.key == CacheKey::Position ? 2 : 1;
  }
  if (points == 0) {
    cache.on = false;  // nothing cacheable: run the cacheless path, allocate nothing
    std::ostringstream os;
    os << "no cacheable nodes in this scene's materials (none depends on uv alone or position alone with a "
          "sub-graph of at least "
       << setting("cache_min_nodes") << " nodes): the cacheless program runs and no table is allocated";
    cache.reason = os.str();
    return;
  }
  const double per_material = double(key_weight) / double(std::max<size_t>(1, with_points));
  if (config.cache_cells) {
    cache.cells = uint64_t(*config.cache_cells);
    cache.ways = uint32_t(config.cache_entries);
    std::ostringstream os;
    os << "set by " << setting("cache_cells") << "/" << setting("cache_entries");
    cache.reason = os.str();
  } else {
    // cache_entries alone: the cell count follows, so the table holds the same keys.
    const uint64_t avail = available_memory_bytes();
    const CacheSize cs =
        choose_cache_size(width, height, spp, per_material, std::min<uint64_t>(avail / 4, 4ull << 30),
                          uint32_t(config.cache_entries));
    cache.cells = cs.cells;
    cache.ways = cs.entries;
    cache.reason = cs.reason;
    if (std::string problem = table_memory_problem(cs.cells, cs.entries); !problem.empty())
      fail_config(setting("cache_cells"), "/", setting("cache_entries"), ": ", problem);
  }
  // A table smaller than the frame's keys need misses more and more (below
  // about 1/4 of that the cached render is slower than the cacheless one,
  // docs/BENCHMARKS.md); cache_fit coarsens the texels until they fit.
  const double expected = expected_entries(width, height, spp, per_material);
  const uint64_t entries = cache.cells * cache.ways;
  const float short_levels = fit_levels(expected, entries);
  std::ostringstream os;
  os.precision(3);
  if (config.cache_fit) {
    cache.fit_levels = short_levels;
    if (short_levels > 0.0f)
      os << "; " << setting("cache_fit") << ": the frame's keys need " << uint64_t(expected)
         << " entries at load factor 1/2, the table has " << entries << ", so texels are " << short_levels
         << " levels coarser";
    else
      os << "; " << setting("cache_fit") << ": the frame's keys fit, texels follow the footprint";
  } else if (short_levels > 0.0f) {
    os << "; the frame's keys need about " << uint64_t(expected)
       << " entries at load factor 1/2 and the table has " << entries << ": expect misses ("
       << setting("cache_fit") << " on makes texels " << short_levels << " levels coarser to fit)";
  }
  cache.reason += os.str();
}

}  // namespace

Camera resolve_camera(const RenderConfig& c, const Scene& scene) {
  const float fov = c.fov.value_or(45.0f);
  Camera camera;
  if (c.camera_from) {
    std::copy(c.camera_from->begin(), c.camera_from->end(), camera.from);
    std::copy(c.camera_at->begin(), c.camera_at->end(), camera.at);
    if (c.camera_up) std::copy(c.camera_up->begin(), c.camera_up->end(), camera.up);
    camera.fov_degrees = fov;
  } else if (auto file = read_camera_file(std::filesystem::path(c.scene).replace_extension(".camera"))) {
    camera = *file;
    if (c.fov) camera.fov_degrees = fov;
  } else {
    camera = frame_bounds(scene.bounds, fov, float(c.width) / float(c.height));
    if (c.camera_up) std::copy(c.camera_up->begin(), c.camera_up->end(), camera.up);
  }
  return camera;
}

SceneLights resolve_lights(const RenderConfig& c) {
  SceneLights lights;
  if (c.lights != "none") {
    const std::string beside = std::filesystem::path(c.scene).replace_extension(".lights.json").string();
    if (!c.lights.empty())
      lights = read_lights_file(c.lights);
    else if (std::filesystem::exists(beside))
      lights = read_lights_file(beside);
  }
  if (!c.env_map.empty()) {
    try {
      lights.environment = environment_from_map(c.env_map, 1.0f, 0.0f);
    } catch (const ConfigError&) {
      throw;
    } catch (const Error& e) {
      fail_config(setting("env_map"), ": ", e.what());
    }
  } else if (c.env[0] > 0.0f || c.env[1] > 0.0f || c.env[2] > 0.0f) {
    lights.environment = constant_environment(c.env.data());
  }
  auto no_environment = [&](const char* name) {
    fail_config(setting(name), ": there is no environment to change (give ", setting("env"), ", ",
                setting("env_map"), " or a lights file with one)");
  };
  if (c.env_scale && !lights.environment.present) no_environment("env_scale");
  if (c.env_rotate && !lights.environment.present) no_environment("env_rotate");
  if (c.env_scale) lights.environment.scale = *c.env_scale;
  if (c.env_rotate) lights.environment.rotate_y_deg = *c.env_rotate;
  return lights;
}

RenderSession::RenderSession(const RenderConfig& config, const ClContext& cl) : RenderSession(config, &cl) {}

RenderSession::RenderSession(const RenderConfig& config) : RenderSession(config, nullptr) {}

RenderSession::RenderSession(const RenderConfig& config, const ClContext* cl) : config_(config), cl_(cl) {
  config_.validate();
  TextureCache::instance().configure(config_.texture_cache);
  Clock::time_point mark = Clock::now();
  auto lap = [&mark](double& seconds) {
    const Clock::time_point now = Clock::now();
    seconds = std::chrono::duration<double>(now - mark).count();
    mark = now;
  };
  // No device given: open it beside the scene's loading (the thread limit first, on this thread).
  std::optional<Background<std::unique_ptr<ClContext>>> opening;
  if (!cl_) {
    limit_threads(config_);
    opening.emplace([device = config_.device] { return std::make_unique<ClContext>(device); });
  }
  // The kernel build, from the end of material compiling: beside the texture
  // decoding and the BVH build (declared after `opening`, so it is waited for first).
  std::optional<Background<std::unique_ptr<WaveKernels>>> building;
  // Waited for inside the materials step: before compiling when the cache's
  // cost model needs the device, else once the materials are compiled.
  auto device = [&]() -> const ClContext& {
    if (opening && !cl_) {
      const Clock::time_point wait = Clock::now();
      own_cl_ = opening->get();
      cl_ = own_cl_.get();
      setup_.background_opencl_device = opening->seconds();
      setup_.opencl_device = std::chrono::duration<double>(Clock::now() - wait).count();
    }
    return *cl_;
  };
  auto start_kernel_build = [&](MaterialSet& set) {
    for (CompiledMaterial& m : set.program.materials)
      m.peak_stack = std::max(m.peak_stack, config_.min_kernel_stack);
    const ClContext& cl = device();
    const int lanes = config_.shade_lanes > 0 ? config_.shade_lanes : default_shade_lanes(cl, set);
    // By value: the device (owned by the caller or own_cl_) outlives `building`.
    building.emplace([device = cl_, lanes, options = wave_program_options(set, lanes, cl.info().is_gpu)] {
      return std::make_unique<WaveKernels>(*device, lanes, options);
    });
  };
  try {
    prepare_scene(lap, device, start_kernel_build);
  } catch (...) {
    if (opening && !cl_) opening->get();  // the device's error first, as when it was opened first
    throw;
  }
  if (!building) start_kernel_build(materials_);  // (the hook always runs; this keeps it so)
  setup_.materials -= setup_.opencl_device;       // reported apart
  renderer_ = std::make_unique<WavefrontRenderer>(*cl_, scene_, materials_, *tracer_, building->get());
  setup_.background_kernel_build = building->seconds();
  lap(setup_.renderer);
}

void RenderSession::prepare_scene(const std::function<void(double&)>& lap,
                                  const std::function<const ClContext&()>& device,
                                  const std::function<void(MaterialSet&)>& compiled) {
  ObjLoadOptions load;
  load.load_textures = false;  // the material compiler loads what live nodes read
  scene_ = load_obj(config_.scene, load);
  lap(setup_.scene);
  MaterialOptions mo;
  mo.mtlx_files = config_.mtlx;
  mo.override_material = config_.material;
  mo.mtlx.library_dir = config_.mtlx_library;
  mo.mtlx.search_paths = config_.mtlx_search_paths;
  mo.compile.cache = config_.cache;
  mo.compile.cache_min_nodes = config_.cache_min_nodes;
  mo.compile.cache_position_keys = config_.cache_position_keys;
  mo.compile.cache_feature_texels =
      config_.cache_bandwidth != CacheBandwidth::Off ? config_.cache_feature_texels : 0.0;
  if (config_.cache_eval == CacheEval::Center)  // hit mode stores the hit's value: nothing to average
    mo.compile.cache_supersample = cache_supersample_ =
        resolve_supersample(cache_frame(config_), config_.cache_supersample);
  if (config_.cache && config_.cache_model == CacheModel::Cost)
    mo.compile.cache_model = cache_model_ =
        CacheCostModel{device_cache_costs(device()), cache_frame(config_)};
  mo.compiled = compiled;
  materials_ = build_material_set(scene_, mo);
  lap(setup_.materials);
  settings_ = base_render_settings(config_);
  settings_.camera = resolve_camera(config_, scene_);
  settings_.lights = resolve_lights(config_);
  if (settings_.cache.on)
    size_cache(config_, materials_, settings_.cache, config_.width, config_.height, config_.spp);
  lap(setup_.lights);
  cutout_ = std::make_unique<CutoutTester>(scene_, materials_);
  tracer_ =
      std::make_unique<EmbreeTracer>(scene_, config_.trace_mode, cutout_->any() ? cutout_.get() : nullptr);
  lap(setup_.bvh);
}

RenderSession::~RenderSession() = default;

size_t RenderSession::cache_points() const {
  size_t points = 0;
  for (const CompiledMaterial& m : materials_.program.materials) points += m.cache_plan.points.size();
  return points;
}

RenderOutput RenderSession::render(const RenderSettings& settings, const ProgressFn& progress) {
  return renderer_->render(settings, progress);
}

CacheFrame cache_frame(const RenderConfig& c) {
  return CacheFrame{c.width, c.height, c.spp, c.max_depth, c.cache_camera_samples};
}

std::unique_ptr<ClContext> open_device(const RenderConfig& config) {
  limit_threads(config);
  return std::make_unique<ClContext>(config.device);
}

void limit_threads(const RenderConfig& config) {
  if (config.threads) {
    if (*config.threads <= 0) fail_config(setting("threads"), ": must be at least 1, got ", *config.threads);
    static std::unique_ptr<tbb::global_control> control;
    control = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    size_t(*config.threads));
    // PoCL's CPU driver reads these when the platform is first opened.
    const std::string t = std::to_string(*config.threads);
    setenv("POCL_MAX_PTHREAD_COUNT", t.c_str(), 1);
    setenv("POCL_CPU_MAX_CU_NUM", t.c_str(), 1);
  }
}

}  // namespace pmc
