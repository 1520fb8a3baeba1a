// grazing_texture_render_test.cpp — anisotropic texture filtering in a
// render: a ground plane striped along the view direction (black and white
// stripes 1 unit wide, running away from the camera), seen at a grazing
// angle. Far away the footprint is long along the stripes and thin across
// them: filtered at the major axis' level (isotropic) the stripes fade to
// grey, filtered along the ellipse they keep their contrast.
//
// The expectation is independent of the renderer's filtering: each
// pixel's 4 x 4 sub-pixel rays are intersected with the plane here and the stripes they land on
// read from the texture's definition (a box average); the rows 12-30 units away
// (footprints 8-20 times longer than wide) are compared by their variance
// across the row. The material is pure emission (no base, no specular, a
// black environment), so a pixel is its texture value.
//   * image(uv * 0.125): a uniform scale, filtered anisotropically: at least
//     60% of the expected variance;
//   * image(uv * (0.125, 0.12501)): an uneven scale, which the compiler
//     leaves isotropic (PMC_IMAGE_ANISO), the filtering before anisotropy:
//     less than half the anisotropic render's variance.
// Seen in a mirror (a smooth metal plane just above a lower camera, looking
// up into it), the same stripes come from the second surface hit of each
// path: a near-delta lobe keeps the footprint's ellipse there
// (pmc_texture_ellipse_needed), so the mirrored far rows keep their contrast
// as well, against the same box averages traced through the mirror here.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/hard_cases/hard_support.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

constexpr int kW = 96, kH = 48, kTex = 64;
constexpr double kFrom[3] = {0.0, 2.0, 0.0}, kAt[3] = {0.0, 1.2, -10.0};
constexpr double kFov = 30.0;

// The ground y = 0, x in [-60, 60], z in [-120, 0]; uv = (x, -z) in world units
// (the material scales them: 8 units a texture repeat). Relative indices: the
// same lines follow the mirror's in the mirror scene.
const char* kGround = R"(v -60 0 0
v 60 0 0
v 60 0 -120
v -60 0 -120
vt -60 0
vt 60 0
vt 60 120
vt -60 120
vn 0 1 0
usemtl M
f -4/-4/-1 -3/-3/-1 -2/-2/-1
f -4/-4/-1 -2/-2/-1 -1/-1/-1
)";

// The mirror: the plane y = kMirrorY over the ground, facing down.
constexpr double kMirrorY = 1.0;
const char* kMirror = R"(v -60 1 0
v 60 1 0
v 60 1 -120
v -60 1 -120
vn 0 -1 0
usemtl Mirror
f 1//1 3//1 2//1
f 1//1 4//1 3//1
)";

// Texture column x is white in every other band of 8 (8 bands: 1 unit each).
bool white(int x) { return (x / 8) % 2 == 0; }

std::string document(const std::string& image, const std::string& scale) {
  return R"(<?xml version="1.0"?><materialx version="1.39">
<texcoord name="uv" type="vector2"/>
<multiply name="uvs" type="vector2"><input name="in1" type="vector2" nodename="uv"/><input name="in2" type="vector2" value=")" +
         scale + R"("/></multiply>
<image name="c" type="color3"><input name="file" type="filename" value=")" +
         image + R"("/><input name="texcoord" type="vector2" nodename="uvs"/></image>
<standard_surface name="S" type="surfaceshader"><input name="base" type="float" value="0"/><input name="specular" type="float" value="0"/><input name="emission" type="float" value="1"/><input name="emission_color" type="color3" nodename="c"/></standard_surface>
<surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial>
<standard_surface name="SM" type="surfaceshader"><input name="base" type="float" value="1"/><input name="base_color" type="color3" value="1, 1, 1"/><input name="metalness" type="float" value="1"/><input name="specular_color" type="color3" value="1, 1, 1"/><input name="specular_roughness" type="float" value="0"/></standard_surface>
<surfacematerial name="Mirror" type="material"><input name="surfaceshader" type="surfaceshader" nodename="SM"/></surfacematerial></materialx>)";
}

