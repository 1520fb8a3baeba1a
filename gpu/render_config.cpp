// render_config.cpp — RenderConfig's checks and the scene-free settings.
#include "gpu/render_config.h"

#include <cmath>

#include "core/cache_sizing.h"
#include "core/error.h"

namespace pmc {
namespace {

bool finite3(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

void check_finite(const std::optional<Vec3>& v, const char* name) {
  if (v && !finite3(*v)) fail_config(setting(name), ": must be three finite numbers");
}

}  // namespace

CacheFilter RenderConfig::effective_cache_filter() const {
  if (cache_filter) return *cache_filter;
  return cache_eval == CacheEval::Center ? CacheFilter::Bilinear : CacheFilter::Nearest;
}

void RenderConfig::validate() const {
  if (scene.empty()) fail_config(setting("scene"), ": no OBJ file given");
  if (width <= 0 || height <= 0)
    fail_config(setting("width"), "/", setting("height"), ": the image size must be positive, got ", width,
                "x", height);
  if (size_t(width) * size_t(height) > (size_t(1) << 28))
    fail_config(setting("width"), "/", setting("height"), ": image too large (", width, "x", height,
                " pixels; at most 2^28)");
  if (spp <= 0) fail_config(setting("spp"), ": samples per pixel must be at least 1, got ", spp);
  if (samples && !((*samples)[0] >= 0 && (*samples)[0] < (*samples)[1] && (*samples)[1] <= spp))
    fail_config(setting("samples"), ": the range A:B must satisfy 0 <= A < B <= ", setting("spp"), " (", spp,
                "), got ", (*samples)[0], ":", (*samples)[1]);
  if (crop) {
    const auto& w = *crop;
    if (!(w[0] >= 0 && w[1] >= 0 && w[0] < w[2] && w[1] < w[3] && w[2] <= width && w[3] <= height))
      fail_config(setting("crop"), ": the window x0,y0,x1,y1 must satisfy 0 <= x0 < x1 <= ", setting("width"),
                  " (", width, ") and 0 <= y0 < y1 <= ", setting("height"), " (", height, "), got ", w[0],
                  ",", w[1], ",", w[2], ",", w[3]);
  }
  if (max_depth <= 0 || max_depth > 1024)
    fail_config(setting("max_depth"), ": must be in 1..1024, got ", max_depth);
  if (seed < 0 || seed > 0xffffffffLL) fail_config(setting("seed"), ": must be in 0..4294967295, got ", seed);
  if (!finite3(env)) fail_config(setting("env"), ": radiance must be finite");
  for (float v : env)
    if (v < 0.0f) fail_config(setting("env"), ": radiance must not be negative");
  if (!env_map.empty() && (env[0] > 0.0f || env[1] > 0.0f || env[2] > 0.0f))
    fail_config(setting("env"), " and ", setting("env_map"), ": give one environment, not both");
  if (env_scale && !(*env_scale >= 0.0f && std::isfinite(*env_scale)))
    fail_config(setting("env_scale"), ": must be a finite number >= 0, got ", *env_scale);
  if (env_rotate && !std::isfinite(*env_rotate))
    fail_config(setting("env_rotate"), ": must be a finite angle in degrees, got ", *env_rotate);
  if (chunk_rays < 0) fail_config(setting("chunk_rays"), ": must not be negative");
  if (shade_lanes < 0 || shade_lanes > 64 || (shade_lanes & (shade_lanes - 1)) != 0)
    fail_config(setting("shade_lanes"), ": must be 0 (automatic) or a power of two up to 64, got ",
                shade_lanes);
  if (threads && *threads <= 0) fail_config(setting("threads"), ": must be at least 1, got ", *threads);

  if (fov && !(*fov > 0.0f && *fov < 180.0f))
    fail_config(setting("fov"), ": must be in (0, 180) degrees, got ", *fov);
  if (camera_from.has_value() != camera_at.has_value())
    fail_config(setting("camera_from"), " and ", setting("camera_at"), " go together");
  check_finite(camera_from, "camera_from");
  check_finite(camera_at, "camera_at");
  check_finite(camera_up, "camera_up");

  if (cache_min_nodes < 1) fail_config(setting("cache_min_nodes"), ": must be at least 1");
  if (!(cache_feature_texels >= 0.125 && cache_feature_texels <= 64))
    fail_config(setting("cache_feature_texels"), ": must be 0.125..64, got ", cache_feature_texels);
  if (cache_max_refine < 0 || cache_max_refine > 16)
    fail_config(setting("cache_max_refine"), ": must be 0..16, got ", cache_max_refine);
  if (!(cache_lobe_spread >= 0.0f && cache_lobe_spread <= 4.0f))
    fail_config(setting("cache_lobe_spread"), ": must be 0..4, got ", cache_lobe_spread);
  if (!material.empty() && mtlx.empty())
    fail_config(setting("material"), " needs at least one ", setting("mtlx"), " document");
  if (!(std::fabs(mip_bias) <= 32.0f))
    fail_config(setting("mip_bias"), ": must be within -32..32, got ", mip_bias);
  if (cache_filter == CacheFilter::Bilinear && cache_eval != CacheEval::Center)
    fail_config(setting("cache_filter"), " bilinear needs ", setting("cache_eval"),
                " center (a hit-mode texel holds the value at one sample's uv, not at its centre, so "
                "there is nothing to interpolate)");
  if (cache_policy != CachePolicy::KeepFirst && cache_policy != CachePolicy::Priority)
    fail_config(setting("cache_policy"), ": must be keep-first or priority, got value ", int(cache_policy));
  // Checked even when this scene will not use the cache: a bad value is bad input either way.
  if (cache_cells && *cache_cells <= 0)
    fail_config(setting("cache_cells"), ": must be at least 1, got ", *cache_cells);
  if (cache_entries <= 0 || cache_entries > 1024)
    fail_config(setting("cache_entries"), ": must be in 1..1024, got ", cache_entries);
  if (cache_cells)
    if (std::string problem = table_memory_problem(uint64_t(*cache_cells), uint64_t(cache_entries));
        !problem.empty())
      fail_config(setting("cache_cells"), "/", setting("cache_entries"), ": ", problem);
}

RenderSettings base_render_settings(const RenderConfig& c) {
  RenderSettings s;
  s.width = c.width;
  s.height = c.height;
  s.spp = c.spp;
  if (c.samples) {
    s.sample_begin = (*c.samples)[0];
    s.sample_end = (*c.samples)[1];
  }
  if (c.crop)
    for (int i = 0; i < 4; ++i) s.crop[i] = (*c.crop)[size_t(i)];
  s.max_depth = c.max_depth;
  s.seed = uint32_t(c.seed);
  for (int i = 0; i < 3; ++i) s.env[i] = c.env[size_t(i)];
  s.chunk_rays = size_t(c.chunk_rays);
  s.transfer = c.transfer;
  s.cache.on = c.cache;
  s.cache.mip_bias = c.mip_bias;
  s.cache.center = c.cache_eval == CacheEval::Center;
  s.cache.bilinear = c.effective_cache_filter() == CacheFilter::Bilinear;
  s.cache.priority = c.cache_policy == CachePolicy::Priority;
  s.cache.bandwidth = c.cache_bandwidth;
  s.cache.max_refine = c.cache_max_refine;
  s.cache.lobe_spread = c.cache_lobe_spread;
  s.cache.feature_texels = float(c.cache_feature_texels);
  s.cache.audit = c.cache_audit;
  return s;
}

}  // namespace pmc
