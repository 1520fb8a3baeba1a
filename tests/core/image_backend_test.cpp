// image_backend_test.cpp — the image plugin: pmc does not link OpenImageIO,
// loads libpmc_oiio.so at run time, and fails clearly without it.
//
// * The pmc binary's dynamic dependencies (ldd) name no OpenImageIO library.
// * Through the backend, an EXR with per-channel formats (float and uint32),
//   a data window inside a display window and typed attributes reads back
//   exactly as written, checked against OpenImageIO read directly.
// * A render whose plugin cannot be loaded exits 2, names the paths tried and
//   writes no image.
// * first_channels() keeps the leading channels of each pixel.
#include "core/image_backend.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
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

TEST(ImageBackend, WithoutThePluginARenderFailsNamingWhereItLookedAndWritesNothing) {
  const std::string dir = test::temp_dir();
  const std::string plugin = dir + "/nowhere/libpmc_oiio.so";
  int code = 0;
  const std::string text = shell_output("env PMC_IMAGE_PLUGIN=" + plugin + " " + std::string(PMC_BINARY) +
                                            " render " + test::source_path("data/default/room.obj") +
                                            " --width 16 --height 8 --spp 1 -o " + dir + "/out.exr --quiet",
                                        &code);
  EXPECT_EQ(code, 2) << text;
  EXPECT_NE(text.find("cannot load the image plugin"), std::string::npos) << text;
  EXPECT_NE(text.find(plugin), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.exr"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.png"));
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
