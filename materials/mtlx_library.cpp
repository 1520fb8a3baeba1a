// mtlx_library.cpp — finding and indexing MaterialX's data libraries.
#include "materials/mtlx_library.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "core/error.h"

namespace pmc {
namespace fs = std::filesystem;

namespace {

bool looks_like_library(const std::string& dir) {
  std::error_code ec;
  return fs::is_regular_file(fs::path(dir) / "stdlib" / "stdlib_defs.mtlx", ec);
}

}  // namespace

std::string find_mtlx_library(const std::string& explicit_dir) {
  if (!explicit_dir.empty()) {
    if (!looks_like_library(explicit_dir))
      fail_config(setting("mtlx_library"), " ", explicit_dir,
                  ": not a MaterialX data library folder (expected stdlib/stdlib_defs.mtlx inside it)");
    return explicit_dir;
  }
  if (const char* env = std::getenv("PMC_MTLX_LIBRARY")) {
    if (*env) {
      if (!looks_like_library(env))
        fail("PMC_MTLX_LIBRARY=", env,
             ": not a MaterialX data library folder (expected stdlib/stdlib_defs.mtlx inside it)");
      return env;
    }
  }
#ifdef PMC_DEFAULT_MTLX_LIBRARY
  if (looks_like_library(PMC_DEFAULT_MTLX_LIBRARY)) return PMC_DEFAULT_MTLX_LIBRARY;
#endif
  return "";
}

void MtlxDefinitions::add(pugi::xml_node root) {
  for (pugi::xml_node nd : root.children("nodedef")) {
    std::string name = nd.attribute("name").as_string();
    if (name.empty() || by_name_.count(name)) continue;  // the first definition of a name wins
    by_name_[name] = nd;
    by_category_[nd.attribute("node").as_string()].push_back(nd);
  }
  for (pugi::xml_node ng : root.children("nodegraph")) {
    std::string nd = ng.attribute("nodedef").as_string();
    if (!nd.empty() && !implementations_.count(nd)) implementations_[nd] = ng;
  }
}

pugi::xml_node MtlxDefinitions::nodedef(const std::string& name) const {
  auto it = by_name_.find(name);
  return it == by_name_.end() ? pugi::xml_node() : it->second;
}

const std::vector<pugi::xml_node>& MtlxDefinitions::nodedefs_for(const std::string& category) const {
  static const std::vector<pugi::xml_node> none;
  auto it = by_category_.find(category);
  return it == by_category_.end() ? none : it->second;
}

pugi::xml_node MtlxDefinitions::implementation(const std::string& nodedef_name) const {
  auto it = implementations_.find(nodedef_name);
  return it == implementations_.end() ? pugi::xml_node() : it->second;
}

const MtlxLibrary& MtlxLibrary::load(const std::string& dir) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<MtlxLibrary>> loaded;
  std::lock_guard<std::mutex> lock(mutex);
  auto it = loaded.find(dir);
  if (it != loaded.end()) return *it->second;
  auto lib = std::make_unique<MtlxLibrary>();
  lib->dir_ = dir;
  std::vector<fs::path> files;
  // bxdf/translation holds the shader-translation nodes
  // (standard_surface_to_open_pbr_surface ...): data nodes with many outputs;
  // bxdf/lama holds closure nodes built from pbrlib closures (LamaConductor ...).
  for (const char* sub : {"stdlib", "pbrlib", "bxdf", "bxdf/translation", "bxdf/lama", "nprlib", "cmlib"}) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::path(dir) / sub, ec))
      if (e.is_regular_file() && e.path().extension() == ".mtlx") files.push_back(e.path());
  }
  // Definitions before implementations does not matter (indexes are by name),
  // but a fixed order keeps "first definition wins" deterministic.
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    auto doc = std::make_unique<pugi::xml_document>();
    pugi::xml_parse_result r = doc->load_file(f.c_str());
    if (!r) fail(f.string(), ": MaterialX library file is not valid XML: ", r.description());
    lib->defs_.add(doc->child("materialx"));
    lib->docs_.push_back(std::move(doc));
  }
  if (lib->defs_.empty()) fail(dir, ": no MaterialX node definitions found in this library folder");
  return *(loaded[dir] = std::move(lib));
}

}  // namespace pmc
