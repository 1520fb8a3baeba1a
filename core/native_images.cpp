// native_images.cpp — OpenEXR (libOpenEXR) and 8-bit PNG (libpng) files, read and written directly.
#include "core/native_images.h"

#include <OpenEXR/IlmThreadPool.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <png.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <vector>

#include "core/native_hdr.h"
#include "core/native_jpeg.h"

namespace pmc {
namespace {

std::string lower_extension(const std::string& path) {
  const size_t dot = path.rfind('.');
  if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return {};
  std::string ext = path.substr(dot);
  for (char& c : ext) c = char(std::tolower((unsigned char)c));
  return ext;
}

// The first bytes of a file (fewer when it is shorter or unreadable).
std::vector<unsigned char> magic(const std::string& path, size_t n) {
  std::vector<unsigned char> bytes(n);
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return {};
  bytes.resize(std::fread(bytes.data(), 1, n, f));
  std::fclose(f);
  return bytes;
}

size_t format_bytes(PixelFormat f) {
  switch (f) {
    case PixelFormat::U8:
      return 1;
    case PixelFormat::U16:
    case PixelFormat::Half:
      return 2;
    case PixelFormat::U32:
    case PixelFormat::Float:
      return 4;
    case PixelFormat::Other:
      break;
  }
  return 0;
}

// ---- PNG -----------------------------------------------------------------

// libpng reports errors by longjmp: the handlers copy the message here, and
// every libpng call sits in a function whose locals are plain data.
struct PngState {
  FILE* file = nullptr;
  png_structp png = nullptr;
  png_infop info = nullptr;
  char error[256] = {};
};

void png_fail(png_structp png, png_const_charp message) {
  auto* s = static_cast<PngState*>(png_get_error_ptr(png));
  std::snprintf(s->error, sizeof(s->error), "%s", message);
  longjmp(png_jmpbuf(png), 1);
}

void png_ignore_warning(png_structp, png_const_charp) {}

// Reads the header and sets the expansions; false on a libpng error.
// `unsupported` is set for what the plugin should read instead.
bool png_read_header(PngState& s, bool unassociated_alpha, ImageHeader& h, bool& unsupported) {
  s.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &s, png_fail, png_ignore_warning);
  if (!s.png) return false;
  s.info = png_create_info_struct(s.png);
  if (!s.info) return false;
  if (setjmp(png_jmpbuf(s.png))) return false;
  png_init_io(s.png, s.file);
  png_read_info(s.png, s.info);
  const int depth = png_get_bit_depth(s.png, s.info), type = png_get_color_type(s.png, s.info);
  if (depth > 8) {
    unsupported = true;
    return true;
  }
  if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(s.png);
  if (type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(s.png);
  if (png_get_valid(s.png, s.info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(s.png);
  png_set_interlace_handling(s.png);
  png_read_update_info(s.png, s.info);
  h.width = int(png_get_image_width(s.png, s.info));
  h.height = int(png_get_image_height(s.png, s.info));
  h.channels = png_get_channels(s.png, s.info);
  h.full_width = h.width;
  h.full_height = h.height;
  h.format = PixelFormat::U8;
  const std::string size =
      native_size_problem(png_get_image_width(s.png, s.info), png_get_image_height(s.png, s.info));
  if (!size.empty()) {
    std::snprintf(s.error, sizeof(s.error), "%s", size.c_str());
    return false;
  }
  static const char* const kNames[4][4] = {{"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
  if (h.channels < 1 || h.channels > 4) return false;
  h.channel_names.assign(kNames[h.channels - 1], kNames[h.channels - 1] + h.channels);
  // Associated alpha means premultiplying, which OpenImageIO does in its own way: its job.
  unsupported = !unassociated_alpha && (h.channels == 2 || h.channels == 4);
  return true;
}

bool png_read_rows(PngState& s, png_bytepp rows) {
  if (setjmp(png_jmpbuf(s.png))) return false;
  png_read_image(s.png, rows);
  png_read_end(s.png, nullptr);
  return true;
}

// One row of a non-interlaced image into `row`; false on corrupt data.
bool png_read_one_row(PngState& s, png_bytep row) {
  if (setjmp(png_jmpbuf(s.png))) return false;
  png_read_row(s.png, row, nullptr);
  return true;
}

bool png_finish(PngState& s) {
  if (setjmp(png_jmpbuf(s.png))) return false;
  png_read_end(s.png, nullptr);
  return true;
}

// A non-interlaced image row by row, `pixels` grown with each: a file cut
// short fails before the size its header claims is allocated.
bool png_read_growing(PngState& s, size_t row, size_t height, std::vector<unsigned char>& pixels) {
  if (setjmp(png_jmpbuf(s.png))) return false;
  for (size_t y = 0; y < height; ++y) {
    pixels.resize((y + 1) * row);
    png_read_row(s.png, &pixels[y * row], nullptr);
  }
  png_read_end(s.png, nullptr);
  return true;
}

void png_release(PngState& s) {
  if (s.png) png_destroy_read_struct(&s.png, s.info ? &s.info : nullptr, nullptr);
  if (s.file) std::fclose(s.file);
  s.png = nullptr;
  s.info = nullptr;
  s.file = nullptr;
}

class PngReader final : public ImageReader {
 public:
  PngReader(PngState s, ImageHeader h) : s_(s), h_(std::move(h)) {
    png_set_error_fn(s_.png, &s_, png_fail, png_ignore_warning);  // its messages now land in this copy
  }
  ~PngReader() override { png_release(s_); }
  const ImageHeader& header() const override { return h_; }
  bool read(int c0, int c1, PixelFormat format, void* data, std::ptrdiff_t xs, std::ptrdiff_t ys) override {
    if (pixels_.empty() && s_.png && png_get_interlace_type(s_.png, s_.info) == PNG_INTERLACE_NONE)
      return stream(c0, c1, format, data, xs, ys);
    return decoded() && copy_u8_channels(pixels_.data(), h_, c0, c1, format, data, xs, ys, error_);
  }
  std::string error() override { return error_; }
  void close() override { png_release(s_); }

 private:
  // A non-interlaced image row by row straight into `data`, through one row
  // of memory: no whole-image buffer to allocate, fault in and copy from.
  // The file is read once; a second read() finds it closed.
  bool stream(int c0, int c1, PixelFormat format, void* data, std::ptrdiff_t xs, std::ptrdiff_t ys) {
    bool decoded = true;
    const bool ok = stream_u8_channels(
        h_, c0, c1, format, data, xs, ys,
        [&](unsigned char* row) { return decoded = png_read_one_row(s_, row); }, error_);
    const bool finished = ok && png_finish(s_);
    if (!decoded || (ok && !finished)) error_ = s_.error[0] ? s_.error : "corrupt PNG data";
    png_release(s_);
    return finished;
  }

  bool decoded() {
    if (!pixels_.empty()) return true;
    if (!s_.png) {
      error_ = "the file was closed";
      return false;
    }
    const size_t row = size_t(h_.width) * size_t(h_.channels);
    bool ok;
    if (png_get_interlace_type(s_.png, s_.info) == PNG_INTERLACE_NONE) {
      ok = png_read_growing(s_, row, size_t(h_.height), pixels_);
    } else {  // Adam7 passes fill the whole image at once
      pixels_.resize(row * size_t(h_.height));
      std::vector<png_bytep> rows(size_t(h_.height));
      for (size_t y = 0; y < rows.size(); ++y) rows[y] = &pixels_[y * row];
      ok = png_read_rows(s_, rows.data());
    }
    if (!ok) {
      error_ = s_.error[0] ? s_.error : "corrupt PNG data";
      pixels_.clear();
    }
    png_release(s_);
    return ok;
  }

  PngState s_;
  ImageHeader h_;
  std::vector<unsigned char> pixels_;
  std::string error_;
};

std::unique_ptr<ImageReader> open_png(const std::string& path, bool unassociated_alpha, std::string& why) {
  PngState s;
  s.file = std::fopen(path.c_str(), "rb");
  if (!s.file) {
    why = std::string("cannot open: ") + std::strerror(errno);
    return nullptr;
  }
  ImageHeader h;
  bool unsupported = false;
  if (!png_read_header(s, unassociated_alpha, h, unsupported)) {
    why = s.error[0] ? s.error : "not a readable PNG";
    png_release(s);
    return nullptr;
  }
  if (unsupported) {
    png_release(s);
    return nullptr;  // the plugin reads it
  }
  return std::make_unique<PngReader>(s, std::move(h));
}

bool png_write_rows(PngState& s, const ImageWrite& image, png_bytepp rows) {
  s.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &s, png_fail, png_ignore_warning);
  if (!s.png) return false;
  s.info = png_create_info_struct(s.png);
  if (!s.info) return false;
  if (setjmp(png_jmpbuf(s.png))) return false;
  static const int kTypes[4] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                PNG_COLOR_TYPE_RGB_ALPHA};
  png_init_io(s.png, s.file);
  png_set_IHDR(s.png, s.info, png_uint_32(image.header.width), png_uint_32(image.header.height), 8,
               kTypes[image.header.channels - 1], PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  // zlib level 3, not libpng's 6: a third of the time for a ~10% larger
  // file (640x360 render: 11 ms against 29 ms).
  png_set_compression_level(s.png, 3);
  png_write_info(s.png, s.info);
  png_write_image(s.png, rows);
  png_write_end(s.png, nullptr);
  return true;
}

bool write_png(const std::string& file, const ImageWrite& image, std::string& why) {
  PngState s;
  s.file = std::fopen(file.c_str(), "wb");
  if (!s.file) {
    why = std::string("cannot open for writing: ") + std::strerror(errno);
    return false;
  }
  const size_t row = size_t(image.header.width) * size_t(image.header.channels);
  std::vector<png_bytep> rows(size_t(image.header.height));
  auto* pixels = static_cast<const unsigned char*>(image.pixels);
  for (size_t y = 0; y < rows.size(); ++y) rows[y] = const_cast<png_bytep>(pixels + y * row);
  bool ok = png_write_rows(s, image, rows.data());
  if (!ok) why = s.error[0] ? s.error : "writing the PNG failed";
  if (s.png) png_destroy_write_struct(&s.png, s.info ? &s.info : nullptr);
  ok = std::fclose(s.file) == 0 && ok;
  if (!ok && why.empty()) why = "writing the PNG failed";
  return ok;
}

// ---- OpenEXR -------------------------------------------------------------

Imf::PixelType exr_type(PixelFormat f) {
  switch (f) {
    case PixelFormat::U32:
      return Imf::UINT;
    case PixelFormat::Half:
      return Imf::HALF;
    default:
      return Imf::FLOAT;
  }
}

PixelFormat format_of(Imf::PixelType t) {
  switch (t) {
    case Imf::UINT:
      return PixelFormat::U32;
    case Imf::HALF:
      return PixelFormat::Half;
    case Imf::FLOAT:
      return PixelFormat::Float;
    default:
      return PixelFormat::Other;
  }
}

// The header alone, checked before Imf::InputFile reads the file's offset
// tables: their size follows the data window, so a broken header claiming
// 10^8 scanlines cost seconds and gigabytes before any check of ours.
// Returns the file opened once its header passed.
std::unique_ptr<Imf::InputFile> open_checked_exr(const std::string& path) {
  Imf::StdIFStream in(path.c_str());
  char magic_and_version[8];
  in.read(magic_and_version, 8);  // throws at the end of the file
  int version = 0;
  for (int k = 0; k < 4; ++k) version |= int((unsigned char)magic_and_version[4 + k]) << (8 * k);
  Imf::Header header;
  header.readFrom(in, version);
  const Imath::Box2i data = header.dataWindow();
  const long long w = (long long)data.max.x - data.min.x + 1, h = (long long)data.max.y - data.min.y + 1;
  std::string size = native_size_problem(w, h);
  if (size.empty() && h > kMaxNativeRows)
    size = std::to_string(h) + " scanlines is over pmc's limit of " + std::to_string(kMaxNativeRows);
  if (!size.empty()) throw std::runtime_error("data window: " + size);
  return std::make_unique<Imf::InputFile>(path.c_str());
}

class ExrReader final : public ImageReader {
 public:
  // The data window is within the native limits (open_checked_exr).
  explicit ExrReader(const std::string& path) : file_(open_checked_exr(path)) {
    const Imf::Header& hd = file_->header();
    const Imath::Box2i data = hd.dataWindow(), display = hd.displayWindow();
    // Sizes in 64 bits: a display window may span the whole int range.
    const auto extent = [](int lo, int hi) { return (long long)hi - (long long)lo + 1; };
    const long long full_w = extent(display.min.x, display.max.x),
                    full_h = extent(display.min.y, display.max.y);
    if (full_w <= 0 || full_h <= 0 || full_w > INT32_MAX || full_h > INT32_MAX)
      throw std::runtime_error("impossible display window");
    h_.x = data.min.x;
    h_.y = data.min.y;
    h_.width = int(extent(data.min.x, data.max.x));
    h_.height = int(extent(data.min.y, data.max.y));
    h_.full_x = display.min.x;
    h_.full_y = display.min.y;
    h_.full_width = int(full_w);
    h_.full_height = int(full_h);
    std::vector<std::string> rgba, rest;
    for (auto c = hd.channels().begin(); c != hd.channels().end(); ++c) {
      const std::string name = c.name();
      (name == "R" || name == "G" || name == "B" || name == "A" ? rgba : rest).push_back(name);
    }
    auto rank = [](const std::string& n) { return std::string("RGBA").find(n); };
    std::sort(rgba.begin(), rgba.end(), [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
    h_.channel_names = rgba;
    h_.channel_names.insert(h_.channel_names.end(), rest.begin(), rest.end());
    h_.channels = int(h_.channel_names.size());
    h_.format =
        h_.channels ? format_of(hd.channels().findChannel(h_.channel_names[0])->type) : PixelFormat::Other;
  }
  const ImageHeader& header() const override { return h_; }
  bool read(int c0, int c1, PixelFormat format, void* data, std::ptrdiff_t xs, std::ptrdiff_t ys) override {
    if (c0 < 0 || c1 > h_.channels || c0 >= c1 ||
        (format != PixelFormat::Float && format != PixelFormat::U32)) {
      error_ = "unsupported channel range or pixel format";
      return false;
    }
    try {
      const std::ptrdiff_t size = 4;
      if (!xs) xs = size * (c1 - c0);
      if (!ys) ys = xs * h_.width;
      // OpenEXR addresses slices by absolute pixel coordinates.
      char* origin = static_cast<char*>(data) - h_.x * xs - h_.y * ys;
      Imf::FrameBuffer fb;
      for (int c = c0; c < c1; ++c)
        fb.insert(h_.channel_names[size_t(c)],
                  Imf::Slice(exr_type(format), origin + size * (c - c0), size_t(xs), size_t(ys)));
      file_->setFrameBuffer(fb);
      file_->readPixels(h_.y, h_.y + h_.height - 1);
      return true;
    } catch (const std::exception& e) {
      error_ = e.what();
      return false;
    }
  }
  std::string error() override { return error_; }
  void close() override {}
  std::string string_attribute(const std::string& name, const std::string& fallback) const override {
    const auto* a = file_->header().findTypedAttribute<Imf::StringAttribute>(name);
    return a ? a->value() : fallback;
  }
  int int_attribute(const std::string& name, int fallback) const override {
    const auto* a = file_->header().findTypedAttribute<Imf::IntAttribute>(name);
    return a ? a->value() : fallback;
  }
  float float_attribute(const std::string& name, float fallback) const override {
    const auto* a = file_->header().findTypedAttribute<Imf::FloatAttribute>(name);
    return a ? a->value() : fallback;
  }

 private:
  std::unique_ptr<Imf::InputFile> file_;
  ImageHeader h_;
  std::string error_;
};

Imf::Compression exr_compression(const std::string& name) {
  if (name == "none") return Imf::NO_COMPRESSION;
  if (name == "rle") return Imf::RLE_COMPRESSION;
  if (name == "zips") return Imf::ZIPS_COMPRESSION;
  if (name == "piz") return Imf::PIZ_COMPRESSION;
  return Imf::ZIP_COMPRESSION;
}

bool write_exr_file(const std::string& file, const ImageWrite& image, std::string& why) {
  try {
    const ImageHeader& h = image.header;
    const Imath::Box2i data(Imath::V2i(h.x, h.y), Imath::V2i(h.x + h.width - 1, h.y + h.height - 1));
    const Imath::Box2i display =
        h.full_width > 0 ? Imath::Box2i(Imath::V2i(h.full_x, h.full_y),
                                        Imath::V2i(h.full_x + h.full_width - 1, h.full_y + h.full_height - 1))
                         : data;
    Imf::Header hd(display, data);
    hd.compression() = Imf::ZIP_COMPRESSION;
    // Rendered floats barely compress (about 11% at any zlib level), so the
    // fastest level; and OpenEXR compresses its 16-line blocks on as many
    // threads as the thread budget allows (a 640x360 RGBA render: 31 ms
    // against 60 ms at level 4 on one thread).
    hd.zipCompressionLevel() = 1;
    static const int threads = [] {  // sized once: concurrent writers share the pool
      const int n = std::max<int>(
          1, int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
      IlmThread::ThreadPool::globalThreadPool().setNumThreads(n);
      return n;
    }();
    for (const ImageAttribute& a : image.attributes) {
      if (a.name == "compression") {
        hd.compression() = exr_compression(a.text);
        continue;
      }
      switch (a.kind) {
        case ImageAttribute::Kind::String:
          hd.insert(a.name, Imf::StringAttribute(a.text));
          break;
        case ImageAttribute::Kind::Int:
          hd.insert(a.name, Imf::IntAttribute(a.integer));
          break;
        case ImageAttribute::Kind::Float:
          hd.insert(a.name, Imf::FloatAttribute(a.real));
          break;
      }
    }
    static const char* const kNames[4][4] = {{"Y"}, {"R", "G"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
    std::vector<std::string> names = h.channel_names;
    if (names.empty() && h.channels <= 4)
      names.assign(kNames[h.channels - 1], kNames[h.channels - 1] + h.channels);
    std::vector<PixelFormat> formats = image.channel_formats;
    if (formats.empty()) formats.assign(size_t(h.channels), image.format);
    std::ptrdiff_t pixel = 0;
    for (PixelFormat f : formats) pixel += std::ptrdiff_t(format_bytes(f));
    const std::ptrdiff_t row = pixel * h.width;
    const char* origin = static_cast<const char*>(image.pixels) - h.x * pixel - h.y * row;
    Imf::FrameBuffer fb;
    std::ptrdiff_t at = 0;
    for (size_t c = 0; c < names.size(); ++c) {
      hd.channels().insert(names[c], Imf::Channel(exr_type(formats[c])));
      fb.insert(names[c],
                Imf::Slice(exr_type(formats[c]), const_cast<char*>(origin + at), size_t(pixel), size_t(row)));
      at += std::ptrdiff_t(format_bytes(formats[c]));
    }
    Imf::OutputFile out(file.c_str(), hd, threads);
    out.setFrameBuffer(fb);
    out.writePixels(h.height);
    return true;
  } catch (const std::exception& e) {
    why = e.what();
    return false;
  }
}

}  // namespace

std::unique_ptr<ImageReader> open_native_image(const std::string& path, bool unassociated_alpha,
                                               std::string& why) {
  const std::vector<unsigned char> m = magic(path, 8);
  if (m.size() == 8 && png_sig_cmp(m.data(), 0, 8) == 0) return open_png(path, unassociated_alpha, why);
  if (is_jpeg(m.data(), m.size())) return open_jpeg(path, why);
  if (is_radiance_hdr(m.data(), m.size())) return open_radiance_hdr(path, why);
  if (m.size() >= 4 && m[0] == 0x76 && m[1] == 0x2f && m[2] == 0x31 && m[3] == 0x01) {
    try {
      return std::make_unique<ExrReader>(path);
    } catch (const std::exception& e) {
      why = e.what();
      return nullptr;
    }
  }
  return nullptr;
}

bool native_image_writes(const std::string& format_path, const ImageWrite& image) {
  const std::string ext = lower_extension(format_path);
  const int n = image.header.channels;
  if (ext == ".png")
    return image.format == PixelFormat::U8 && image.channel_formats.empty() && n >= 1 && n <= 4;
  if (ext == ".exr") {
    std::vector<PixelFormat> f = image.channel_formats;
    if (f.empty()) f.assign(size_t(std::max(n, 0)), image.format);
    const bool named = !image.header.channel_names.empty() || (n >= 1 && n <= 4);
    return n >= 1 && named && std::all_of(f.begin(), f.end(), [](PixelFormat p) {
             return p == PixelFormat::Float || p == PixelFormat::U32;
           });
  }
  return false;
}

bool write_native_image(const std::string& file, const std::string& format_path, const ImageWrite& image,
                        std::string& why) {
  return lower_extension(format_path) == ".png" ? write_png(file, image, why)
                                                : write_exr_file(file, image, why);
}

std::string native_size_problem(long long width, long long height) {
  if (width <= 0 || height <= 0)
    return "impossible size " + std::to_string(width) + "x" + std::to_string(height);
  if (width > kMaxNativePixels / height)
    return "size " + std::to_string(width) + "x" + std::to_string(height) + " is over pmc's limit of " +
           std::to_string(kMaxNativePixels) + " pixels";
  return {};
}

namespace {

// One row of `width` pixels, channels [c0, c0 + N) of NCH, as bytes `xs` apart:
// the channel counts known at compile time, so the loop is plain loads and stores.
template <int NCH, int N>
void copy_u8_row(const unsigned char* src, int c0, unsigned char* dst, std::ptrdiff_t xs, int width) {
  src += c0;
  for (int x = 0; x < width; ++x, src += NCH, dst += xs)
    for (int c = 0; c < N; ++c) dst[c] = src[c];
}

// Channels [c0, c1) of `h` as U8 or Float: what the 8-bit copies can do.
bool u8_request_ok(const ImageHeader& h, int c0, int c1, PixelFormat format, std::string& error) {
  if (c0 < 0 || c1 > h.channels || c0 >= c1 || (format != PixelFormat::U8 && format != PixelFormat::Float)) {
    error = "unsupported channel range or pixel format";
    return false;
  }
  return true;
}

using CopyRow = void (*)(const unsigned char*, int, unsigned char*, std::ptrdiff_t, int);

CopyRow u8_row_copier(int nch, int n) {
  switch (nch * 8 + n) {
    case 1 * 8 + 1:
      return &copy_u8_row<1, 1>;
    case 2 * 8 + 1:
      return &copy_u8_row<2, 1>;
    case 2 * 8 + 2:
      return &copy_u8_row<2, 2>;
    case 3 * 8 + 1:
      return &copy_u8_row<3, 1>;
    case 3 * 8 + 3:
      return &copy_u8_row<3, 3>;
    case 4 * 8 + 1:
      return &copy_u8_row<4, 1>;
    case 4 * 8 + 3:
      return &copy_u8_row<4, 3>;
    case 4 * 8 + 4:
      return &copy_u8_row<4, 4>;
    default:
      return nullptr;
  }
}

}  // namespace

bool stream_u8_channels(const ImageHeader& h, int c0, int c1, PixelFormat format, void* data,
                        std::ptrdiff_t xs, std::ptrdiff_t ys,
                        const std::function<bool(unsigned char* row)>& read_row, std::string& error) {
  if (!u8_request_ok(h, c0, c1, format, error)) return false;  // before any row is decoded
  ImageHeader one_row = h;
  one_row.height = 1;
  if (!xs) xs = std::ptrdiff_t(size_t(std::max(0, c1 - c0)) * format_bytes(format));
  if (!ys) ys = xs * h.width;
  std::vector<unsigned char> row(size_t(h.width) * size_t(h.channels));
  auto* out = static_cast<unsigned char*>(data);
  for (int y = 0; y < h.height; ++y)
    if (!read_row(row.data()) ||
        !copy_u8_channels(row.data(), one_row, c0, c1, format, out + y * ys, xs, 0, error))
      return false;
  return true;
}

bool copy_u8_channels(const unsigned char* pixels, const ImageHeader& h, int c0, int c1, PixelFormat format,
                      void* data, std::ptrdiff_t xs, std::ptrdiff_t ys, std::string& error) {
  if (!u8_request_ok(h, c0, c1, format, error)) return false;
  const size_t nch = size_t(h.channels), size = format_bytes(format);
  if (!xs) xs = std::ptrdiff_t(size_t(c1 - c0) * size);
  if (!ys) ys = xs * h.width;
  auto* out = static_cast<unsigned char*>(data);
  const size_t row = size_t(h.width) * nch;
  if (CopyRow copy = format == PixelFormat::U8 ? u8_row_copier(h.channels, c1 - c0) : nullptr) {
    for (int y = 0; y < h.height; ++y) copy(pixels + size_t(y) * row, c0, out + y * ys, xs, h.width);
    return true;
  }
  for (int y = 0; y < h.height; ++y)
    for (int x = 0; x < h.width; ++x) {
      const unsigned char* src = &pixels[size_t(y) * row + size_t(x) * nch];
      unsigned char* dst = out + y * ys + x * xs;
      for (int c = c0; c < c1; ++c) {
        if (format == PixelFormat::U8)
          dst[c - c0] = src[c];
        else
          reinterpret_cast<float*>(dst)[c - c0] = float(src[c]) * (1.0f / 255.0f);
      }
    }
  return true;
}

}  // namespace pmc
