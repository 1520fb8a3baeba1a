// lights_render_test.cpp — lights and environments through the whole renderer
// (real OpenCL on PoCL) against answers computed here:
//   * a point light above a diffuse plane: L = rho/pi I cos(theta) / d^2 per
//     pixel; a spot's cone and blend; a quad's one-sidedness (Lambert's
//     polygon formula for its irradiance);
//   * furnaces: a point light and a sphere light at the centre of a closed
//     diffuse sphere, whose walls then have one radiance known in closed form;
//   * a constant map renders like --env; a map's orientation (what a camera
//     looking along -Z / +X sees, which side of a ball it lights, rotation);
//   * light sample clamping: the capped value and its hue under a point
//     light, and the closed sphere split into its direct and indirect light;
//   * importance sampling of a sun-like map beats uniform sampling at equal
//     samples (relMSE against the exact image), and the HDR maps in
//     ../shared/scenes/envmaps load and light a plane as their texels say.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <sstream>
#include <vector>

#include "core/camera.h"
#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct D3 {
  double x, y, z;
};
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot3(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross3(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
D3 unit(D3 a) { return a * (1.0 / std::sqrt(dot3(a, a))); }

// A square in the plane y = 0, [-h, h]^2, facing up.
std::string plane_obj(double h, const std::string& mtl) {
  std::ostringstream os;
  os << "mtllib " << mtl << ".mtl\nusemtl m\n";
  os << "v " << -h << " 0 " << -h << "\nv " << h << " 0 " << -h << "\nv " << h << " 0 " << h << "\nv " << -h
     << " 0 " << h << "\nf 1 4 3\nf 1 3 2\n";
  return os.str();
}

// A UV sphere (flat-shaded), appended as its own `usemtl` group with vertex
// numbers starting after `first_vertex` vertices.
std::string sphere_obj(D3 c, double r, int rings, int segments, const std::string& material,
                       int first_vertex = 0) {
  std::ostringstream os;
  os << "usemtl " << material << "\n";
  os << "v " << c.x << " " << c.y + r << " " << c.z << "\n";
  for (int i = 1; i < rings; ++i) {
    double th = kPi * i / rings;
    for (int j = 0; j < segments; ++j) {
      double ph = 2 * kPi * j / segments;
      os << "v " << c.x + r * std::sin(th) * std::cos(ph) << " " << c.y + r * std::cos(th) << " "
         << c.z + r * std::sin(th) * std::sin(ph) << "\n";
    }
  }
  os << "v " << c.x << " " << c.y - r << " " << c.z << "\n";
  auto ring = [&](int i, int j) { return first_vertex + 2 + (i - 1) * segments + (j % segments); };
  int top = first_vertex + 1, bottom = first_vertex + 2 + (rings - 1) * segments;
  for (int j = 0; j < segments; ++j) os << "f " << top << " " << ring(1, j + 1) << " " << ring(1, j) << "\n";
  for (int i = 1; i < rings - 1; ++i)
    for (int j = 0; j < segments; ++j)
      os << "f " << ring(i, j) << " " << ring(i, j + 1) << " " << ring(i + 1, j + 1) << " " << ring(i + 1, j)
         << "\n";
  for (int j = 0; j < segments; ++j)
    os << "f " << bottom << " " << ring(rings - 1, j) << " " << ring(rings - 1, j + 1) << "\n";
  return os.str();
}
int sphere_vertices(int rings, int segments) { return 2 + (rings - 1) * segments; }

RenderOutput render_files(const std::string& dir, const std::string& obj, const std::string& mtl,
                          const RenderSettings& s) {
  test::write_file(dir + "/scene.mtl", mtl);
  test::write_file(dir + "/scene.obj", obj);
  RenderConfig config;
  config.scene = dir + "/scene.obj";
  config.cache = false;  // constant MTL materials: nothing to cache
  RenderSession session(config, test::cl());
  return session.render(s);  // these settings: camera, lights, samples
}

void set_camera(RenderSettings& s, D3 from, D3 at, D3 up, float fov) {
  s.camera.from[0] = float(from.x), s.camera.from[1] = float(from.y), s.camera.from[2] = float(from.z);
  s.camera.at[0] = float(at.x), s.camera.at[1] = float(at.y), s.camera.at[2] = float(at.z);
  s.camera.up[0] = float(up.x), s.camera.up[1] = float(up.y), s.camera.up[2] = float(up.z);
  s.camera.fov_degrees = fov;
}

// The camera looks straight down at the plane y = 0 from height 4.
RenderSettings top_view(int size, int spp) {
  RenderSettings s;
  s.width = s.height = size;
  s.spp = spp;
  s.max_depth = 2;
  set_camera(s, {0, 4, 0}, {0, 0, 0}, {0, 0, -1}, 60.0f);
  return s;
}

// Where the ray through image position (px, py) (pixels, continuous) meets
// y = 0, from the camera as the camera kernel builds it.
D3 plane_point(const RenderSettings& s, double px, double py) {
  PmcFrame f{};
  f.width = s.width;
  f.height = s.height;
  fill_frame_camera(s.camera, f);
  double sx = px / s.width * 2.0 - 1.0, sy = 1.0 - py / s.height * 2.0;
  D3 dir{f.cam_forward[0] + f.cam_right[0] * sx + f.cam_up[0] * sy,
         f.cam_forward[1] + f.cam_right[1] * sx + f.cam_up[1] * sy,
         f.cam_forward[2] + f.cam_right[2] * sx + f.cam_up[2] * sy};
  D3 eye{f.cam_eye[0], f.cam_eye[1], f.cam_eye[2]};
  return eye + dir * (-eye.y / dir.y);
}

// A pixel's expected value: `radiance(q)` of plane points averaged over a
// 6 x 6 grid inside the pixel (the film averages jittered samples).
template <class F>
double pixel_expectation(const RenderSettings& s, int x, int y, F&& radiance) {
  double sum = 0.0;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) sum += radiance(plane_point(s, x + (j + 0.5) / 6.0, y + (i + 0.5) / 6.0));
  return sum / 36.0;
}

// Lambert's formula for the irradiance at p (normal n) from a convex polygon
// of radiance L above p's horizon.
double polygon_irradiance(const std::vector<D3>& poly, D3 p, D3 n, double L) {
  double sum = 0.0;
  for (size_t i = 0; i < poly.size(); ++i) {
    D3 a = unit(poly[i] - p), b = unit(poly[(i + 1) % poly.size()] - p);
    sum += std::acos(std::max(-1.0, std::min(1.0, dot3(a, b)))) * dot3(n, unit(cross3(a, b)));
  }
  return 0.5 * L * std::fabs(sum);
}

LightSpec point_spec(D3 p, float intensity) {
  LightSpec l;
  l.type = LightSpec::Type::Point;
  l.position[0] = float(p.x), l.position[1] = float(p.y), l.position[2] = float(p.z);
  l.rgb[0] = l.rgb[1] = l.rgb[2] = intensity;
  return l;
}

const char* kGreyMtl = "newmtl m\nKd 0.5 0.5 0.5\nKs 0 0 0\n";

TEST(LightsRender, PointLightAboveDiffusePlaneGivesRhoOverPiICosOverD2) {
  const std::string dir = test::temp_dir();
  RenderSettings s = top_view(32, 64);  // enough samples that pixel jitter averages out
  const D3 light{0.5, 1.5, -0.3};
  s.lights.lights.push_back(point_spec(light, 4.0f));
  RenderOutput out = render_files(dir, plane_obj(4.0, "scene"), kGreyMtl, s);
  double worst = 0.0, sum = 0.0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      double expected = pixel_expectation(s, x, y, [&](D3 q) {
        D3 d = light - q;
        double d2 = dot3(d, d);
        return 0.5 / kPi * 4.0 * (d.y / std::sqrt(d2)) / d2;
      });
      double got = out.image.pixels[3 * (size_t(y) * s.width + x) + 1];
      worst = std::max(worst, std::fabs(got / expected - 1.0));
      sum += std::fabs(got / expected - 1.0);
    }
  EXPECT_LT(worst, 0.025);
  EXPECT_LT(sum / (s.width * s.height), 0.005);
}

