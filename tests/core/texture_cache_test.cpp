// texture_cache_test.cpp — decoded textures kept between runs
// (core/texture_cache.h).
//
// The independent answer is the pool decoded with the cache off: a texture
// served from the cache must equal it byte for byte, mip chain included.
// An edited source (same size, same time stamps), a damaged or cut entry,
// and an unwritable folder must all fall back to decoding; the folder stays
// under its size limit, least recently used entries going first.
#include "core/texture_cache.h"

#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/texture.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

namespace fs = std::filesystem;

// An RGB PNG of noise from `seed`.
void write_noise_png(const std::string& path, int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> px(size_t(w) * h * 3);
  for (uint8_t& v : px) v = uint8_t(rng() & 255u);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
  out->close();
}

// The decoded pool (every texel of every level) of `path` read as sRGB colour.
std::vector<uint8_t> decoded(const std::string& path) {
  TexturePool pool;
  pool.load(path, true, "test");
  TexelBytes t = pool.texels();
  return std::vector<uint8_t>(t.begin(), t.end());
}

std::vector<fs::path> entries(const std::string& dir) {
  std::vector<fs::path> out;
  if (!fs::exists(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".pmctex") out.push_back(e.path());
  return out;
}

// Configures the process's cache for one test and restores the default after it.
class TextureCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir();
    folder_ = dir_ + "/cache";
    TextureCache::instance().configure("off");
    png_ = dir_ + "/noise.png";
    write_noise_png(png_, 37, 20, 1);
    uncached_ = decoded(png_);
    TextureCache::instance().configure(folder_);
  }
  void TearDown() override { TextureCache::instance().configure(""); }

  std::string dir_, folder_, png_;
  std::vector<uint8_t> uncached_;
};

TEST_F(TextureCacheTest, SecondLoadIsServedFromTheCacheWithTheSameTexels) {
  TextureCache& cache = TextureCache::instance();
  const TextureCacheStats s0 = cache.stats();
  EXPECT_EQ(decoded(png_), uncached_);
  const TextureCacheStats s1 = cache.stats();
  EXPECT_EQ(s1.writes, s0.writes + 1);
  EXPECT_EQ(s1.hits, s0.hits);
  ASSERT_EQ(entries(folder_).size(), 1u);
  EXPECT_EQ(decoded(png_), uncached_) << "a cache hit must give the decoded chain, every level";
  const TextureCacheStats s2 = cache.stats();
  EXPECT_EQ(s2.hits, s1.hits + 1);
  EXPECT_EQ(s2.writes, s1.writes) << "a hit writes nothing";
  // Linear data is another entry (its mips average without the sRGB curve).
  TexturePool linear;
  linear.load(png_, false, "test");
  linear.resolve();
  EXPECT_EQ(entries(folder_).size(), 2u);
}

TEST_F(TextureCacheTest, AnEditedTextureIsNeverServedStale) {
  decoded(png_);  // cached
  struct stat before {};
  ASSERT_EQ(::stat(png_.c_str(), &before), 0);
  write_noise_png(png_, 37, 20, 2);  // same size and format, other texels
  struct stat after {};
  ASSERT_EQ(::stat(png_.c_str(), &after), 0);
  // Same time stamps as before, so only the content tells the versions apart.
  const struct timespec times[2] = {before.st_atim, before.st_mtim};
  ASSERT_EQ(::utimensat(AT_FDCWD, png_.c_str(), times, 0), 0);
  TextureCache::instance().configure("off");
  const std::vector<uint8_t> edited = decoded(png_);
  TextureCache::instance().configure(folder_);
  ASSERT_NE(edited, uncached_);
  EXPECT_EQ(decoded(png_), edited);
}

TEST_F(TextureCacheTest, DamagedOrCutEntriesAreIgnoredAndRewritten) {
  decoded(png_);
  const std::vector<fs::path> e = entries(folder_);
  ASSERT_EQ(e.size(), 1u);
  const std::string entry = e[0].string();
  std::string bytes = test::read_file(entry);
  TextureCache& cache = TextureCache::instance();

  std::string damaged = bytes;
  damaged[100] = char(damaged[100] ^ 0x40);  // one texel bit
  test::write_file(entry, damaged);
  TextureCacheStats s0 = cache.stats();
  EXPECT_EQ(decoded(png_), uncached_);
  TextureCacheStats s1 = cache.stats();
  EXPECT_EQ(s1.hits, s0.hits) << "a damaged entry must fail its checksum";
  EXPECT_EQ(s1.writes, s0.writes + 1) << "and be written again";
  EXPECT_EQ(test::read_file(entry), bytes);

  test::write_file(entry, bytes.substr(0, bytes.size() / 2));
  EXPECT_EQ(decoded(png_), uncached_);
  EXPECT_EQ(cache.stats().hits, s1.hits) << "a cut entry is not a hit";
  EXPECT_EQ(test::read_file(entry), bytes);
}

