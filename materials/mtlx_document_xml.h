// mtlx_document_xml.h — the pugixml document behind an MtlxDocument, for the
// reader's own files (mtlx_reader.cpp loads it; the surface mapper and the
// looks read it).
#pragma once

#include <pugixml.hpp>

#include "materials/mtlx_reader.h"

namespace pmc {

struct MtlxDocument::Xml {
  pugi::xml_document doc;
  pugi::xml_node root;  // <materialx>
};

}  // namespace pmc
