// image_backend_test.cpp — images without linking OpenImageIO: native
// OpenEXR, PNG, JPEG and Radiance HDR, the plugin for the rest, and a clear error without it.
//
// * The pmc binary's dynamic dependencies (ldd) name no OpenImageIO library.
// * Through the backend, an EXR with per-channel formats (float and uint32),
//   a data window inside a display window and typed attributes reads back
//   exactly as written, checked against OpenImageIO read directly.
// * PNGs of every colour type OpenImageIO writes (grey, grey + alpha, RGB,
//   RGBA, 8-bit) and a palette PNG with transparency read natively to the
//   same bytes as OpenImageIO reads them; what pmc writes, OpenImageIO reads
//   back exactly.
// * JPEGs (grey and colour, and the MaterialX examples' textures) read
//   natively to the same bytes as OpenImageIO reads them; one cut short is
//   refused with libjpeg's reason.
// * Radiance HDRs (run-length encoded and flat, and the shared environment
//   maps) read natively to the same floats as OpenImageIO reads them, also
//   into strided memory (a sky map's texels); one cut short or with a bad
//   run is refused when its pixels are read, one with an impossible size or
//   one over pmc's limit of 2^28 pixels when it is opened, each saying so
//   (a JPEG over the limit too).
// * TIFF and TGA go to the plugin and read as OpenImageIO reads them.
// * A render that needs the plugin (a TIFF environment map) when the
//   plugin cannot be loaded exits 2, names the paths tried and writes no
//   image; the same render with a Radiance HDR map needs no plugin.
// * first_channels() keeps the leading channels of each pixel.
#include "core/image_backend.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <png.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "tests/support/test_support.h"

namespace pmc {
namespace {

std::string shell_output(const std::string& cmd, int* code) {
  FILE* pipe = popen((cmd + " 2>&1").c_str(), "r");
  if (!pipe) return {};
  std::string text;
  std::array<char, 4096> buf{};
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) text.append(buf.data(), n);
  const int status = pclose(pipe);
  *code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return text;
}

TEST(ImageBackend, PmcDoesNotLinkOpenImageIO) {
  int code = 0;
  const std::string deps = shell_output("ldd " + std::string(PMC_BINARY), &code);
  ASSERT_EQ(code, 0) << deps;
  EXPECT_NE(deps.find("libembree3"), std::string::npos) << deps;  // ldd did list the dependencies
  EXPECT_EQ(deps.find("OpenImageIO"), std::string::npos) << deps;
}

TEST(ImageBackend, WritesAndReadsChannelFormatsWindowsAndAttributes) {
  const std::string path = test::temp_dir() + "/part.exr";
  const int w = 3, h = 2, nch = 4;
  std::vector<uint32_t> px(size_t(w) * h * nch);
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    const float rgb[3] = {0.25f * float(i), -1.5f, 1e6f};
    std::memcpy(&px[i * nch], rgb, sizeof(rgb));
    px[i * nch + 3] = 4000000000u - uint32_t(i);  // above 2^31: a float would round it
  }
  ImageWrite out;
  out.header.width = w;
  out.header.height = h;
  out.header.channels = nch;
  out.header.x = 5;
  out.header.y = 7;
  out.header.full_width = 20;
  out.header.full_height = 10;
  out.header.channel_names = {"R", "G", "B", "count"};
  out.channel_formats = {PixelFormat::Float, PixelFormat::Float, PixelFormat::Float, PixelFormat::U32};
  out.attributes = {ImageAttribute::of("pmc:text", std::string("sponza")), ImageAttribute::of("pmc:int", 42),
                    ImageAttribute::of("pmc:real", 2.5f)};
  out.pixels = px.data();
  std::string why;
  ASSERT_TRUE(image_backend().write(path, path, out, why)) << why;

  // OpenImageIO itself, as the independent reader.
  auto direct = OIIO::ImageInput::open(path);
  ASSERT_TRUE(direct);
  EXPECT_EQ(direct->spec().x, 5);
  EXPECT_EQ(direct->spec().full_width, 20);
  EXPECT_EQ(direct->spec().get_int_attribute("pmc:int"), 42);
  std::vector<uint32_t> counts(size_t(w) * h);
  ASSERT_TRUE(direct->read_image(0, 0, 3, 4, OIIO::TypeDesc::UINT, counts.data()));
  for (size_t i = 0; i < counts.size(); ++i) EXPECT_EQ(counts[i], 4000000000u - uint32_t(i));

