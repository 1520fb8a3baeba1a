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

namespace pmc {

// Memory for large pools: blocks of 2 MiB and more are 2 MiB-aligned and
// marked for transparent huge pages (madvise), so filling a texture pool of
// a hundred megabytes takes a few hundred page faults instead of tens of
// thousands (on Linux with THP in "madvise" or "always" mode; elsewhere
// plain aligned memory). Freed with std::free.
void* allocate_pool_bytes(size_t bytes);

// An allocator that leaves value-initialised elements uninitialised (resize
// without a memset) and takes its memory from allocate_pool_bytes.
template <typename T>
struct NoInitAllocator {
  using value_type = T;
  template <typename U>
  struct rebind {
    using other = NoInitAllocator<U>;
  };
  NoInitAllocator() = default;
  template <typename U>
  NoInitAllocator(const NoInitAllocator<U>&) noexcept {}
  T* allocate(size_t n) {
    if (n > size_t(-1) / sizeof(T)) throw std::bad_alloc();
    return static_cast<T*>(allocate_pool_bytes(n * sizeof(T)));
  }
  void deallocate(T* p, size_t) noexcept { std::free(p); }
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <typename U>
  bool operator==(const NoInitAllocator<U>&) const noexcept {
    return true;
  }
  template <typename U>
  bool operator!=(const NoInitAllocator<U>&) const noexcept {
    return false;
  }
};
using TexelWords = std::vector<uint32_t, NoInitAllocator<uint32_t>>;

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
