// mtlx_reader.cpp — a MaterialX document loaded once (MtlxDocument: parsed,
// upgraded, its includes expanded) and the entry points that read its
// materials. The materials themselves are read by the surface mapper
// (mtlx_surface_mapper.cpp) over the instantiator (mtlx_instantiator.h);
// looks by mtlx_looks.cpp.
#include "materials/mtlx_reader.h"

#include <cstdlib>
#include <pugixml.hpp>

#include "core/error.h"
#include "materials/mtlx_document_xml.h"
#include "materials/mtlx_include.h"
#include "materials/mtlx_upgrade.h"

namespace pmc {

// MATERIALX_SEARCH_PATH's folders (':' or ';' separated), then the options'.
std::vector<std::string> mtlx_search_paths(const MtlxReadOptions& options) {
  std::vector<std::string> search;
  if (const char* env = std::getenv("MATERIALX_SEARCH_PATH")) {
    std::string s = env;
    size_t start = 0;
    while (start <= s.size()) {
      size_t end = s.find_first_of(":;", start);
      if (end == std::string::npos) end = s.size();
      if (end > start) search.push_back(s.substr(start, end - start));
      start = end + 1;
    }
  }
  search.insert(search.end(), options.search_paths.begin(), options.search_paths.end());
  return search;
}

MtlxDocument::MtlxDocument(const std::string& path, const MtlxReadOptions& options,
                           std::shared_ptr<Xml> parsed)
    : path_(path), options_(options), xml_(std::move(parsed)) {
  xml_->root = xml_->doc.child("materialx");
  if (!xml_->root) fail(path, ": not a MaterialX document (no <materialx> root element)");
  upgrade_mtlx_document(xml_->root, path);
  expand_mtlx_includes(xml_->root, path, mtlx_search_paths(options));
}

MtlxDocument MtlxDocument::from_file(const std::string& path, const MtlxReadOptions& options) {
  auto xml = std::make_shared<Xml>();
  pugi::xml_parse_result r = xml->doc.load_file(path.c_str());
  if (r.status == pugi::status_file_not_found || r.status == pugi::status_io_error)
    fail(path, ": cannot read MaterialX file");
  if (!r) fail(path, ": not valid XML at byte ", r.offset, ": ", r.description());
  return MtlxDocument(path, options, xml);
}

MtlxDocument MtlxDocument::from_string(const std::string& xml_text, const std::string& path,
                                       const MtlxReadOptions& options) {
  auto xml = std::make_shared<Xml>();
  pugi::xml_parse_result r = xml->doc.load_buffer(xml_text.data(), xml_text.size());
  if (!r) fail(path, ": not valid XML at byte ", r.offset, ": ", r.description());
  return MtlxDocument(path, options, xml);
}

std::vector<Graph> read_mtlx_string(const std::string& xml, const std::string& path,
                                    const MtlxReadOptions& options) {
  return read_mtlx_graphs(MtlxDocument::from_string(xml, path, options));
}

std::vector<Graph> read_mtlx_file(const std::string& path, const MtlxReadOptions& options) {
  return read_mtlx_graphs(MtlxDocument::from_file(path, options));
}

}  // namespace pmc
