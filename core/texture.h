// texture.h — images for the kernels: one RGBA8 texel pool with mip chains.
//
// Images are read through OpenImageIO (the image plugin, core/image_backend.h), converted to 8-bit RGBA
// (sRGB-encoded for colour textures, linear for data), and stored with a full box-filtered mip chain in one
// texel pool that is uploaded as a single buffer. A texture is loaded once however many materials use it;
// only used textures are loaded. load() opens the file and checks its header at once (a missing or unreadable
// file is an error naming who uses it) and hands out the texture's index; the pixels are decoded later, all
// pending textures in parallel, when the pool is first read (textures(), texels()) or by resolve(). 8-bit RGB
// and RGBA files are read straight into the pool (strided reads), others
// through a conversion buffer.
//
// The pool is kept as 32-bit words whose bytes in memory are R, G, B, A
// (TexelWords, allocated without zero-filling: every texel is written by its
// decode), held by a shared pointer: words() hands it to the material set
// without a copy, and a pool whose words are shared copies them before it
// changes them (add() or a decode after words()), so what was handed out
// never changes.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "core/abi/pmc_types.h"
#include "core/pool_memory.h"

namespace pmc {

using TexelWords = PoolVector<uint32_t>;

// The pool's bytes (RGBA8, 4 per texel), valid while the pool is unchanged.
class TexelBytes {
 public:
  TexelBytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  const uint8_t* data() const { return data_; }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const uint8_t& operator[](size_t i) const { return data_[i]; }
  const uint8_t* begin() const { return data_; }
  const uint8_t* end() const { return data_ + size_; }

 private:
  const uint8_t* data_;
  size_t size_;
};

class TexturePool {
 public:
  TexturePool();
  ~TexturePool();
  TexturePool(TexturePool&&) noexcept;
  TexturePool& operator=(TexturePool&&) noexcept;
  // A copy decodes what is pending first, then copies the pool.
  TexturePool(const TexturePool& other);
  TexturePool& operator=(const TexturePool& other);

  // Opens `path` (once) and returns its index. Throws pmc::Error naming
  // `path` and `used_by` when the file is missing or not an image.
  int load(const std::string& path, bool srgb, const std::string& used_by);
  // Adds an image from memory (RGBA8 rows, top row first).
  int add(const std::string& name, int width, int height, std::vector<uint8_t> rgba, bool srgb);
  // Decodes every pending texture (in parallel). Throws pmc::Error naming
  // the file and its user when one cannot be decoded.
  void resolve() const;

  const std::vector<PmcTexture>& textures() const {
    resolve();
    return textures_;
  }
  TexelBytes texels() const {  // RGBA8
    resolve();
    if (!words_) return TexelBytes(nullptr, 0);  // moved from
    return TexelBytes(reinterpret_cast<const uint8_t*>(words_->data()), words_->size() * 4);
  }
  // The decoded pool as words, shared (no copy); it never changes afterwards.
  std::shared_ptr<const TexelWords> words() const {
    resolve();
    return words_ ? words_ : std::make_shared<TexelWords>();
  }
  const std::vector<std::string>& names() const { return names_; }
  size_t size() const { return textures_.size(); }

 private:
  struct Pending;
  mutable std::vector<PmcTexture> textures_;
  std::vector<std::string> names_;
  TexelWords& own_words() const;  // words_, copied first if shared
  mutable std::shared_ptr<TexelWords> words_ = std::make_shared<TexelWords>();
  std::map<std::string, int> by_key_;
  mutable std::vector<std::unique_ptr<Pending>> pending_;
};

// The sRGB-to-linear table the kernels decode texels with (256 entries).
std::vector<float> srgb_decode_table();

// Linear value -> sRGB-encoded byte, exactly as rounding the sRGB encoding
// of `linear` to 8 bits (by table, without a pow per call).
uint8_t encode_srgb_byte(float linear);

}  // namespace pmc