TEST(LightsRender, SpotConeAndBlendFalloff) {
  const std::string dir = test::temp_dir();
  RenderSettings s = top_view(32, 64);
  const D3 light{0.2, 1.0, 0.1};
  LightSpec spot = point_spec(light, 3.0f);
  spot.type = LightSpec::Type::Spot;
  spot.direction[0] = 0.0f, spot.direction[1] = -1.0f, spot.direction[2] = 0.0f;
  spot.cone_angle_deg = 90.0f;  // full angle: 45 degrees from the axis
  spot.blend = 0.4f;            // fades over the outer 40%: from 27 to 45 degrees
  s.lights.lights.push_back(spot);
  RenderOutput out = render_files(dir, plane_obj(4.0, "scene"), kGreyMtl, s);
  // Where the spot is full, pixels match closely; in the fade (steep: a
  // pixel spans ~3 degrees) each is noisier, so the ring is also summed.
  int inside = 0, outside = 0;
  double worst_inside = 0.0, worst_fade = 0.0, ring_got = 0.0, ring_expected = 0.0, ring_hard = 0.0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      D3 centre = plane_point(s, x + 0.5, y + 0.5);
      double deg = std::acos(dot3(unit(centre - light), {0, -1, 0})) * 180.0 / kPi;
      double expected = pixel_expectation(s, x, y, [&](D3 q) {
        D3 d = light - q;
        double d2 = dot3(d, d);
        double a = std::acos(d.y / std::sqrt(d2)) * 180.0 / kPi;
        double t = std::min(1.0, std::max(0.0, (45.0 - a) / 18.0));
        return 0.5 / kPi * 3.0 * t * t * (3.0 - 2.0 * t) * (d.y / std::sqrt(d2)) / d2;
      });
      double got = out.image.pixels[3 * (size_t(y) * s.width + x)];
      if (deg < 24.0) {
        ++inside;
        worst_inside = std::max(worst_inside, std::fabs(got / expected - 1.0));
      } else if (deg > 30.0 && deg < 42.0) {
        worst_fade = std::max(worst_fade, std::fabs(got / expected - 1.0));
        ring_got += got;
        ring_expected += expected;
        ring_hard += pixel_expectation(s, x, y, [&](D3 q) {
          D3 d = light - q;
          double d2 = dot3(d, d);
          return 0.5 / kPi * 3.0 * (d.y / std::sqrt(d2)) / d2;
        });
      } else if (deg > 50.0) {  // a pixel spans about 3 degrees here
        ++outside;
        EXPECT_EQ(got, 0.0f) << x << "," << y;
      }
    }
  EXPECT_GT(inside, 20);
  EXPECT_GT(outside, 60);
  EXPECT_LT(worst_inside, 0.02);
  EXPECT_LT(worst_fade, 0.15);
  EXPECT_NEAR(ring_got, ring_expected, 0.01 * ring_expected);
  // A hard-edged cone (no blend) would light the ring fully: the check can fail.
  EXPECT_LT(ring_got, 0.75 * ring_hard);
}

