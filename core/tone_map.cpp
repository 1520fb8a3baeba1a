// tone_map.cpp — exposure, view curve (ACES fit or clip), sRGB encoding.
#include "core/tone_map.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace pmc {
namespace {

float aces_fit(float x) {  // Narkowicz 2015 fit of the ACES filmic curve
  const float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;
  return std::clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0f, 1.0f);
}

float srgb_encode(float c) {
  if (c >= 1.0f) return 1.0f;  // exact at white (1.055 - 0.055 is not 1 in float)
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

}  // namespace

float tone_map(float linear, const ToneMap& tm) {
  float v = linear * std::exp2(tm.exposure_ev);
  if (!std::isfinite(v) || !(v > 0.0f)) return 0.0f;
  v = tm.view == ViewTransform::Filmic ? aces_fit(v) : std::min(v, 1.0f);
  return srgb_encode(v);
}

Image tone_map_image(const Image& linear, const ToneMap& tm) {
  Image out = linear;
  for (float& v : out.pixels) v = tone_map(v, tm);
  return out;
}

ViewTransform parse_view_transform(const std::string& name, const std::string& option) {
  if (name == "filmic") return ViewTransform::Filmic;
  if (name == "standard") return ViewTransform::Standard;
  fail(option, ": expected filmic or standard, got '", name, "'");
}

}  // namespace pmc
