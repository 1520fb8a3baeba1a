// heatmap.cpp — viridis, the colour bar and its digit labels.
#include "core/heatmap.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace pmc {
namespace {

// Viridis sampled at 9 points (matplotlib's published colour map).
const float kViridis[9][3] = {{68, 1, 84},    {71, 44, 122}, {59, 81, 139},  {44, 113, 142}, {33, 144, 141},
                              {39, 173, 129}, {92, 200, 99}, {170, 220, 50}, {253, 231, 37}};

// 3x5 digit glyphs, rows top to bottom, 3 bits per row.
const unsigned char kDigits[10][5] = {{7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7},
                                      {5, 5, 7, 1, 1}, {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1},
                                      {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};

void put(Image& img, int x, int y, float r, float g, float b) {
  if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
  float* p = &img.pixels[3 * (size_t(y) * img.width + x)];
  p[0] = r, p[1] = g, p[2] = b;
}

void draw_text(Image& img, int x, int y, const std::string& text, int scale) {
  for (char c : text) {
    if (c < '0' || c > '9') continue;
    const unsigned char* g = kDigits[c - '0'];
    for (int row = 0; row < 5; ++row)
      for (int col = 0; col < 3; ++col)
        if (g[row] & (4 >> col))
          for (int dy = 0; dy < scale; ++dy)
            for (int dx = 0; dx < scale; ++dx) put(img, x + col * scale + dx, y + row * scale + dy, 1, 1, 1);
    x += 4 * scale;
  }
}

}  // namespace

void viridis(float t, float rgb[3]) {
  if (!std::isfinite(t)) t = 0.0f;
  t = std::clamp(t, 0.0f, 1.0f) * 8.0f;
  int i = std::min(7, int(t));
  float f = t - float(i);
  for (int c = 0; c < 3; ++c) rgb[c] = (kViridis[i][c] + (kViridis[i + 1][c] - kViridis[i][c]) * f) / 255.0f;
}

Image heatmap_with_colorbar(const Image& values, float max_value) {
  const int scale = std::max(1, values.height / 120);
  const int bar_w = 6 * scale + 14 * scale;
  Image out;
  out.width = values.width + bar_w;
  out.height = values.height;
  out.channels = 3;
  out.pixels.assign(size_t(out.width) * out.height * 3, 0.0f);
  for (int y = 0; y < values.height; ++y)
    for (int x = 0; x < values.width; ++x) {
      float rgb[3];
      viridis(values.pixels[size_t(y) * values.width + x] / max_value, rgb);
      put(out, x, y, rgb[0], rgb[1], rgb[2]);
    }
  // The bar: top = max_value, bottom = 0, with a margin for the labels.
  const int margin = 4 * scale, x0 = values.width + 2 * scale, x1 = x0 + 5 * scale;
  const int top = margin, bottom = values.height - margin;
  for (int y = top; y < bottom; ++y) {
    float rgb[3];
    viridis(1.0f - float(y - top) / float(std::max(1, bottom - top - 1)), rgb);
    for (int x = x0; x < x1; ++x) put(out, x, y, rgb[0], rgb[1], rgb[2]);
  }
  const int label_x = x1 + scale;
  const int m = int(max_value);
  draw_text(out, label_x, top, std::to_string(m), scale);
  draw_text(out, label_x, (top + bottom) / 2 - 2 * scale, std::to_string(m / 2), scale);
  draw_text(out, label_x, bottom - 5 * scale, "0", scale);
  return out;
}

}  // namespace pmc
