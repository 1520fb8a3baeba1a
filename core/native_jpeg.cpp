// native_jpeg.cpp — JPEG decoding with libjpeg (see native_jpeg.h).
#include "core/native_jpeg.h"

#include <cerrno>
#include <csetjmp>
#include <cstdio>  // before jpeglib.h, which uses FILE and size_t
#include <cstring>
#include <vector>

// clang-format off
#include <jpeglib.h>
#include <jerror.h>
// clang-format on

#include "core/native_images.h"

namespace pmc {
namespace {

// libjpeg reports errors through error_exit, which must not return: the
// message is kept and control jumps back to decode(), whose locals are plain.
struct JpegErrors {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void jpeg_fail(j_common_ptr c) {
  auto* e = reinterpret_cast<JpegErrors*>(c->err);
  (*c->err->format_message)(c, e->message);
  std::longjmp(e->jump, 1);
}

// Warnings are ignored, except a stream that ends early: libjpeg would fill
// the missing rows with grey and go on.
void jpeg_message(j_common_ptr c, int level) {
  if (level < 0 && c->err->msg_code == JWRN_JPEG_EOF) jpeg_fail(c);
}

enum class Decoded { Ok, Broken, Unsupported };

Decoded decode(std::FILE* file, ImageHeader& h, std::vector<unsigned char>& pixels, char* why) {
  jpeg_decompress_struct cinfo;
  JpegErrors errors;
  cinfo.err = jpeg_std_error(&errors.mgr);
  errors.mgr.error_exit = jpeg_fail;
  errors.mgr.emit_message = jpeg_message;
  errors.message[0] = 0;
  if (setjmp(errors.jump)) {
    std::snprintf(why, JMSG_LENGTH_MAX, "%s", errors.message);
    jpeg_destroy_decompress(&cinfo);
    return Decoded::Broken;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_stdio_src(&cinfo, file);
  jpeg_read_header(&cinfo, TRUE);
  if (cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK) {
    jpeg_destroy_decompress(&cinfo);
    return Decoded::Unsupported;
  }
  cinfo.out_color_space = cinfo.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_start_decompress(&cinfo);
  h.width = int(cinfo.output_width);
  h.height = int(cinfo.output_height);
  h.channels = cinfo.output_components;
  h.full_width = h.width;
  h.full_height = h.height;
  h.format = PixelFormat::U8;
  h.channel_names = h.channels == 1 ? std::vector<std::string>{"Y"} : std::vector<std::string>{"R", "G", "B"};
  const size_t row = size_t(h.width) * size_t(h.channels);
  pixels.resize(row * size_t(h.height));
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPROW at = &pixels[size_t(cinfo.output_scanline) * row];
    jpeg_read_scanlines(&cinfo, &at, 1);
  }
  jpeg_finish_decompress(&cinfo);
  jpeg_destroy_decompress(&cinfo);
  return Decoded::Ok;
}

class JpegReader final : public DecodedImageReader<unsigned char> {
 public:
  using DecodedImageReader::DecodedImageReader;
  bool read(int c0, int c1, PixelFormat format, void* data, std::ptrdiff_t xs, std::ptrdiff_t ys) override {
    return open_pixels() && copy_u8_channels(pixels_.data(), h_, c0, c1, format, data, xs, ys, error_);
  }
};

}  // namespace

bool is_jpeg(const unsigned char* magic, size_t n) {
  return n >= 3 && magic[0] == 0xff && magic[1] == 0xd8 && magic[2] == 0xff;
}

std::unique_ptr<ImageReader> open_jpeg(const std::string& path, std::string& why) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) {
    why = std::string("cannot open: ") + std::strerror(errno);
    return nullptr;
  }
  ImageHeader h;
  std::vector<unsigned char> pixels;
  char message[JMSG_LENGTH_MAX] = {};
  const Decoded result = decode(file, h, pixels, message);
  std::fclose(file);
  if (result == Decoded::Broken) {
    why = std::string("corrupt JPEG: ") + message;
    return nullptr;
  }
  if (result == Decoded::Unsupported) return nullptr;
  return std::make_unique<JpegReader>(std::move(h), std::move(pixels));
}

}  // namespace pmc
