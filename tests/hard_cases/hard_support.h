// hard_support.h — small helpers shared by the hard-case tests (header only:
// CMake compiles tests/**/*_test.cpp, nothing else from this folder).
//
// * OBJ text builders (quads, boxes, a scaled test scene) that write plain
//   numbers with full float precision;
// * image writers (PNG / float EXR through OpenImageIO) for textures;
// * render(): a RenderSession (gpu/render_session.h) of an OBJ and its
//   materials (MTL or MaterialX) with the progressive material cache on or
//   off, as `pmc render` renders;
// * expect_clean(): the image has no NaN/Inf and the stats report none.
#pragma once

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "gpu/render_session.h"
#include "tests/support/test_support.h"

namespace pmc::hard {

inline std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// OBJ fragment builder with running vertex/uv counters (1-based indices).
struct ObjText {
  std::ostringstream os;
  int nv = 0, nt = 0, nn = 0;
  int v(double x, double y, double z) {
    os << "v " << num(x) << " " << num(y) << " " << num(z) << "\n";
    return ++nv;
  }
  int vt(double u, double w) {
    os << "vt " << num(u) << " " << num(w) << "\n";
    return ++nt;
  }
  int vn(double x, double y, double z) {
    os << "vn " << num(x) << " " << num(y) << " " << num(z) << "\n";
    return ++nn;
  }
  void line(const std::string& s) { os << s << "\n"; }
  void f(int a, int b, int c) { os << "f " << a << " " << b << " " << c << "\n"; }
  void ft(int a, int ta, int b, int tb, int c, int tc) {
    os << "f " << a << "/" << ta << " " << b << "/" << tb << " " << c << "/" << tc << "\n";
  }
  // An axis-aligned quad given by its four corners (counter-clockwise), with
  // uvs (u0,v0)-(u1,v1) across it.
  void quad(const double p[4][3], double u0 = 0, double v0 = 0, double u1 = 1, double v1 = 1) {
    int a = v(p[0][0], p[0][1], p[0][2]), b = v(p[1][0], p[1][1], p[1][2]);
    int c = v(p[2][0], p[2][1], p[2][2]), d = v(p[3][0], p[3][1], p[3][2]);
    int ta = vt(u0, v0), tb = vt(u1, v0), tc = vt(u1, v1), td = vt(u0, v1);
    ft(a, ta, b, tb, c, tc);
    ft(a, ta, c, tc, d, td);
  }
  // A closed axis-aligned box [lo, hi] of 12 triangles sharing 8 vertices
  // (watertight: every edge is shared by exactly two triangles).
  void box(const double lo[3], const double hi[3]) {
    int base = nv;
    for (int i = 0; i < 8; ++i) v(i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]);
    static const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : faces) {
      f(base + 1 + q[0], base + 1 + q[1], base + 1 + q[2]);
      f(base + 1 + q[0], base + 1 + q[2], base + 1 + q[3]);
    }
  }
  std::string str() const { return os.str(); }
};

// An RGB 8-bit PNG (or any format OIIO infers from the extension) from floats in [0,1].
inline void write_image(const std::string& path, int w, int h, int channels, const std::vector<float>& px,
                        OIIO::TypeDesc format = OIIO::TypeDesc::UINT8) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << path << ": " << OIIO::geterror();
  OIIO::ImageSpec spec(w, h, channels, format);
  ASSERT_TRUE(out->open(path, spec)) << path << ": " << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data())) << path << ": " << out->geterror();
  out->close();
}

// A w x h two-colour checker (RGB, 8-bit).
inline void write_checker_png(const std::string& path, int w = 16, int h = 16) {
  std::vector<float> px;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool a = ((x / 2) + (y / 2)) % 2 == 0;
      px.push_back(a ? 0.9f : 0.1f);
      px.push_back(a ? 0.7f : 0.2f);
      px.push_back(a ? 0.3f : 0.6f);
    }
  write_image(path, w, h, 3, px);
}

