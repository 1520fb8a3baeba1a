// image_buf.h — pmc's Image as an OpenImageIO ImageBuf and back.
//
// For the image operations OpenImageIO's ImageBufAlgo provides (absolute
// differences, channel selection, colour maps, pasting): the pixels are
// copied in and out, which is nothing next to a render.
#pragma once

#include <OpenImageIO/imagebuf.h>

#include "core/image_io.h"

namespace pmc {

OIIO::ImageBuf to_image_buf(const Image& image);
Image from_image_buf(const OIIO::ImageBuf& buf);  // float pixels; throws pmc::Error if buf has an error
// The first `channels` channels of `image` (RGB of an RGBA image).
Image first_channels(const Image& image, int channels);

}  // namespace pmc
