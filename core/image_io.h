// image_io.h — writing and reading images through OpenImageIO.
//
// Every write goes to a temporary file beside the target and is renamed into
// place only when complete, so a failed or interrupted render never leaves a
// half-written image. PNGs of renders go through the view transform below;
// EXRs stay linear.
#pragma once

#include <string>
#include <vector>

namespace pmc {

struct Image {
  int width = 0, height = 0, channels = 3;
  std::vector<float> pixels;  // row-major, top row first
};

// How a linear render becomes a PNG: scale by 2^exposure_ev, apply the view
// curve per channel, encode with the sRGB transfer function, round to 8 bits.
//   filmic   : Narkowicz's fit of the ACES filmic tone curve (2015),
//              x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1]:
//              highlights roll off instead of clipping (the default);
//   standard : clamp to [0, 1] (linear values above 1 clip to white).
// NaN/Inf and negative values display as 0.
enum class ViewTransform { Filmic, Standard };
struct DisplaySettings {
  float exposure_ev = 0.0f;
  ViewTransform view = ViewTransform::Filmic;
};
// One linear value through the view transform, in [0, 1] before 8-bit quantisation.
float display_encode(float linear, const DisplaySettings& display);
// "filmic" / "standard" -> ViewTransform (pmc::Error otherwise, naming `option`).
ViewTransform parse_view_transform(const std::string& name, const std::string& option);

void write_exr(const std::string& path, const Image& image);
// 8-bit sRGB PNG of a linear image through the view transform.
void write_png_tonemapped(const std::string& path, const Image& image, const DisplaySettings& display = {});
// 8-bit PNG of values already in display space [0,1] (heat maps, plots).
void write_png_display(const std::string& path, const Image& image);
Image read_image(const std::string& path);

// "out.exr" -> "out.png".
std::string replace_extension(const std::string& path, const std::string& extension);

}  // namespace pmc
