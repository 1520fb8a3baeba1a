// mtlx_library.h — MaterialX's own data libraries: node definitions and the
// nodegraphs that implement them.
//
// pmc compiles the nodes of its node table (node_table.h) natively. Every
// other standard node is expanded, the way MaterialX's shader generators do,
// from the nodegraph the library gives as its implementation
// (stdlib_ng.mtlx: NG_separate3_color3, NG_switch_float ...). The library
// is never copied into pmc: it is the `libraries` folder of a MaterialX
// installation (the PyPI `materialx` package ships one, which scripts/setup
// installs into .venv). Which folder: mtlx_library DIR, else the
// PMC_MTLX_LIBRARY environment variable, else the folder CMake found at
// configure time (PMC_DEFAULT_MTLX_LIBRARY), else none: documents that only
// use table nodes still load, and one that needs the library gets an error
// that says how to point pmc at it.
//
// Loaded once per folder and process: every top-level .mtlx file of its
// stdlib, pbrlib, bxdf, bxdf/translation, nprlib and cmlib folders (a few ms
// with pugixml).
#pragma once

#include <map>
#include <memory>
#include <pugixml.hpp>
#include <string>
#include <vector>

namespace pmc {

// The library folder to use: `explicit_dir` if not empty, else
// $PMC_MTLX_LIBRARY, else the configure-time default; "" when none is set or
// found. An explicit or environment folder that is not a MaterialX library
// throws pmc::Error naming it.
std::string find_mtlx_library(const std::string& explicit_dir);

// Node definitions and implementation graphs from one or more documents
// (the library's, and a document's own custom nodes).
class MtlxDefinitions {
 public:
  // Indexes the <nodedef> and <nodegraph nodedef=...> children of `root`.
  void add(pugi::xml_node root);
  pugi::xml_node nodedef(const std::string& name) const;
  const std::vector<pugi::xml_node>& nodedefs_for(const std::string& category) const;
  pugi::xml_node implementation(const std::string& nodedef_name) const;  // its nodegraph, or null
  bool empty() const { return by_name_.empty(); }

 private:
  std::map<std::string, pugi::xml_node> by_name_;
  std::map<std::string, std::vector<pugi::xml_node>> by_category_;
  std::map<std::string, pugi::xml_node> implementations_;
};

class MtlxLibrary {
 public:
  // The library in `dir`, loaded on first use and kept for the process.
  // Throws pmc::Error naming a file that is not valid XML.
  static const MtlxLibrary& load(const std::string& dir);
  const MtlxDefinitions& definitions() const { return defs_; }
  const std::string& dir() const { return dir_; }
  size_t files() const { return docs_.size(); }

 private:
  std::string dir_;
  std::vector<std::unique_ptr<pugi::xml_document>> docs_;
  MtlxDefinitions defs_;
};

}  // namespace pmc