  auto in = image_backend().open(path, false, why);
  ASSERT_TRUE(in) << why;
  const ImageHeader& hd = in->header();
  EXPECT_EQ(hd.width, w);
  EXPECT_EQ(hd.height, h);
  EXPECT_EQ(hd.channels, nch);
  EXPECT_EQ(hd.x, 5);
  EXPECT_EQ(hd.y, 7);
  EXPECT_EQ(hd.full_width, 20);
  EXPECT_EQ(hd.full_height, 10);
  EXPECT_EQ(hd.format, PixelFormat::Float);
  EXPECT_EQ(hd.channel_index("count"), 3);
  EXPECT_EQ(hd.channel_index("A"), -1);
  EXPECT_EQ(in->string_attribute("pmc:text"), "sponza");
  EXPECT_EQ(in->int_attribute("pmc:int"), 42);
  EXPECT_EQ(in->float_attribute("pmc:real"), 2.5f);
  EXPECT_EQ(in->string_attribute("pmc:absent", "none"), "none");
  std::vector<uint32_t> back(size_t(w) * h);
  ASSERT_TRUE(in->read(3, 4, PixelFormat::U32, back.data())) << in->error();
  EXPECT_EQ(back, counts);
  std::vector<float> rgb(size_t(w) * h * 3);
  ASSERT_TRUE(in->read(0, 3, PixelFormat::Float, rgb.data())) << in->error();
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    EXPECT_EQ(rgb[i * 3], 0.25f * float(i));
    EXPECT_EQ(rgb[i * 3 + 1], -1.5f);
    EXPECT_EQ(rgb[i * 3 + 2], 1e6f);
  }
}

TEST(ImageBackend, OpeningAMissingFileSaysWhy) {
  std::string why;
  EXPECT_FALSE(image_backend().open(test::temp_dir() + "/absent.png", false, why));
  EXPECT_FALSE(why.empty());
}

std::string render_without_plugin(const std::string& dir, const std::string& extra, int* code) {
  return shell_output("env PMC_IMAGE_PLUGIN=" + dir + "/nowhere/libpmc_oiio.so " + std::string(PMC_BINARY) +
                          " render " + test::source_path("data/default/room.obj") +
                          " --width 16 --height 8 --spp 1 -o " + dir + "/out.exr --quiet " + extra,
                      code);
}

TEST(ImageBackend, WithoutThePluginARenderThatNeedsItFailsNamingWhereItLookedAndWritesNothing) {
  const std::string dir = test::temp_dir();
  // An environment map in TIFF needs the plugin.
  {
    auto out = OIIO::ImageOutput::create(dir + "/sky.tif");
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(dir + "/sky.tif", OIIO::ImageSpec(8, 4, 3, OIIO::TypeDesc::FLOAT)));
    const std::vector<float> sky(8 * 4 * 3, 0.5f);
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, sky.data()));
    ASSERT_TRUE(out->close());
  }
  int code = 0;
  std::string text = render_without_plugin(dir, "--env-map " + dir + "/sky.tif", &code);
  EXPECT_EQ(code, 2) << text;
  EXPECT_NE(text.find("cannot load the image plugin"), std::string::npos) << text;
  EXPECT_NE(text.find(dir + "/sky.tif: reading this file needs the image plugin"), std::string::npos) << text;
  EXPECT_NE(text.find(dir + "/nowhere/libpmc_oiio.so"), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.exr"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.png"));
  // PNG textures and a Radiance HDR map in, EXR and PNG out: no plugin needed.
  text = render_without_plugin(dir, "--env-map " + test::shared_scene("envmaps/table_mountain.hdr"), &code);
  EXPECT_EQ(code, 0) << text;
  EXPECT_TRUE(std::filesystem::exists(dir + "/out.exr"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/out.png"));
}

// Writes `bytes` (w x h x nch, 8-bit) with OpenImageIO.
void oiio_write(const std::string& path, int w, int h, int nch, const std::vector<unsigned char>& bytes) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path, OIIO::ImageSpec(w, h, nch, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, bytes.data()));
  ASSERT_TRUE(out->close());
}

