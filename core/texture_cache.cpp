// texture_cache.cpp — decoded textures kept on disk between runs.
#include "core/texture_cache.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <sstream>
#include <system_error>
#include <thread>
#include <vector>

#include "core/content_hash.h"
#include "core/error.h"
#include "core/image_backend.h"

namespace pmc {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'P', 'M', 'C', 'T', 'E', 'X', 'C', '1'};
constexpr size_t kKeyChars = 32;
constexpr const char* kSuffix = ".pmctex";

// The fixed part at the start of an entry; its texels follow, then the
// 16 hex digits of their checksum.
struct EntryHeader {
  char magic[8];
  uint32_t version;
  uint32_t reserved;
  char key[kKeyChars];
  uint64_t bytes;
};
static_assert(sizeof(EntryHeader) == 56, "entry header layout");

std::string default_folder() {
  if (const char* env = std::getenv("PMC_TEXTURE_CACHE"); env && *env) return env;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/pmc/textures";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::string(home) + "/.cache/pmc/textures";
  return "off";
}

bool read_all(int fd, void* dst, size_t bytes) {
  auto* p = static_cast<char*>(dst);
  while (bytes > 0) {
    ssize_t n = ::read(fd, p, std::min(bytes, size_t(1) << 30));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    bytes -= size_t(n);
  }
  return true;
}

bool write_all(int fd, const void* src, size_t bytes) {
  const auto* p = static_cast<const char*>(src);
  while (bytes > 0) {
    ssize_t n = ::write(fd, p, std::min(bytes, size_t(1) << 30));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    bytes -= size_t(n);
  }
  return true;
}

std::string checksum(const void* data, size_t bytes) {
  ContentHash h;
  h.bytes(data, bytes);
  return h.hex();
}

struct Fd {
  int fd = -1;
  explicit Fd(int f) : fd(f) {}
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
};

}  // namespace

TextureCache& TextureCache::instance() {
  static TextureCache cache;
  return cache;
}

TextureCache::TextureCache() { configure(""); }

void TextureCache::configure(const std::string& where, uint64_t max_bytes) {
  const std::string chosen = where.empty() ? default_folder() : where;
  std::lock_guard<std::mutex> lock(mutex_);
  folder_ = chosen == "off" ? "" : chosen;
  max_bytes_ = max_bytes;
  warned_ = false;
}

bool TextureCache::enabled() const { return !folder().empty(); }

std::string TextureCache::folder() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return folder_;
}

std::string TextureCache::key(const std::string& path, const ImageHeader& header, bool srgb) const {
  if (!enabled()) return "";
  // Regular files only: a FIFO or device named as a texture is not read
  // twice (non-blocking open: a FIFO without a writer would block).
  Fd f(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK));
  struct stat st {};
  if (f.fd < 0 || ::fstat(f.fd, &st) != 0 || !S_ISREG(st.st_mode)) return "";
  // Two 64-bit hashes of the file that start from different states: a
  // 128-bit name, so two different textures never share an entry.
  ContentHash a, b;
  b.word(0x5bd1e9955bd1e995ull);
  std::vector<char> chunk(size_t(1) << 20);
  uint64_t size = 0;
  for (;;) {
    ssize_t n = ::read(f.fd, chunk.data(), chunk.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return "";
    if (n == 0) break;
    a.bytes(chunk.data(), size_t(n));
    b.bytes(chunk.data(), size_t(n));
    size += uint64_t(n);
  }
  for (ContentHash* h : {&a, &b}) {
    h->word(size);
    h->word(uint64_t(header.width) << 32 | uint32_t(header.height));
    h->word(uint64_t(header.channels) << 32 | uint32_t(header.format));
    h->word(srgb ? 1 : 0);
    h->word(kTextureCacheVersion);
  }
  return a.hex() + b.hex();
}

