// session_setup_test.cpp — the overlapped setup of gpu/render_session.h, on PoCL.
//
//  * A session that opens its own device (beside the scene's loading)
//    renders bit for bit what a session given a device renders, and its
//    setup steps still add up to their total.
//  * An error opening the device, raised on the background job, surfaces
//    with its message and type, and ahead of the scene's own error (a missing
//    OBJ), as when the device was opened before the scene was read.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "core/error.h"
#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

RenderConfig room() {
  RenderConfig c;
  c.scene = test::source_path("data/default/room.obj");  // textured (map_Kd)
  c.width = 40;
  c.height = 24;
  c.spp = 4;
  c.max_depth = 4;
  c.cache = false;
  return c;
}

TEST(SessionSetup, OwnDeviceRendersTheSameBitsAsAGivenDevice) {
  RenderSession given(room(), test::cl());
  RenderSession own(room());
  RenderOutput a = given.render(), b = own.render();
  ASSERT_EQ(a.image.pixels.size(), b.image.pixels.size());
  ASSERT_GT(test::image_mean(a.image), 0.0);
  EXPECT_EQ(0,
            std::memcmp(a.image.pixels.data(), b.image.pixels.data(), a.image.pixels.size() * sizeof(float)));
  const SetupSeconds& s = own.setup_seconds();
  EXPECT_GT(s.background_opencl_device, 0.0);
  EXPECT_GE(s.opencl_device, 0.0);
  EXPECT_DOUBLE_EQ(s.total(), s.opencl_device + s.scene + s.materials + s.lights + s.bvh + s.renderer);
  EXPECT_EQ(given.setup_seconds().opencl_device, 0.0);
  EXPECT_EQ(given.setup_seconds().background_opencl_device, 0.0);
}

TEST(SessionSetup, DeviceErrorFromTheBackgroundComesFirstWithItsMessage) {
  RenderConfig c = room();
  c.device = "no-such-device";
  try {
    RenderSession s(c);
    FAIL() << "no exception";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("no OpenCL device matches 'no-such-device'"), std::string::npos)
        << e.what();
  }
  c.scene = test::temp_dir() + "/missing.obj";  // both wrong: the device's error, as before
  try {
    RenderSession s(c);
    FAIL() << "no exception";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-device"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("missing.obj"), std::string::npos) << e.what();
  }
  c.device = "";  // the scene's error alone still reads as it did
  try {
    RenderSession s(c);
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.obj"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pmc
