// lobe_spread_test.cpp — the material cache's cone widening at a bounce
// (core/device/pmc_raycone.h: pmc_lobe_spread).
//
// A direction sampled with solid-angle pdf p stands for 1/p steradians; the
// cone with that solid angle has (small-angle) half-angle sqrt(1 / (pi p)),
// and the cache cone's spread grows by C times its full angle. Checked
// against that formula at hand-picked pdfs (a cosine lobe at normal
// incidence, 1/pi, is 2 radians), the solid angle the cone encloses, its
// 1/sqrt(p) scaling, the cap at pi, and the guards (C <= 0, NaN, pdf <= 0,
// infinite or NaN) that give the paper's cone back. The path state packs the
// extra cone's width and spread into one word as bfloat16s (pmc_pack_cone):
// each comes back within 2^-7 below the float, never above, for values from
// 1e-30 to 1e30; zeros and infinities survive. pmc_texture_ellipse_needed,
// which decides from the same lobe whether a hit's textures filter over the
// footprint's ellipse, at the camera, diffuse and mirror bounces, its
// threshold and bad inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/device/pmc_raycone.h"

namespace pmc {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();
const double kPi = 3.14159265358979323846;

TEST(LobeSpread, DiffuseLobeAtNormalIncidenceIsTwoRadiansTimesC) {
  const float cosine_pdf = float(1.0 / kPi);  // cos(theta) / pi at theta = 0
  EXPECT_NEAR(pmc_lobe_spread(cosine_pdf, 1.0f), 2.0f, 1e-6f);
  EXPECT_NEAR(pmc_lobe_spread(cosine_pdf, 0.125f), 0.25f, 1e-6f);
  EXPECT_NEAR(pmc_lobe_spread(cosine_pdf, 0.0625f), 0.125f, 1e-6f);
}

TEST(LobeSpread, ConeEnclosesTheSolidAngleOfOneSample) {
  for (float pdf : {0.5f, 3.0f, 100.0f, 1e4f}) {
    const double half_angle = 0.5 * double(pmc_lobe_spread(pdf, 1.0f));
    EXPECT_NEAR(kPi * half_angle * half_angle, 1.0 / double(pdf), 1e-5 / double(pdf)) << "pdf " << pdf;
  }
}

TEST(LobeSpread, SharperLobesWidenLessAsOneOverTheSquareRootOfThePdf) {
  const float a = pmc_lobe_spread(1.0f, 0.25f), b = pmc_lobe_spread(4.0f, 0.25f),
              c = pmc_lobe_spread(400.0f, 0.25f);
  EXPECT_NEAR(b, 0.5f * a, 1e-6f);
  EXPECT_NEAR(c, 0.05f * a, 1e-6f);
  EXPECT_LT(pmc_lobe_spread(1e8f, 0.25f), 1e-4f) << "a mirror-like lobe barely widens the cone";
}

TEST(LobeSpread, CappedAtPiForVeryWideLobesAndLargeC) {
  EXPECT_FLOAT_EQ(pmc_lobe_spread(float(1.0 / kPi), 4.0f), float(kPi));
  EXPECT_FLOAT_EQ(pmc_lobe_spread(1e-30f, 0.125f), float(kPi));
  EXPECT_FLOAT_EQ(pmc_lobe_spread(1e-45f, 0.125f), float(kPi)) << "subnormal pdf: 1 / (pi p) overflows";
}

TEST(LobeSpread, GuardsGiveThePapersConeBack) {
  EXPECT_EQ(pmc_lobe_spread(1.0f, 0.0f), 0.0f) << "C = 0: the texture's cone";
  EXPECT_EQ(pmc_lobe_spread(1.0f, -1.0f), 0.0f);
  EXPECT_EQ(pmc_lobe_spread(1.0f, kNaN), 0.0f);
  EXPECT_EQ(pmc_lobe_spread(1.0f, kInf), 0.0f);
  for (float pdf : {0.0f, -1.0f, kNaN, kInf, -kInf}) EXPECT_EQ(pmc_lobe_spread(pdf, 0.25f), 0.0f) << pdf;
}

TEST(LobeSpread, PackedConeKeepsEightBitsOfEachValue) {
  EXPECT_EQ(pmc_pack_cone(0.0f, 0.0f), 0u) << "a camera ray's word";
  EXPECT_EQ(pmc_cone_width(0u), 0.0f);
  EXPECT_EQ(pmc_cone_spread(0u), 0.0f);
  for (float w : {1e-30f, 3e-7f, 0.01f, 0.3f, 1.0f, 2.5f, 777.0f, 1e30f})
    for (float s : {0.0f, 1e-6f, 0.0625f, 0.9f, 3.14159265f, 1e30f}) {
      const uint32_t packed = pmc_pack_cone(w, s);
      const float w2 = pmc_cone_width(packed), s2 = pmc_cone_spread(packed);
      EXPECT_LE(w2, w);
      EXPECT_GE(w2, w * (1.0f - 1.0f / 128.0f)) << w;
      EXPECT_LE(s2, s);
      EXPECT_GE(s2, s * (1.0f - 1.0f / 128.0f)) << s;
    }
  EXPECT_EQ(pmc_cone_width(pmc_pack_cone(kInf, 1.0f)), kInf);
  EXPECT_EQ(pmc_cone_spread(pmc_pack_cone(1.0f, kInf)), kInf);
  EXPECT_EQ(pmc_cone_width(pmc_pack_cone(1.0f, 2.0f)), 1.0f) << "exact where 8 bits suffice";
  EXPECT_EQ(pmc_cone_spread(pmc_pack_cone(1.0f, 2.0f)), 2.0f);
}

// pmc_texture_ellipse_needed: the ellipse where the lobe that sampled the ray
// covers less than `ratio` texture cones at the hit.
TEST(TextureEllipseNeeded, CameraRaysKeepTheEllipse) {
  // no lobe (pdf 0), no width at the camera
  EXPECT_TRUE(pmc_texture_ellipse_needed(0.0f, 5.0f, 0.002f, 0.0f, 8.0f));
}

TEST(TextureEllipseNeeded, DiffuseBouncesAreRound) {
  const float cosine_pdf = float(1.0 / kPi);  // a 2-radian lobe
  EXPECT_FALSE(pmc_texture_ellipse_needed(0.01f, 1.0f, 0.002f, cosine_pdf, 8.0f));
  // also a hit just beside the bounce, whose cone is still the width it had there
  EXPECT_FALSE(pmc_texture_ellipse_needed(0.01f, 0.05f, 0.002f, cosine_pdf, 8.0f));
}

TEST(TextureEllipseNeeded, NearMirrorBouncesKeepTheEllipse) {
  EXPECT_TRUE(pmc_texture_ellipse_needed(0.01f, 1.0f, 0.002f, 1e8f, 8.0f));
  EXPECT_TRUE(pmc_texture_ellipse_needed(0.0f, 1.0f, 0.002f, 1e8f, 8.0f));
}

TEST(TextureEllipseNeeded, TheLobeAgainstRatioTimesTheConeDecides) {
  // From a point (no width at the origin) the lobe's footprint is t * angle
  // against ratio * t * spread: round from angle = ratio * spread up.
  const float spread = 0.004f, ratio = 8.0f;
  for (float factor : {0.5f, 0.9f, 1.1f, 2.0f}) {
    const double angle = double(ratio * spread * factor);
    const float pdf = float(4.0 / (kPi * angle * angle));  // pmc_lobe_spread(pdf, 1) == angle
    EXPECT_EQ(pmc_texture_ellipse_needed(0.0f, 3.0f, spread, pdf, ratio), factor < 1.0f ? 1 : 0) << factor;
  }
  // a wide origin counts on both sides: a lobe 10 times the cone, but the
  // width at the origin dominates both footprints
  const float pdf10 = float(4.0 / (kPi * std::pow(10.0 * spread, 2.0)));
  EXPECT_TRUE(pmc_texture_ellipse_needed(1.0f, 3.0f, spread, pdf10, ratio));
}

TEST(TextureEllipseNeeded, BadInputsKeepTheEllipse) {
  EXPECT_TRUE(pmc_texture_ellipse_needed(0.01f, kNaN, 0.002f, 1.0f, 8.0f));
  EXPECT_TRUE(pmc_texture_ellipse_needed(kNaN, 1.0f, 0.002f, 1.0f, 8.0f));
  EXPECT_TRUE(pmc_texture_ellipse_needed(0.01f, 1.0f, 0.002f, kNaN, 8.0f));
  EXPECT_TRUE(pmc_texture_ellipse_needed(0.01f, 1.0f, 0.002f, -1.0f, 8.0f));
  EXPECT_TRUE(pmc_texture_ellipse_needed(0.01f, 1.0f, 0.002f, kInf, 8.0f));
}

}  // namespace
}  // namespace pmc