struct View {
  double from[3], at[3];
  bool mirror;  // the rays reach the ground through the mirror
};
const View kDirect = {{kFrom[0], kFrom[1], kFrom[2]}, {kAt[0], kAt[1], kAt[2]}, false};
// A camera half a unit above the ground, pitched up 7 degrees into the mirror:
// its rays meet the ground after 1.5 units of height, as steeply as the direct
// view's far rows do after 2.
const View kInMirror = {{0.0, 0.5, 0.0}, {0.0, 0.5 + 10.0 * std::tan(7.0 * M_PI / 180.0), -10.0}, true};

// Where pixel (x, y)'s ray through (ox, oy) inside it (the centre by default) meets the ground (in the
// mirror view, after its reflection): world x and the path's length; false for the sky.
bool ground_hit(const View& v, int px, int py, double* gx, double* dist, double ox = 0.5, double oy = 0.5) {
  double f[3] = {v.at[0] - v.from[0], v.at[1] - v.from[1], v.at[2] - v.from[2]};
  double fl = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  for (double& c : f) c /= fl;
  // right = f x up(0,1,0), up' = right x f
  double r[3] = {-f[2], 0.0, f[0]};
  double rl = std::sqrt(r[0] * r[0] + r[2] * r[2]);
  for (double& c : r) c /= rl;
  double u[3] = {r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]};
  const double t = std::tan(kFov * M_PI / 360.0);
  const double sx = (2.0 * (px + ox) / kW - 1.0) * t * double(kW) / kH;
  const double sy = (1.0 - 2.0 * (py + oy) / kH) * t;
  double d[3];
  for (int i = 0; i < 3; ++i) d[i] = f[i] + r[i] * sx + u[i] * sy;
  double o[3] = {v.from[0], v.from[1], v.from[2]};
  double travelled = 0.0;
  const double dl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (v.mirror) {  // up to the mirror, then down
    if (!(d[1] > 0.0)) return false;
    const double s = (kMirrorY - o[1]) / d[1];
    for (int i = 0; i < 3; ++i) o[i] += s * d[i];
    if (o[2] < -120.0) return false;  // past the mirror's far edge
    travelled = s * dl;
    d[1] = -d[1];
  }
  if (!(d[1] < 0.0)) return false;
  const double s = -o[1] / d[1];
  *gx = o[0] + s * d[0];
  *dist = travelled + s * dl;
  return true;
}

// Mean over the far rows of the variance across each row (channel 0).
double far_row_variance(const std::vector<double>& v, const std::vector<int>& rows) {
  double total = 0.0;
  for (int y : rows) {
    double m = 0.0, m2 = 0.0;
    for (int x = 0; x < kW; ++x) m += v[size_t(y) * kW + size_t(x)];
    m /= kW;
    for (int x = 0; x < kW; ++x) m2 += std::pow(v[size_t(y) * kW + size_t(x)] - m, 2.0);
    total += m2 / kW;
  }
  return total / double(rows.size());
}

// The expected far-row variance of a view: each pixel's box average of the stripes (4 x 4 sub-pixel rays),
// over the rows whose every pixel sees the ground 12-30 away.
double expected_variance(const View& v, std::vector<int>* rows) {
  std::vector<double> expect(size_t(kW) * kH, 0.0);
  for (int y = 0; y < kH; ++y) {
    bool far = true;
    for (int x = 0; x < kW; ++x) {
      double gx = 0, dist = 0;
      if (!ground_hit(v, x, y, &gx, &dist)) {
        far = false;
        continue;
      }
      double sum = 0.0;
      for (int j = 0; j < 16; ++j) {
        double sgx = 0, sd = 0;
        if (!ground_hit(v, x, y, &sgx, &sd, (j % 4 + 0.5) / 4.0, (j / 4 + 0.5) / 4.0)) continue;
        double u = sgx * 0.125;
        sum += white(int(std::floor((u - std::floor(u)) * kTex))) ? 1.0 : 0.0;
      }
      expect[size_t(y) * kW + size_t(x)] = sum / 16.0;
      far = far && dist > 12.0 && dist < 30.0;
    }
    if (far) rows->push_back(y);
  }
  return far_row_variance(expect, *rows);
}

