// mtlx_looks.cpp — a document's <look>s: which material goes on which
// geometry (read_mtlx_assignments), and MaterialX geometry-name matching.
#include <string>
#include <vector>

#include "core/error.h"
#include "materials/mtlx_document_xml.h"
#include "materials/mtlx_reader.h"

namespace pmc {
namespace {

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= s.size()) {
    size_t end = s.find(',', start);
    if (end == std::string::npos) end = s.size();
    std::string item = s.substr(start, end - start);
    size_t a = item.find_first_not_of(" \t"), b = item.find_last_not_of(" \t");
    if (a != std::string::npos) out.push_back(item.substr(a, b - a + 1));
    start = end + 1;
  }
  return out;
}

std::vector<std::string> path_components(const std::string& path) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start < path.size()) {
    size_t end = path.find('/', start);
    if (end == std::string::npos) end = path.size();
    if (end > start) out.push_back(path.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

bool glob(const char* p, const char* s) {
  if (*p == '\0') return *s == '\0';
  if (*p == '*') return glob(p + 1, s) || (*s != '\0' && glob(p, s + 1));
  if (*s == '\0') return false;
  return (*p == '?' || *p == *s) && glob(p + 1, s + 1);
}

}  // namespace

bool mtlx_geom_matches(const std::string& pattern, const std::string& path) {
  std::vector<std::string> p = path_components(pattern), g = path_components(path);
  if (p.size() > g.size()) return false;  // "/" (no components) matches everything
  for (size_t i = 0; i < p.size(); ++i)
    if (!glob(p[i].c_str(), g[i].c_str())) return false;
  return true;
}

std::vector<MtlxAssignment> read_mtlx_assignments(const MtlxDocument& doc) {
  const pugi::xml_node root = doc.xml().root;
  const std::string& path = doc.path();
  std::vector<MtlxAssignment> out;
  for (pugi::xml_node look : root.children("look"))
    for (pugi::xml_node a : look.children("materialassign")) {
      MtlxAssignment m;
      m.material = a.attribute("material").as_string();
      m.geom = a.attribute("geom").as_string();
      m.origin = path + ": look '" + look.attribute("name").as_string() + "' materialassign '" +
                 a.attribute("name").as_string() + "'";
      std::string collection = a.attribute("collection").as_string();
      if (!collection.empty()) {
        pugi::xml_node c = root.find_child_by_attribute("collection", "name", collection.c_str());
        if (!c) fail(m.origin, ": collection '", collection, "' does not exist (dangling reference)");
        m.geom += (m.geom.empty() ? "" : ",") + std::string(c.attribute("includegeom").as_string());
        m.exclude = c.attribute("excludegeom").as_string();
      }
      if (m.material.empty()) fail(m.origin, ": names no material");
      out.push_back(m);
    }
  return out;
}

bool mtlx_assignment_covers(const MtlxAssignment& a, const std::string& geometry) {
  bool in = false;
  for (const std::string& p : split_list(a.geom)) in = in || mtlx_geom_matches(p, geometry);
  for (const std::string& p : split_list(a.exclude)) in = in && !mtlx_geom_matches(p, geometry);
  return in;
}

}  // namespace pmc
