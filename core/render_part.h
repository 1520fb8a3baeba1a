// render_part.h — one part of a frame (a sample range, a window) as an EXR, and merging parts.
//
// A render of the samples A:B (the samples setting) in the window x0,y0,x1,y1
// (crop) writes a part: an EXR whose
// data window is the crop inside the frame's display window, with the mean
// rgb (R, G, B, float) and the film's exact sums (core/film_sum.h) as extra
// 32-bit unsigned channels (pmc.sum0..pmc.sum11, pmc.samples, pmc.bad,
// pmc.hits), and attributes saying which part of which frame it is:
//   pmc:scene_hash, pmc:settings_hash  content hashes (gpu/part_identity.h);
//   pmc:spp, pmc:sample_begin, pmc:sample_end   the frame's samples and this part's [begin, end);
//   pmc:seed, pmc:scene                 the RNG seed and the OBJ path (information);
//   pmc:cache:*                         cache counters (lookups, hits, ...), strings of integers;
//   pmc:render_seconds, pmc:partial     time spent; 1 on a merge that lacks samples;
//   pmc:passes                          the render passes written as layers (core/render_passes.h);
//   pmc:adaptive                        1: adaptive sampling (every part holds all samples 0:spp of
//                                       its window, each pixel the ones it drew; split by window only).
// A part rendered with passes also holds the pass film's exact sums
// (pmc.pass0..pmc.pass39, pmc.pass_hits, pmc.pass_material), and its pass
// layers (albedo.R, N.X, Z, ...); parts with and without pass sums do not merge.
// merge_parts() checks that parts belong together (same hashes, frame size,
// spp and seed; no pixel sample drawn twice; every pixel's samples complete
// unless allow_partial) and adds their films; every refusal is a pmc::Error
// naming the file(s). Nothing here writes anything unless asked to.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/film_sum.h"
#include "core/image_io.h"

namespace pmc {

struct PartCacheCounters {
  uint64_t lookups = 0, hits = 0, misses = 0, inserts = 0, dropped_full = 0;
};

struct PartInfo {
  std::string scene_hash, settings_hash;
  std::string scene;  // OBJ path, for messages and stats
  int frame_width = 0, frame_height = 0;
  int spp = 0;  // of the whole frame
  int sample_begin = 0, sample_end = 0;
  std::array<int, 4> crop = {0, 0, 0, 0};  // x0, y0, x1, y1: the part's window
  uint32_t seed = 0;
  bool cache = false;
  PartCacheCounters cache_counters;
  double render_seconds = 0.0;
  bool partial = false;  // a merge with samples missing (not mergeable again)
  uint32_t passes = 0;   // PassBit: the pass layers written
  bool adaptive = false;  // adaptive sampling: a pixel holds between 1 and spp samples
};

struct RenderPart {
  std::string path;
  PartInfo info;
  FilmSums film;  // the window's exact sums
};

// Writes `image` (the window's mean) with `info`'s attributes, the `layers`
// (render passes) and, when `film` is given, its exact sums (with its pass
// sums when it has them), atomically (core/atomic_write.h).
void write_part_exr(const std::string& path, const Image& image, const PartInfo& info, const FilmSums* film,
                    const std::vector<ImageLayer>& layers = {});
// Reads a part back; pmc::Error naming `path` if it is not a pmc part with sums.
RenderPart read_part_exr(const std::string& path);

struct MergedFrame {
  PartInfo info;                       // the frame's (crop: whole frame), counters and seconds summed
  FilmSums film;                       // the whole frame
  uint64_t missing_pixel_samples = 0;  // allow_partial: pixel samples no part drew
};

// Checks and adds `parts` (see above). Parts are added in the order given;
// the sum is exact, so any order gives the same bits.
MergedFrame merge_parts(const std::vector<RenderPart>& parts, bool allow_partial);

}  // namespace pmc