// A path's last hit weighs its light sample against its BSDF sample too (the
// BSDF sample is traced for the emission it meets), so no sample there takes
// an area light's 1/d^2 at full weight. With the power heuristic a Lambertian
// hit's light sample adds at most L rho / 2 (w f cos / pdf_l <= f cos / (2
// pdf_b)), and its BSDF sample's emission at most rho L: at --max-depth 1 a
// floor sample is at most 1.5 rho L whatever its distance to the emitter,
// and one that sees the emitter (black, Kd 0) exactly L. An emissive triangle
// standing on the floor puts floor points as close to it as pixels go; light
// samples there without MIS reached hundreds.
TEST(LightsRender, LastHitsLightSampleIsWeighedByMisSoNoPixelPassesTheBound) {
  const std::string dir = test::temp_dir();
  RenderSettings s = top_view(64, 16);
  s.max_depth = 1;
  set_camera(s, {0.3, 1.2, 0.9}, {0, 0.1, 0}, {0, 1, 0},
             50.0f);  // the triangle's face and the floor at its base
  std::ostringstream obj;
  obj << plane_obj(4.0, "scene") << "usemtl lamp\nv -0.5 0 0\nv 0.5 0 0\nv 0 1 0\nf 5 6 7\n";
  const double L = 5.0, rho = 0.5;
  RenderOutput out =
      render_files(dir, obj.str(), std::string(kGreyMtl) + "newmtl lamp\nKd 0 0 0\nKe 5 5 5\n", s);
  ASSERT_LT(1.5 * rho * L, L);  // so every pixel, the lamp's and the floor's alike, is at most L
  double brightest = 0.0;
  int lamp = 0, dark = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const double v = out.image.pixels[3 * (size_t(y) * s.width + x) + 1];
      brightest = std::max(brightest, v);
      lamp += v > 0.999 * L;
      dark += v < 0.01;
    }
  EXPECT_GT(lamp, 100);                     // the lamp is in view...
  EXPECT_LT(dark, s.width * s.height / 4);  // ...and so is the floor it lights
  EXPECT_LE(brightest, L * (1.0 + 1e-4));
}

TEST(LightsRender, QuadLightEmitsFromOneSideUnlessTwoSided) {
  const std::string dir = test::temp_dir();
  const D3 corner{0.3, 1.0, -0.4}, eu{0.6, 0.0, 0.0}, ev{0.0, 0.0, 0.6};  // eu x ev = -y: faces down
  auto quad = [&](bool flipped, bool two_sided) {
    LightSpec q;
    q.type = LightSpec::Type::Quad;
    for (int k = 0; k < 3; ++k) {
      q.corner[k] = float((&corner.x)[k]);
      q.edge_u[k] = float(flipped ? (&ev.x)[k] : (&eu.x)[k]);
      q.edge_v[k] = float(flipped ? (&eu.x)[k] : (&ev.x)[k]);
      q.rgb[k] = 5.0f;
    }
    q.two_sided = two_sided;
    return q;
  };
  const std::vector<D3> poly = {corner, corner + eu, corner + eu + ev, corner + ev};
  auto through_quad = [&](const RenderSettings& s, int x, int y) {  // the pixel's centre ray crosses it
    D3 q = plane_point(s, x + 0.5, y + 0.5);
    D3 at = q + (D3{0, 4, 0} - q) * 0.25;  // the ray at height 1
    const double m = 0.15;                 // a pixel's footprint at that height is about 0.17 wide
    return at.x > corner.x - m && at.x < corner.x + 0.6 + m && at.z > corner.z - m &&
           at.z < corner.z + 0.6 + m;
  };
  for (int variant = 0; variant < 3; ++variant) {  // facing down, flipped, flipped two-sided
    RenderSettings s = top_view(20, 48);
    s.lights.lights.push_back(quad(variant > 0, variant == 2));
    RenderOutput out = render_files(dir, plane_obj(4.0, "scene"), kGreyMtl, s);
    double sum_got = 0.0, sum_expected = 0.0;
    int lit = 0;
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x) {
        if (through_quad(s, x, y)) continue;
        double got = out.image.pixels[3 * (size_t(y) * s.width + x) + 2];
        if (variant == 1) {
          EXPECT_EQ(got, 0.0f) << "the quad's back lit the plane at " << x << "," << y;
          continue;
        }
        D3 q = plane_point(s, x + 0.5, y + 0.5);
        double expected = 0.5 / kPi * polygon_irradiance(poly, q, {0, 1, 0}, 5.0);
        sum_got += got;
        sum_expected += expected;
        EXPECT_NEAR(got, expected, 0.15 * expected + 0.01) << variant << ": " << x << "," << y;
        ++lit;
      }
    if (variant != 1) {
      EXPECT_GT(lit, 300);
      EXPECT_NEAR(sum_got, sum_expected, 0.02 * sum_expected) << "variant " << variant;
    }
    // Seen from above (its front when flipped): the camera sees its radiance over the plane's.
    const int cx = 13, cy = 10;  // a pixel well inside the quad's image
    ASSERT_TRUE(through_quad(s, cx, cy));
    float centre = out.image.pixels[3 * (size_t(cy) * s.width + cx)];
    if (variant == 1)
      EXPECT_NEAR(centre, 5.0f, 1e-4f);
    else if (variant == 0)
      EXPECT_LT(centre, 1.0f);  // through its back: only the lit plane
    else
      EXPECT_GT(centre, 5.0f);
  }
}

