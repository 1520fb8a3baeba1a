// output_guard.h — "no half-written output": files a command promised are
// removed again if the command fails before it completes; and output paths
// are checked before any work starts, so a typo in a folder name fails in a
// second, not after a long render.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"

namespace pmc {

// Whether `path` ends in `extension` (".exr"), in any case.
inline bool has_extension(const std::string& path, const std::string& extension) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == extension;
}

// Fails (pmc::Error naming `option`) unless `path` can be created: its folder
// exists and is writable, the path is not a folder, and when
// `extension` is given (".exr"), the path ends with it (any case).
inline void check_output_path(const std::string& option, const std::string& path,
                              const std::string& extension = "") {
  if (path.empty()) fail(option, ": empty path");
  namespace fs = std::filesystem;
  const fs::path p(path);
  if (!extension.empty() && !has_extension(path, extension))
    fail(option, ": '", path, "' must end in ", extension);
  std::error_code ec;
  if (fs::is_directory(p, ec)) fail(option, ": '", path, "' is a folder");
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec)) fail(option, ": folder '", dir.string(), "' does not exist");
  if (access(dir.c_str(), W_OK) != 0) fail(option, ": folder '", dir.string(), "' is not writable");
}

// --out-dir: checked when constructed, before any work starts (an existing
// writable folder, or one that can be made under the nearest existing,
// writable folder), created only once the inputs are valid by create(), and
// unless committed the folders create() made are removed again (when empty:
// the files in them are an OutputGuard's).
class OutDir {
 public:
  explicit OutDir(std::string dir) : dir_(std::move(dir)) {
    namespace fs = std::filesystem;
    if (dir_.empty()) fail("--out-dir: empty path");
    fs::path path = fs::path(dir_).lexically_normal();
    if (path.filename().empty() && path.has_parent_path()) path = path.parent_path();
    std::error_code ec;
    fs::path existing = path;
    while (!existing.empty() && !fs::exists(existing, ec)) {
      missing_.push_back(existing);
      existing = existing.parent_path();
    }
    if (existing.empty()) existing = ".";
    if (!fs::is_directory(existing, ec)) {
      if (missing_.empty()) fail("--out-dir: '", dir_, "' is not a folder");
      fail("--out-dir: cannot create '", dir_, "': '", existing.string(), "' is not a folder");
    }
    if (access(existing.c_str(), W_OK) != 0)
      fail("--out-dir: folder '", existing.string(), "' is not writable");
  }
  OutDir(const OutDir&) = delete;
  OutDir& operator=(const OutDir&) = delete;
  void create() {
    std::error_code ec;
    if (!missing_.empty()) std::filesystem::create_directories(missing_.front(), ec);
    created_ = missing_;
    if (ec) fail("--out-dir: cannot create '", dir_, "': ", ec.message());
  }
  void commit() { created_.clear(); }
  ~OutDir() {
    std::error_code ec;
    for (const std::filesystem::path& q : created_) std::filesystem::remove(q, ec);
  }

 private:
  std::string dir_;
  std::vector<std::filesystem::path> missing_, created_;  // deepest first
};

// Fails if two outputs of one command would land on the same file.
inline void check_distinct_outputs(const std::vector<std::pair<std::string, std::string>>& outputs) {
  namespace fs = std::filesystem;
  for (size_t i = 0; i < outputs.size(); ++i)
    for (size_t j = i + 1; j < outputs.size(); ++j)
      if (fs::absolute(outputs[i].second).lexically_normal() ==
          fs::absolute(outputs[j].second).lexically_normal())
        fail(outputs[i].first, " and ", outputs[j].first, " would both write '", outputs[i].second, "'");
}

class OutputGuard {
 public:
  void track(const std::string& path) { paths_.push_back(path); }
  void commit() { paths_.clear(); }
  ~OutputGuard() {  // files only: a folder of that name is the user's, never ours
    std::error_code ec;
    for (const std::string& p : paths_)
      if (std::filesystem::is_regular_file(p, ec)) std::remove(p.c_str());
  }

 private:
  std::vector<std::string> paths_;
};

}  // namespace pmc