// A small MaterialX document with procedural and image-based materials on
// uv chains long enough (>= 4 nodes) to get cache points:
//   M_noise : base_color = |noise2d(uv * 8)| * colour + 0.1
//   M_tiled : base_color = tiledimage(image, uv, tiling 3) * colour
//   M_bright: a procedural emitter, emission_color = |noise2d(uv*4)| * 1e6 (not
//             encodable as RGB9E5, whose largest value is 65408)
inline std::string materials_mtlx(const std::string& image) {
  return R"(<?xml version="1.0"?>
<materialx version="1.39">
  <texcoord name="uv" type="vector2"/>
  <multiply name="uv8" type="vector2">
    <input name="in1" type="vector2" nodename="uv"/>
    <input name="in2" type="vector2" value="8.0, 8.0"/>
  </multiply>
  <noise2d name="n" type="color3">
    <input name="texcoord" type="vector2" nodename="uv8"/>
    <input name="amplitude" type="color3" value="1.0, 1.0, 1.0"/>
  </noise2d>
  <absval name="na" type="color3"><input name="in" type="color3" nodename="n"/></absval>
  <multiply name="nc" type="color3">
    <input name="in1" type="color3" nodename="na"/>
    <input name="in2" type="color3" value="0.6, 0.5, 0.4"/>
  </multiply>
  <add name="nb" type="color3">
    <input name="in1" type="color3" nodename="nc"/>
    <input name="in2" type="color3" value="0.1, 0.1, 0.1"/>
  </add>
  <standard_surface name="S_noise" type="surfaceshader">
    <input name="base_color" type="color3" nodename="nb"/>
    <input name="specular" type="float" value="0.2"/>
  </standard_surface>
  <surfacematerial name="M_noise" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S_noise"/>
  </surfacematerial>

  <tiledimage name="img" type="color3">
    <input name="file" type="filename" value=")" +
         image + R"(" colorspace="srgb_texture"/>
    <input name="uvtiling" type="vector2" value="3.0, 3.0"/>
  </tiledimage>
  <multiply name="imgc" type="color3">
    <input name="in1" type="color3" nodename="img"/>
    <input name="in2" type="color3" value="0.8, 0.8, 0.8"/>
  </multiply>
  <standard_surface name="S_tiled" type="surfaceshader">
    <input name="base_color" type="color3" nodename="imgc"/>
    <input name="specular" type="float" value="0.0"/>
  </standard_surface>
  <surfacematerial name="M_tiled" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S_tiled"/>
  </surfacematerial>

  <multiply name="uv4" type="vector2">
    <input name="in1" type="vector2" nodename="uv"/>
    <input name="in2" type="vector2" value="4.0, 4.0"/>
  </multiply>
  <noise2d name="e" type="color3">
    <input name="texcoord" type="vector2" nodename="uv4"/>
  </noise2d>
  <absval name="ea" type="color3"><input name="in" type="color3" nodename="e"/></absval>
  <multiply name="eb" type="color3">
    <input name="in1" type="color3" nodename="ea"/>
    <input name="in2" type="color3" value="1000000.0, 1000000.0, 1000000.0"/>
  </multiply>
  <standard_surface name="S_bright" type="surfaceshader">
    <input name="base_color" type="color3" value="0.5, 0.5, 0.5"/>
    <input name="emission" type="float" value="1.0"/>
    <input name="emission_color" type="color3" nodename="eb"/>
  </standard_surface>
  <surfacematerial name="M_bright" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S_bright"/>
  </surfacematerial>
</materialx>
)";
}

struct RenderCase {
  std::string obj;
  std::vector<std::string> mtlx;  // --mtlx documents
  std::string material;           // --material override ("" = the OBJ's own)
  int cache_min_nodes = 2;        // low, so MTL texture chains get cache points too
};

struct Rendered {
  RenderOutput out;
  size_t skipped_triangles = 0;
  size_t cache_points = 0;
};

// `config` with the case's scene and materials; a table of 2^14 cells x 8
// entries unless the config names one.
inline Rendered render(const RenderCase& c, RenderConfig config, bool cache) {
  config.scene = c.obj;
  config.mtlx = c.mtlx;
  config.material = c.material;
  config.cache = cache;
  config.cache_min_nodes = c.cache_min_nodes;
  // The node count alone: these frames are too small for their points to pay.
  config.cache_model = CacheModel::Nodes;
  if (!config.cache_cells) config.cache_cells = 1 << 14;
  RenderSession session(config, test::cl());
  Rendered r;
  r.skipped_triangles = session.scene().skipped_triangles;
  r.cache_points = session.cache_points();
  r.out = session.render();
  return r;
}

// No NaN/Inf anywhere: image, nan_pixels, and no sample dropped as NaN/Inf.
inline void expect_clean(const RenderOutput& out, const std::string& what) {
  EXPECT_EQ(test::non_finite(out.image), 0u) << what;
  EXPECT_EQ(out.stats.nan_pixels, 0u) << what;
  EXPECT_EQ(out.stats.bad_samples, 0u) << what << ": NaN/Inf path samples were dropped";
  EXPECT_TRUE(std::isfinite(test::image_mean(out.image))) << what;
}

inline void set_camera(RenderConfig& s, double fx, double fy, double fz, double ax, double ay, double az,
                       float fov = 45.0f) {
  s.camera_from = Vec3{float(fx), float(fy), float(fz)};
  s.camera_at = Vec3{float(ax), float(ay), float(az)};
  s.fov = fov;
}

// A small image; the cache in hit mode (the renderer's own default) unless a
// case asks for center.
inline RenderConfig small_config(int w = 32, int h = 24, int spp = 4, int depth = 4) {
  RenderConfig s;
  s.width = w;
  s.height = h;
  s.spp = spp;
  s.max_depth = depth;
  s.cache_eval = CacheEval::Hit;
  return s;
}

}  // namespace pmc::hard
