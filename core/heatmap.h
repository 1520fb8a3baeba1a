// heatmap.h — the cache hit map as a picture (the paper's Fig. 1d).
//
// Values (cache points found per sample) map through the viridis colour map
// (OpenImageIO's ImageBufAlgo::color_map) on a fixed 0..max scale, so maps of
// different renders compare directly; a colour bar with max / max/2 / 0
// labels is drawn to the right of the image.
#pragma once

#include "core/image_io.h"

namespace pmc {

// An RGB display image: the map plus a labelled colour bar.
Image heatmap_with_colorbar(const Image& values, float max_value = 20.0f);

}  // namespace pmc