// A camera inside the unit sphere, away from its centre, looking at its wall.
RenderSettings inside_sphere_view() {
  RenderSettings s;
  s.width = 32;
  s.height = 24;
  s.spp = 32;
  s.max_depth = 100;
  set_camera(s, {0, 0, 0.5}, {0.3, 0.1, 1.0}, {0, 1, 0}, 70.0f);
  return s;
}

// Inside a closed sphere of albedo a whose walls all receive the same direct
// irradiance E, every wall point has radiance L = (a/pi) (E + pi L f), f the
// fraction of the cosine-weighted hemisphere that sees walls.
TEST(LightsRender, PointLightAndSphereLightInClosedDiffuseSphere) {
  const std::string dir = test::temp_dir();
  const double a = 0.5;
  RenderSettings s = inside_sphere_view();
  const std::string mtl =
      "newmtl wall\nKd 0.5 0.5 0.5\nKs 0 0 0\nnewmtl bulb\nKd 0 0 0\nKs 0 0 0\nKe 25 25 25\n";
  // Point light of intensity pi at the centre of a unit sphere: E = pi, L = a / (1 - a) = 1.
  {
    RenderSettings sp = s;
    sp.lights.lights.push_back(point_spec({0, 0, 0}, float(kPi)));
    RenderOutput out =
        render_files(dir, "mtllib scene.mtl\n" + sphere_obj({0, 0, 0}, 1.0, 48, 96, "wall"), mtl, sp);
    EXPECT_EQ(out.stats.nan_pixels, 0u);
    RecordProperty("point_furnace_mean", std::to_string(test::image_mean(out.image)));
    EXPECT_NEAR(test::image_mean(out.image), a / (1.0 - a), 0.015);
  }
  // An emissive sphere of radius r = 0.2 and radiance 25 (black, so it absorbs):
  // E = pi Le (r/R)^2 and the walls see it in sin^2 = (r/R)^2 of the
  // cosine-weighted hemisphere, so L = a Le (r/R)^2 / (1 - a (1 - (r/R)^2)).
  {
    const int v = sphere_vertices(48, 96);
    RenderOutput out = render_files(dir,
                                    "mtllib scene.mtl\n" + sphere_obj({0, 0, 0}, 1.0, 48, 96, "wall") +
                                        sphere_obj({0, 0, 0}, 0.2, 24, 48, "bulb", v),
                                    mtl, s);
    const double k = 0.04, expected = a * 25.0 * k / (1.0 - a * (1.0 - k));
    EXPECT_EQ(out.stats.nan_pixels, 0u);
    RecordProperty("sphere_light_furnace_over_expected",
                   std::to_string(test::image_mean(out.image) / expected));
    EXPECT_NEAR(test::image_mean(out.image), expected, 0.02 * expected);
  }
}

// Light sample clamping (clamp_direct): under a point light a sample's only
// contribution is its next-event estimate, rho/pi I cos / d^2 at its plane
// point, so the clamped pixel is the average of that value capped at the
// limit in its largest channel, the other channels scaled alike (the light's
// colour 4 : 2 : 1 kept). The plane has no indirect light, so clamp_indirect
// alone changes no bit.
TEST(LightsRender, DirectClampCapsEachSampleAndKeepsItsHue) {
  const std::string dir = test::temp_dir();
  RenderSettings s = top_view(32, 64);
  const D3 light{0.5, 1.5, -0.3};
  LightSpec l = point_spec(light, 4.0f);
  l.rgb[1] = 2.0f, l.rgb[2] = 1.0f;
  s.lights.lights.push_back(l);
  const float limit = 0.15f;  // below the brightest third of the pixels (0.28 under the light)
  auto red = [&](D3 q) {
    D3 d = light - q;
    double d2 = dot3(d, d);
    return 0.5 / kPi * 4.0 * (d.y / std::sqrt(d2)) / d2;
  };
  RenderSettings clamped = s;
  clamped.clamp_direct = limit;
  const RenderOutput out = render_files(dir, plane_obj(4.0, "scene"), kGreyMtl, clamped);
  double worst = 0.0;
  int capped = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const double expected =
          pixel_expectation(s, x, y, [&](D3 q) { return std::min(red(q), double(limit)); });
      const float* px = &out.image.pixels[3 * (size_t(y) * s.width + x)];
      worst = std::max(worst, std::fabs(px[0] / expected - 1.0));
      EXPECT_NEAR(px[1], 0.5 * px[0], 1e-5 * px[0]) << x << "," << y;
      EXPECT_NEAR(px[2], 0.25 * px[0], 1e-5 * px[0]) << x << "," << y;
      EXPECT_LE(px[0], limit * (1.0f + 1e-6f)) << x << "," << y;
      capped += px[0] > 0.99f * limit;
    }
  EXPECT_LT(worst, 0.025);
  EXPECT_GT(capped, 20);  // the limit did cut: the check can fail

  RenderSettings indirect_only = s;
  indirect_only.clamp_indirect = 1e-6f;
  const RenderOutput plain = render_files(dir, plane_obj(4.0, "scene"), kGreyMtl, s);
  const RenderOutput same = render_files(dir, plane_obj(4.0, "scene"), kGreyMtl, indirect_only);
  EXPECT_EQ(plain.image.pixels, same.image.pixels);
}

