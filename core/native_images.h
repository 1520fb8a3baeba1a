// native_images.h — the image formats pmc reads and writes without OpenImageIO.
//
// OpenEXR files (libOpenEXR: any channels, half/float/uint, data and display
// windows, string/int/float attributes) and 8-bit PNGs (libpng: grey, grey +
// alpha, RGB, RGBA, palettes expanded, tRNS as alpha), the formats of pmc's
// own outputs and of most textures, JPEGs and Radiance HDRs (read only;
// core/native_jpeg.h, core/native_hdr.h).
// Loading these libraries costs a few
// milliseconds; everything else goes to the OpenImageIO plugin, loaded only
// when a file needs it (core/image_backend.h).
//
// Conventions follow OpenImageIO's, so a file reads the same either way:
// PNG bytes are returned as stored (no gamma conversion; 8-bit reads as
// Float divide by 255); EXR channels come R, G, B, A first, then the rest in
// the file's (alphabetical) order. A PNG with alpha opened with associated
// alpha, and 16-bit PNGs, are left to the plugin.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/image_backend.h"

namespace pmc {

// A reader when the file is an OpenEXR, PNG, JPEG or Radiance HDR this code handles; null
// otherwise (`why` set only when the file is one of those formats but broken).
std::unique_ptr<ImageReader> open_native_image(const std::string& path, bool unassociated_alpha,
                                               std::string& why);
// Whether write_native_image takes `image` for a file named `format_path`.
bool native_image_writes(const std::string& format_path, const ImageWrite& image);
bool write_native_image(const std::string& file, const std::string& format_path, const ImageWrite& image,
                        std::string& why);
// The most pixels a native reader decodes (16384 x 16384): a larger size in a
// header is refused before anything is allocated, so a small broken file
// cannot ask for gigabytes.
constexpr long long kMaxNativePixels = 1LL << 28;
constexpr long long kMaxNativeRows = 1LL << 20;  // OpenEXR: scanlines (its offset tables follow them)
// "" when width x height is a size the native readers decode, else why not.
std::string native_size_problem(long long width, long long height);

// A reader of an image decoded whole when opened (JPEG, Radiance HDR): its
// header and pixels, no attributes; read() is the format's.
template <typename Pixel>
class DecodedImageReader : public ImageReader {
 public:
  DecodedImageReader(ImageHeader h, std::vector<Pixel> pixels)
      : h_(std::move(h)), pixels_(std::move(pixels)) {}
  const ImageHeader& header() const override { return h_; }
  std::string error() override { return error_; }
  void close() override { pixels_ = {}; }

 protected:
  bool open_pixels() {
    if (pixels_.empty()) error_ = "the file was closed";
    return !pixels_.empty();
  }
  ImageHeader h_;
  std::vector<Pixel> pixels_;
  std::string error_;
};

// Channels [c0, c1) of 8-bit interleaved `pixels` (h.width x h.height x
// h.channels) into `data` as U8, or as Float (bytes / 255); strides in bytes,
// 0 for packed. False with `error` set on a bad channel range or format.
bool copy_u8_channels(const unsigned char* pixels, const ImageHeader& h, int c0, int c1, PixelFormat format,
                      void* data, std::ptrdiff_t x_stride, std::ptrdiff_t y_stride, std::string& error);

// The same for an image decoded row by row: read_row(row) fills one row of
// h.width x h.channels bytes (rows in order, false on a decode error, which
// the caller reports); each row's channels go to `data` through one row of
// buffer, so no whole-image copy is made. False with `error` set on a bad
// channel range or format, or false when read_row failed.
bool stream_u8_channels(const ImageHeader& h, int c0, int c1, PixelFormat format, void* data,
                        std::ptrdiff_t x_stride, std::ptrdiff_t y_stride,
                        const std::function<bool(unsigned char* row)>& read_row, std::string& error);

}  // namespace pmc
