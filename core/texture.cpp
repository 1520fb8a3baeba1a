// texture.cpp — reading (the image backend), 8-bit conversion and mip chains.
#include "core/texture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "core/error.h"
#include "core/image_backend.h"
#include "core/parallel.h"
#include "core/texture_cache.h"

namespace pmc {
namespace {

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }
float linear_to_srgb(float c) {
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}
uint8_t to_byte(float v) {
  if (!(v > 0.0f)) return 0;  // also NaN
  if (v >= 1.0f) return 255;
  return static_cast<uint8_t>(v * 255.0f + 0.5f);
}

// threshold[k] is the smallest non-negative float whose sRGB byte,
// to_byte(linear_to_srgb(x)), is at least k. The byte is monotonic in x
// (checked for every float in [0, 1.01]), so counting the thresholds at or
// below x gives exactly that byte with 8 comparisons instead of a pow.
const std::array<float, 256>& srgb_thresholds() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    t[0] = 0.0f;
    for (int k = 1; k < 256; ++k) {
      uint32_t lo = 0, hi = 0x3f800000u;  // [0, 1.0f]: to_byte(linear_to_srgb(1)) = 255
      while (lo < hi) {                   // first bit pattern whose byte reaches k
        uint32_t mid = lo + (hi - lo) / 2;
        float x;
        std::memcpy(&x, &mid, sizeof(x));
        if (to_byte(linear_to_srgb(x)) >= k)
          hi = mid;
        else
          lo = mid + 1;
      }
      std::memcpy(&t[size_t(k)], &lo, sizeof(float));
    }
    return t;
  }();
  return table;
}

// The sRGB byte of every positive float below 1.0 from one table lookup and
// one comparison, exactly the byte counting thresholds gives: floats are cut
// into buckets by their top bits (2^15 consecutive bit patterns, a relative
// width of 1/256), base[] is the byte at a bucket's first float and next[] the
// one threshold that may fall inside it. The curve rises by less than half a
// byte across any bucket, so no bucket holds two thresholds; construction
// checks that for every bucket.
struct SrgbEncodeTable {
  static constexpr int kShift = 15;
  static constexpr uint32_t kBuckets = (0x3f800000u >> kShift) + 1;
  std::vector<uint8_t> base;
  std::vector<float> next;
};

const SrgbEncodeTable& srgb_encode_table() {
  static const SrgbEncodeTable table = [] {
    const std::array<float, 256>& t = srgb_thresholds();
    SrgbEncodeTable e;
    e.base.resize(SrgbEncodeTable::kBuckets);
    e.next.resize(SrgbEncodeTable::kBuckets);
    int k = 0;  // largest k with t[k] <= the bucket's first float
    for (uint32_t b = 0; b < SrgbEncodeTable::kBuckets; ++b) {
      const uint32_t first_bits = b << SrgbEncodeTable::kShift;
      const uint32_t last_bits = first_bits + ((1u << SrgbEncodeTable::kShift) - 1);
      float first, last;
      std::memcpy(&first, &first_bits, sizeof(first));
      std::memcpy(&last, &last_bits, sizeof(last));
      while (k < 255 && t[size_t(k) + 1] <= first) ++k;
      e.base[b] = uint8_t(k);
      e.next[b] = k < 255 ? t[size_t(k) + 1] : INFINITY;
      if (k < 254 && t[size_t(k) + 2] <= last)
        throw std::logic_error("sRGB encode table: two thresholds in one bucket");
    }
    return e;
  }();
  return table;
}

// encode_srgb_byte with the table passed in, so loops look it up once.
inline uint8_t encode_srgb_with(const SrgbEncodeTable& table, float linear) {
  if (!(linear > 0.0f)) return 0;  // also NaN
  if (linear >= 1.0f) return 255;
  uint32_t bits;
  std::memcpy(&bits, &linear, sizeof(bits));
  const uint32_t bucket = bits >> SrgbEncodeTable::kShift;
  return uint8_t(table.base[bucket] + (linear >= table.next[bucket] ? 1 : 0));
}