std::vector<unsigned char> oiio_read_bytes(const std::string& path, int* nch) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  EXPECT_TRUE(in);
  if (!in) return {};
  *nch = in->spec().nchannels;
  std::vector<unsigned char> px(size_t(in->spec().image_pixels()) * size_t(*nch));
  EXPECT_TRUE(in->read_image(0, 0, 0, *nch, OIIO::TypeDesc::UINT8, px.data()));
  return px;
}

std::vector<unsigned char> backend_read_bytes(const std::string& path, int* nch) {
  std::string why;
  auto in = image_backend().open(path, true, why);
  EXPECT_TRUE(in) << why;
  if (!in) return {};
  *nch = in->header().channels;
  std::vector<unsigned char> px(size_t(in->header().width) * size_t(in->header().height) * size_t(*nch));
  EXPECT_TRUE(in->read(0, *nch, PixelFormat::U8, px.data())) << in->error();
  return px;
}

TEST(ImageBackend, PngsReadAsOpenImageIOReadsThem) {
  const std::string dir = test::temp_dir();
  const int w = 7, h = 5;
  for (int nch = 1; nch <= 4; ++nch) {
    std::vector<unsigned char> bytes(size_t(w) * h * size_t(nch));
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = (unsigned char)((i * 37 + 11) % 256);
    const std::string path = dir + "/c" + std::to_string(nch) + ".png";
    oiio_write(path, w, h, nch, bytes);
    int n_oiio = 0, n_native = 0;
    const auto a = oiio_read_bytes(path, &n_oiio), b = backend_read_bytes(path, &n_native);
    EXPECT_EQ(n_native, n_oiio) << nch;
    EXPECT_EQ(a, b) << nch;
    if (nch == 1 || nch == 3)
      EXPECT_EQ(b, bytes) << nch;  // OpenImageIO un-premultiplies what it writes with alpha
  }
  // A palette image with transparency (tRNS): expanded to RGBA.
  const unsigned char colormap[3 * 4] = {255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 0};
  const unsigned char index[8] = {0, 1, 2, 0, 2, 1, 0, 1};
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = 4;
  image.height = 2;
  image.format = PNG_FORMAT_RGBA_COLORMAP;
  image.colormap_entries = 3;
  const std::string palette = dir + "/palette.png";
  ASSERT_TRUE(png_image_write_to_file(&image, palette.c_str(), 0, index, 0, colormap)) << image.message;
  int n_oiio = 0, n_native = 0;
  const auto a = oiio_read_bytes(palette, &n_oiio), b = backend_read_bytes(palette, &n_native);
  EXPECT_EQ(n_native, 4);
  EXPECT_EQ(n_oiio, 4);
  EXPECT_EQ(a, b);
  EXPECT_EQ(b[4 * 1 + 3], 128) << "the second pixel's alpha, from tRNS";
  // Sponza's textures, as a third party exported them.
  for (const auto& entry : std::filesystem::directory_iterator(test::shared_scene("sponza/textures"))) {
    if (entry.path().extension() != ".png") continue;
    const auto x = oiio_read_bytes(entry.path().string(), &n_oiio);
    const auto y = backend_read_bytes(entry.path().string(), &n_native);
    EXPECT_EQ(n_native, n_oiio) << entry.path();
    EXPECT_TRUE(x == y) << entry.path();
  }
}

TEST(ImageBackend, APngCutShortOpensAndThenFailsToDecodeSayingWhy) {
  const std::string dir = test::temp_dir();
  const int w = 64, h = 64;
  std::vector<unsigned char> bytes(size_t(w) * h * 3);
  uint32_t state = 2463534242u;  // xorshift noise: compresses poorly, so half the file is half the rows
  for (unsigned char& b : bytes) {
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    b = (unsigned char)(state >> 24);
  }
  oiio_write(dir + "/whole.png", w, h, 3, bytes);
  std::string data = test::read_file(dir + "/whole.png");
  ASSERT_GT(data.size(), 2000u);
  test::write_file(dir + "/cut.png", data.substr(0, data.size() / 2));
  std::string why;
  auto in = image_backend().open(dir + "/cut.png", true, why);
  ASSERT_TRUE(in) << why;  // the header is intact
  std::vector<unsigned char> px(bytes.size());
  EXPECT_FALSE(in->read(0, 3, PixelFormat::U8, px.data()));
  EXPECT_FALSE(in->error().empty());
  EXPECT_FALSE(in->read(0, 3, PixelFormat::U8, px.data())) << "a second read fails the same way";
}

