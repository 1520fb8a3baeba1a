// mtlx_upgrade_bsdf.h — the closure nodes' part of the 1.37 -> 1.39 upgrade.
//
// MaterialX 1.38 renamed the pbrlib BSDF nodes and replaced nested layering
// (a BSDF's `base` input) with `layer` operators; 1.39 folded thin_film_bsdf
// layers into thin-film inputs on the BSDFs below. pmc rewrites the parsed
// XML the same way (Document::upgradeVersion is the reference), so a 1.37
// closure graph reaches the reader (and closure_flatten.h) as 1.39 nodes:
//  - 1.37: diffuse_brdf -> oren_nayar_diffuse_bsdf, burley_diffuse_brdf ->
//    burley_diffuse_bsdf, diffuse_btdf -> translucent_bsdf, subsurface_brdf
//    -> subsurface_bsdf; dielectric_btdf -> dielectric_bsdf with scatter_mode
//    T (its `interior` dropped); conductor_brdf -> conductor_bsdf fed by a new
//    artistic_ior node "<name>__artistic_ior" that takes its reflectivity and
//    edge_color; dielectric_brdf, generalized_schlick_brdf, sheen_brdf and
//    thin_film_brdf -> their _bsdf nodes, and a connected `base` becomes a
//    layer node that takes the BSDF's name (the BSDF becomes
//    "<name>__layer_top"), so connections need no change.
//  - 1.38: a layer whose top is a thin_film_bsdf is bypassed; the film's
//    thickness and ior become thinfilm_thickness / thinfilm_ior on the
//    dielectric, conductor and generalized_schlick BSDFs upstream of its base
//    (except transmission-only ones).
#pragma once

#include <functional>
#include <pugixml.hpp>

namespace pmc {

// Calls `fn` on every element below `n`, depth first, parents before their
// children (the upgrade's passes walk the document with it).
void for_each_mtlx_element(pugi::xml_node n, const std::function<void(pugi::xml_node)>& fn);

void upgrade_bsdf_nodes_137(pugi::xml_node root);
void upgrade_thin_film_layers_138(pugi::xml_node root);

}  // namespace pmc
