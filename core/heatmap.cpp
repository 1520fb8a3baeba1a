// heatmap.cpp — the map and its bar (viridis from the image backend), the bar's digit labels.
//
// The labels are drawn from 3x5 pixel digits of our own rather than with
// OpenImageIO's render_text: they must stay legible at 5 pixels high on a
// 64-pixel map, and render_text needs a TrueType font found on the machine
// at run time (Debian's OpenImageIO ships none: "Could not set default font
// face"), which would make the image depend on the machine's fonts.
#include "core/heatmap.h"

#include <algorithm>
#include <string>

#include "core/image_backend.h"

namespace pmc {
namespace {

// Copies the 3-channel `src` into `dst` with its top-left corner at (x, y).
void paste(Image& dst, int x, int y, const Image& src) {
  for (int row = 0; row < src.height; ++row)
    std::copy_n(&src.pixels[3 * size_t(row) * size_t(src.width)], 3 * size_t(src.width),
                &dst.pixels[3 * ((size_t(y) + size_t(row)) * size_t(dst.width) + size_t(x))]);
}

// 3x5 digit glyphs, rows top to bottom, 3 bits per row.
const unsigned char kDigits[10][5] = {{7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7},
                                      {5, 5, 7, 1, 1}, {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1},
                                      {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};

void draw_digits(Image& img, int x, int y, const std::string& text, int scale) {
  for (char c : text) {
    if (c < '0' || c > '9') continue;
    const unsigned char* g = kDigits[c - '0'];
    for (int row = 0; row < 5; ++row)
      for (int col = 0; col < 3; ++col)
        if (g[row] & (4 >> col))
          for (int dy = 0; dy < scale; ++dy)
            for (int dx = 0; dx < scale; ++dx) {
              const int px = x + col * scale + dx, py = y + row * scale + dy;
              if (px < 0 || py < 0 || px >= img.width || py >= img.height) continue;
              float* p = &img.pixels[3 * (size_t(py) * size_t(img.width) + size_t(px))];
              p[0] = p[1] = p[2] = 1.0f;
            }
    x += 4 * scale;
  }
}

}  // namespace

Image heatmap_with_colorbar(const Image& values, float max_value) {
  const int scale = std::max(1, values.height / 120);
  const int bar_w = 6 * scale + 14 * scale;
  ImageBackend& backend = image_backend();
  Image img;
  img.width = values.width + bar_w;
  img.height = values.height;
  img.channels = 3;
  img.pixels.assign(size_t(img.width) * size_t(img.height) * 3, 0.0f);
  Image scaled = values;
  for (float& v : scaled.pixels) v /= max_value;
  paste(img, 0, 0, backend.viridis(scaled));
  // The bar: top = max_value, bottom = 0, with a margin for the labels.
  const int margin = 4 * scale, x0 = values.width + 2 * scale, x1 = x0 + 5 * scale;
  const int top = margin, bottom = values.height - margin;
  if (bottom > top) {
    Image ramp;
    ramp.width = x1 - x0;
    ramp.height = bottom - top;
    ramp.channels = 1;
    for (int y = 0; y < ramp.height; ++y)
      ramp.pixels.insert(ramp.pixels.end(), size_t(ramp.width),
                         1.0f - float(y) / float(std::max(1, bottom - top - 1)));
    paste(img, x0, top, backend.viridis(ramp));
  }
  const int label_x = x1 + scale, m = int(max_value);
  draw_digits(img, label_x, top, std::to_string(m), scale);
  draw_digits(img, label_x, (top + bottom) / 2 - 2 * scale, std::to_string(m / 2), scale);
  draw_digits(img, label_x, bottom - 5 * scale, "0", scale);
  return img;
}

}  // namespace pmc
