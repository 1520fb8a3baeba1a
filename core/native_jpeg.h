// native_jpeg.h — baseline and progressive JPEG files read with libjpeg-turbo.
//
// JPEG is the texture format of many third-party scenes (the MaterialX
// project's examples among them); reading it here keeps those scenes off the
// OpenImageIO plugin, whose libraries take 0.4-0.5 s to load
// (core/image_backend.h). OpenImageIO's conventions: grey files give one
// channel "Y", colour files three ("R", "G", "B") as libjpeg decodes them to
// RGB, bytes as stored (no colour conversion). CMYK and YCCK files go to the
// plugin. A file cut short is an error, not a grey-filled image. Opening
// reads the header; the pixels decode when read (once), row by row.
#pragma once

#include <memory>
#include <string>

#include "core/image_backend.h"

namespace pmc {

// True when `magic` (a file's first bytes) starts a JPEG stream.
bool is_jpeg(const unsigned char* magic, size_t n);
// A reader of the image (its header read); null with `why` set when the header is broken,
// null with `why` empty when the plugin should read it (CMYK, YCCK).
std::unique_ptr<ImageReader> open_jpeg(const std::string& path, std::string& why);

}  // namespace pmc