size_t mip_chain_texels(int w, int h) {
  size_t n = 0;
  for (;;) {
    n += size_t(w) * size_t(h);
    if (w == 1 && h == 1) return n;
    w = std::max(1, w >> 1);
    h = std::max(1, h >> 1);
  }
}

int mip_levels(int w, int h) {
  int levels = 1;
  while (w > 1 || h > 1) {
    w = std::max(1, w >> 1);
    h = std::max(1, h >> 1);
    ++levels;
  }
  return levels;
}

// One 2x2 box-filter reduction (odd sizes clamp the last row/column). The
// four taps of a texel add in the order (x, y), (x+1, y), (x, y+1),
// (x+1, y+1), through lookup tables that hold exactly the values the
// per-texel formula gives, so every level is bit for bit what the plain loop
// makes; the loop runs over rows through pointers because mip building was a
// tenth of the setup time of texture-heavy scenes.
void downsample(const uint8_t* src, int w, int h, bool srgb, uint8_t* dst) {
  static const std::vector<float> srgb_lut = srgb_decode_table();
  static const std::array<float, 256> unorm_lut = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = i / 255.0f;
    return t;
  }();
  const float* colour_lut = srgb ? srgb_lut.data() : unorm_lut.data();
  const float* alpha_lut = unorm_lut.data();
  const SrgbEncodeTable& encode = srgb_encode_table();
  const int nw = std::max(1, w >> 1), nh = std::max(1, h >> 1);
  for (int y = 0; y < nh; ++y) {
    const uint8_t* row0 = src + size_t(std::min(h - 1, 2 * y)) * w * 4;
    const uint8_t* row1 = src + size_t(std::min(h - 1, 2 * y + 1)) * w * 4;
    uint8_t* out = dst + size_t(y) * nw * 4;
    for (int x = 0; x < nw; ++x) {
      const size_t x0 = size_t(std::min(w - 1, 2 * x)) * 4, x1 = size_t(std::min(w - 1, 2 * x + 1)) * 4;
      auto average = [&](const float* lut, int c) {
        float sum = lut[row0[x0 + c]];
        sum += lut[row0[x1 + c]];
        sum += lut[row1[x0 + c]];
        sum += lut[row1[x1 + c]];
        return sum * 0.25f;
      };
      for (int c = 0; c < 3; ++c) {
        const float avg = average(colour_lut, c);
        out[size_t(x) * 4 + c] = srgb ? encode_srgb_with(encode, avg) : to_byte(avg);
      }
      out[size_t(x) * 4 + 3] = to_byte(average(alpha_lut, 3));
    }
  }
}

// Fills the levels after the first of a chain that starts at `base`.
void build_mips(uint8_t* base, int w, int h, bool srgb) {
  uint8_t* level = base;
  while (w > 1 || h > 1) {
    uint8_t* next = level + size_t(w) * h * 4;
    downsample(level, w, h, srgb, next);
    level = next;
    w = std::max(1, w >> 1);
    h = std::max(1, h >> 1);
  }
}

}  // namespace

std::vector<float> srgb_decode_table() {
  std::vector<float> lut(256);
  for (int i = 0; i < 256; ++i) lut[i] = srgb_to_linear(i / 255.0f);
  return lut;
}

uint8_t encode_srgb_byte(float linear) { return encode_srgb_with(srgb_encode_table(), linear); }

// A texture whose header has been read and whose pixels are not decoded yet.
struct TexturePool::Pending {
  int index = 0;
  std::string path, used_by;
  bool srgb = false;
  std::unique_ptr<ImageReader> in;
  std::string warning;  // set by the decode (NaN/Inf texels)
  std::string error;    // set by a failed decode
};

TexturePool::TexturePool() = default;
TexturePool::~TexturePool() = default;
TexturePool::TexturePool(TexturePool&&) noexcept = default;
TexturePool& TexturePool::operator=(TexturePool&&) noexcept = default;

TexturePool::TexturePool(const TexturePool& other) { *this = other; }

TexturePool& TexturePool::operator=(const TexturePool& other) {
  if (this == &other) return *this;
  other.resolve();
  textures_ = other.textures_;
  names_ = other.names_;
  words_ = other.words_;
  by_key_ = other.by_key_;
  pending_.clear();
  return *this;
}