TEST(ImageBackend, WrittenPngsAndExrsReadBackInOpenImageIO) {
  const std::string dir = test::temp_dir();
  Image img;
  img.width = 4;
  img.height = 3;
  img.channels = 3;
  for (int i = 0; i < 36; ++i) img.pixels.push_back(float(i) / 35.0f * 1.2f - 0.1f);
  write_exr(dir + "/a.exr", img);
  write_png_display(dir + "/a.png", img);
  auto exr = OIIO::ImageInput::open(dir + "/a.exr");
  ASSERT_TRUE(exr);
  EXPECT_EQ(exr->spec().channelnames, (std::vector<std::string>{"R", "G", "B"}));
  std::vector<float> f(36);
  ASSERT_TRUE(exr->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, f.data()));
  EXPECT_EQ(f, img.pixels);
  int nch = 0;
  const auto png = oiio_read_bytes(dir + "/a.png", &nch);
  ASSERT_EQ(nch, 3);
  for (size_t i = 0; i < png.size(); ++i)
    EXPECT_EQ(png[i], (unsigned char)std::lround(255.0f * std::clamp(img.pixels[i], 0.0f, 1.0f))) << i;
}

TEST(ImageBackend, JpegsReadAsOpenImageIOReadsThem) {
  const std::string dir = test::temp_dir();
  const int w = 19, h = 13;  // not a multiple of the 8x8 blocks or of chroma subsampling
  for (int nch : {1, 3}) {
    std::vector<unsigned char> bytes(size_t(w) * h * size_t(nch));
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = (unsigned char)((i * 37 + 11) % 256);
    const std::string path = dir + "/c" + std::to_string(nch) + ".jpg";
    oiio_write(path, w, h, nch, bytes);
    int n_oiio = 0, n_native = 0;
    const auto a = oiio_read_bytes(path, &n_oiio), b = backend_read_bytes(path, &n_native);
    EXPECT_EQ(n_native, nch);
    EXPECT_EQ(n_oiio, nch);
    EXPECT_EQ(a, b) << nch;
  }
  // The MaterialX project's example textures, as a third party made them.
  int seen = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::shared_scene("materialx/images"))) {
    if (entry.path().extension() != ".jpg") continue;
    int n_oiio = 0, n_native = 0;
    const auto x = oiio_read_bytes(entry.path().string(), &n_oiio);
    const auto y = backend_read_bytes(entry.path().string(), &n_native);
    EXPECT_EQ(n_native, n_oiio) << entry.path();
    EXPECT_FALSE(y.empty()) << entry.path();
    EXPECT_TRUE(x == y) << entry.path();
    ++seen;
  }
  EXPECT_GE(seen, 8);
}

TEST(ImageBackend, AJpegCutShortIsRefusedSayingWhy) {
  const std::string dir = test::temp_dir();
  const int w = 64, h = 64;
  std::vector<unsigned char> bytes(size_t(w) * h * 3);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = (unsigned char)((i * i) >> 3);
  oiio_write(dir + "/whole.jpg", w, h, 3, bytes);
  std::string data = test::read_file(dir + "/whole.jpg");
  ASSERT_GT(data.size(), 1000u);
  test::write_file(dir + "/cut.jpg", data.substr(0, data.size() / 2));
  // The header is whole, so the file opens; its rows decode when read, and
  // the read fails there (not a grey-filled image).
  std::string why;
  auto in = image_backend().open(dir + "/cut.jpg", true, why);
  ASSERT_TRUE(in) << why;
  std::vector<unsigned char> px(size_t(w) * h * 3);
  EXPECT_FALSE(in->read(0, 3, PixelFormat::U8, px.data()));
  EXPECT_NE(in->error().find("corrupt JPEG"), std::string::npos) << in->error();
  EXPECT_NE(in->error().find("Premature end"), std::string::npos) << in->error();
}

