// heatmap.cpp — the map and its bar (matplotlib's viridis, 17 knots interpolated in
// display space), the bar's digit labels.
//
// The labels are drawn from 3x5 pixel digits of our own rather than with
// OpenImageIO's render_text: they must stay legible at 5 pixels high on a
// 64-pixel map, and render_text needs a TrueType font found on the machine
// at run time (Debian's OpenImageIO ships none: "Could not set default font
// face"), which would make the image depend on the machine's fonts.
#include "core/heatmap.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/image_io.h"

namespace pmc {
namespace {

// matplotlib's viridis at t = i / 16 (display values).
const float kViridis[17][3] = {
    {0.267004f, 0.004874f, 0.329415f}, {0.282327f, 0.094955f, 0.417331f}, {0.278826f, 0.175490f, 0.483397f},
    {0.258965f, 0.251537f, 0.524736f}, {0.229739f, 0.322361f, 0.545706f}, {0.199430f, 0.387607f, 0.554642f},
    {0.172719f, 0.448791f, 0.557885f}, {0.149039f, 0.508051f, 0.557250f}, {0.127568f, 0.566949f, 0.550556f},
    {0.120638f, 0.625828f, 0.533488f}, {0.157851f, 0.683765f, 0.501686f}, {0.246070f, 0.738910f, 0.452024f},
    {0.369214f, 0.788888f, 0.382914f}, {0.515992f, 0.831158f, 0.294279f}, {0.678489f, 0.863742f, 0.189503f},
    {0.845561f, 0.887322f, 0.099702f}, {0.993248f, 0.906157f, 0.143936f}};

// Viridis display colours (sRGB-encoded, 3 channels) of one-channel values in [0, 1].
Image viridis(const Image& values) {
  Image out;
  out.width = values.width;
  out.height = values.height;
  out.channels = 3;
  const size_t n = size_t(values.width) * size_t(values.height);
  out.pixels.resize(n * 3);
  for (size_t i = 0; i < n; ++i) {
    float t = values.pixels[i * size_t(values.channels)];
    t = std::isfinite(t) ? std::clamp(t, 0.0f, 1.0f) * 16.0f : 0.0f;
    const int k = std::min(15, int(t));
    const float f = t - float(k);
    for (int c = 0; c < 3; ++c)
      out.pixels[i * 3 + size_t(c)] = kViridis[k][c] + f * (kViridis[k + 1][c] - kViridis[k][c]);
  }
  return out;
}

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
  Image img;
  img.width = values.width + bar_w;
  img.height = values.height;
  img.channels = 3;
  img.pixels.assign(size_t(img.width) * size_t(img.height) * 3, 0.0f);
  Image scaled = values;
  for (float& v : scaled.pixels) v /= max_value;
  paste(img, 0, 0, viridis(scaled));
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
    paste(img, x0, top, viridis(ramp));
  }
  const int label_x = x1 + scale, m = int(max_value);
  draw_digits(img, label_x, top, std::to_string(m), scale);
  draw_digits(img, label_x, (top + bottom) / 2 - 2 * scale, std::to_string(m / 2), scale);
  draw_digits(img, label_x, bottom - 5 * scale, "0", scale);
  return img;
}

}  // namespace pmc
