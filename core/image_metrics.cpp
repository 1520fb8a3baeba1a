// image_metrics.cpp — RMSE, relMSE, PSNR, max error, difference images.
//
// The four errors come from one pass of our own: relMSE and the clamped PSNR
// (999 dB for identical images) are pmc's conventions, which
// ImageBufAlgo::compare does not compute; the difference image is
// ImageBufAlgo's absdiff of the tone-mapped images.
#include "core/image_metrics.h"

#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/image_buf.h"
#include "core/tone_map.h"

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

Image difference_image(const Image& a, const Image& b, float scale) {
  if (a.pixels.size() != b.pixels.size()) fail("difference image: sizes differ");
  namespace IBA = OIIO::ImageBufAlgo;
  const OIIO::ImageBuf diff = IBA::absdiff(to_image_buf(tone_map_image(a)), to_image_buf(tone_map_image(b)));
  return from_image_buf(IBA::min(IBA::mul(diff, scale), 1.0f));
}

}  // namespace pmc
