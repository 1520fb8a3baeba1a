// native_hdr.cpp — Radiance RGBE decoding (see native_hdr.h).
#include "core/native_hdr.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "core/native_images.h"

namespace pmc {
namespace {

// A byte cursor over the whole file; every read checks the end.
struct Bytes {
  const std::vector<unsigned char>& data;
  size_t at = 0;
  bool line(std::string& out) {
    out.clear();
    while (at < data.size() && data[at] != '\n') out.push_back(char(data[at++]));
    if (at >= data.size()) return false;
    ++at;
    return true;
  }
  bool take(size_t n, const unsigned char** p) {
    if (data.size() - at < n) return false;
    *p = &data[at];
    at += n;
    return true;
  }
};

enum class Parsed { Ok, Broken, Unsupported };

// Header and resolution line; `why` says what is wrong when Broken.
Parsed parse_header(Bytes& in, int& width, int& height, std::string& why) {
  std::string line;
  if (!in.line(line) || line.compare(0, 2, "#?") != 0) {
    why = "no '#?' signature line";
    return Parsed::Broken;
  }
  for (;;) {
    if (!in.line(line)) {
      why = "the header has no end (an empty line)";
      return Parsed::Broken;
    }
    if (line.empty()) break;
    if (line.compare(0, 7, "FORMAT=") == 0 && line != "FORMAT=32-bit_rle_rgbe") return Parsed::Unsupported;
  }
  if (!in.line(line)) {
    why = "no resolution line";
    return Parsed::Broken;
  }
  char ya[3] = {}, xa[3] = {};
  long h = 0, w = 0;
  if (std::sscanf(line.c_str(), "%2s %ld %2s %ld", ya, &h, xa, &w) != 4) {
    why = "bad resolution line '" + line + "'";
    return Parsed::Broken;
  }
  if (std::string(ya) != "-Y" || std::string(xa) != "+X") return Parsed::Unsupported;  // another orientation
  why = native_size_problem(w, h);
  if (!why.empty()) return Parsed::Broken;
  width = int(w);
  height = int(h);
  return Parsed::Ok;
}

void to_float(const unsigned char* rgbe, float* rgb) {
  if (rgbe[3] == 0) {
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    return;
  }
  // One power of two a texel, and products that are exact (an 8-bit
  // mantissa times 2^(e - 136) is a float even below the normal range):
  // the values ldexp would give each channel, at a third of the calls.
  const float scale = std::ldexp(1.0f, int(rgbe[3]) - 136);
  for (int c = 0; c < 3; ++c) rgb[c] = float(rgbe[c]) * scale;
}

// `count` pixels from the cursor on, flat RGBE, appended to `out` (checked
// against the bytes left before anything is allocated).
bool flat_pixels(Bytes& in, size_t count, std::vector<float>& out) {
  const unsigned char* p = nullptr;
  if (!in.take(count * 4, &p)) return false;
  const size_t first = out.size() / 3;
  out.resize(out.size() + 3 * count);
  for (size_t i = 0; i < count; ++i) to_float(p + 4 * i, &out[3 * (first + i)]);
  return true;
}

// The pixels, appended scanline by scanline: a file cut short fails before
// the whole image is allocated.
bool decode_pixels(Bytes& in, int width, int height, std::vector<float>& out, std::string& why) {
  const size_t w = size_t(width), total = w * size_t(height);
  out.clear();
  why = "the file ends inside the pixels";
  if (width < 8 || width > 0x7fff) return flat_pixels(in, total, out);
  std::vector<unsigned char> line(4 * w);
  for (size_t y = 0; y < size_t(height); ++y) {
    const unsigned char* head = nullptr;
    if (!in.take(4, &head)) return false;
    if (head[0] != 2 || head[1] != 2 || (head[2] & 0x80)) {  // not run-length encoded: flat from here on
      out.resize(out.size() + 3);
      to_float(head, &out[3 * y * w]);
      return flat_pixels(in, total - y * w - 1, out);
    }
    if (((size_t(head[2]) << 8) | head[3]) != w) {
      why = "a scanline of the wrong width";
      return false;
    }
    for (int c = 0; c < 4; ++c) {  // each component's runs in turn
      for (size_t x = 0; x < w;) {
        const unsigned char* p = nullptr;
        if (!in.take(1, &p)) return false;
        size_t n = *p;
        const bool run = n > 128;
        if (run) n -= 128;
        if (n == 0 || n > w - x) {
          why = "bad run-length data";
          return false;
        }
        if (!in.take(run ? 1 : n, &p)) return false;
        for (size_t k = 0; k < n; ++k) line[4 * (x + k) + size_t(c)] = run ? p[0] : p[k];
        x += n;
      }
    }
    out.resize(out.size() + 3 * w);
    for (size_t x = 0; x < w; ++x) to_float(&line[4 * x], &out[3 * (y * w + x)]);
  }
  return true;
}

class HdrReader final : public DecodedImageReader<float> {
 public:
  using DecodedImageReader::DecodedImageReader;
  bool read(int c0, int c1, PixelFormat format, void* data, std::ptrdiff_t xs, std::ptrdiff_t ys) override {
    if (c0 < 0 || c1 > 3 || c0 >= c1 || format != PixelFormat::Float) {
      error_ = "unsupported channel range or pixel format";
      return false;
    }
    if (!open_pixels()) return false;
    if (!xs) xs = std::ptrdiff_t(size_t(c1 - c0) * sizeof(float));
    if (!ys) ys = xs * h_.width;
    auto* out = static_cast<unsigned char*>(data);
    for (int y = 0; y < h_.height; ++y)
      for (int x = 0; x < h_.width; ++x) {
        const float* src = &pixels_[3 * (size_t(y) * size_t(h_.width) + size_t(x))];
        std::memcpy(out + y * ys + x * xs, src + c0, size_t(c1 - c0) * sizeof(float));
      }
    return true;
  }
};

}  // namespace

bool is_radiance_hdr(const unsigned char* magic, size_t n) {
  return n >= 2 && magic[0] == '#' && magic[1] == '?';
}

std::unique_ptr<ImageReader> open_radiance_hdr(const std::string& path, std::string& why) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    why = std::string("cannot open: ") + std::strerror(errno);
    return nullptr;
  }
  const std::vector<unsigned char> data{std::istreambuf_iterator<char>(file), {}};
  Bytes in{data};
  int width = 0, height = 0;
  std::string problem;
  const Parsed header = parse_header(in, width, height, problem);
  if (header == Parsed::Unsupported) return nullptr;
  std::vector<float> pixels;
  if (header == Parsed::Broken || !decode_pixels(in, width, height, pixels, problem)) {
    why = "corrupt Radiance HDR: " + problem;
    return nullptr;
  }
  ImageHeader h;
  h.width = h.full_width = width;
  h.height = h.full_height = height;
  h.channels = 3;
  h.format = PixelFormat::Float;
  h.channel_names = {"R", "G", "B"};
  return std::make_unique<HdrReader>(std::move(h), std::move(pixels));
}

}  // namespace pmc