class GrazingTextureRender : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir();
    std::vector<float> px;
    for (int y = 0; y < kTex; ++y)
      for (int x = 0; x < kTex; ++x)
        for (int c = 0; c < 3; ++c) px.push_back(white(x) ? 1.0f : 0.0f);
    hard::write_image(dir_ + "/stripes.png", kTex, kTex, 3, px);
    test::write_file(dir_ + "/ground.obj", kGround);
    test::write_file(dir_ + "/mirror.obj", std::string(kMirror) + kGround);
    test::write_file(dir_ + "/aniso.mtlx", document(dir_ + "/stripes.png", "0.125, 0.125"));
    test::write_file(dir_ + "/iso.mtlx", document(dir_ + "/stripes.png", "0.125, 0.12501"));
  }

  // The far rows' variance in a render of `obj` with `mtlx` from view v.
  double rendered_variance(const View& v, const std::string& obj, const std::string& mtlx,
                           const std::vector<int>& rows) {
    RenderConfig s = hard::small_config(kW, kH, 16, v.mirror ? 2 : 1);
    hard::set_camera(s, v.from[0], v.from[1], v.from[2], v.at[0], v.at[1], v.at[2], float(kFov));
    s.env = {0.0f, 0.0f, 0.0f};
    hard::Rendered r = hard::render({dir_ + "/" + obj, {dir_ + "/" + mtlx}, ""}, s, false);
    hard::expect_clean(r.out, mtlx);
    EXPECT_EQ(r.out.image.width, kW);
    EXPECT_EQ(r.out.image.height, kH);
    std::vector<double> img(size_t(kW) * kH);
    const int ch = r.out.image.channels;
    for (size_t i = 0; i < img.size(); ++i) img[i] = r.out.image.pixels[i * size_t(ch)];
    return far_row_variance(img, rows);
  }

  // The far rows of view v keep at least `fraction` of the expected variance
  // (which must exceed `least`) filtered anisotropically, and the uneven
  // scale's isotropic lookup less than half of that.
  void expect_contrast(const View& v, const std::string& obj, double least, double fraction,
                       const char* label) {
    std::vector<int> rows;
    const double v_expect = expected_variance(v, &rows);
    ASSERT_GE(rows.size(), 3u);
    ASSERT_GT(v_expect, least);
    const double v_aniso = rendered_variance(v, obj, "aniso.mtlx", rows);
    const double v_iso = rendered_variance(v, obj, "iso.mtlx", rows);
    std::printf("far-row variance%s: expected %.4f, anisotropic %.4f, isotropic %.4f (%zu rows)\n", label,
                v_expect, v_aniso, v_iso, rows.size());
    EXPECT_GT(v_aniso, fraction * v_expect);
    EXPECT_LT(v_aniso, 1.1 * v_expect);
    EXPECT_LT(v_iso, 0.5 * v_aniso);
  }

  std::string dir_;
};

TEST_F(GrazingTextureRender, StripesFarAwayKeepTheirContrast) {
  expect_contrast(kDirect, "ground.obj", 0.15, 0.6, "");
}

TEST_F(GrazingTextureRender, StripesInAMirrorKeepTheirContrast) {
  // (these rows lie farther along their paths: more of their footprints pass the 8 taps' limit)
  expect_contrast(kInMirror, "mirror.obj", 0.1, 0.45, " in the mirror");
}

}  // namespace
}  // namespace pmc
