// texture_cache.h — decoded textures kept on disk between runs.
//
// Decoding a scene's PNG and JPEG textures and building their mip chains is
// the longest step of a textured scene's setup (Sponza: 38 MB of PNG become
// 110 MB of RGBA8 mips). Renderers that are run again and again on the same
// scene keep the decoded form (Arnold's and RenderMan's .tx/.tex files); pmc
// does it without a conversion step: the first decode of a texture writes
// its whole mip chain, exactly as the pool holds it, to a cache folder, and
// later runs read it back instead of decoding.
//
// An entry is named by a hash of what determines its texels: the source
// file's bytes (so an edited texture is never served stale, whatever its
// time stamps), its size and header, the colour space it is read in, and
// kTextureCacheVersion, which must change whenever decoding or mip building
// changes what a texel holds. The entry repeats that key and ends with a
// checksum of its texels; a short, damaged or mismatched entry is ignored and
// the texture decodes as without a cache. Entries are written under a
// temporary name and renamed into place, so concurrent runs (a farm's parts,
// ctest -j) share the folder safely. The folder is kept under a size limit:
// after a write, the least recently used entries are removed.
//
// Where: the texture_cache setting (DIR or off), else $PMC_TEXTURE_CACHE (DIR or "off"),
// else $XDG_CACHE_HOME/pmc/textures, else ~/.cache/pmc/textures. A folder
// that cannot be written costs one warning and the render goes on.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>

namespace pmc {

struct ImageHeader;

// Bump when decode_rgba8 or build_mips change the texels they produce.
constexpr uint32_t kTextureCacheVersion = 1;
constexpr uint64_t kDefaultTextureCacheBytes = uint64_t(4) << 30;  // 4 GiB

struct TextureCacheStats {
  uint64_t hits = 0, misses = 0, writes = 0;
};

class TextureCache {
 public:
  // The process's cache, configured from the environment until configure() is called.
  static TextureCache& instance();

  // `where`: a folder, "off", or "" for the default location.
  void configure(const std::string& where, uint64_t max_bytes = kDefaultTextureCacheBytes);
  bool enabled() const;
  std::string folder() const;

  // The entry name of a texture file read with `header` in the given colour
  // space, or "" when the cache is off or the file cannot be read.
  std::string key(const std::string& path, const ImageHeader& header, bool srgb) const;
  // Fills `bytes` bytes at `dst` from the entry `key`; false (dst
  // unspecified) when there is no valid entry.
  bool read(const std::string& key, void* dst, size_t bytes);
  // Stores `bytes` bytes as entry `key` (best effort: a failure warns once).
  void write(const std::string& key, const void* src, size_t bytes);

  // Removes the least recently used entries while the folder holds more
  // than its limit (TexturePool calls it after a batch that wrote entries).
  void trim();

  TextureCacheStats stats() const;

 private:
  TextureCache();

  mutable std::mutex mutex_;  // guards folder_, max_bytes_, warned_
  std::string folder_;        // "" when off
  uint64_t max_bytes_ = kDefaultTextureCacheBytes;
  bool warned_ = false;
  std::atomic<uint64_t> hits_{0}, misses_{0}, writes_{0};
};

}  // namespace pmc