TEST_F(TextureCacheTest, AnUnwritableFolderWarnsOnceAndTexturesStillDecode) {
  test::write_file(dir_ + "/a_file", "not a folder");
  TextureCache::instance().configure(dir_ + "/a_file/cache");
  write_noise_png(dir_ + "/other.png", 9, 9, 3);
  testing::internal::CaptureStderr();
  EXPECT_EQ(decoded(png_), uncached_);
  decoded(dir_ + "/other.png");
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("texture cache: cannot write to " + dir_ + "/a_file/cache"), std::string::npos) << err;
  EXPECT_NE(err.find("(texture_cache DIR chooses another folder, texture_cache off turns the cache off)"),
            std::string::npos)
      << "below app/ a warning names the setting, not its flag: " << err;
  EXPECT_EQ(err.find("texture cache", err.find("texture cache") + 1), std::string::npos)
      << "one warning, not one per texture: " << err;
}

TEST_F(TextureCacheTest, OffWritesNothing) {
  TextureCache::instance().configure("off");
  EXPECT_FALSE(TextureCache::instance().enabled());
  EXPECT_EQ(decoded(png_), uncached_);
  EXPECT_TRUE(entries(folder_).empty());
}

TEST_F(TextureCacheTest, TrimKeepsTheFolderUnderItsLimitDroppingTheLeastRecentlyUsed) {
  // Five textures of the same size; room for three entries.
  std::vector<std::string> pngs;
  for (unsigned i = 0; i < 5; ++i) {
    pngs.push_back(dir_ + "/t" + std::to_string(i) + ".png");
    write_noise_png(pngs.back(), 16, 16, 10 + i);
  }
  decoded(pngs[0]);
  ASSERT_EQ(entries(folder_).size(), 1u);
  const uint64_t entry_bytes = fs::file_size(entries(folder_)[0]);
  TextureCache::instance().configure(folder_, 3 * entry_bytes + entry_bytes / 2);
  for (size_t i = 1; i < pngs.size(); ++i) {
    // Every entry so far is made older than the one about to be written
    // (distinct use times whatever the file system clock's resolution).
    for (const fs::path& e : entries(folder_)) {
      struct stat st {};
      ASSERT_EQ(::stat(e.c_str(), &st), 0);
      struct timespec t[2] = {st.st_atim, st.st_mtim};
      t[0].tv_sec -= 10;
      t[1].tv_sec -= 10;
      ASSERT_EQ(::utimensat(AT_FDCWD, e.c_str(), t, 0), 0);
    }
    decoded(pngs[i]);
  }
  const std::vector<fs::path> left = entries(folder_);
  uint64_t total = 0;
  for (const fs::path& e : left) total += fs::file_size(e);
  EXPECT_LE(total, 3 * entry_bytes + entry_bytes / 2);
  EXPECT_GE(left.size(), 2u);
  // The newest texture is kept: its second load is a hit.
  const uint64_t hits = TextureCache::instance().stats().hits;
  decoded(pngs.back());
  EXPECT_EQ(TextureCache::instance().stats().hits, hits + 1);
  // The oldest is gone: its load decodes again.
  decoded(pngs.front());
  EXPECT_EQ(TextureCache::instance().stats().hits, hits + 1);
}

TEST_F(TextureCacheTest, TemporariesOfDeadRunsAreRemovedAndLiveOnesKept) {
  fs::create_directories(folder_);
  const std::string dead = folder_ + "/0123.pmctex.tmp.4242.7";
  const std::string live = folder_ + "/4567.pmctex.tmp.4243.7";
  test::write_file(dead, "half an entry");
  test::write_file(live, "an entry being written");
  struct timespec two_hours_ago[2] = {};
  ASSERT_EQ(clock_gettime(CLOCK_REALTIME, &two_hours_ago[0]), 0);
  two_hours_ago[0].tv_sec -= 7200;
  two_hours_ago[1] = two_hours_ago[0];
  ASSERT_EQ(::utimensat(AT_FDCWD, dead.c_str(), two_hours_ago, 0), 0);
  decoded(png_);  // writes an entry, then trims
  EXPECT_FALSE(fs::exists(dead)) << "a temporary untouched for an hour belongs to a run that died";
  EXPECT_TRUE(fs::exists(live)) << "a recent temporary may still be written";
}

}  // namespace
}  // namespace pmc