// In the closed sphere of albedo a around a point light of intensity pi, the
// walls' direct radiance is a and their whole radiance a / (1 - a) (the test
// above). A tiny clamp_indirect leaves the direct light alone (light reaching
// the camera ray's hit: its next-event estimates); a tiny clamp_direct leaves
// the indirect light alone. a = 0.75 tells the two apart: 0.75 against 2.25.
// Emitters that BSDF samples hit are checked below.
TEST(LightsRender, ClampsSplitTheClosedSphereIntoItsDirectAndIndirectLight) {
  const std::string dir = test::temp_dir();
  const double a = 0.75;
  RenderSettings s = inside_sphere_view();
  s.lights.lights.push_back(point_spec({0, 0, 0}, float(kPi)));
  const std::string obj = "mtllib scene.mtl\n" + sphere_obj({0, 0, 0}, 1.0, 48, 96, "wall");
  const std::string mtl = "newmtl wall\nKd 0.75 0.75 0.75\nKs 0 0 0\n";
  RenderSettings direct_only = s, indirect_only = s;
  direct_only.clamp_indirect = 1e-9f;
  indirect_only.clamp_direct = 1e-9f;
  const double direct = test::image_mean(render_files(dir, obj, mtl, direct_only).image);
  const double indirect = test::image_mean(render_files(dir, obj, mtl, indirect_only).image);
  RecordProperty("direct", std::to_string(direct));
  RecordProperty("indirect", std::to_string(indirect));
  EXPECT_NEAR(direct, a, 0.01 * a);
  EXPECT_NEAR(indirect, a / (1.0 - a) - a, 0.03 * a / (1.0 - a));

  // Light that BSDF samples reach counts by the hit it lights, too. Walls
  // that emit Le = 1 themselves have radiance Le / (1 - a) = 4: Le seen
  // directly and a Le reaching the first hit (much of it, by MIS, through
  // BSDF rays that hit a wall) are direct, the rest indirect.
  RenderSettings glow = direct_only;
  glow.lights.lights.clear();
  const std::string glow_mtl = "newmtl wall\nKd 0.75 0.75 0.75\nKs 0 0 0\nKe 1 1 1\n";
  const double glow_direct = test::image_mean(render_files(dir, obj, glow_mtl, glow).image);
  RecordProperty("glowing_walls_direct", std::to_string(glow_direct));
  EXPECT_NEAR(glow_direct, 1.0 + a, 0.01 * (1.0 + a));
}

// ... and so does the sky: a grey plane under a constant environment of
// radiance 1 has radiance a = 0.5, most of it (by MIS) from BSDF rays that
// escape. Counted as indirect light, a tiny clamp would take it away.
TEST(LightsRender, IndirectClampKeepsTheSkyThatTheFirstHitsBsdfRaysSee) {
  const std::string dir = test::temp_dir();
  RenderSettings s = top_view(16, 32);
  s.env[0] = s.env[1] = s.env[2] = 1.0f;
  s.clamp_indirect = 1e-9f;
  const RenderOutput out = render_files(dir, plane_obj(4.0, "scene"), kGreyMtl, s);
  EXPECT_NEAR(test::image_mean(out.image), 0.5, 0.01);
}

