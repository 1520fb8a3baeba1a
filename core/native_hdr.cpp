// native_hdr.cpp — Radiance RGBE decoding (see native_hdr.h).
#include "core/native_hdr.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
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

// The pixels, scanline by scanline: each row's width x 3 floats go to
// emit(y, row) as soon as they are decoded, so no whole-image copy is made.
// A scanline that is not run-length encoded starts flat RGBE, which runs to
// the end of the image (as OpenImageIO reads it).
bool decode_rows(Bytes& in, int width, int height, const std::function<void(size_t, const float*)>& emit,
                 std::string& why) {
  const size_t w = size_t(width), h = size_t(height);
  std::vector<float> row(3 * w);
  why = "the file ends inside the pixels";
  // Flat pixels from (x0, y) on; the row's first x0 pixels are decoded already.
  auto flat_from = [&](size_t y, size_t x0) {
    for (; y < h; ++y, x0 = 0) {
      const unsigned char* p = nullptr;
      if (!in.take(4 * (w - x0), &p)) return false;
      for (size_t x = x0; x < w; ++x) to_float(p + 4 * (x - x0), &row[3 * x]);
      emit(y, row.data());
    }
    return true;
  };
  if (width < 8 || width > 0x7fff) return flat_from(0, 0);
  std::vector<unsigned char> line(4 * w);
  for (size_t y = 0; y < h; ++y) {
    const unsigned char* head = nullptr;
    if (!in.take(4, &head)) return false;
    if (head[0] != 2 || head[1] != 2 || (head[2] & 0x80)) {  // not run-length encoded: flat from here on
      to_float(head, &row[0]);
      return flat_from(y, 1);
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
    for (size_t x = 0; x < w; ++x) to_float(&line[4 * x], &row[3 * x]);
    emit(y, row.data());
  }
  return true;
}

// Keeps the file's bytes and decodes them in read(), straight into the
// caller's memory: a sky map read into its table holds the file and the
// table, not a decoded copy beside them. A file whose pixels are broken
// opens (its header is sound) and fails in read(), saying why.
class HdrReader final : public ImageReader {
 public:
  HdrReader(ImageHeader h, std::vector<unsigned char> file, size_t pixels_at)
      : h_(std::move(h)), file_(std::move(file)), pixels_at_(pixels_at) {}
  const ImageHeader& header() const override { return h_; }
  std::string error() override { return error_; }
  void close() override { file_ = {}; }
  bool read(int c0, int c1, PixelFormat format, void* data, std::ptrdiff_t xs, std::ptrdiff_t ys) override {
    if (c0 < 0 || c1 > 3 || c0 >= c1 || format != PixelFormat::Float) {
      error_ = "unsupported channel range or pixel format";
      return false;
    }
    if (file_.empty()) {
      error_ = "the file was closed";
      return false;
    }
    if (!xs) xs = std::ptrdiff_t(size_t(c1 - c0) * sizeof(float));
    if (!ys) ys = xs * h_.width;
    auto* out = static_cast<unsigned char*>(data);
    Bytes in{file_};
    in.at = pixels_at_;
    std::string problem;
    const bool ok = decode_rows(
        in, h_.width, h_.height,
        [&](size_t y, const float* row) {
          for (size_t x = 0; x < size_t(h_.width); ++x)
            std::memcpy(out + std::ptrdiff_t(y) * ys + std::ptrdiff_t(x) * xs, row + 3 * x + size_t(c0),
                        size_t(c1 - c0) * sizeof(float));
        },
        problem);
    close();  // the pixels are read once
    if (!ok) error_ = "corrupt Radiance HDR: " + problem;
    return ok;
  }

 private:
  ImageHeader h_;
  std::vector<unsigned char> file_;
  size_t pixels_at_ = 0;
  std::string error_;
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
  std::vector<unsigned char> data{std::istreambuf_iterator<char>(file), {}};
  Bytes in{data};
  int width = 0, height = 0;
  std::string problem;
  const Parsed header = parse_header(in, width, height, problem);
  if (header == Parsed::Unsupported) return nullptr;
  if (header == Parsed::Broken) {
    why = "corrupt Radiance HDR: " + problem;
    return nullptr;
  }
  // The fewest bytes a scanline can take (flat: 4 a pixel; run-length
  // encoded: its 4-byte start and a 2-byte run of at most 127 pixels per
  // component), so that a file far too short for its size line fails here,
  // before a caller allocates the image it claims.
  const size_t w = size_t(width), row_bytes = width < 8 || width > 0x7fff ? 4 * w : 4 + 8 * ((w + 126) / 127);
  if ((data.size() - in.at) / size_t(height) < row_bytes) {
    why = "corrupt Radiance HDR: the file ends inside the pixels";
    return nullptr;
  }
  ImageHeader h;
  h.width = h.full_width = width;
  h.height = h.full_height = height;
  h.channels = 3;
  h.format = PixelFormat::Float;
  h.channel_names = {"R", "G", "B"};
  const size_t pixels_at = in.at;
  return std::make_unique<HdrReader>(std::move(h), std::move(data), pixels_at);
}

}  // namespace pmc
