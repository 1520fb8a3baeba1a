// image_io.cpp — image writes (atomic) and reads through the image backend.
#include "core/image_io.h"

#include <algorithm>
#include <cmath>

#include "core/atomic_write.h"
#include "core/error.h"
#include "core/image_backend.h"

namespace pmc {
namespace {

void write_pixels(const std::string& path, const Image& image, PixelFormat format, const void* data) {
  ImageWrite w;
  w.header.width = image.width;
  w.header.height = image.height;
  w.header.channels = image.channels;
  w.format = format;
  w.pixels = data;
  ImageBackend& backend = image_backend();
  write_atomically(path, [&](const std::string& tmp) {
    std::string why;
    if (!backend.write(tmp, path, w, why)) fail(path, ": ", why);
  });
}

}  // namespace

void write_exr(const std::string& path, const Image& image) {
  write_pixels(path, image, PixelFormat::Float, image.pixels.data());
}

void write_exr_layers(const std::string& path, const Image& image, const std::vector<ImageLayer>& layers) {
  PMC_CHECK(image.channels == 3, "write_exr_layers: rgb");
  ImageWrite w;
  w.header.width = image.width;
  w.header.height = image.height;
  w.header.channel_names = {"R", "G", "B"};
  for (const ImageLayer& l : layers) {
    PMC_CHECK(l.image.width == image.width && l.image.height == image.height &&
                  size_t(l.image.channels) == l.channels.size(),
              "write_exr_layers: layer size");
    w.header.channel_names.insert(w.header.channel_names.end(), l.channels.begin(), l.channels.end());
  }
  const size_t n = size_t(image.width) * size_t(image.height), nch = w.header.channel_names.size();
  w.header.channels = int(nch);
  w.format = PixelFormat::Float;
  std::vector<float> data(n * nch);
  for (size_t i = 0; i < n; ++i) {
    float* px = &data[i * nch];
    for (int c = 0; c < 3; ++c) *px++ = image.pixels[3 * i + size_t(c)];
    for (const ImageLayer& l : layers)
      for (int c = 0; c < l.image.channels; ++c)
        *px++ = l.image.pixels[i * size_t(l.image.channels) + size_t(c)];
  }
  w.pixels = data.data();
  ImageBackend& backend = image_backend();
  write_atomically(path, [&](const std::string& tmp) {
    std::string why;
    if (!backend.write(tmp, path, w, why)) fail(path, ": ", why);
  });
}

void write_png_display(const std::string& path, const Image& image) {
  std::vector<unsigned char> bytes(image.pixels.size());
  for (size_t i = 0; i < bytes.size(); ++i) {
    float v = image.pixels[i];
    bytes[i] = (unsigned char)std::lround(255.0f * (std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f));
  }
  write_pixels(path, image, PixelFormat::U8, bytes.data());
}

Image read_image(const std::string& path) {
  std::string why;
  auto in = image_backend().open(path, false, why);
  if (!in) fail(path, ": cannot read image: ", why);
  const ImageHeader& h = in->header();
  Image img;
  img.width = h.width;
  img.height = h.height;
  img.channels = h.channels;
  img.pixels.resize(size_t(img.width) * img.height * img.channels);
  if (!in->read(0, img.channels, PixelFormat::Float, img.pixels.data()))
    fail(path, ": cannot decode image: ", in->error());
  return img;
}

Image first_channels(const Image& image, int channels) {
  PMC_CHECK(channels > 0 && channels <= image.channels, "first_channels");
  Image out;
  out.width = image.width;
  out.height = image.height;
  out.channels = channels;
  const size_t n = size_t(image.width) * size_t(image.height);
  out.pixels.resize(n * size_t(channels));
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < channels; ++c)
      out.pixels[i * size_t(channels) + size_t(c)] = image.pixels[i * size_t(image.channels) + size_t(c)];
  return out;
}

}  // namespace pmc