// Thirty-two lights (points, spots, one-sided quads) above a grey plane: both
// samplers agree with the exact image (rho/pi x the sum of the lights'
// irradiance, the BSDF rays' MIS against the quads included), and at equal
// samples the light tree, which follows the shading point, is less noisy
// than the pick by power.
TEST(LightsRender, ManyLightsTreeAndPowerMatchTheExactImageAndTheTreeIsLessNoisy) {
  const std::string dir = test::temp_dir();
  std::mt19937 gen(12);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * double(gen() >> 8) / 16777216.0; };
  struct Point {
    D3 p, axis;
    double intensity, outer_deg, blend;
    bool spot;
  };
  struct Quad {
    D3 corner, eu, ev;
    double radiance;
  };
  std::vector<Point> points;
  std::vector<Quad> quads;
  RenderSettings base = top_view(40, 16);
  for (int i = 0; i < 24; ++i) {
    Point pt{{uniform(-3, 3), uniform(0.3, 2.0), uniform(-3, 3)},
             unit({uniform(-0.5, 0.5), -1.0, uniform(-0.5, 0.5)}),
             uniform(0.05, 1.0),
             uniform(30, 80),
             uniform(0.1, 0.6),
             i % 3 == 0};
    points.push_back(pt);
    LightSpec l = point_spec(pt.p, float(pt.intensity));
    if (pt.spot) {
      l.type = LightSpec::Type::Spot;
      l.direction[0] = float(pt.axis.x), l.direction[1] = float(pt.axis.y), l.direction[2] = float(pt.axis.z);
      l.cone_angle_deg = float(2.0 * pt.outer_deg);
      l.blend = float(pt.blend);
    }
    base.lights.lights.push_back(l);
  }
  for (int i = 0; i < 8; ++i) {
    const double w = uniform(0.1, 0.5), d = uniform(0.1, 0.5);
    Quad q{{uniform(-3, 3), uniform(0.5, 2.5), uniform(-3, 3)}, {w, 0, 0}, {0, 0, d}, uniform(0.2, 2.0)};
    quads.push_back(q);  // edge_u x edge_v = -y: faces down
    LightSpec l;
    l.type = LightSpec::Type::Quad;
    for (int k = 0; k < 3; ++k) {
      l.corner[k] = float((&q.corner.x)[k]);
      l.edge_u[k] = float((&q.eu.x)[k]);
      l.edge_v[k] = float((&q.ev.x)[k]);
      l.rgb[k] = float(q.radiance);
    }
    base.lights.lights.push_back(l);
  }
  auto radiance = [&](D3 q) {
    double e = 0.0;
    for (const Point& pt : points) {
      D3 d = pt.p - q;
      double d2 = dot3(d, d), c = d.y / std::sqrt(d2), falloff = 1.0;
      if (pt.spot) {
        double a = std::acos(std::max(-1.0, std::min(1.0, -dot3(unit(d), pt.axis)))) * 180.0 / kPi;
        double inner = pt.outer_deg * (1.0 - pt.blend);
        double t = std::min(1.0, std::max(0.0, (pt.outer_deg - a) / (pt.outer_deg - inner)));
        falloff = a <= inner ? 1.0 : a >= pt.outer_deg ? 0.0 : t * t * (3.0 - 2.0 * t);
      }
      e += pt.intensity * falloff * c / d2;
    }
    for (const Quad& qd : quads)
      e += polygon_irradiance({qd.corner, qd.corner + qd.eu, qd.corner + qd.eu + qd.ev, qd.corner + qd.ev}, q,
                              {0, 1, 0}, qd.radiance);
    return 0.5 / kPi * e;
  };
  std::vector<double> expected(size_t(base.width * base.height));
  for (int y = 0; y < base.height; ++y)
    for (int x = 0; x < base.width; ++x)
      expected[size_t(y * base.width + x)] = pixel_expectation(base, x, y, radiance);
  double rel_mse[2];
  for (int tree = 0; tree < 2; ++tree) {
    RenderSettings s = base;
    s.light_tree = tree == 1;
    RenderOutput out = render_files(dir, plane_obj(4.0, "scene"), kGreyMtl, s);
    EXPECT_EQ(out.stats.nan_pixels, 0u);
    double diff = 0.0, diff2 = 0.0, err = 0.0;
    const size_t n = expected.size();
    for (size_t i = 0; i < n; ++i) {
      const double got = out.image.pixels[3 * i + 1], want = expected[i], r = (got - want) / want;
      diff += r;
      diff2 += r * r;
      err += (got - want) * (got - want) / (want * want + 1e-4);
    }
    const double mean = diff / double(n), stderr_ = std::sqrt((diff2 / double(n) - mean * mean) / double(n));
    rel_mse[tree] = err / double(n);
    const char* name = tree ? "tree" : "power";
    EXPECT_LT(std::fabs(mean), 4.0 * stderr_ + 2e-3)
        << name << ": the mean relative error is off by " << mean / stderr_ << " standard errors";
    RecordProperty(std::string(name) + "_rel_mse", std::to_string(rel_mse[tree]));
    std::printf("%s: relMSE %.4g, mean relative error %.2g +- %.2g\n", name, rel_mse[tree], mean, stderr_);
  }
  EXPECT_LT(rel_mse[1], 0.7 * rel_mse[0]) << "the tree should need fewer samples for the same noise";
}

// --- environment maps ---------------------------------------------------

void write_map(const std::string& path, int w, int h, const std::function<void(double, double, float*)>& f) {
  Image img;
  img.width = w;
  img.height = h;
  img.channels = 3;
  img.pixels.resize(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) f((x + 0.5) / w, (y + 0.5) / h, &img.pixels[3 * (size_t(y) * w + x)]);
  write_exr(path, img);
}

// A sphere of radius 0.5 resting on a plane, seen at an angle.
std::string ball_on_plane_obj() {
  return plane_obj(3.0, "scene") + sphere_obj({0, 0.5, 0}, 0.5, 16, 32, "m", 4);
}

RenderSettings ball_view() {
  RenderSettings s;
  s.width = 40;
  s.height = 30;
  s.spp = 24;
  s.max_depth = 4;
  set_camera(s, {1.5, 1.6, 2.5}, {0, 0.4, 0}, {0, 1, 0}, 45.0f);
  return s;
}

// Means over 4 x 3 blocks of the image.
std::vector<double> block_means(const Image& img) {
  std::vector<double> m(12, 0.0);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c)
        m[size_t((y * 3 / img.height) * 4 + x * 4 / img.width)] +=
            img.pixels[3 * (size_t(y) * img.width + x) + c];
  for (double& v : m) v /= 3.0 * (img.width / 4) * (img.height / 3);
  return m;
}

TEST(LightsRender, ConstantMapEqualsConstantEnvironment) {
  const std::string dir = test::temp_dir();
  write_map(dir + "/grey.exr", 16, 8,
            [](double, double, float* c) { c[0] = 0.6f, c[1] = 0.5f, c[2] = 0.4f; });
  RenderSettings with_env = ball_view();
  with_env.env[0] = 0.6f, with_env.env[1] = 0.5f, with_env.env[2] = 0.4f;
  RenderOutput a = render_files(dir, ball_on_plane_obj(), kGreyMtl, with_env);
  RenderSettings with_map = ball_view();
  with_map.lights.environment = environment_from_map(dir + "/grey.exr", 1.0f, 33.0f);
  RenderOutput b = render_files(dir, ball_on_plane_obj(), kGreyMtl, with_map);
  RecordProperty("map_over_env", std::to_string(test::image_mean(b.image) / test::image_mean(a.image)));
  EXPECT_NEAR(test::image_mean(b.image), test::image_mean(a.image), 0.01 * test::image_mean(a.image));
  std::vector<double> ma = block_means(a.image), mb = block_means(b.image);
  for (size_t i = 0; i < ma.size(); ++i) EXPECT_NEAR(mb[i], ma[i], 0.03 * ma[i]) << "block " << i;
  // Half the map's brightness is half the image (the comparison can fail).
  with_map.lights.environment.scale = 0.5f;
  RenderOutput c = render_files(dir, ball_on_plane_obj(), kGreyMtl, with_map);
  EXPECT_NEAR(test::image_mean(c.image), 0.5 * test::image_mean(a.image), 0.01 * test::image_mean(a.image));
}

