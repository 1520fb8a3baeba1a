// texture_test.cpp — the texel pool: sRGB encoding by table, mip chains,
// deferred parallel decoding.
//
// * encode_srgb_byte (a threshold table) equals rounding the sRGB encoding
//   formula to 8 bits, checked at every threshold, one float either side, and
//   on a dense sweep of [0, 1.1].
// * A mip chain of a known image has the box-filtered values (linear data:
//   plain averages; colour: averaged in linear light), and every level of an
//   odd-sized noise image equals the plain per-texel box filter bit for bit.
// * Files decode later, in parallel, into the places their indices promise;
//   a copy of a pool with pending files decodes first; a corrupt file fails
//   naming the file and its user when the pool is resolved.
#include "core/texture.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
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

// The plain per-texel box filter, written out as the mip chain is defined:
// four taps (odd sizes clamp), colour averaged in linear light.
std::vector<uint8_t> reference_downsample(const std::vector<uint8_t>& src, int w, int h, bool srgb) {
  auto to_linear = [](uint8_t b) {
    float c = b / 255.0f;
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
  };
  const int nw = std::max(1, w >> 1), nh = std::max(1, h >> 1);
  std::vector<uint8_t> dst(size_t(nw) * nh * 4);
  for (int y = 0; y < nh; ++y)
    for (int x = 0; x < nw; ++x)
      for (int c = 0; c < 4; ++c) {
        float sum = 0.0f;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            uint8_t b = src[(size_t(std::min(h - 1, 2 * y + dy)) * w + std::min(w - 1, 2 * x + dx)) * 4 + c];
            sum += (srgb && c < 3) ? to_linear(b) : b / 255.0f;
          }
        float avg = sum * 0.25f;
        uint8_t data = avg >= 1.0f ? 255 : uint8_t(avg * 255.0f + 0.5f);
        dst[(size_t(y) * nw + x) * 4 + c] = (srgb && c < 3) ? reference_srgb_byte(avg) : data;
      }
  return dst;
}

TEST(Texture, MipChainOfAnOddSizedImageEqualsThePlainBoxFilter) {
  const int w = 37, h = 10;
  std::vector<uint8_t> px(size_t(w) * h * 4);
  uint32_t state = 12345u;
  for (uint8_t& b : px) {
    state = state * 1664525u + 1013904223u;
    b = uint8_t(state >> 24);
  }
  for (bool srgb : {false, true}) {
    TexturePool pool;
    const PmcTexture& t = pool.textures()[size_t(pool.add("noise", w, h, px, srgb))];
    std::vector<uint8_t> level = px;
    int lw = w, lh = h;
    size_t offset = size_t(t.offset);
    for (int l = 1; l < t.levels; ++l) {
      offset += size_t(lw) * lh;
      level = reference_downsample(level, lw, lh, srgb);
      lw = std::max(1, lw >> 1);
      lh = std::max(1, lh >> 1);
      for (size_t i = 0; i < level.size(); ++i)
        ASSERT_EQ(pool.texels()[offset * 4 + i], level[i])
            << "level " << l << " byte " << i << " srgb " << srgb;
    }
    EXPECT_EQ(t.levels, 6);  // 37x10, 18x5, 9x2, 4x1, 2x1, 1x1
  }
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

// Pending files stay open until they decode; a scene with more textures
// than the open-file limit allows must still load (they decode in batches).
TEST(Texture, ThousandsOfFilesLoadInBatchesUnderTheOpenFileLimit) {
  const std::string dir = test::temp_dir();
  const int files = 1100;  // past the default limit of 1024 open files
  for (int i = 0; i < files; ++i) write_png(dir + "/t" + std::to_string(i) + ".png", 2, 2, uint8_t(i % 251));
  // This machine's limit may be high: lower it to 700 for the loads.
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_NOFILE, &old), 0);
  rlimit low = old;
  low.rlim_cur = std::min<rlim_t>(old.rlim_cur, 700);
  ASSERT_EQ(setrlimit(RLIMIT_NOFILE, &low), 0);
  TexturePool pool;
  std::vector<int> index;
  std::string error;
  try {
    for (int i = 0; i < files; ++i)
      index.push_back(pool.load(dir + "/t" + std::to_string(i) + ".png", false, "test"));
  } catch (const Error& e) {
    error = e.what();
  }
  setrlimit(RLIMIT_NOFILE, &old);
  ASSERT_EQ(error, "");
  for (int i = 0; i < files; ++i) {
    const PmcTexture& t = pool.textures()[size_t(index[size_t(i)])];
    ASSERT_EQ(pool.texels()[size_t(t.offset) * 4], uint8_t(i % 251)) << i;
  }
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