std::vector<float> oiio_read_floats(const std::string& path, int* w, int* h) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in);
  if (!in) return {};
  *w = in->spec().width;
  *h = in->spec().height;
  std::vector<float> px(size_t(in->spec().image_pixels()) * size_t(in->spec().nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeDesc::FLOAT, px.data()));
  return px;
}

std::vector<float> backend_read_floats(const std::string& path, int* w, int* h, std::string* why = nullptr) {
  std::string error;
  auto in = image_backend().open(path, true, error);
  if (why) *why = error;
  if (!in) return {};
  *w = in->header().width;
  *h = in->header().height;
  EXPECT_EQ(in->header().channels, 3);
  std::vector<float> px(size_t(*w) * size_t(*h) * 3);
  if (why) {  // a file may open and fail when its pixels are read: the caller checks why
    if (in->read(0, 3, PixelFormat::Float, px.data())) return px;
    *why = in->error();
    return {};
  }
  EXPECT_TRUE(in->read(0, 3, PixelFormat::Float, px.data())) << in->error();
  return px;
}

TEST(ImageBackend, RadianceHdrsReadAsOpenImageIOReadsThem) {
  const std::string dir = test::temp_dir();
  // Written by OpenImageIO: run-length encoded (width 37) and flat (width 5, under RLE's minimum of 8).
  for (int w : {37, 5}) {
    const int h = 6;
    std::vector<float> px(size_t(w) * h * 3);
    for (size_t i = 0; i < px.size(); ++i)
      px[i] = float(std::pow(2.0, double(i % 23) - 11.0)) * float(i % 7 + 1);
    px[4] = 0.0f;
    const std::string path = dir + "/w" + std::to_string(w) + ".hdr";
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    ASSERT_TRUE(out->close());
    int w1 = 0, h1 = 0, w2 = 0, h2 = 0;
    const auto a = oiio_read_floats(path, &w1, &h1), b = backend_read_floats(path, &w2, &h2);
    EXPECT_EQ(w2, w);
    EXPECT_EQ(h2, h);
    EXPECT_EQ(a, b) << w;
  }
  // The shared environment maps, as third parties made them.
  for (const char* name : {"goegap.hdr", "san_giuseppe_bridge.hdr", "table_mountain.hdr"}) {
    const std::string path = test::shared_scene(std::string("envmaps/") + name);
    int w1 = 0, h1 = 0, w2 = 0, h2 = 0;
    const auto a = oiio_read_floats(path, &w1, &h1), b = backend_read_floats(path, &w2, &h2);
    EXPECT_EQ(w2, w1) << name;
    EXPECT_EQ(h2, h1) << name;
    EXPECT_FALSE(b.empty()) << name;
    EXPECT_TRUE(a == b) << name;
  }
  // Into strided memory, a channel range at a time: green and blue into the
  // last two of four floats a pixel (rows padded by 8 bytes) hold OpenImageIO's.
  const std::string path = test::shared_scene("envmaps/table_mountain.hdr");
  int w = 0, h = 0;
  const auto a = oiio_read_floats(path, &w, &h);
  std::string why;
  auto in = image_backend().open(path, true, why);
  ASSERT_TRUE(in) << why;
  const std::ptrdiff_t xs = 4 * sizeof(float), ys = xs * w + 8;
  std::vector<unsigned char> strided(size_t(ys) * size_t(h), 0);
  ASSERT_TRUE(in->read(1, 3, PixelFormat::Float, strided.data() + 2 * sizeof(float), xs, ys)) << in->error();
  size_t differ = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 1; c < 3; ++c) {
        float v;
        std::memcpy(&v, strided.data() + y * ys + x * xs + (c + 1) * sizeof(float), sizeof v);
        differ += v != a[3 * (size_t(y) * size_t(w) + size_t(x)) + size_t(c)];
      }
  EXPECT_EQ(differ, 0u);
  EXPECT_FALSE(in->read(0, 3, PixelFormat::Float, strided.data()));  // the pixels are read once
}

