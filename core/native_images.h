// native_images.h — the image formats pmc reads and writes without OpenImageIO.
//
// OpenEXR files (libOpenEXR: any channels, half/float/uint, data and display
// windows, string/int/float attributes) and 8-bit PNGs (libpng: grey, grey +
// alpha, RGB, RGBA, palettes expanded, tRNS as alpha), the formats of pmc's
// own outputs and of most textures. Loading these two libraries costs a few
// milliseconds; everything else goes to the OpenImageIO plugin, loaded only
// when a file needs it (core/image_backend.h).
//
// Conventions follow OpenImageIO's, so a file reads the same either way:
// PNG bytes are returned as stored (no gamma conversion; 8-bit reads as
// Float divide by 255); EXR channels come R, G, B, A first, then the rest in
// the file's (alphabetical) order. A PNG with alpha opened with associated
// alpha, and 16-bit PNGs, are left to the plugin.
#pragma once

#include <memory>
#include <string>

#include "core/image_backend.h"

namespace pmc {

// A reader when the file is an OpenEXR or PNG this code handles; null
// otherwise (`why` set only when the file is one of those formats but broken).
std::unique_ptr<ImageReader> open_native_image(const std::string& path, bool unassociated_alpha,
                                               std::string& why);
// Whether write_native_image takes `image` for a file named `format_path`.
bool native_image_writes(const std::string& format_path, const ImageWrite& image);
bool write_native_image(const std::string& file, const std::string& format_path, const ImageWrite& image,
                        std::string& why);

}  // namespace pmc
