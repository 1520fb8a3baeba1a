// env_map.cpp — loading an environment map and building its sampling CDFs.
#include "core/env_map.h"

#include <cmath>

#include "core/error.h"
#include "core/image_io.h"

namespace pmc {
namespace {

constexpr double kPi = 3.14159265358979323846;

double luminance(const float* c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

// Inclusive running sums of `w`, normalised so that the last is exactly 1
// (uniform when everything is zero). Returns the total.
double fill_cdf(const std::vector<double>& w, float* cdf) {
  double total = 0.0;
  for (double x : w) total += x;
  double running = 0.0;
  for (size_t i = 0; i < w.size(); ++i) {
    running += w[i];
    cdf[i] = total > 0.0 ? float(running / total) : float(double(i + 1) / double(w.size()));
  }
  if (!w.empty()) cdf[w.size() - 1] = 1.0f;
  return total;
}

}  // namespace

double EnvMap::luminance_integral() const {
  // Each texel spans (2 pi / w) x (pi / h) in (phi, theta); its solid angle is
  // that times sin(theta) (at the row centre, as for the sampling weights).
  return integral * 2.0 * kPi * kPi / (double(width) * double(height));
}

double EnvMap::row_sine(int y) const { return std::sin((double(y) + 0.5) * kPi / double(height)); }

std::vector<float> cdf_guide(const float* cdf, int n) {
  std::vector<float> guide(size_t(n) + 1);
  int i = 0;
  for (int k = 0; k <= n; ++k) {
    const double threshold = double(k) / double(n);
    while (i < n - 1 && !(double(cdf[i]) > threshold)) ++i;
    guide[size_t(k)] = float(i);
  }
  return guide;
}

PoolVector<float> EnvMap::device_data(float scale) const {
  PoolVector<float> out;
  out.reserve(rgb.size() + 2 * (marginal.size() + conditional.size()) + 2 * size_t(height) + 1);
  for (float v : rgb) out.push_back(v * scale);
  out.insert(out.end(), marginal.begin(), marginal.end());
  out.insert(out.end(), conditional.begin(), conditional.end());
  for (int y = 0; y < height; ++y) out.push_back(float(row_sine(y)));
  const std::vector<float> rows = cdf_guide(marginal.data(), height);
  out.insert(out.end(), rows.begin(), rows.end());
  for (int y = 0; y < height; ++y) {
    const std::vector<float> cols = cdf_guide(&conditional[size_t(y) * size_t(width)], width);
    out.insert(out.end(), cols.begin(), cols.end());
  }
  return out;
}

EnvMap env_map_from_rgb(int width, int height, std::vector<float> rgb, const std::string& path) {
  PMC_CHECK(width > 0 && height > 0 && rgb.size() == size_t(width) * size_t(height) * 3);
  EnvMap m;
  m.path = path;
  m.width = width;
  m.height = height;
  m.rgb = std::move(rgb);
  m.marginal.resize(size_t(height));
  m.conditional.resize(size_t(width) * size_t(height));
  std::vector<double> row_weight(static_cast<size_t>(height)), col_weight(static_cast<size_t>(width));
  for (int y = 0; y < height; ++y) {
    const double sin_theta = m.row_sine(y);
    for (int x = 0; x < width; ++x)
      col_weight[size_t(x)] = luminance(&m.rgb[3 * (size_t(y) * size_t(width) + size_t(x))]) * sin_theta;
    row_weight[size_t(y)] = fill_cdf(col_weight, &m.conditional[size_t(y) * size_t(width)]);
  }
  m.integral = fill_cdf(row_weight, m.marginal.data());
  return m;
}

EnvMap load_env_map(const std::string& path) {
  Image img = read_image(path);  // names the file when it cannot be read or decoded
  if (img.width <= 0 || img.height <= 0 || img.channels <= 0) fail(path, ": the environment map is empty");
  const size_t texels = size_t(img.width) * size_t(img.height);
  std::vector<float> rgb(texels * 3);
  size_t bad = 0, negative = 0, first_bad = 0;
  for (size_t i = 0; i < texels; ++i) {
    bool is_bad = false, is_negative = false;
    for (int c = 0; c < 3; ++c) {
      // Grey maps (1 or 2 channels: value, alpha) repeat the value.
      float v = img.pixels[i * size_t(img.channels) + size_t(img.channels >= 3 ? c : 0)];
      if (!std::isfinite(v)) {
        is_bad = true;
        v = 0.0f;
      } else if (v < 0.0f) {
        is_negative = true;
        v = 0.0f;
      }
      rgb[3 * i + size_t(c)] = v;
    }
    if (is_bad && bad++ == 0) first_bad = i;
    negative += is_negative ? 1 : 0;
  }
  if (bad > 0)
    fail(path, ": ", bad, " texels with NaN or infinite values in the environment map (first at x ",
         first_bad % size_t(img.width), ", y ", first_bad / size_t(img.width), ")");
  if (negative > 0)
    warn(path + ": " + std::to_string(negative) +
         " texels with negative values in the environment map (read as 0)");
  return env_map_from_rgb(img.width, img.height, std::move(rgb), path);
}

}  // namespace pmc
