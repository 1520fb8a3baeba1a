// heatmap.h — the cache hit map as a picture (the paper's Fig. 1d).
//
// Values (cache points found per sample) map through the viridis colour map
// on a fixed 0..20 scale, so maps of different renders compare directly; a
// colour bar with 0 / 10 / 20 labels is drawn to the right of the image.
#pragma once

#include "core/image_io.h"

namespace pmc {

// Viridis colour (display values in [0,1]) for t in [0,1].
void viridis(float t, float rgb[3]);
// An RGB display image: the map plus a labelled colour bar.
Image heatmap_with_colorbar(const Image& values, float max_value = 20.0f);

}  // namespace pmc
