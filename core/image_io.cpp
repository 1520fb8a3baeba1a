// image_io.cpp — OpenImageIO writes (atomic) and reads.
#include "core/image_io.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"

namespace pmc {
namespace {

void write_atomic(const std::string& path, const Image& image, OIIO::TypeDesc format, const void* data) {
  std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  // OIIO picks the format from the extension: keep it on the temporary name.
  size_t dot = path.find_last_of('.');
  if (dot != std::string::npos)
    tmp = path.substr(0, dot) + ".tmp" + std::to_string(::getpid()) + path.substr(dot);
  auto out = OIIO::ImageOutput::create(path);
  if (!out) fail(path, ": cannot write this image format (", OIIO::geterror(), ")");
  OIIO::ImageSpec spec(image.width, image.height, image.channels, format);
  if (!out->open(tmp, spec)) fail(path, ": cannot open for writing: ", out->geterror());
  bool ok = out->write_image(format, data);
  ok = out->close() && ok;
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    fail(path, ": writing the image failed");
  }
}

float aces_fit(float x) {  // Narkowicz 2015 fit of the ACES filmic curve
  float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;
  return std::clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0f, 1.0f);
}
float srgb_encode(float c) {
  if (c >= 1.0f) return 1.0f;  // exact at white (1.055 - 0.055 is not 1 in float)
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

}  // namespace

std::string replace_extension(const std::string& path, const std::string& extension) {
  size_t slash = path.find_last_of('/');
  size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + extension;
  return path.substr(0, dot) + extension;
}

void write_exr(const std::string& path, const Image& image) {
  write_atomic(path, image, OIIO::TypeDesc::FLOAT, image.pixels.data());
}

float display_encode(float linear, const DisplaySettings& display) {
  float v = linear * std::exp2(display.exposure_ev);
  if (!std::isfinite(v) || !(v > 0.0f)) return 0.0f;
  v = display.view == ViewTransform::Filmic ? aces_fit(v) : std::min(v, 1.0f);
  return srgb_encode(v);
}

ViewTransform parse_view_transform(const std::string& name, const std::string& option) {
  if (name == "filmic") return ViewTransform::Filmic;
  if (name == "standard") return ViewTransform::Standard;
  fail(option, ": expected filmic or standard, got '", name, "'");
}

void write_png_tonemapped(const std::string& path, const Image& image, const DisplaySettings& display) {
  std::vector<unsigned char> bytes(image.pixels.size());
  for (size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = (unsigned char)std::lround(255.0f * display_encode(image.pixels[i], display));
  write_atomic(path, image, OIIO::TypeDesc::UINT8, bytes.data());
}

void write_png_display(const std::string& path, const Image& image) {
  std::vector<unsigned char> bytes(image.pixels.size());
  for (size_t i = 0; i < bytes.size(); ++i) {
    float v = image.pixels[i];
    bytes[i] = (unsigned char)std::lround(255.0f * (std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f));
  }
  write_atomic(path, image, OIIO::TypeDesc::UINT8, bytes.data());
}

Image read_image(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) fail(path, ": cannot read image: ", OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  Image img;
  img.width = spec.width;
  img.height = spec.height;
  img.channels = spec.nchannels;
  img.pixels.resize(size_t(img.width) * img.height * img.channels);
  if (!in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
    fail(path, ": cannot decode image: ", in->geterror());
  return img;
}

}  // namespace pmc
