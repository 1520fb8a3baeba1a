// texture.cpp — OpenImageIO reading, 8-bit conversion and mip chains.
#include "core/texture.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace pmc {
namespace {

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }
float linear_to_srgb(float c) {
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}
uint8_t to_byte(float v) {
  if (!(v > 0.0f)) return 0;  // also NaN
  if (v >= 1.0f) return 255;
  return static_cast<uint8_t>(v * 255.0f + 0.5f);
}

// One 2x2 box-filter reduction (odd sizes clamp the last row/column).
std::vector<uint8_t> downsample(const std::vector<uint8_t>& src, int w, int h, bool srgb,
                                const std::vector<float>& lut) {
  int nw = std::max(1, w >> 1), nh = std::max(1, h >> 1);
  std::vector<uint8_t> dst(size_t(nw) * nh * 4);
  for (int y = 0; y < nh; ++y)
    for (int x = 0; x < nw; ++x)
      for (int c = 0; c < 4; ++c) {
        float sum = 0.0f;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            int sx = std::min(w - 1, 2 * x + dx), sy = std::min(h - 1, 2 * y + dy);
            uint8_t b = src[(size_t(sy) * w + sx) * 4 + c];
            sum += (srgb && c < 3) ? lut[b] : b / 255.0f;
          }
        float avg = sum * 0.25f;
        dst[(size_t(y) * nw + x) * 4 + c] = to_byte((srgb && c < 3) ? linear_to_srgb(avg) : avg);
      }
  return dst;
}

}  // namespace

std::vector<float> srgb_decode_table() {
  std::vector<float> lut(256);
  for (int i = 0; i < 256; ++i) lut[i] = srgb_to_linear(i / 255.0f);
  return lut;
}

int TexturePool::add(const std::string& name, int width, int height, std::vector<uint8_t> rgba, bool srgb) {
  PMC_CHECK(width > 0 && height > 0 && rgba.size() == size_t(width) * height * 4, name);
  PmcTexture t{};
  t.offset = static_cast<pmc_u32>(texels_.size() / 4);
  t.width = width;
  t.height = height;
  t.flags = srgb ? PMC_TEX_SRGB : 0u;
  static const std::vector<float> lut = srgb_decode_table();
  int w = width, h = height, levels = 0;
  std::vector<uint8_t> level = std::move(rgba);
  for (;;) {
    texels_.insert(texels_.end(), level.begin(), level.end());
    ++levels;
    if (w == 1 && h == 1) break;
    level = downsample(level, w, h, srgb, lut);
    w = std::max(1, w >> 1);
    h = std::max(1, h >> 1);
  }
  t.levels = levels;
  textures_.push_back(t);
  names_.push_back(name);
  return static_cast<int>(textures_.size()) - 1;
}

int TexturePool::load(const std::string& path, bool srgb, const std::string& used_by) {
  std::string key = path + (srgb ? "#srgb" : "#linear");
  auto found = by_key_.find(key);
  if (found != by_key_.end()) return found->second;

  // Keep colour and alpha separate: cut-out masks need the unpremultiplied colour.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) {
    std::string why = OIIO::geterror();
    fail(used_by, ": cannot read texture '", path, "': ", why.empty() ? "not an image" : why);
  }
  const OIIO::ImageSpec& spec = in->spec();
  int w = spec.width, h = spec.height, nch = spec.nchannels;
  if (w <= 0 || h <= 0 || nch <= 0 || size_t(w) * h > (size_t(1) << 28))
    fail(used_by, ": texture '", path, "' has an unusable size ", w, "x", h, "x", nch);
  std::vector<float> px(size_t(w) * h * nch);
  bool ok = in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, px.data());
  if (!ok) fail(used_by, ": cannot decode texture '", path, "': ", in->geterror());
  in->close();
  // 8-bit sources are stored sRGB-encoded already; float sources get encoded.
  bool float_source =
      spec.format.basetype == OIIO::TypeDesc::FLOAT || spec.format.basetype == OIIO::TypeDesc::HALF;
  std::vector<uint8_t> rgba(size_t(w) * h * 4);
  size_t non_finite = 0;
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    float c[4];
    bool bad = false;
    for (int k = 0; k < 4; ++k) {
      int src = k < 3 ? (nch >= 3 ? k : 0) : (nch == 2 ? 1 : (nch >= 4 ? 3 : -1));
      float v = src < 0 ? 1.0f : px[i * nch + src];
      if (!std::isfinite(v)) v = 0.0f, bad = true;  // NaN/Inf channels become 0 (black)
      c[k] = v;
    }
    non_finite += bad ? 1 : 0;
    for (int k = 0; k < 4; ++k) {
      float v = c[k];
      if (float_source && srgb && k < 3) v = linear_to_srgb(std::max(0.0f, std::min(1.0f, v)));
      rgba[i * 4 + k] = to_byte(v);
    }
  }
  if (non_finite > 0)
    warn(used_by + ": texture '" + path + "': " + std::to_string(non_finite) + " of " +
         std::to_string(size_t(w) * h) + " texels hold NaN or Inf; those channels are read as 0 (black)");
  int index = add(path, w, h, std::move(rgba), srgb);
  by_key_[key] = index;
  return index;
}

}  // namespace pmc
