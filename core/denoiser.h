// denoiser.h — Intel Open Image Denoise (OIDN 2.x) on a beauty image with its albedo and normal passes.
//
// Binding: OIDN is loaded with dlopen when a denoise is first asked for, and
// the dozen functions of its stable C API pmc calls are declared in
// core/denoiser.cpp. Debian 12 does not package OIDN and the PyPI wheel
// that ships it (pyoidn, installed into .venv by scripts/setup) has no C
// headers, so pmc neither needs OIDN to build nor to run: only --denoise
// and `pmc denoise` need it (docs/DESIGN.md, "Denoising"). The library is
// looked for in order: $PMC_OIDN_LIBRARY (a file, then the only place
// tried); this source tree's .venv (pyoidn's libOpenImageDenoise.so.2);
// the dynamic loader's own search (libOpenImageDenoise.so.2). A missing
// library is a pmc::Error naming what to install and every place tried.
//
// The device is OIDN_DEVICE_TYPE_DEFAULT: a GPU where OIDN finds a
// supported one (CUDA, HIP, SYCL), else the CPU. Images travel through
// OIDN buffers (oidnNewBuffer), which every device type can read.
#pragma once

#include <string>

#include "core/image_io.h"

namespace pmc {

struct DenoiseInputs {
  const Image* color = nullptr;   // linear rgb (HDR)
  const Image* albedo = nullptr;  // rgb in [0, 1]
  const Image* normal = nullptr;  // world-space xyz in [-1, 1]
  // Prefilter albedo and normal with the RT filter first and denoise with
  // cleanAux: for auxiliary images that are themselves noisy (see
  // denoise_needs_clean_aux).
  bool prefilter_aux = true;
};

struct DenoiseResult {
  Image image;
  std::string device;  // "CPU", "CUDA", ...
  double seconds = 0;  // filters' commit and execution (without loading the library)
};

// Whether OIDN can be loaded (tests, `pmc info`); `why` says what was tried.
bool denoiser_available(std::string* why = nullptr);

// Denoises `in.color` (all images the same size, 3 channels). pmc::Error
// when OIDN is missing or fails (its message).
DenoiseResult denoise(const DenoiseInputs& in);

// The prefilter decision: pmc's albedo and normal passes average the first
// non-specular hit over a pixel's samples, which is noisy at low sample
// counts (anti-aliasing, textures under the cone, rough glass and glossy
// paths before that hit); below this many samples per pixel they are
// prefiltered (OIDN's cleanAux mode), from it on they go to the filter as
// they are (measured: docs/BENCHMARKS.md, "Denoising").
constexpr int kCleanAuxBelowSpp = 256;
inline bool denoise_needs_clean_aux(int spp) { return spp < kCleanAuxBelowSpp; }

}  // namespace pmc
