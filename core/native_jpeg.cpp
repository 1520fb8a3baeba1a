// native_jpeg.cpp — JPEG decoding with libjpeg (see native_jpeg.h).
#include "core/native_jpeg.h"

#include <algorithm>
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
  // libjpeg allocates a progressive file's coefficients for the whole image
  // at the start; without this bound a 1 KB file claiming 20000x10000
  // pixels takes 1.2 GB before its data runs out. The bound grows with the
  // file (a real 16K x 16K progressive JPEG is tens of megabytes).
  std::fseek(file, 0, SEEK_END);
  const long bytes = std::ftell(file);
  std::rewind(file);
  cinfo.mem->max_memory_to_use = std::max(256L << 20, 64L * std::max(bytes, 0L));
  jpeg_stdio_src(&cinfo, file);
  jpeg_read_header(&cinfo, TRUE);
  if (cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK) {
    jpeg_destroy_decompress(&cinfo);
    return Decoded::Unsupported;
  }
  cinfo.out_color_space = cinfo.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_start_decompress(&cinfo);
  const std::string size = native_size_problem(cinfo.output_width, cinfo.output_height);
  if (!size.empty()) {
    std::snprintf(why, JMSG_LENGTH_MAX, "%s", size.c_str());
    jpeg_destroy_decompress(&cinfo);
    return Decoded::Broken;
  }
  h.width = int(cinfo.output_width);
  h.height = int(cinfo.output_height);
  h.channels = cinfo.output_components;
  h.full_width = h.width;
  h.full_height = h.height;
  h.format = PixelFormat::U8;
  h.channel_names = h.channels == 1 ? std::vector<std::string>{"Y"} : std::vector<std::string>{"R", "G", "B"};
  // Grown row by row: a file cut short fails before the whole image is allocated.
  const size_t row = size_t(h.width) * size_t(h.channels);
  while (cinfo.output_scanline < cinfo.output_height) {
    pixels.resize(pixels.size() + row);
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
