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
// message is kept and control jumps back to the JpegStream call that set the
// target.
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

enum class Opened { Ok, Broken, Unsupported };

// One JPEG file from its header to its last row. The header is read when the
// file opens; the rows decode when read() asks for them, straight into the
// caller's memory through one row of buffer, so a texture's decode runs on
// the pool's parallel decode (core/texture.cpp), not while materials compile.
// Every libjpeg call sits in a function that sets the jump target itself and
// has only plain locals (libjpeg's errors longjmp there).
class JpegStream {
 public:
  explicit JpegStream(std::FILE* file) : file_(file) {
    cinfo_.err = jpeg_std_error(&errors_.mgr);
    errors_.mgr.error_exit = jpeg_fail;
    errors_.mgr.emit_message = jpeg_message;
    errors_.message[0] = 0;
  }
  ~JpegStream() { release(); }
  JpegStream(const JpegStream&) = delete;
  JpegStream& operator=(const JpegStream&) = delete;

  Opened open(ImageHeader& h, char* why) {
    if (setjmp(errors_.jump)) {
      std::snprintf(why, JMSG_LENGTH_MAX, "%s", errors_.message);
      release();
      return Opened::Broken;
    }
    jpeg_create_decompress(&cinfo_);
    created_ = true;
    // libjpeg allocates a progressive file's coefficients for the whole image
    // at the start; without this bound a 1 KB file claiming 20000x10000
    // pixels takes 1.2 GB before its data runs out. The bound grows with the
    // file (a real 16K x 16K progressive JPEG is tens of megabytes).
    std::fseek(file_, 0, SEEK_END);
    const long bytes = std::ftell(file_);
    std::rewind(file_);
    cinfo_.mem->max_memory_to_use = std::max(256L << 20, 64L * std::max(bytes, 0L));
    jpeg_stdio_src(&cinfo_, file_);
    jpeg_read_header(&cinfo_, TRUE);
    if (cinfo_.jpeg_color_space == JCS_CMYK || cinfo_.jpeg_color_space == JCS_YCCK) {
      release();
      return Opened::Unsupported;
    }
    cinfo_.out_color_space = cinfo_.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_calc_output_dimensions(&cinfo_);
    const std::string size = native_size_problem(cinfo_.output_width, cinfo_.output_height);
    if (!size.empty()) {
      std::snprintf(why, JMSG_LENGTH_MAX, "%s", size.c_str());
      release();
      return Opened::Broken;
    }
    h.width = int(cinfo_.output_width);
    h.height = int(cinfo_.output_height);
    h.channels = cinfo_.output_components;
    h.full_width = h.width;
    h.full_height = h.height;
    h.format = PixelFormat::U8;
    h.channel_names =
        h.channels == 1 ? std::vector<std::string>{"Y"} : std::vector<std::string>{"R", "G", "B"};
    return Opened::Ok;
  }

  // Starts the decode; then next_row() for each row, then finish(). Each
  // is false with error() set on corrupt or short data (the file is then closed).
  bool start() {
    if (!created_) {
      std::snprintf(errors_.message, sizeof(errors_.message), "the file was closed");
      return false;
    }
    if (setjmp(errors_.jump)) {
      release();
      return false;
    }
    jpeg_start_decompress(&cinfo_);
    return true;
  }
  bool next_row(unsigned char* row) {
    if (setjmp(errors_.jump)) {
      release();
      return false;
    }
    JSAMPROW at = row;
    jpeg_read_scanlines(&cinfo_, &at, 1);
    return true;
  }
  bool finish() {
    if (setjmp(errors_.jump)) {
      release();
      return false;
    }
    jpeg_finish_decompress(&cinfo_);
    release();
    return true;
  }
  const char* error() const { return errors_.message; }

  void release() {
    if (created_) jpeg_destroy_decompress(&cinfo_);
    created_ = false;
    if (file_) std::fclose(file_);
    file_ = nullptr;
  }

 private:
  std::FILE* file_;
  jpeg_decompress_struct cinfo_{};
  JpegErrors errors_{};
  bool created_ = false;
};

class JpegReader final : public ImageReader {
 public:
  JpegReader(std::unique_ptr<JpegStream> stream, ImageHeader h)
      : stream_(std::move(stream)), h_(std::move(h)) {}
  const ImageHeader& header() const override { return h_; }
  std::string error() override { return error_; }
  void close() override { stream_->release(); }
  bool read(int c0, int c1, PixelFormat format, void* data, std::ptrdiff_t xs, std::ptrdiff_t ys) override {
    bool decoded = stream_->start();
    const bool ok =
        decoded && stream_u8_channels(
                       h_, c0, c1, format, data, xs, ys,
                       [&](unsigned char* row) { return decoded = stream_->next_row(row); }, error_);
    const bool finished = ok && stream_->finish();
    if (!decoded || (ok && !finished)) error_ = std::string("corrupt JPEG: ") + stream_->error();
    stream_->release();
    return finished;
  }

 private:
  std::unique_ptr<JpegStream> stream_;
  ImageHeader h_;
  std::string error_;
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
  auto stream = std::make_unique<JpegStream>(file);
  ImageHeader h;
  char message[JMSG_LENGTH_MAX] = {};
  const Opened result = stream->open(h, message);
  if (result == Opened::Broken) {
    why = std::string("corrupt JPEG: ") + message;
    return nullptr;
  }
  if (result == Opened::Unsupported) return nullptr;
  return std::make_unique<JpegReader>(std::move(stream), std::move(h));
}

}  // namespace pmc
