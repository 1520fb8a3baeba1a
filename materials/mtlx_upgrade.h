// mtlx_upgrade.h — older MaterialX documents (1.36-1.38) brought to 1.39 on load.
//
// MaterialX's own loader upgrades a document when it reads it
// (Document::upgradeVersion); pmc does the part of it that changes what a
// material computes, on the parsed XML before reading:
//  - <parameter> elements become <input>s (1.38);
//  - <material> with a <shaderref node=X> and its <bindinput>s becomes an X
//    shader node with those inputs plus a <surfacematerial> (1.38);
//  - an input's `channels` attribute becomes a swizzle node in front of it (1.38);
//  - atan2's inputs in1/in2 become inx/iny (1.36-1.37) or iny/inx (1.38);
//  - geomattrvalue becomes geompropvalue (1.37; its attrname input stays, as
//    MaterialX's own upgrade leaves it);
//  - color2 becomes vector2, with separate2's outr/outa and channel letters
//    r/a read from a color2 becoming x/y (1.37);
//  - pbrlib's BSDF nodes are renamed, nested layering becomes layer nodes,
//    and thin-film layers become thin-film inputs (mtlx_upgrade_bsdf.h).
// The version attribute is then 1.39. Documents already at 1.39 are untouched.
// tests/materials/mtlx_library_test.cpp (OldDocumentsUpgradeLikeMaterialXDoes)
// compares the result with what the materialx Python package's upgrade gives.
#pragma once

#include <pugixml.hpp>
#include <string>

namespace pmc {

// Upgrades the document under `root` (a <materialx> element) in place.
// `path` is for messages.
void upgrade_mtlx_document(pugi::xml_node root, const std::string& path);

}  // namespace pmc
