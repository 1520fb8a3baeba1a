// image_metrics.h — how far one render is from another.
//
// Errors are measured on linear radiance. PSNR uses values clamped to [0, 1]
// with peak 1 (what a display shows at exposure 1; HDR outliers would
// otherwise dominate); relMSE divides each squared error by the reference's
// squared value plus 0.01 (the usual guard for dark pixels); RMSE and the
// maximum absolute error are unclamped. The worst tile is the 16x16 tile
// (partial at the right and bottom edges) with the lowest clamped PSNR: a
// local artefact (an aliasing pattern, one mis-cached object) hides in the
// whole-image PSNR but not there. The trimmed worst tile leaves out each
// tile's kTrimPixels pixels of largest error first: two same-seed renders
// whose paths part at one pixel (one firefly found by one of them) can
// decide the plain figure alone, which says nothing about a tile's bias.
#pragma once

#include "core/image_io.h"

namespace pmc {

constexpr int kMetricTile = 16;
constexpr int kTrimPixels = 2;  // of a tile's 256 (tiles of fewer than 3x that are not trimmed)

struct ImageError {
  double rmse = 0, relmse = 0, psnr = 0, max_abs = 0;
  double worst_tile_psnr = 0;
  int worst_tile_x = 0, worst_tile_y = 0;  // its top-left pixel
  double worst_trimmed_tile_psnr = 0;      // without each tile's kTrimPixels largest pixel errors
  int worst_trimmed_tile_x = 0, worst_trimmed_tile_y = 0;
};

// Throws pmc::Error if the sizes differ.
ImageError compare_images(const Image& test, const Image& reference);

// The cache's bias with the noise taken out, from a cacheless and a cached
// render with one seed (off1, on1) and another pair with an independent seed
// (off2, on2): each seed's noise is independent of the other's, so the mean
// of (on1 - off1)(on2 - off2) over an area estimates the squared bias there,
// where (on1 - off1)^2 also holds both renders' noise (a same-seed
// comparison reads fireflies as error). On the clamped [0, 1] scale of the
// PSNR above, averaged over the channels; where the bias is far below the
// noise the estimate can come out negative, reported as 999 dB (none
// measurable). The noise floor is the two cacheless renders against each
// other: what a same-seed comparison cannot see below. A non-finite value
// counts as 0 (pmc warns of such pixels).
struct BiasEstimate {
  double psnr = 0, worst_tile_psnr = 0;  // the squared bias's mean over the image, its worst tile
  int worst_tile_x = 0, worst_tile_y = 0;
  double noise_psnr = 0;  // off1 against off2
};
// Throws pmc::Error if the sizes differ.
BiasEstimate estimate_bias(const Image& off1, const Image& on1, const Image& off2, const Image& on2);
// |a - b| * scale of the tone-mapped display values, at most 1 (the paper's Fig. 1c).
Image difference_image(const Image& a, const Image& b, float scale);

}  // namespace pmc