// Every channel count of 8-bit files lands as RGBA: 3 and 4 channels are read
// straight into the pool (4 bytes apart), 1 and 2 through the conversion
// loop; the expected texels come from the written pixels, not from the code.
TEST(Texture, EightBitFilesOfEveryChannelCountDecodeToRgba) {
  const std::string dir = test::temp_dir();
  const int w = 7, h = 3;
  TexturePool pool;
  std::vector<int> index;
  for (int nch = 1; nch <= 4; ++nch) {
    const std::string path = dir + "/c" + std::to_string(nch) + ".png";
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(w, h, nch, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // the bytes as given, alpha not divided out
    ASSERT_TRUE(out->open(path, spec));
    std::vector<uint8_t> px(size_t(w) * h * size_t(nch));
    for (size_t i = 0; i < size_t(w) * h; ++i)
      for (int c = 0; c < nch; ++c) px[i * size_t(nch) + size_t(c)] = uint8_t(40 * c + 3 * i + 1);
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
    index.push_back(pool.load(path, true, "test"));
  }
  for (int nch = 1; nch <= 4; ++nch) {
    const PmcTexture& t = pool.textures()[size_t(index[size_t(nch - 1)])];
    for (size_t i = 0; i < size_t(w) * h; ++i) {
      auto value = [&](int c) { return uint8_t(40 * c + 3 * i + 1); };
      const uint8_t* texel = &pool.texels()[(size_t(t.offset) + i) * 4];
      const int colour[3] = {0, nch >= 3 ? 1 : 0, nch >= 3 ? 2 : 0};
      for (int k = 0; k < 3; ++k) EXPECT_EQ(texel[k], value(colour[k])) << nch << " channels, texel " << i;
      const uint8_t alpha = nch == 2 ? value(1) : nch == 4 ? value(3) : uint8_t(255);
      EXPECT_EQ(texel[3], alpha) << nch << " channels, texel " << i;
    }
  }
}

// words() shares the pool (bytes R, G, B, A in memory) without a copy, and
// what it handed out never changes: the pool copies its words before adding
// to them; the pool stays whole (build_material_set may run twice on a scene).
TEST(Texture, SharedWordsAreNotCopiedAndNeverChange) {
  TexturePool pool;
  std::vector<uint8_t> px = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  pool.add("memory", 2, 2, px, false);
  std::vector<uint8_t> before(pool.texels().begin(), pool.texels().end());
  std::shared_ptr<const TexelWords> words = pool.words();
  ASSERT_EQ(words->size() * 4, before.size());
  EXPECT_EQ(static_cast<const void*>(words->data()), static_cast<const void*>(pool.texels().data()));
  EXPECT_EQ(0, std::memcmp(words->data(), before.data(), before.size()));
  EXPECT_EQ(pool.words(), words) << "the same words twice";
  pool.add("more", 1, 1, {9, 9, 9, 9}, false);
  EXPECT_EQ(words->size() * 4, before.size()) << "handed-out words changed";
  EXPECT_EQ(0, std::memcmp(words->data(), before.data(), before.size()));
  EXPECT_EQ(pool.texels().size(), before.size() + 4);
  EXPECT_EQ(0, std::memcmp(pool.texels().data(), before.data(), before.size()));
  EXPECT_EQ(pool.texels()[before.size()], 9);
  TexturePool moved = std::move(pool);
  EXPECT_EQ(moved.size(), 2u);
}

}  // namespace
}  // namespace pmc
