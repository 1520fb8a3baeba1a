// cutout_test.cpp — MTL map_d cut-outs are honoured during traversal.
//
// A black quad whose map_d mask is transparent on its left half hangs in a
// white environment. Where the mask is 0 the camera must see the environment
// (radiance exactly 1), where it is 1 the black quad (radiance exactly 0);
// shadow rays use the same filter. Without the Embree filter the left half
// would be black, so the test fails if cut-outs are ignored (the session must
// hand its cut-out tester to the tracer).
#include "materials/cutout.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

TEST(Cutout, MapDMaskMakesHalfTheQuadTransparent) {
  const std::string dir = test::temp_dir();
  // 8x1 grey mask: 4 transparent texels, then 4 opaque ones.
  unsigned char mask[8] = {0, 0, 0, 0, 255, 255, 255, 255};
  auto out = OIIO::ImageOutput::create(dir + "/mask.png");
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(dir + "/mask.png", OIIO::ImageSpec(8, 1, 1, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, mask));
  out->close();
  test::write_file(dir + "/q.mtl", "newmtl leaf\nKd 0 0 0\nmap_d mask.png\n");
  test::write_file(dir + "/q.obj",
                   "mtllib q.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                   "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl leaf\nf 1/1 2/2 3/3 4/4\n");
  RenderConfig s;
  s.scene = dir + "/q.obj";
  s.cache = false;
  s.width = 32;
  s.height = 32;
  s.spp = 2;
  s.max_depth = 2;
  s.env = {1.0f, 1.0f, 1.0f};
  s.camera_from = Vec3{0.0f, 0.0f, 3.0f};
  s.camera_at = Vec3{0.0f, 0.0f, 0.0f};
  s.fov = 30.0f;  // the quad covers the whole view
  RenderSession session(s, test::cl());
  ASSERT_TRUE(CutoutTester(session.scene(), session.materials()).any());
  RenderOutput r = session.render();
  auto px = [&](int x, int y) { return r.image.pixels[3 * size_t(y * 32 + x)]; };
  for (int y = 4; y < 28; y += 6) {
    EXPECT_FLOAT_EQ(px(4, y), 1.0f) << "left half must be transparent, row " << y;
    EXPECT_FLOAT_EQ(px(27, y), 0.0f) << "right half must be opaque black, row " << y;
  }
}

}  // namespace
}  // namespace pmc
