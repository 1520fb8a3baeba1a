// texture.h — images for the kernels: one RGBA8 texel pool with mip chains.
//
// Images are read through OpenImageIO, converted to 8-bit RGBA (sRGB-encoded
// for colour textures, linear for data), and appended with a full box-filtered
// mip chain to one texel pool that is uploaded as a single buffer. A texture is
// loaded once however many materials use it; only used textures are loaded.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/abi/pmc_types.h"

namespace pmc {

class TexturePool {
 public:
  // Loads `path` (once) and returns its index. Throws pmc::Error naming
  // `path` and `used_by` when the file is missing or not an image.
  int load(const std::string& path, bool srgb, const std::string& used_by);
  // Adds an image from memory (RGBA8 rows, top row first).
  int add(const std::string& name, int width, int height, std::vector<uint8_t> rgba, bool srgb);

  const std::vector<PmcTexture>& textures() const { return textures_; }
  const std::vector<uint8_t>& texels() const { return texels_; }  // RGBA8
  const std::vector<std::string>& names() const { return names_; }
  size_t size() const { return textures_.size(); }

 private:
  std::vector<PmcTexture> textures_;
  std::vector<std::string> names_;
  std::vector<uint8_t> texels_;
  std::map<std::string, int> by_key_;
};

// The sRGB-to-linear table the kernels decode texels with (256 entries).
std::vector<float> srgb_decode_table();

}  // namespace pmc
