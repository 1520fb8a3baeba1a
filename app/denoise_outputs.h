// denoise_outputs.h — the files a denoise writes: the denoised image and the noisy one beside it.
//
// `pmc render -o OUT.exr --denoise` and `pmc denoise IN.exr -o OUT.exr` both
// write the denoised image to OUT.exr (with the passes as layers) and
// OUT.png, and the noisy image to OUT.noisy.exr (same layers) and
// OUT.noisy.png. The paths are checked before any work starts.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace pmc {

struct DenoisePaths {
  std::string exr, png, noisy_exr, noisy_png;
};

DenoisePaths denoise_paths(const std::string& exr);
// The noisy pair's (option, path) entries, each checked writable (the
// caller checks OUT.exr and OUT.png as it always does).
std::vector<std::pair<std::string, std::string>> check_noisy_outputs(const DenoisePaths& paths);

}  // namespace pmc
