// image_io.cpp — OpenImageIO writes (atomic) and reads.
#include "core/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

#include "core/atomic_write.h"
#include "core/error.h"

namespace pmc {
namespace {

void write_image(const std::string& path, const Image& image, OIIO::TypeDesc format, const void* data) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) fail(path, ": cannot write this image format (", OIIO::geterror(), ")");
  write_atomically(path, [&](const std::string& tmp) {
    OIIO::ImageSpec spec(image.width, image.height, image.channels, format);
    if (!out->open(tmp, spec)) fail(path, ": cannot open for writing: ", out->geterror());
    bool ok = out->write_image(format, data);
    ok = out->close() && ok;
    if (!ok) fail(path, ": writing the image failed");
  });
}

}  // namespace

void write_exr(const std::string& path, const Image& image) {
  write_image(path, image, OIIO::TypeDesc::FLOAT, image.pixels.data());
}

void write_png_display(const std::string& path, const Image& image) {
  std::vector<unsigned char> bytes(image.pixels.size());
  for (size_t i = 0; i < bytes.size(); ++i) {
    float v = image.pixels[i];
    bytes[i] = (unsigned char)std::lround(255.0f * (std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f));
  }
  write_image(path, image, OIIO::TypeDesc::UINT8, bytes.data());
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
