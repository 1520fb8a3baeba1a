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

// A number of the table (`v`: the setting or its RenderSettings copy) in its range.
template <typename T, typename V>
void check_range(const SettingInfo<T>& info, const V& v) {
  if (*info.check && !(double(v) >= info.lo && double(v) <= info.hi)) {
    const std::string check = info.check;
    const size_t at = check.find("{}");
    if (at == std::string::npos) fail_config(setting(info.name), ": ", check);
    fail_config(setting(info.name), ": ", check.substr(0, at), v, check.substr(at + 2));
  }
}

// A table setting's own check (gpu/render_settings_table.h): a number in its
// range, an enum one of its words.
template <typename T>
void check_setting(const SettingInfo<T>& info, const T& v) {
  if constexpr (std::is_enum_v<T>) {
    const std::vector<std::string> words = setting_words(info.value);
    const auto i = static_cast<std::underlying_type_t<T>>(v);
    if (i < 0 || size_t(i) >= words.size()) {
      std::string list;
      for (size_t w = 0; w < words.size(); ++w)
        list += (w == 0 ? "" : w + 1 == words.size() ? " or " : ", ") + words[w];
      fail_config(setting(info.name), ": must be ", list, ", got value ", int(i));
    }
  } else if constexpr (!std::is_same_v<T, bool>) {
    check_range(info, v);
  }
}

}  // namespace

std::vector<std::string> setting_words(const char* value) {
  std::vector<std::string> words;
  std::string w;
  for (const char* p = value;; ++p) {
    if (*p == '|' || *p == '\0') {
      words.push_back(w);
      w.clear();
      if (*p == '\0') break;
    } else {
      w += *p;
    }
  }
  return words;
}

std::vector<std::string> shown_setting_words(const char* value) {
  std::vector<std::string> words = setting_words(value);
  if (words == std::vector<std::string>{"off", "on"}) std::swap(words[0], words[1]);
  return words;
}

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
  // Each table setting in its range (gpu/render_settings_table.h).
  visit_render_settings(
      [this](const auto& info, auto config_field, auto) { check_setting(info, config_field(*this)); });
  if (samples && !((*samples)[0] >= 0 && (*samples)[0] < (*samples)[1] && (*samples)[1] <= spp))
    fail_config(setting("samples"), ": the range A:B must satisfy 0 <= A < B <= ", setting("spp"), " (", spp,
                "), got ", (*samples)[0], ":", (*samples)[1]);
  if (samples && adaptive_threshold > 0.0 && ((*samples)[0] != 0 || (*samples)[1] != spp))
    fail_config(setting("adaptive_threshold"),
                " needs every sample of a pixel in one process (a pixel's "
                "error decides its next samples), got ",
                setting("samples"), " ", (*samples)[0], ":", (*samples)[1], " of ", spp,
                "; split the frame with ", setting("crop"), " instead");
  if (crop) {
    const auto& w = *crop;
    if (!(w[0] >= 0 && w[1] >= 0 && w[0] < w[2] && w[1] < w[3] && w[2] <= width && w[3] <= height))
      fail_config(setting("crop"), ": the window x0,y0,x1,y1 must satisfy 0 <= x0 < x1 <= ", setting("width"),
                  " (", width, ") and 0 <= y0 < y1 <= ", setting("height"), " (", height, "), got ", w[0],
                  ",", w[1], ",", w[2], ",", w[3]);
  }
  if (!finite3(env)) fail_config(setting("env"), ": radiance must be finite");
  for (float v : env)
    if (v < 0.0f) fail_config(setting("env"), ": radiance must not be negative");
  if (!env_map.empty() && (env[0] > 0.0f || env[1] > 0.0f || env[2] > 0.0f))
    fail_config(setting("env"), " and ", setting("env_map"), ": give one environment, not both");
  if (env_scale && !(*env_scale >= 0.0f && std::isfinite(*env_scale)))
    fail_config(setting("env_scale"), ": must be a finite number >= 0, got ", *env_scale);
  if (env_rotate && !std::isfinite(*env_rotate))
    fail_config(setting("env_rotate"), ": must be a finite angle in degrees, got ", *env_rotate);
  if (shade_lanes < 0 || shade_lanes > 64 || (shade_lanes & (shade_lanes - 1)) != 0)
    fail_config(setting("shade_lanes"), ": must be 0 (automatic) or a power of two up to 64, got ",
                shade_lanes);
  if (cache_supersample < 0 || cache_supersample > 16 ||
      (cache_supersample != 0 && (cache_supersample & (cache_supersample - 1)) != 0))
    fail_config(setting("cache_supersample"), ": must be 0 (auto) or a power of two 1..16, got ",
                cache_supersample);
  if (threads && *threads <= 0) fail_config(setting("threads"), ": must be at least 1, got ", *threads);

  if (fov && !(*fov > 0.0f && *fov < 180.0f))
    fail_config(setting("fov"), ": must be in (0, 180) degrees, got ", *fov);
  if (camera_from.has_value() != camera_at.has_value())
    fail_config(setting("camera_from"), " and ", setting("camera_at"), " go together");
  check_finite(camera_from, "camera_from");
  check_finite(camera_at, "camera_at");
  check_finite(camera_up, "camera_up");

  if (!material.empty() && mtlx.empty())
    fail_config(setting("material"), " needs at least one ", setting("mtlx"), " document");
  if (cache_filter == CacheFilter::Bilinear && cache_eval != CacheEval::Center)
    fail_config(setting("cache_filter"), " bilinear needs ", setting("cache_eval"),
                " center (a hit-mode texel holds the value at one sample's uv, not at its centre, so "
                "there is nothing to interpolate)");
  // Checked even when this scene will not use the cache: a bad value is bad input either way.
  if (cache_cells && *cache_cells <= 0)
    fail_config(setting("cache_cells"), ": must be at least 1, got ", *cache_cells);
  if (cache_cells)
    if (std::string problem = table_memory_problem(uint64_t(*cache_cells), uint64_t(cache_entries));
        !problem.empty())
      fail_config(setting("cache_cells"), "/", setting("cache_entries"), ": ", problem);
}