TEST(ImageBackend, ARadianceHdrCutShortOrWithBadRunsIsRefusedSayingWhy) {
  const std::string dir = test::temp_dir();
  std::string data = test::read_file(test::shared_scene("envmaps/goegap.hdr"));
  ASSERT_GT(data.size(), 10000u);
  const size_t pixels_at = data.find("\n\n") + 2;  // the resolution line
  const size_t first_scanline = data.find('\n', pixels_at) + 1;
  auto refused = [&](const std::string& bytes, const std::string& says) {
    const std::string path = dir + "/bad.hdr";
    test::write_file(path, bytes);
    int w = 0, h = 0;
    std::string why;
    EXPECT_TRUE(backend_read_floats(path, &w, &h, &why).empty()) << says;
    EXPECT_NE(why.find("corrupt Radiance HDR"), std::string::npos) << why;
    EXPECT_NE(why.find(says), std::string::npos) << why;
  };
  refused(data.substr(0, data.size() / 2), "ends inside the pixels");
  refused(data.substr(0, pixels_at), "no resolution line");
  std::string bad = data;
  bad[first_scanline + 4] = 0;  // the first run's length: 0
  refused(bad, "bad run-length data");
  bad = data;
  bad.replace(pixels_at, first_scanline - pixels_at, "-Y 10 +X -4\n");
  refused(bad, "impossible size");
  bad = data;
  bad.replace(pixels_at, first_scanline - pixels_at, "-Y 20000 +X 20000\n");
  refused(bad, "over pmc's limit of 268435456 pixels");  // refused before allocating 4.8 GB
  // A size line far beyond the file's bytes (64M pixels in 80 KB) is refused
  // when the file is opened, before a caller allocates the image it claims.
  bad = data;
  bad.replace(pixels_at, first_scanline - pixels_at, "-Y 8192 +X 8192\n");
  test::write_file(dir + "/claims.hdr", bad);
  std::string why;
  EXPECT_FALSE(image_backend().open(dir + "/claims.hdr", true, why));
  EXPECT_NE(why.find("corrupt Radiance HDR: the file ends inside the pixels"), std::string::npos) << why;
}

TEST(ImageBackend, AJpegLargerThanTheLimitIsRefusedBeforeDecoding) {
  const std::string dir = test::temp_dir();
  std::vector<unsigned char> bytes(16 * 16 * 3, 128);
  oiio_write(dir + "/small.jpg", 16, 16, 3, bytes);
  std::string data = test::read_file(dir + "/small.jpg");
  const size_t sof = data.find("\xff\xc0");  // baseline frame header: length, precision, height, width
  ASSERT_NE(sof, std::string::npos);
  for (size_t k : {sof + 5, sof + 7}) {  // 30000 x 30000: 900 M pixels
    data[k] = char(30000 >> 8);
    data[k + 1] = char(30000 & 0xff);
  }
  test::write_file(dir + "/huge.jpg", data);
  std::string why;
  EXPECT_FALSE(image_backend().open(dir + "/huge.jpg", true, why));
  EXPECT_NE(why.find("30000x30000 is over pmc's limit"), std::string::npos) << why;
}

TEST(ImageBackend, OtherFormatsGoToThePlugin) {
  const std::string dir = test::temp_dir();
  const int w = 8, h = 8;
  std::vector<unsigned char> bytes(size_t(w) * h * 3);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = (unsigned char)(i * 3);
  for (const char* ext : {".tif", ".tga"}) {
    const std::string path = dir + "/a" + ext;
    oiio_write(path, w, h, 3, bytes);
    int n_oiio = 0, n_backend = 0;
    const auto a = oiio_read_bytes(path, &n_oiio), b = backend_read_bytes(path, &n_backend);
    EXPECT_EQ(n_backend, 3) << ext;
    EXPECT_EQ(a, b) << ext;
    EXPECT_EQ(b, bytes) << ext;
  }
}

TEST(FirstChannels, KeepsTheLeadingChannelsOfEveryPixel) {
  Image rgba;
  rgba.width = 2;
  rgba.height = 1;
  rgba.channels = 4;
  rgba.pixels = {1, 2, 3, 4, 5, 6, 7, 8};
  const Image rgb = first_channels(rgba, 3);
  EXPECT_EQ(rgb.channels, 3);
  EXPECT_EQ(rgb.pixels, (std::vector<float>{1, 2, 3, 5, 6, 7}));
}

}  // namespace
}  // namespace pmc
