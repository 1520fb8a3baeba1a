// env_map.cpp — loading an environment map and building its sampling CDFs.
#include "core/env_map.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/image_backend.h"

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

// cdf_guide's n + 1 entries, written to `guide`.
void fill_cdf_guide(const float* cdf, int n, float* guide) {
  int i = 0;
  for (int k = 0; k <= n; ++k) {
    const double threshold = double(k) / double(n);
    while (i < n - 1 && !(double(cdf[i]) > threshold)) ++i;
    guide[k] = float(i);
  }
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
  fill_cdf_guide(cdf, n, guide.data());
  return guide;
}

size_t EnvMap::data_floats(int width, int height) {
  const size_t texels = size_t(width) * size_t(height), h = size_t(height);
  // texels, marginal, conditional, sines, the marginal's guide, the rows' guides
  return 3 * texels + h + texels + h + (h + 1) + h * (size_t(width) + 1);
}

namespace {

// An EnvMap of width x height whose `data` is sized and holds no values yet.
EnvMap blank_map(int width, int height, const std::string& path) {
  EnvMap m;
  m.path = path;
  m.width = width;
  m.height = height;
  m.data.resize(EnvMap::data_floats(width, height));
  return m;
}

// Fills everything after the texels: the CDFs, sines and guides.
void build_distribution(EnvMap& m) {
  const size_t w = size_t(m.width), h = size_t(m.height);
  float* marginal = m.data.data() + 3 * m.texel_count();
  float* conditional = marginal + h;
  float* sines = conditional + m.texel_count();
  float* guides = sines + h;
  std::vector<double> row_weight(h), col_weight(w);
  for (size_t y = 0; y < h; ++y) {
    const double sin_theta = m.row_sine(int(y));
    sines[y] = float(sin_theta);
    for (size_t x = 0; x < w; ++x) col_weight[x] = luminance(&m.rgb()[3 * (y * w + x)]) * sin_theta;
    row_weight[y] = fill_cdf(col_weight, conditional + y * w);
  }
  m.integral = fill_cdf(row_weight, marginal);
  fill_cdf_guide(marginal, m.height, guides);
  for (size_t y = 0; y < h; ++y) fill_cdf_guide(conditional + y * w, m.width, guides + (h + 1) + y * (w + 1));
}

}  // namespace

EnvMap env_map_from_rgb(int width, int height, const std::vector<float>& rgb, const std::string& path) {
  PMC_CHECK(width > 0 && height > 0 && rgb.size() == size_t(width) * size_t(height) * 3);
  EnvMap m = blank_map(width, height, path);
  std::copy(rgb.begin(), rgb.end(), m.data.begin());
  build_distribution(m);
  return m;
}

EnvMap load_env_map(const std::string& path) {
  std::string why;
  auto in = image_backend().open(path, false, why);
  if (!in) fail(path, ": cannot read image: ", why);
  const ImageHeader h = in->header();  // a copy: the reader goes before the checks
  if (h.width <= 0 || h.height <= 0 || h.channels <= 0) fail(path, ": the environment map is empty");
  // The file's pixels go straight into the map's texels (no decoded copy
  // beside them): its first three channels, or a grey map's (1 or 2
  // channels: value, alpha) value into red, repeated below.
  EnvMap m = blank_map(h.width, h.height, path);
  float* rgb = m.data.data();
  const int channels = std::min(h.channels, 3) == 2 ? 1 : std::min(h.channels, 3);
  const std::ptrdiff_t texel = 3 * sizeof(float);
  if (!in->read(0, channels, PixelFormat::Float, rgb, texel, texel * h.width))
    fail(path, ": cannot decode image: ", in->error());
  in.reset();
  const size_t texels = m.texel_count();
  size_t bad = 0, negative = 0, first_bad = 0;
  for (size_t i = 0; i < texels; ++i) {
    bool is_bad = false, is_negative = false;
    float* c = &rgb[3 * i];
    if (channels == 1) c[1] = c[2] = c[0];
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(c[k])) {
        is_bad = true;
        c[k] = 0.0f;
      } else if (c[k] < 0.0f) {
        is_negative = true;
        c[k] = 0.0f;
      }
    }
    if (is_bad && bad++ == 0) first_bad = i;
    negative += is_negative ? 1 : 0;
  }
  if (bad > 0)
    fail(path, ": ", bad, " texels with NaN or infinite values in the environment map (first at x ",
         first_bad % size_t(h.width), ", y ", first_bad / size_t(h.width), ")");
  if (negative > 0)
    warn(path + ": " + std::to_string(negative) +
         " texels with negative values in the environment map (read as 0)");
  build_distribution(m);
  return m;
}

}  // namespace pmc
