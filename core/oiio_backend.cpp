// oiio_backend.cpp — the image plugin (libpmc_oiio.so): core/image_backend.h
// implemented with OpenImageIO. The only file that includes OpenImageIO; it
// is built as its own shared library, not into pmc (see image_backend.h for
// why), and reports failures as messages, never as exceptions.
#include <OpenImageIO/imageio.h>

#include <exception>

#include "core/image_backend.h"

namespace pmc {
namespace {

OIIO::TypeDesc type_of(PixelFormat f) {
  switch (f) {
    case PixelFormat::U8:
      return OIIO::TypeDesc::UINT8;
    case PixelFormat::U16:
      return OIIO::TypeDesc::UINT16;
    case PixelFormat::U32:
      return OIIO::TypeDesc::UINT;
    case PixelFormat::Half:
      return OIIO::TypeDesc::HALF;
    case PixelFormat::Float:
      return OIIO::TypeDesc::FLOAT;
    case PixelFormat::Other:
      break;
  }
  return OIIO::TypeDesc::UNKNOWN;
}

PixelFormat format_of(OIIO::TypeDesc t) {
  switch (t.basetype) {
    case OIIO::TypeDesc::UINT8:
      return PixelFormat::U8;
    case OIIO::TypeDesc::UINT16:
      return PixelFormat::U16;
    case OIIO::TypeDesc::UINT32:
      return PixelFormat::U32;
    case OIIO::TypeDesc::HALF:
      return PixelFormat::Half;
    case OIIO::TypeDesc::FLOAT:
      return PixelFormat::Float;
    default:
      return PixelFormat::Other;
  }
}

class OiioReader final : public ImageReader {
 public:
  explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in) : in_(std::move(in)) {
    const OIIO::ImageSpec& s = in_->spec();
    h_.width = s.width;
    h_.height = s.height;
    h_.channels = s.nchannels;
    h_.x = s.x;
    h_.y = s.y;
    h_.full_x = s.full_x;
    h_.full_y = s.full_y;
    h_.full_width = s.full_width;
    h_.full_height = s.full_height;
    h_.format = format_of(s.format);
    h_.channel_names = s.channelnames;
  }
  const ImageHeader& header() const override { return h_; }
  bool read(int c0, int c1, PixelFormat format, void* data, std::ptrdiff_t x_stride,
            std::ptrdiff_t y_stride) override {
    try {
      return in_->read_image(0, 0, c0, c1, type_of(format), data, x_stride ? x_stride : OIIO::AutoStride,
                             y_stride ? y_stride : OIIO::AutoStride);
    } catch (const std::exception& e) {
      error_ = e.what();
      return false;
    }
  }
  std::string error() override { return error_.empty() ? in_->geterror() : error_; }
  void close() override { in_->close(); }
  std::string string_attribute(const std::string& name, const std::string& fallback) const override {
    return in_->spec().get_string_attribute(name, fallback);
  }
  int int_attribute(const std::string& name, int fallback) const override {
    return in_->spec().get_int_attribute(name, fallback);
  }
  float float_attribute(const std::string& name, float fallback) const override {
    return in_->spec().get_float_attribute(name, fallback);
  }

 private:
  std::unique_ptr<OIIO::ImageInput> in_;
  ImageHeader h_;
  std::string error_;
};

class OiioBackend final : public ImageBackend {
 public:
  std::unique_ptr<ImageReader> open(const std::string& path, bool unassociated_alpha,
                                    std::string& why) override {
    try {
      OIIO::ImageSpec config;
      if (unassociated_alpha) config.attribute("oiio:UnassociatedAlpha", 1);
      auto in = OIIO::ImageInput::open(path, &config);
      if (!in) {
        why = OIIO::geterror();
        return nullptr;
      }
      return std::make_unique<OiioReader>(std::move(in));
    } catch (const std::exception& e) {
      why = e.what();
      return nullptr;
    }
  }

  bool write(const std::string& file, const std::string& format_path, const ImageWrite& image,
             std::string& why) override {
    try {
      auto out = OIIO::ImageOutput::create(format_path);
      if (!out) {
        why = "cannot write this image format (" + OIIO::geterror() + ")";
        return false;
      }
      const ImageHeader& h = image.header;
      OIIO::ImageSpec spec(h.width, h.height, h.channels, type_of(image.format));
      spec.x = h.x;
      spec.y = h.y;
      if (h.full_width > 0) {
        spec.full_x = h.full_x;
        spec.full_y = h.full_y;
        spec.full_width = h.full_width;
        spec.full_height = h.full_height;
      }
      if (!h.channel_names.empty()) spec.channelnames = h.channel_names;
      for (PixelFormat f : image.channel_formats) spec.channelformats.push_back(type_of(f));
      for (const ImageAttribute& a : image.attributes) switch (a.kind) {
          case ImageAttribute::Kind::String:
            spec.attribute(a.name, a.text);
            break;
          case ImageAttribute::Kind::Int:
            spec.attribute(a.name, a.integer);
            break;
          case ImageAttribute::Kind::Float:
            spec.attribute(a.name, a.real);
            break;
        }
      if (!out->open(file, spec)) {
        why = "cannot open for writing: " + out->geterror();
        return false;
      }
      // Several channel formats: the pixels are in the channels' own formats.
      const OIIO::TypeDesc given =
          image.channel_formats.empty() ? type_of(image.format) : OIIO::TypeDesc::UNKNOWN;
      bool ok = out->write_image(given, image.pixels);
      ok = out->close() && ok;
      if (!ok) why = "writing the image failed";
      return ok;
    } catch (const std::exception& e) {
      why = e.what();
      return false;
    }
  }
};

}  // namespace
}  // namespace pmc

extern "C" pmc::ImageBackend* pmc_image_backend_v1() {
  static pmc::OiioBackend backend;
  return &backend;
}
