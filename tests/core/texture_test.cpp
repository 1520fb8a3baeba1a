// texture_test.cpp — the texel pool: sRGB encoding by table, mip chains,
// deferred parallel decoding.
//
// * encode_srgb_byte (a threshold table) equals rounding the sRGB encoding
//   formula to 8 bits, checked at every threshold, one float either side, and
//   on a dense sweep of [0, 1.1].
// * A mip chain of a known image has the box-filtered values (linear data:
//   plain averages; colour: averaged in linear light).
// * Files decode later, in parallel, into the places their indices promise;
//   a copy of a pool with pending files decodes first; a corrupt file fails
//   naming the file and its user when the pool is resolved.
#include "core/texture.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

uint8_t reference_srgb_byte(float linear) {
  float c = linear <= 0.0031308f ? linear * 12.92f : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
  if (!(c > 0.0f)) return 0;
  if (c >= 1.0f) return 255;
  return uint8_t(c * 255.0f + 0.5f);
}

TEST(Texture, SrgbEncodingByTableEqualsTheFormula) {
  size_t checked = 0;
  for (uint32_t bits = 0; bits <= 0x3f8ccccdu; bits += 389) {  // [0, 1.1] in steps of 389 ulps
    float x;
    std::memcpy(&x, &bits, sizeof(x));
    ASSERT_EQ(encode_srgb_byte(x), reference_srgb_byte(x)) << "at " << x;
    ++checked;
  }
  // Around every rounding boundary: the first float of each byte and its neighbours.
  for (int k = 1; k < 256; ++k) {
    float lo = 0.0f, hi = 1.0f;
    for (int i = 0; i < 64; ++i) {
      float mid = 0.5f * (lo + hi);
      (reference_srgb_byte(mid) >= k ? hi : lo) = mid;
    }
    for (float x : {std::nextafter(hi, 0.0f), hi, std::nextafter(hi, 2.0f)})
      ASSERT_EQ(encode_srgb_byte(x), reference_srgb_byte(x)) << "byte " << k << " at " << x;
  }
  EXPECT_EQ(encode_srgb_byte(-1.0f), 0);
  EXPECT_EQ(encode_srgb_byte(std::nanf("")), 0);
  EXPECT_EQ(encode_srgb_byte(7.0f), 255);
  EXPECT_GT(checked, 2500000u);
}

TEST(Texture, MipChainAveragesLinearDataAndColourInLinearLight) {
  TexturePool pool;
  // 2x2: texels 0, 255, 255, 0 in every channel.
  std::vector<uint8_t> px = {0, 0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 0, 0, 0, 0};
  int data = pool.add("data", 2, 2, px, false);
  int colour = pool.add("colour", 2, 2, px, true);
  const PmcTexture& d = pool.textures()[size_t(data)];
  const PmcTexture& c = pool.textures()[size_t(colour)];
  EXPECT_EQ(d.levels, 2);
  const uint8_t* d1 = &pool.texels()[(size_t(d.offset) + 4) * 4];
  const uint8_t* c1 = &pool.texels()[(size_t(c.offset) + 4) * 4];
  EXPECT_EQ(d1[0], 128);                        // (0 + 1 + 1 + 0) / 4 = 0.5 -> 127.5 rounds up
  EXPECT_EQ(c1[0], reference_srgb_byte(0.5f));  // linear 0.5 encoded: 188, not 128
  EXPECT_EQ(c1[3], 128);                        // alpha is data
}

void write_png(const std::string& path, int w, int h, uint8_t value) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
  ASSERT_TRUE(out->open(path, spec));
  std::vector<uint8_t> px(size_t(w) * h * 3, value);
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
  out->close();
}

TEST(Texture, FilesDecodeLaterIntoTheirPlacesAndCopiesDecodeFirst) {
  const std::string dir = test::temp_dir();
  for (int i = 0; i < 6; ++i) write_png(dir + "/t" + std::to_string(i) + ".png", 8 + i, 5, uint8_t(40 * i));
  TexturePool pool;
  std::vector<uint8_t> px(4 * 4, 7);
  int first = pool.add("memory", 2, 2, px, false);
  std::vector<int> index;
  for (int i = 0; i < 6; ++i)
    index.push_back(pool.load(dir + "/t" + std::to_string(i) + ".png", false, "test"));
  EXPECT_EQ(pool.load(dir + "/t2.png", false, "test"), index[2]) << "a file is loaded once";
  EXPECT_EQ(first, 0);
  TexturePool copy = pool;  // decodes the pending files first
  for (const TexturePool* p : {&pool, &copy})
    for (int i = 0; i < 6; ++i) {
      const PmcTexture& t = p->textures()[size_t(index[size_t(i)])];
      EXPECT_EQ(t.width, 8 + i);
      EXPECT_EQ(t.height, 5);
      const uint8_t* texel = &p->texels()[size_t(t.offset) * 4];
      EXPECT_EQ(texel[0], uint8_t(40 * i));
      EXPECT_EQ(texel[3], 255) << "no alpha channel reads as opaque";
      const uint8_t* last = &p->texels()[(size_t(t.offset) + size_t(t.width) * 5 - 1) * 4];
      EXPECT_EQ(last[1], uint8_t(40 * i));
    }
  EXPECT_EQ(pool.texels()[0], 7);
}

TEST(Texture, CorruptFileFailsNamingItAndItsUserWhenResolved) {
  const std::string dir = test::temp_dir();
  write_png(dir + "/good.png", 64, 64, 9);
  std::string bytes;
  {
    std::ifstream in(dir + "/good.png", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  test::write_file(dir + "/cut.png", bytes.substr(0, bytes.size() / 2));  // header intact, data cut
  TexturePool pool;
  pool.load(dir + "/good.png", true, "scene.mtl: material 'a'");
  pool.load(dir + "/cut.png", true, "scene.mtl: material 'b'");
  try {
    pool.resolve();
    FAIL() << "a truncated image must not decode";
  } catch (const Error& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("cut.png"), std::string::npos) << what;
    EXPECT_NE(what.find("material 'b'"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace pmc
