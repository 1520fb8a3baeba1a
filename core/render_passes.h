// render_passes.h — render passes (AOVs): which ones, their images from the film's exact sums, their EXR
// layers.
//
// The kernels fill every pass whenever a render has any (core/device/pmc_passes.h:
// what each holds and at which hit); a PassSet only chooses which are written.
// Conventions of the images resolved here:
//   albedo    mean over the pixel's samples of the first non-specular hit's
//             directional albedo (0 for samples that escaped);
//   normal    the mean world-space shading normal of those hits, normalised
//             (0 where no sample found one);
//   depth (Z) the mean distance from the camera to the camera ray's hit (the
//             Euclidean distance along the ray, not the view-axis depth), over
//             the samples that hit; 0 where none did;
//   position  the mean world position of those hits, likewise;
//   material  the smallest material index any sample's camera ray hit (an
//             index into the scene's material table), -1 where none hit;
//   hits      cache points found per sample (the hit map's values).
// Each is a function of the exact sums alone, so merged parts give the same
// pass images as one process, bit for bit.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/film_sum.h"
#include "core/image_io.h"

namespace pmc {

enum PassBit : uint32_t {
  kPassAlbedo = 1u << 0,
  kPassNormal = 1u << 1,
  kPassDepth = 1u << 2,
  kPassPosition = 1u << 3,
  kPassMaterial = 1u << 4,
  kPassHits = 1u << 5,
  kPassAll = (1u << 6) - 1u,
};

// One pass: its bit, its word in a pass list, its EXR channels.
struct PassName {
  uint32_t bit;
  const char* word;
  std::vector<std::string> channels;
};
const std::vector<PassName>& pass_names();

// "albedo,normal,depth,position,material,hits" (any subset, any order, or
// "all"; "" is none) as bits; false with `error` naming the bad word.
bool parse_pass_list(const std::string& list, uint32_t& bits, std::string& error);
// The bits as a list in the table's order ("" for none).
std::string pass_list_text(uint32_t bits);

struct PassImages {
  Image albedo, normal, depth, position, material, hits;
};
// The film's passes (it must have pass sums).
PassImages film_passes(const FilmSums& film);
// The passes in `bits` as EXR layers, in the table's order.
std::vector<ImageLayer> pass_layers(const PassImages& passes, uint32_t bits);

}  // namespace pmc
