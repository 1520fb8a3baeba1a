// image_metrics.cpp — RMSE, relMSE, PSNR, max error, difference images.
#include "core/image_metrics.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace pmc {

ImageError compare_images(const Image& t, const Image& r) {
  if (t.width != r.width || t.height != r.height || t.channels != r.channels ||
      t.pixels.size() != r.pixels.size())
    fail("image comparison: sizes differ (", t.width, "x", t.height, "x", t.channels, " vs ", r.width, "x",
         r.height, "x", r.channels, ")");
  ImageError e;
  double se = 0, rel = 0, se_clamped = 0;
  const size_t n = t.pixels.size();
  for (size_t i = 0; i < n; ++i) {
    double a = t.pixels[i], b = r.pixels[i];
    if (!std::isfinite(a) || !std::isfinite(b)) {
      e.max_abs = INFINITY;
      continue;
    }
    double d = a - b;
    se += d * d;
    rel += d * d / (b * b + 0.01);
    double dc = std::clamp(a, 0.0, 1.0) - std::clamp(b, 0.0, 1.0);
    se_clamped += dc * dc;
    e.max_abs = std::max(e.max_abs, std::fabs(d));
  }
  e.rmse = n ? std::sqrt(se / double(n)) : 0.0;
  e.relmse = n ? rel / double(n) : 0.0;
  double mse_c = n ? se_clamped / double(n) : 0.0;
  e.psnr = mse_c > 0 ? 10.0 * std::log10(1.0 / mse_c) : 999.0;  // identical images: reported as 999 dB
  return e;
}

Image tonemap_display(const Image& linear) {
  Image out = linear;
  for (float& v : out.pixels) {
    float x = std::isfinite(v) ? std::max(0.0f, v) : 0.0f;
    float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;
    x = std::clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0f, 1.0f);
    v = x <= 0.0031308f ? x * 12.92f : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
  }
  return out;
}

Image difference_image(const Image& a, const Image& b, float scale) {
  if (a.pixels.size() != b.pixels.size()) fail("difference image: sizes differ");
  Image da = tonemap_display(a), db = tonemap_display(b);
  Image out = da;
  for (size_t i = 0; i < out.pixels.size(); ++i)
    out.pixels[i] = std::min(1.0f, std::fabs(da.pixels[i] - db.pixels[i]) * scale);
  return out;
}

}  // namespace pmc