int TexturePool::add(const std::string& name, int width, int height, std::vector<uint8_t> rgba, bool srgb) {
  PMC_CHECK(width > 0 && height > 0 && rgba.size() == size_t(width) * height * 4, name);
  PmcTexture t{};
  TexelWords& words = own_words();
  t.offset = static_cast<pmc_u32>(words.size());
  t.width = width;
  t.height = height;
  t.levels = mip_levels(width, height);
  t.flags = srgb ? PMC_TEX_SRGB : 0u;
  const size_t at = words.size();
  words.resize(at + mip_chain_texels(width, height));
  uint8_t* base = reinterpret_cast<uint8_t*>(words.data() + at);
  std::memcpy(base, rgba.data(), rgba.size());
  build_mips(base, width, height, srgb);
  textures_.push_back(t);
  names_.push_back(name);
  return static_cast<int>(textures_.size()) - 1;
}

namespace {
constexpr size_t kMaxPendingTextures = 256;
}  // namespace

int TexturePool::load(const std::string& path, bool srgb, const std::string& used_by) {
  std::string key = path + (srgb ? "#srgb" : "#linear");
  auto found = by_key_.find(key);
  if (found != by_key_.end()) return found->second;

  // Keep colour and alpha separate: cut-out masks need the unpremultiplied colour.
  std::string why;
  auto in = image_backend().open(path, true, why);
  if (!in) fail(used_by, ": cannot read texture '", path, "': ", why.empty() ? "not an image" : why);
  const ImageHeader& spec = in->header();
  int w = spec.width, h = spec.height, nch = spec.channels;
  if (w <= 0 || h <= 0 || nch <= 0 || size_t(w) * h > (size_t(1) << 28))
    fail(used_by, ": texture '", path, "' has an unusable size ", w, "x", h, "x", nch);
  PmcTexture t{};
  t.width = w;
  t.height = h;
  t.levels = mip_levels(w, h);
  t.flags = srgb ? PMC_TEX_SRGB : 0u;
  textures_.push_back(t);  // offset set when decoded
  names_.push_back(path);
  auto p = std::make_unique<Pending>();
  p->index = int(textures_.size()) - 1;
  p->path = path;
  p->used_by = used_by;
  p->srgb = srgb;
  p->in = std::move(in);
  pending_.push_back(std::move(p));
  by_key_[key] = int(textures_.size()) - 1;
  // Each pending texture keeps its file open until it decodes: decode a
  // full batch now, so a scene of thousands of textures stays far below the
  // process's open-file limit (1024 by default).
  if (pending_.size() >= kMaxPendingTextures) resolve();
  return int(textures_.size()) - 1;
}