TEST(LightsRender, MapOrientationFollowsTheConvention) {
  const std::string dir = test::temp_dir();
  // Red around u = 0.5 (-Z), green around u = 0.75 (+X), both on the horizon.
  write_map(dir + "/marks.exr", 64, 32, [](double u, double v, float* c) {
    c[0] = c[1] = c[2] = 0.0f;
    if (std::fabs(v - 0.5) < 0.06 && std::fabs(u - 0.5) < 0.04) c[0] = 4.0f;
    if (std::fabs(v - 0.5) < 0.06 && std::fabs(u - 0.75) < 0.04) c[1] = 4.0f;
  });
  const std::string far_ball = "mtllib scene.mtl\n" + sphere_obj({0, -50, 0}, 0.1, 6, 8, "m");
  auto centre_pixel = [&](D3 look, float rotate) {
    RenderSettings s;
    s.width = s.height = 9;
    s.spp = 1;
    set_camera(s, {0, 0, 0}, look, {0, 1, 0}, 5.0f);
    s.lights.environment = environment_from_map(dir + "/marks.exr", 1.0f, rotate);
    RenderOutput out = render_files(dir, far_ball, kGreyMtl, s);
    const float* p = &out.image.pixels[3 * (4 * 9 + 4)];
    return std::vector<float>{p[0], p[1], p[2]};
  };
  EXPECT_EQ(centre_pixel({0, 0, -1}, 0.0f), (std::vector<float>{4, 0, 0}));  // looking along -Z: the centre
  EXPECT_EQ(centre_pixel({1, 0, 0}, 0.0f), (std::vector<float>{0, 4, 0}));   // along +X: u = 0.75
  EXPECT_EQ(centre_pixel({0, 0, 1}, 0.0f), (std::vector<float>{0, 0, 0}));
  // Turned 90 degrees counter-clockwise (seen from above): -Z moves to -X, +X to -Z.
  EXPECT_EQ(centre_pixel({-1, 0, 0}, 90.0f), (std::vector<float>{4, 0, 0}));
  EXPECT_EQ(centre_pixel({0, 0, -1}, 90.0f), (std::vector<float>{0, 4, 0}));

  // A ball seen from +Z: the green light from +X falls on its right side only.
  RenderSettings s;
  s.width = 32;
  s.height = 16;
  s.spp = 16;
  set_camera(s, {0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 20.0f);
  s.lights.environment = environment_from_map(dir + "/marks.exr", 1.0f, 0.0f);
  RenderOutput out =
      render_files(dir, "mtllib scene.mtl\n" + sphere_obj({0, 0, 0}, 1.0, 24, 48, "m"), kGreyMtl, s);
  double left = 0.0, right = 0.0;
  for (int y = 6; y < 10; ++y)
    for (int x = 0; x < 32; ++x) {
      double g = out.image.pixels[3 * (size_t(y) * 32 + x) + 1];
      if (x >= 5 && x < 10) left += g;    // on the ball, facing -X (it spans columns 4 to 27)
      if (x >= 20 && x < 25) right += g;  // on the ball, facing +X
    }
  EXPECT_EQ(left, 0.0);
  EXPECT_GT(right, 0.3);
}

// Exact irradiance on an upward plane from a map (piecewise-constant texels;
// 8 x 8 midpoint rule inside each texel), written from the convention.
double map_irradiance_up(const Image& map, double scale) {
  double total = 0.0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const float* c = &map.pixels[size_t(map.channels) * (size_t(y) * map.width + x)];
      double L = map.channels >= 3 ? 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2] : c[0];
      double acc = 0.0;
      for (int i = 0; i < 8; ++i) {
        double theta = (y + (i + 0.5) / 8.0) / map.height * kPi;
        acc += std::max(0.0, std::cos(theta)) * std::sin(theta) * 8.0;
      }
      total += scale * std::max(0.0, L) * acc * 2.0 * kPi * kPi / (double(map.width) * map.height * 64.0);
    }
  return total;
}

double rel_mse(const Image& img, double reference) {
  double sum = 0.0;
  for (int i = 0; i < img.width * img.height; ++i) {
    const float* c = &img.pixels[3 * size_t(i)];
    double l = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    sum += (l - reference) * (l - reference) / (reference * reference);
  }
  return sum / (img.width * img.height);
}

TEST(LightsRender, ImportanceSamplingBeatsUniformOnASunLikeMap) {
  const std::string dir = test::temp_dir();
  // A dim sky and one bright texel 40 degrees above the horizon.
  write_map(dir + "/sun.exr", 128, 64, [](double u, double v, float* c) {
    c[0] = c[1] = c[2] = 0.05f;
    if (int(u * 128) == 40 && int(v * 64) == 16) c[0] = c[1] = c[2] = 5000.0f;
  });
  const double exact = 0.5 / kPi * map_irradiance_up(read_image(dir + "/sun.exr"), 1.0);
  RenderSettings s = top_view(16, 4);
  s.max_depth = 1;
  s.lights.environment = environment_from_map(dir + "/sun.exr", 1.0f, 0.0f);
  RenderOutput is = render_files(dir, plane_obj(4.0, "scene"), kGreyMtl, s);
  s.env_importance = false;
  RenderOutput uniform = render_files(dir, plane_obj(4.0, "scene"), kGreyMtl, s);
  const double e_is = rel_mse(is.image, exact), e_uniform = rel_mse(uniform.image, exact);
  RecordProperty("relmse_importance", std::to_string(e_is));
  RecordProperty("relmse_uniform", std::to_string(e_uniform));
  // Both estimate the same image (the importance-sampled one closely) ...
  EXPECT_NEAR(test::image_mean(is.image), exact, 0.03 * exact);
  EXPECT_LT(e_is, 0.03);  // measured 0.009 (uniform: 0.95)
  // ... and importance sampling has far less error at equal samples.
  EXPECT_LT(e_is * 20.0, e_uniform) << "relMSE importance " << e_is << ", uniform " << e_uniform;
}

