// exr_channels.h — every channel of an image file by name, for the tests of
// render passes and denoising (pmc.* exact sums read as their u32 bits, the
// others as floats). Header-only: the CLI tests that read layered EXRs share it.
#ifndef PMC_TESTS_SUPPORT_EXR_CHANNELS_H
#define PMC_TESTS_SUPPORT_EXR_CHANNELS_H

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "core/image_backend.h"

namespace pmc::test {

inline std::map<std::string, std::vector<float>> exr_channels(const std::string& path) {
  std::string why;
  auto in = image_backend().open(path, false, why);
  EXPECT_TRUE(in) << path << ": " << why;
  std::map<std::string, std::vector<float>> out;
  if (!in) return out;
  const ImageHeader& h = in->header();
  const size_t n = size_t(h.width) * size_t(h.height);
  for (int c = 0; c < h.channels; ++c) {
    std::vector<float> v(n);
    const std::string& name = h.channel_names[size_t(c)];
    const bool sum = name.rfind("pmc.", 0) == 0;
    EXPECT_TRUE(in->read(c, c + 1, sum ? PixelFormat::U32 : PixelFormat::Float, v.data())) << name;
    out[name] = v;
  }
  return out;
}

}  // namespace pmc::test

#endif  // PMC_TESTS_SUPPORT_EXR_CHANNELS_H
