// mtlx_include.cpp — root-level <xi:include> expansion (mtlx_include.h).
#include "materials/mtlx_include.h"

#include <cstdint>
#include <filesystem>
#include <set>

#include "core/error.h"
#include "materials/mtlx_upgrade.h"

namespace pmc {
namespace {

namespace fs = std::filesystem;

// Nested includes deeper than this are certainly a mistake (each file is
// included once anyway, so this only bounds the recursion).
constexpr int kMaxIncludeDepth = 64;
// Real documents are kilobytes; a huge file named by mistake is not read.
constexpr uintmax_t kMaxIncludeBytes = uintmax_t(64) << 20;

std::string folder_of(const std::string& path) {
  size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// The including folder, then the search paths; "" if no regular file matches.
std::string find_include(const std::string& href, const std::string& from_dir,
                         const std::vector<std::string>& search) {
  std::error_code ec;
  if (!href.empty() && href[0] == '/') return fs::is_regular_file(href, ec) ? href : std::string();
  if (fs::is_regular_file(from_dir + href, ec)) return from_dir + href;
  for (const std::string& sp : search) {
    if (sp.empty()) continue;
    std::string candidate = sp + (sp.back() == '/' ? "" : "/") + href;
    if (fs::is_regular_file(candidate, ec)) return candidate;
  }
  return {};
}

std::string canonical_or_self(const std::string& path) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(path, ec);
  return ec ? path : c.string();
}

class IncludeExpander {
 public:
  explicit IncludeExpander(const std::vector<std::string>& search) : search_(search) {}

  void expand(pugi::xml_node root, const std::string& path, const std::string& chain, int depth) {
    seen_.insert(canonical_or_self(path));
    std::vector<pugi::xml_node> includes;
    for (pugi::xml_node c : root.children("xi:include")) includes.push_back(c);
    for (pugi::xml_node inc : includes) {
      merge(root, inc, path, chain, depth);
      root.remove_child(inc);
    }
  }

 private:
  void merge(pugi::xml_node root, pugi::xml_node inc, const std::string& path, const std::string& chain,
             int depth) {
    const std::string href = inc.attribute("href").as_string();
    const std::string where = chain + ": xi:include href '" + href + "'";
    if (href.empty()) fail(where, ": names no file");
    if (depth >= kMaxIncludeDepth) fail(where, ": includes nest deeper than ", kMaxIncludeDepth, " files");
    const std::string file = find_include(href, folder_of(path), search_);
    if (file.empty())
      fail(where, ": no such file in '", folder_of(path).empty() ? "." : folder_of(path),
           "' or the MaterialX search paths");
    if (seen_.count(canonical_or_self(file))) return;  // included already (or a cycle)
    std::error_code ec;
    const uintmax_t bytes = fs::file_size(file, ec);
    if (!ec && bytes > kMaxIncludeBytes)
      fail(where, ": ", file, " is larger than ", kMaxIncludeBytes >> 20, " MiB: not a MaterialX document");

    pugi::xml_document doc;
    pugi::xml_parse_result r = doc.load_file(file.c_str());
    if (r.status == pugi::status_file_not_found || r.status == pugi::status_io_error)
      fail(where, ": cannot read ", file);
    if (!r) fail(where, ": ", file, " is not valid XML at byte ", r.offset, ": ", r.description());
    pugi::xml_node sub = doc.child("materialx");
    if (!sub) fail(where, ": ", file, " is not a MaterialX document (no <materialx> root element)");
    upgrade_mtlx_document(sub, file);
    expand(sub, file, chain + " -> " + file, depth + 1);

    const std::string dir = folder_of(file);
    for (pugi::xml_node c = sub.first_child(); c; c = c.next_sibling()) {
      if (c.type() != pugi::node_element) continue;
      pugi::xml_node copy = root.insert_copy_before(c, inc);
      for (const char* a : {"colorspace", "fileprefix", "namespace"})
        if (sub.attribute(a) && !copy.attribute(a)) copy.append_attribute(a) = sub.attribute(a).value();
      if (!copy.attribute(kIncludeDirAttr)) copy.append_attribute(kIncludeDirAttr) = dir.c_str();
    }
  }

  const std::vector<std::string>& search_;
  std::set<std::string> seen_;
};

}  // namespace

void expand_mtlx_includes(pugi::xml_node root, const std::string& path,
                          const std::vector<std::string>& search) {
  IncludeExpander(search).expand(root, path, path, 0);
}

}  // namespace pmc
