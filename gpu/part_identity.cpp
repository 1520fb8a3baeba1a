// part_identity.cpp — content hashes of a session's scene and settings.
#include "gpu/part_identity.h"

#include "core/content_hash.h"

namespace pmc {
namespace {

void add_floats(ContentHash& h, const float* v, size_t n) { h.bytes(v, n * sizeof(float)); }

}  // namespace

std::string scene_hash(const RenderSession& session) {
  const Scene& s = session.scene();
  const MaterialSet& m = session.materials();
  ContentHash h;
  h.vec(s.positions);
  h.vec(s.normals);
  h.vec(s.uvs);
  h.vec(s.triangles);
  h.vec(m.program.code);
  h.vec(m.infos);
  h.vec(*m.texel_words);
  const EnvironmentSpec& env = session.settings().lights.environment;
  if (env.map) h.vec(env.map->rgb);
  return h.hex();
}

std::string settings_hash(const RenderSettings& s) {
  ContentHash h;
  h.word(uint64_t(s.width));
  h.word(uint64_t(s.height));
  h.word(uint64_t(s.spp));
  h.word(uint64_t(s.max_depth));
  h.word(s.seed);
  add_floats(h, s.env, 3);
  h.word(s.env_importance ? 1 : 0);
  add_floats(h, s.camera.from, 3);
  add_floats(h, s.camera.at, 3);
  add_floats(h, s.camera.up, 3);
  add_floats(h, &s.camera.fov_degrees, 1);
  const SceneLights& l = s.lights;
  h.word(l.lights.size());
  for (const LightSpec& x : l.lights) {
    h.word(uint64_t(x.type));
    add_floats(h, x.position, 3);
    add_floats(h, x.direction, 3);
    add_floats(h, x.rgb, 3);
    add_floats(h, &x.cone_angle_deg, 1);
    add_floats(h, &x.blend, 1);
    add_floats(h, &x.angle_deg, 1);
    add_floats(h, x.corner, 3);
    add_floats(h, x.edge_u, 3);
    add_floats(h, x.edge_v, 3);
    h.word(x.two_sided ? 1 : 0);
  }
  const EnvironmentSpec& e = l.environment;
  h.word(e.present ? 1 : 0);
  add_floats(h, e.radiance, 3);
  add_floats(h, &e.scale, 1);
  add_floats(h, &e.rotate_y_deg, 1);
  const CacheSettings& c = s.cache;
  h.word(c.on ? 1 : 0);
  if (c.on) {
    h.word(c.cells);
    h.word(c.ways);
    add_floats(h, &c.mip_bias, 1);
    h.word(c.center ? 1 : 0);
    h.word(c.bilinear ? 1 : 0);
    if (c.priority) h.word(0x7072696f72697479ull);  // "priority"; keep-first parts keep their old hashes
    if (c.fit_levels != 0.0f) {                     // coarser texels change the image
      h.word(0x666974ull);                          // "fit"
      add_floats(h, &c.fit_levels, 1);
    }
    if (c.lobe_spread != 0.0f) {  // wider cells after rough bounces change the image
      h.word(0x6c6f6265ull);      // "lobe"
      add_floats(h, &c.lobe_spread, 1);
    }
    if (c.bandwidth) {                // level floors change the image
      h.word(0x62616e6477696474ull);  // "bandwidt(h)"
      h.word(uint64_t(c.max_refine));
      add_floats(h, &c.feature_texels, 1);
    }
  }
  return h.hex();
}

PartInfo part_info(const RenderSession& session, const RenderSettings& s, const RenderOutput& out) {
  PartInfo p;
  p.scene_hash = scene_hash(session);
  p.settings_hash = settings_hash(s);
  p.scene = session.config().scene;
  p.frame_width = s.width;
  p.frame_height = s.height;
  p.spp = s.spp;
  p.sample_begin = s.sample_begin;
  p.sample_end = s.sample_end > 0 ? s.sample_end : s.spp;
  if (s.crop[2] > 0)
    p.crop = {s.crop[0], s.crop[1], s.crop[2], s.crop[3]};
  else
    p.crop = {0, 0, s.width, s.height};
  p.seed = s.seed;
  p.cache = s.cache.on;
  const CacheStats& c = out.stats.cache;
  p.cache_counters = {c.lookups, c.hits, c.misses, c.inserts, c.dropped_full};
  p.render_seconds = out.stats.render_seconds;
  return p;
}

}  // namespace pmc
