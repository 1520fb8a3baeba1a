// texture.h — images for the kernels: one RGBA8 texel pool with mip chains.
//
// Images are read through OpenImageIO, converted to 8-bit RGBA (sRGB-encoded
// for colour textures, linear for data), and stored with a full box-filtered
// mip chain in one texel pool that is uploaded as a single buffer. A texture
// is loaded once however many materials use it; only used textures are
// loaded. load() opens the file and checks its header at once (a missing or
// unreadable file is an error naming who uses it) and hands out the texture's
// index; the pixels are decoded later, all pending textures in parallel, when
// the pool is first read (textures(), texels()) or by resolve().
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/abi/pmc_types.h"

namespace pmc {

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
  const std::vector<uint8_t>& texels() const {  // RGBA8
    resolve();
    return texels_;
  }
  const std::vector<std::string>& names() const { return names_; }
  size_t size() const { return textures_.size(); }

 private:
  struct Pending;
  mutable std::vector<PmcTexture> textures_;
  std::vector<std::string> names_;
  mutable std::vector<uint8_t> texels_;
  std::map<std::string, int> by_key_;
  mutable std::vector<std::unique_ptr<Pending>> pending_;
};

// The sRGB-to-linear table the kernels decode texels with (256 entries).
std::vector<float> srgb_decode_table();

// Linear value -> sRGB-encoded byte, exactly as rounding the sRGB encoding
// of `linear` to 8 bits (by table, without a pow per call).
uint8_t encode_srgb_byte(float linear);

}  // namespace pmc
