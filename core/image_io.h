// image_io.h — writing and reading images (through the image plugin, core/image_backend.h).
//
// Every write is atomic (core/atomic_write.h): a failed or interrupted
// render never leaves a half-written image. PNGs hold display values: tone
// map a render first (core/tone_map.h).
#pragma once

#include <string>
#include <vector>

namespace pmc {

struct Image {
  int width = 0, height = 0, channels = 3;
  std::vector<float> pixels;  // row-major, top row first
};

// Channels of an image written under their own names beside an image's
// R, G, B (an EXR layer: "albedo.R", ..., or "Z").
struct ImageLayer {
  std::vector<std::string> channels;  // one name per channel of `image`
  Image image;
};

void write_exr(const std::string& path, const Image& image);
// An EXR of `image`'s R, G, B (it must have 3 channels) and the layers (same size).
void write_exr_layers(const std::string& path, const Image& image, const std::vector<ImageLayer>& layers);
// 8-bit PNG of values already in display space [0,1] (tone-mapped renders, heat maps).
void write_png_display(const std::string& path, const Image& image);
Image read_image(const std::string& path);
// The first `channels` channels of `image` (RGB of an RGBA image).
Image first_channels(const Image& image, int channels);

}  // namespace pmc