namespace {

// Decodes one image into its level 0 (RGBA8) at `dst`; returns a warning, if any.
std::string decode_rgba8(ImageReader& in, const std::string& path, const std::string& used_by, bool srgb,
                         uint8_t* dst) {
  const ImageHeader& spec = in.header();
  const int w = spec.width, h = spec.height, nch = spec.channels;
  const size_t n = size_t(w) * h;
  auto channel_of = [nch](int k) {
    return k < 3 ? (nch >= 3 ? k : 0) : (nch == 2 ? 1 : (nch >= 4 ? 3 : -1));
  };
  if (spec.format == PixelFormat::U8 && nch >= 3) {
    // RGB(A) 8-bit: straight into the pool (4 bytes apart), opaque alpha added
    // for RGB; the channels past the fourth are not read.
    const int read = std::min(nch, 4);
    if (!in.read(0, read, PixelFormat::U8, dst, 4, std::ptrdiff_t(w) * 4))
      fail(used_by, ": cannot decode texture '", path, "': ", in.error());
    if (read == 3)
      for (size_t i = 0; i < n; ++i) dst[i * 4 + 3] = 255;
    return {};
  }
  if (spec.format == PixelFormat::U8) {
    // 8-bit sources are stored as they are (sRGB-encoded colour stays encoded).
    std::vector<uint8_t> px(n * size_t(nch));
    if (!in.read(0, nch, PixelFormat::U8, px.data()))
      fail(used_by, ": cannot decode texture '", path, "': ", in.error());
    for (size_t i = 0; i < n; ++i)
      for (int k = 0; k < 4; ++k) {
        int src = channel_of(k);
        dst[i * 4 + k] = src < 0 ? 255 : px[i * nch + size_t(src)];
      }
    return {};
  }
  std::vector<float> px(n * size_t(nch));
  if (!in.read(0, nch, PixelFormat::Float, px.data()))
    fail(used_by, ": cannot decode texture '", path, "': ", in.error());
  // Float sources get sRGB-encoded; other integer formats are scaled to 0..1 by OIIO.
  const bool float_source = spec.format == PixelFormat::Float || spec.format == PixelFormat::Half;
  size_t non_finite = 0;
  for (size_t i = 0; i < n; ++i) {
    float c[4];
    bool bad = false;
    for (int k = 0; k < 4; ++k) {
      int src = channel_of(k);
      float v = src < 0 ? 1.0f : px[i * nch + size_t(src)];
      if (!std::isfinite(v)) v = 0.0f, bad = true;  // NaN/Inf channels become 0 (black)
      c[k] = v;
    }
    non_finite += bad ? 1 : 0;
    for (int k = 0; k < 4; ++k) {
      float v = c[k];
      dst[i * 4 + k] = float_source && srgb && k < 3 ? encode_srgb_byte(std::min(1.0f, v)) : to_byte(v);
    }
  }
  if (non_finite == 0) return {};
  return used_by + ": texture '" + path + "': " + std::to_string(non_finite) + " of " + std::to_string(n) +
         " texels hold NaN or Inf; those channels are read as 0 (black)";
}

}  // namespace

void TexturePool::resolve() const {
  if (pending_.empty()) return;
  // Offsets first (sizes are known from the headers), then every texture
  // decodes into its own part of the pool on its own thread.
  TexelWords& words = own_words();
  size_t at = words.size();
  for (const auto& p : pending_) {
    PmcTexture& t = textures_[size_t(p->index)];
    t.offset = static_cast<pmc_u32>(at);
    at += mip_chain_texels(t.width, t.height);
  }
  words.resize(at);  // not zero-filled: each decode writes all of its chain
  // A texture decoded by an earlier run is read back from the texture cache
  // (core/texture_cache.h) instead; one decoded now is stored there, unless
  // its decode warned (the warning would not repeat on a cache hit).
  TextureCache& cache = TextureCache::instance();
  const uint64_t writes_before = cache.stats().writes;
  parallel_for_each_index(pending_.size(), [&](size_t i) {
    Pending& p = *pending_[i];
    const PmcTexture& t = textures_[size_t(p.index)];
    uint8_t* base = reinterpret_cast<uint8_t*>(words.data() + t.offset);
    const size_t bytes = mip_chain_texels(t.width, t.height) * 4;
    try {
      const std::string key = cache.key(p.path, p.in->header(), p.srgb);
      if (!key.empty() && cache.read(key, base, bytes)) {
        p.in->close();
        return;
      }
      p.warning = decode_rgba8(*p.in, p.path, p.used_by, p.srgb, base);
      p.in->close();
      build_mips(base, t.width, t.height, p.srgb);
      if (!key.empty() && p.warning.empty()) cache.write(key, base, bytes);
    } catch (const Error& e) {
      p.error = e.what();
      std::memset(base, 0, mip_chain_texels(t.width, t.height) * 4);  // no uninitialised texels remain
    }
  });
  if (cache.stats().writes != writes_before) cache.trim();
  std::vector<std::unique_ptr<Pending>> done;
  done.swap(pending_);
  for (const auto& p : done) {
    if (!p->error.empty()) fail(p->error);
    if (!p->warning.empty()) warn(p->warning);
  }
}

TexelWords& TexturePool::own_words() const {
  if (!words_)
    words_ = std::make_shared<TexelWords>();  // moved from
  else if (words_.use_count() > 1)
    words_ = std::make_shared<TexelWords>(*words_);
  return *words_;
}

}  // namespace pmc
