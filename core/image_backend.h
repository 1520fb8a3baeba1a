// image_backend.h — image files through one door: native formats, else an OpenImageIO plugin.
//
// Debian's OpenImageIO pulls in about 250 shared libraries (OpenVDB, GDAL,
// DCMTK, Poppler, ...); binding their symbols took 0.4-0.5 s of every pmc
// process before main() ran, a third of Sponza's whole setup
// (docs/BENCHMARKS.md, Tracing). So pmc does not link OpenImageIO. Every
// image read and write goes through this interface: OpenEXR and 8-bit PNG
// files, pmc's outputs and most textures, JPEG textures and Radiance HDR
// environment maps are handled directly (core/native_images.h: libOpenEXR,
// libpng, libjpeg and our own RGBE decoder, a few milliseconds to load);
// anything else (TIFF, TGA, 16-bit PNG, ...) goes to
// core/oiio_backend.cpp, built as the plugin libpmc_oiio.so and loaded with
// dlopen the first time a file needs it. Only pmc's own types cross the
// door: headers, channel ranges read in a pixel format, plain attributes.
//
// Where the plugin is looked for, in order: $PMC_IMAGE_PLUGIN (a file, then
// the only place tried); the executable's folder (the build tree);
// <exe>/../lib/pmc (an install); the dynamic loader's own search. A missing
// or broken plugin is a pmc::Error naming every place tried. A binary that
// links the backend in (the fuzz targets) uses it directly.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace pmc {

enum class PixelFormat { U8, U16, U32, Half, Float, Other };

// What an image file's header says: the data window (x, y, width, height)
// inside the display window (full_*), the channels and their native format.
struct ImageHeader {
  int width = 0, height = 0, channels = 0;
  int x = 0, y = 0;
  int full_x = 0, full_y = 0, full_width = 0, full_height = 0;
  PixelFormat format = PixelFormat::Other;  // the file's (first channel's) format
  std::vector<std::string> channel_names;

  int channel_index(const std::string& name) const;  // -1 when absent
};

class ImageReader {
 public:
  virtual ~ImageReader() = default;
  virtual const ImageHeader& header() const = 0;
  // Channels [c0, c1) of the whole image, converted to `format` (U8, U32 or
  // Float; integers scale to 0..1 when read as Float). Strides in bytes, 0 for
  // packed. False on failure (error() says why). Read the pixels once: a
  // reader may decode straight from the file into `data` and close it.
  virtual bool read(int c0, int c1, PixelFormat format, void* data, std::ptrdiff_t x_stride = 0,
                    std::ptrdiff_t y_stride = 0) = 0;
  virtual std::string error() = 0;
  virtual void close() = 0;
  // Attributes of the header (metadata); `fallback` when absent (always, for
  // a format that keeps none: the defaults).
  virtual std::string string_attribute(const std::string& /*name*/, const std::string& fallback = "") const {
    return fallback;
  }
  virtual int int_attribute(const std::string& /*name*/, int fallback = 0) const { return fallback; }
  virtual float float_attribute(const std::string& /*name*/, float fallback = 0.0f) const { return fallback; }
};

struct ImageAttribute {
  enum class Kind { String, Int, Float } kind = Kind::String;
  std::string name, text;
  int integer = 0;
  float real = 0.0f;
  static ImageAttribute of(std::string name, std::string v) {
    return {Kind::String, std::move(name), std::move(v)};
  }
  static ImageAttribute of(std::string name, int v) { return {Kind::Int, std::move(name), {}, v}; }
  static ImageAttribute of(std::string name, float v) { return {Kind::Float, std::move(name), {}, 0, v}; }
};

// An image to write: interleaved pixels, every channel in its own format
// (`channel_formats`, or `format` for all when empty).
struct ImageWrite {
  ImageHeader header;
  PixelFormat format = PixelFormat::Float;
  std::vector<PixelFormat> channel_formats;
  std::vector<ImageAttribute> attributes;
  const void* pixels = nullptr;
};

class ImageBackend {
 public:
  virtual ~ImageBackend() = default;
  // Opens `path` and reads its header; null with `why` set when it cannot.
  // `unassociated_alpha`: colour is returned as stored, not premultiplied.
  virtual std::unique_ptr<ImageReader> open(const std::string& path, bool unassociated_alpha,
                                            std::string& why) = 0;
  // Writes `image` to `file`, in the format `format_path`'s extension names
  // (the final name when `file` is a temporary). False with `why` on failure.
  virtual bool write(const std::string& file, const std::string& format_path, const ImageWrite& image,
                     std::string& why) = 0;
};

// The backend: native formats (core/native_images.h), else the plugin, loaded
// the first time a file needs it; pmc::Error when it cannot be loaded.
ImageBackend& image_backend();

}  // namespace pmc

// The plugin's entry point (core/oiio_backend.cpp): a backend that lives as long as the process.
extern "C" pmc::ImageBackend* pmc_image_backend_v1();
