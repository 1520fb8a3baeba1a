// image_io.h — writing and reading images through OpenImageIO.
//
// Every write goes to a temporary file beside the target and is renamed into
// place only when complete, so a failed or interrupted render never leaves a
// half-written image. PNGs are tone-mapped (exposure, ACES-fit curve, sRGB).
#pragma once

#include <string>
#include <vector>

namespace pmc {

struct Image {
  int width = 0, height = 0, channels = 3;
  std::vector<float> pixels;  // row-major, top row first
};

void write_exr(const std::string& path, const Image& image);
// Tone-mapped 8-bit sRGB PNG of a linear image.
void write_png_tonemapped(const std::string& path, const Image& image, float exposure = 1.0f);
// 8-bit PNG of values already in display space [0,1] (heat maps, plots).
void write_png_display(const std::string& path, const Image& image);
Image read_image(const std::string& path);

// "out.exr" -> "out.png".
std::string replace_extension(const std::string& path, const std::string& extension);

}  // namespace pmc
