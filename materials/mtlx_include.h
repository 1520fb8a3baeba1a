// mtlx_include.h — XInclude in MaterialX documents.
//
// The MaterialX specification ("XInclude") lets a document pull in others
// with root-level <xi:include href="FILE"/>: each included file is a valid
// document of its own, and the children of its <materialx> root are added to
// the including root. MaterialX's example looks include the materials they
// assign this way, and custom-node libraries are shared by it.
//
// pmc expands them after the including document is upgraded (mtlx_upgrade.h)
// and upgrades each included file by its own version before merging, so
// content of different versions is never upgraded twice. Rules:
//  - FILE is found relative to the including file's folder, then in each
//    search path (MATERIALX_SEARCH_PATH, then mtlx_search_paths), and must
//    be a regular file;
//  - the included root's inherited attributes (colorspace, fileprefix,
//    namespace) go onto its children that do not set their own, and the
//    children record the included file's folder (attribute kIncludeDirAttr),
//    where the reader looks first for their relative filenames;
//  - included files may include others; each file is included once per
//    document, so repeated or circular includes add nothing more;
//  - a missing or unreadable file, or one that is not a MaterialX document,
//    is an error naming the include chain.
#pragma once

#include <pugixml.hpp>
#include <string>
#include <vector>

namespace pmc {

// The attribute that marks an element merged from an included file with
// that file's folder (ending in '/').
constexpr const char* kIncludeDirAttr = "pmc_includedir";

// Expands the root-level <xi:include> elements of `root` (the <materialx>
// element of the document at `path`) in place; `search` are the folders
// tried after the including file's own.
void expand_mtlx_includes(pugi::xml_node root, const std::string& path,
                          const std::vector<std::string>& search);

}  // namespace pmc
