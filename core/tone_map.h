// tone_map.h — linear radiance to display values: the one place it happens.
//
// Every PNG pmc writes beside an EXR, and the difference image of `pmc
// compare`, shows display values in [0, 1]: a linear value is scaled by
// 2^exposure_ev, goes through the view curve per channel, and is encoded with
// the sRGB transfer function. The EXRs stay linear.
//   filmic   : Narkowicz's fit of the ACES filmic tone curve (2015),
//              x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1]:
//              highlights roll off instead of clipping (the default);
//   standard : clamp to [0, 1] (linear values above 1 clip to white).
// NaN/Inf and negative values display as 0. Display options (exposure_ev,
// view) belong in ToneMap, so every caller gets them.
#pragma once

#include <string>

#include "core/image_io.h"

namespace pmc {

enum class ViewTransform { Filmic, Standard };

struct ToneMap {
  float exposure_ev = 0.0f;  // stops: linear values x 2^exposure_ev before the curve
  ViewTransform view = ViewTransform::Filmic;
};

// The display value in [0, 1] of one linear channel value (8-bit PNGs round
// 255 x this).
float tone_map(float linear, const ToneMap& tm = {});
// Every channel of `linear` mapped by tone_map().
Image tone_map_image(const Image& linear, const ToneMap& tm = {});
// "filmic" / "standard" -> ViewTransform (pmc::Error otherwise, naming `option`).
ViewTransform parse_view_transform(const std::string& name, const std::string& option);

}  // namespace pmc
