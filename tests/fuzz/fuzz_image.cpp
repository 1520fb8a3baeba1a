// fuzz_image.cpp — libFuzzer target for image files read by pmc's own
// decoders (core/native_images.h: OpenEXR through libOpenEXR, PNG through
// libpng, JPEG through libjpeg, Radiance HDR through our RGBE decoder): a
// broken file must be refused with a reason, never crash, hang or allocate
// what its header claims before the data is there. The checks live in
// harness.h (check_image). The seed corpus (tests/fuzz/corpus/image) holds
// PNG, JPEG and Radiance HDR files; EXR seeds were left out: under ASan,
// libOpenEXR spent about 0.4 s opening an 8x6 file (zeroing fresh pages),
// which held the whole target to ~70 inputs a second instead of ~1200.
// OpenEXR's own decoding is fuzzed upstream; pmc's header check before it
// (core/native_images.cpp, open_checked_exr) is still reached by mutation.
#include <cstdio>
#include <cstdlib>

#include "tests/fuzz/harness.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string problem = pmc::fuzz::check_image(data, size);
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_image: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