void validate_render_settings(const RenderSettings& s) {
  if (s.width <= 0 || s.height <= 0)
    fail_config(setting("width"), "/", setting("height"), ": the image size must be positive, got ", s.width,
                "x", s.height);
  // Each table setting's RenderSettings copy in the setting's range.
  visit_render_settings([&s](const auto& info, auto, auto frame_field) {
    using T = std::decay_t<decltype(info.dflt)>;
    if constexpr (!std::is_null_pointer_v<decltype(frame_field)> && !kWordSetting<T>)
      check_range(info, frame_field(s));
  });
  const int first_sample = s.sample_begin, end_sample = s.sample_end > 0 ? s.sample_end : s.spp;
  if (first_sample < 0 || first_sample >= end_sample || end_sample > s.spp)
    fail_config(setting("samples"), ": the sample range must lie within 0..", setting("spp"),
                " and hold at least one sample, got ", first_sample, ":", end_sample);
  if (s.crop[2] > 0 && !(s.crop[0] >= 0 && s.crop[1] >= 0 && s.crop[0] < s.crop[2] && s.crop[1] < s.crop[3] &&
                         s.crop[2] <= s.width && s.crop[3] <= s.height))
    fail_config(setting("crop"), ": the window must lie within the image and hold at least one pixel");
  if (s.adaptive_threshold > 0.0 && (first_sample != 0 || end_sample != s.spp))
    fail_config(setting("adaptive_threshold"),
                " needs every sample of a pixel in one process (a pixel's "
                "error decides its next samples), got ",
                setting("samples"), " ", first_sample, ":", end_sample, " of ", s.spp,
                "; split the frame with ", setting("crop"), " instead");
  if (s.cache.on && (s.cache.cells == 0 || s.cache.ways == 0))
    fail_config(setting("cache_cells"), "/", setting("cache_entries"),
                ": the table needs at least one cell and one entry");
}

RenderSettings base_render_settings(const RenderConfig& c) {
  RenderSettings s;
  // The table's settings that are straight copies (gpu/render_settings_table.h's `frame`).
  visit_render_settings([&](const auto&, auto config_field, auto frame_field) {
    if constexpr (!std::is_null_pointer_v<decltype(frame_field)>) {
      auto& to = frame_field(s);
      to = frame_value<std::decay_t<decltype(to)>>(config_field(c));
    }
  });
  if (c.samples) {
    s.sample_begin = (*c.samples)[0];
    s.sample_end = (*c.samples)[1];
  }
  if (c.crop)
    for (int i = 0; i < 4; ++i) s.crop[i] = (*c.crop)[size_t(i)];
  for (int i = 0; i < 3; ++i) s.env[i] = c.env[size_t(i)];
  s.transfer = c.transfer;
  s.cache.bilinear = c.effective_cache_filter() == CacheFilter::Bilinear;
  s.cache.audit = c.cache_audit;
  s.passes = c.passes;
  return s;
}

}  // namespace pmc
