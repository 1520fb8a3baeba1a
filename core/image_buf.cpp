// image_buf.cpp — copies between Image and ImageBuf; channel selection.
#include "core/image_buf.h"

#include <OpenImageIO/imagebufalgo.h>

#include "core/error.h"

namespace pmc {

OIIO::ImageBuf to_image_buf(const Image& image) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(image.width, image.height, image.channels, OIIO::TypeDesc::FLOAT));
  buf.set_pixels(buf.roi(), OIIO::TypeDesc::FLOAT, image.pixels.data());
  return buf;
}

Image from_image_buf(const OIIO::ImageBuf& buf) {
  if (buf.has_error()) fail("image operation failed: ", buf.geterror());
  const OIIO::ImageSpec& spec = buf.spec();
  Image image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.nchannels;
  image.pixels.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  buf.get_pixels(buf.roi(), OIIO::TypeDesc::FLOAT, image.pixels.data());
  return image;
}

Image first_channels(const Image& image, int channels) {
  return from_image_buf(OIIO::ImageBufAlgo::channels(to_image_buf(image), channels, {}));
}

}  // namespace pmc
