// native_hdr.h — Radiance HDR (RGBE) files read directly.
//
// Environment maps come as Radiance .hdr files more often than as anything
// else; reading them here keeps a sky-lit render off the OpenImageIO plugin
// and its 0.4-0.5 s of library loading (core/image_backend.h). The format:
// a "#?" header of NAME=value lines ending in an empty line, a resolution
// line, then scanlines of 4-byte RGBE pixels, each run-length encoded per
// component (the "new" RLE) or stored flat. A pixel is (r, g, b) * 2^(e -
// 136), 0 where e = 0, as OpenImageIO reads it (no +0.5 offset, EXPOSURE and
// GAMMA not applied), three Float channels R, G, B. Files in XYZE, or stored
// in an orientation other than the usual "-Y H +X W", go to the plugin.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "core/image_backend.h"

namespace pmc {

// True when `magic` (a file's first bytes) starts a Radiance header ("#?").
bool is_radiance_hdr(const unsigned char* magic, size_t n);
// A reader of the image: the header is checked here (null with `why` set
// when it is broken, null with `why` empty when the plugin should read
// it); the pixels are decoded by read(), straight into the caller's memory,
// which fails saying why when they are broken (cut short, bad runs).
std::unique_ptr<ImageReader> open_radiance_hdr(const std::string& path, std::string& why);

}  // namespace pmc
