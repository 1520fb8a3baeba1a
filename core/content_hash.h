// content_hash.h — a fast 64-bit hash of bytes, for telling frames apart.
//
// Render parts record a hash of their scene and of their settings
// (core/render_part.h) so `pmc merge` can refuse parts of different frames.
// This is an identity check, not security: a multiply-rotate mix over 8-byte
// words (in the style of MurmurHash's 64-bit mix), written here because the
// project needs no more than that and it runs at memory speed over texel
// pools; the value is stable across runs, machines and builds.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace pmc {

class ContentHash {
 public:
  void bytes(const void* data, size_t n) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
      uint64_t w;
      std::memcpy(&w, p + i, 8);
      word(w);
    }
    uint64_t tail = 0;
    if (n > i) std::memcpy(&tail, p + i, n - i);  // an empty vector's data() may be null
    word(tail ^ (uint64_t(n) << 56));
  }
  template <class T, class A>
  void vec(const std::vector<T, A>& v) {
    word(v.size());
    bytes(v.data(), v.size() * sizeof(T));
  }
  void str(const std::string& s) { bytes(s.data(), s.size()); }
  void word(uint64_t w) {
    w *= 0x87c37b91114253d5ull;
    w = (w << 31) | (w >> 33);
    w *= 0x4cf5ad432745937full;
    h_ ^= w;
    h_ = ((h_ << 27) | (h_ >> 37)) * 5 + 0x52dce729;
  }
  // 16 hex digits.
  std::string hex() const {
    uint64_t h = h_;  // final avalanche (fmix64)
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    static const char* digits = "0123456789abcdef";
    std::string s(16, '0');
    for (int i = 15; i >= 0; --i, h >>= 4) s[size_t(i)] = digits[h & 15];
    return s;
  }

 private:
  uint64_t h_ = 0x9e3779b97f4a7c15ull;
};

}  // namespace pmc