TEST(LightsRender, SharedHdrMapsLoadAndLightAPlaneAsTheirTexelsSay) {
  const std::string dir = test::temp_dir();
  for (const char* name : {"goegap.hdr", "san_giuseppe_bridge.hdr", "table_mountain.hdr"}) {
    const std::string path = test::shared_scene(std::string("envmaps/") + name);
    EnvironmentSpec env = environment_from_map(path, 1.0f, 0.0f);
    ASSERT_GT(env.map->width, 0) << name;
    ASSERT_GT(env.map->height, 0) << name;
    const double exact = 0.5 / kPi * map_irradiance_up(read_image(path), 1.0);
    ASSERT_GT(exact, 0.0) << name;
    RenderSettings s = top_view(16, 32);
    s.max_depth = 1;
    s.lights.environment = env;
    RenderOutput out = render_files(dir, plane_obj(4.0, "scene"), kGreyMtl, s);
    EXPECT_EQ(out.stats.nan_pixels, 0u) << name;
    double l = 0.0;
    for (int i = 0; i < s.width * s.height; ++i) {
      const float* c = &out.image.pixels[3 * size_t(i)];
      l += 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    }
    EXPECT_NEAR(l / (s.width * s.height), exact, 0.02 * exact) << name;
  }
}

}  // namespace
}  // namespace pmc

namespace pmc {
namespace {

// A session keeps its light table while a render's lights stay those of the
// one before (pmc compare, sweeps), and builds a new one when they change:
// each render's image is the one a fresh session renders with its lights.
TEST(LightsRender, ASessionKeepsItsLightTableOnlyWhileTheLightsStayTheSame) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/scene.mtl", std::string(kGreyMtl) + "newmtl glow\nKd 0 0 0\nKe 3 3 3\n");
  test::write_file(dir + "/scene.obj",
                   plane_obj(2.0, "scene") + sphere_obj({0, 1.5, 0}, 0.3, 6, 8, "glow", 4));
  RenderConfig config;
  config.scene = dir + "/scene.obj";
  config.cache = false;
  RenderSettings s = top_view(24, 4);
  s.lights.lights.push_back(point_spec({1, 2, 0}, 2.0f));
  RenderSettings moved = s;
  moved.lights.lights[0].position[0] = -1.0f;
  RenderSettings by_power = s;
  by_power.light_tree = false;
  auto fresh = [&](const RenderSettings& settings) {
    return RenderSession(config, test::cl()).render(settings);
  };

  RenderSession session(config, test::cl());
  const RenderOutput first = session.render(s), again = session.render(s);
  EXPECT_FALSE(first.stats.lights.reused);
  EXPECT_TRUE(again.stats.lights.reused);
  EXPECT_EQ(again.stats.lights.build_seconds, 0.0);
  EXPECT_EQ(again.stats.lights.count, first.stats.lights.count);
  EXPECT_EQ(test::differing_values(first.image, again.image), 0u);
  for (const RenderSettings* next : {&moved, &by_power, &s}) {
    const RenderOutput out = session.render(*next);
    EXPECT_FALSE(out.stats.lights.reused);
    EXPECT_EQ(test::differing_values(out.image, fresh(*next).image), 0u);
  }
  EXPECT_GT(test::differing_values(first.image, fresh(moved).image), 0u);  // the comparison can fail
}

// A sky map's table is the buffer memory itself on CPU devices (no device
// copy: core/pool_memory.h), so a session that moves from one sky to another
// and back must drop the old table's buffer with the table: each render
// still shows the sky a fresh session renders.
TEST(LightsRender, ASessionSwitchingSkyMapsRendersEachAsAFreshSessionDoes) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/scene.mtl", kGreyMtl);
  test::write_file(dir + "/scene.obj", plane_obj(2.0, "scene"));
  RenderConfig config;
  config.scene = dir + "/scene.obj";
  config.cache = false;
  RenderSettings mountain = top_view(24, 4), bridge = mountain;
  mountain.lights.environment =
      environment_from_map(test::shared_scene("envmaps/table_mountain.hdr"), 1.0f, 0.0f);
  bridge.lights.environment =
      environment_from_map(test::shared_scene("envmaps/san_giuseppe_bridge.hdr"), 1.0f, 0.0f);
  RenderSession session(config, test::cl());
  for (const RenderSettings* next : {&mountain, &bridge, &mountain}) {
    const RenderOutput out = session.render(*next);
    EXPECT_GT(test::image_mean(out.image), 0.0);
    EXPECT_EQ(test::differing_values(out.image, RenderSession(config, test::cl()).render(*next).image), 0u);
  }
  EXPECT_GT(test::differing_values(session.render(mountain).image, session.render(bridge).image), 0u);
}

}  // namespace
}  // namespace pmc