bool TextureCache::read(const std::string& key, void* dst, size_t bytes) {
  const std::string dir = folder();
  if (dir.empty() || key.size() != kKeyChars) return false;
  const std::string path = dir + "/" + key + kSuffix;
  bool ok = false;
  {
    Fd f(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    EntryHeader h{};
    char sum[16];
    ok = f.fd >= 0 && read_all(f.fd, &h, sizeof(h)) && std::memcmp(h.magic, kMagic, sizeof(kMagic)) == 0 &&
         h.version == kTextureCacheVersion && std::memcmp(h.key, key.data(), kKeyChars) == 0 &&
         h.bytes == bytes && read_all(f.fd, dst, bytes) && read_all(f.fd, sum, sizeof(sum)) &&
         checksum(dst, bytes) == std::string(sum, sizeof(sum));
  }
  if (ok) ::utimensat(AT_FDCWD, path.c_str(), nullptr, 0);  // recently used: kept longest by trim()
  (ok ? hits_ : misses_) += 1;
  return ok;
}

void TextureCache::write(const std::string& key, const void* src, size_t bytes) {
  const std::string dir = folder();
  if (dir.empty() || key.size() != kKeyChars) return;
  const std::string path = dir + "/" + key + kSuffix;
  const std::string tmp = path + ".tmp." + std::to_string(::getpid()) + "." +
                          std::to_string(std::hash<std::thread::id>()(std::this_thread::get_id()));
  std::string why;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    why = ec.message();
  } else {
    EntryHeader h{};
    std::memcpy(h.magic, kMagic, sizeof(kMagic));
    h.version = kTextureCacheVersion;
    std::memcpy(h.key, key.data(), kKeyChars);
    h.bytes = bytes;
    const std::string sum = checksum(src, bytes);
    Fd f(::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
    bool ok = f.fd >= 0 && write_all(f.fd, &h, sizeof(h)) && write_all(f.fd, src, bytes) &&
              write_all(f.fd, sum.data(), sum.size());
    if (!ok) why = std::strerror(errno);
    if (f.fd >= 0 && ::close(f.fd) != 0 && ok) ok = false, why = std::strerror(errno);
    f.fd = -1;
    if (ok && std::rename(tmp.c_str(), path.c_str()) != 0) ok = false, why = std::strerror(errno);
    if (ok) {
      writes_ += 1;
      return;
    }
    std::remove(tmp.c_str());
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (warned_) return;
  warned_ = true;
  std::ostringstream os;
  os << "texture cache: cannot write to " << printable(dir) << " (" << why
     << "): decoded textures are not kept between runs (" << setting("texture_cache")
     << " DIR chooses another folder, " << setting("texture_cache") << " off turns the cache off)";
  warn(os.str());
}

void TextureCache::trim() {
  std::string dir;
  uint64_t limit;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    dir = folder_;
    limit = max_bytes_;
  }
  if (dir.empty()) return;
  struct Entry {
    fs::path path;
    fs::file_time_type time;
    uint64_t bytes;
  };
  std::vector<Entry> entries;
  uint64_t total = 0;
  std::error_code ec;
  const auto now = fs::file_time_type::clock::now();
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& p = it->path();
    if (p.extension() != kSuffix) {
      // A temporary left by a run that died while writing it.
      std::error_code e0;
      if (p.filename().string().find(std::string(kSuffix) + ".tmp.") != std::string::npos &&
          now - fs::last_write_time(p, e0) > std::chrono::hours(1) && !e0)
        fs::remove(p, e0);
      continue;
    }
    std::error_code e1, e2;
    Entry e{p, fs::last_write_time(p, e1), uint64_t(fs::file_size(p, e2))};
    if (e1 || e2) continue;
    total += e.bytes;
    entries.push_back(std::move(e));
  }
  if (total <= limit) return;
  std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) { return x.time < y.time; });
  const uint64_t target = limit - limit / 10;  // room for a few more before the next trim
  for (const Entry& e : entries) {
    if (total <= target) break;
    std::error_code e3;
    if (fs::remove(e.path, e3)) total -= e.bytes;
  }
}

TextureCacheStats TextureCache::stats() const {
  TextureCacheStats s;
  s.hits = hits_;
  s.misses = misses_;
  s.writes = writes_;
  return s;
}

}  // namespace pmc
