// denoiser.h — Intel Open Image Denoise (OIDN 2.x) on a beauty image with its albedo and normal passes.
//
// Binding: OIDN is loaded with dlopen when a denoise is first asked for, and
// the dozen functions of its stable C API pmc calls are declared in
// core/denoiser.cpp. Debian 12 does not package OIDN and the PyPI wheel
// that ships it (pyoidn, installed into .venv by scripts/setup) has no C
// headers, so pmc neither needs OIDN to build nor to run: only denoising
// needs it (docs/DESIGN.md, "Render passes and denoising"). The library is
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
  // cleanAux (OIDN's advice for noisy auxiliary images). pmc's passes are
  // Monte Carlo means over each pixel's samples (anti-aliasing, textures
  // under the cone, rough glass and glossy paths before the first
  // non-specular hit), so pmc always prefilters: on the default scene at
  // 160x90 it gave 10-16% lower relMSE against a 4096-spp reference at every
  // sample count from 1 to 1024 spp, for about 0.7-1 s more (three filters
  // instead of one; docs/DESIGN.md, "Render passes and denoising").
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

}  // namespace pmc
