// part_identity.cpp — content hashes of a session's scene and settings.
#include "gpu/part_identity.h"

#include "core/content_hash.h"
#include "gpu/render_config.h"

namespace pmc {
namespace {

void add_floats(ContentHash& h, const float* v, size_t n) { h.bytes(v, n * sizeof(float)); }

// A TAG word of gpu/render_settings_table.h as a hash word: its first 8 bytes, big-endian ("lobe":
// 0x6c6f6265).
uint64_t tag_word(const char* tag) {
  uint64_t w = 0;
  for (int i = 0; i < 8 && tag[i]; ++i) w = (w << 8) | uint8_t(tag[i]);
  return w;
}

// The table's TAG settings of the cache (`cache`) or of the rest, in table
// order: each one's word and value when the value is not its default, so a
// part rendered before a setting existed (at its default) keeps its hash.
void add_tagged_settings(ContentHash& h, const RenderSettings& s, bool cache) {
  visit_render_settings([&](const auto& info, auto, auto frame_field) {
    if constexpr (!std::is_null_pointer_v<decltype(frame_field)>) {
      const bool cache_setting = info.group == SettingGroup::Cache || info.group == SettingGroup::CacheSwitch;
      if (info.hash != SettingHash::Tag || cache_setting != cache) return;
      using F = std::decay_t<decltype(frame_field(s))>;
      const F v = frame_field(s);
      if (v == frame_value<F>(info.dflt)) return;
      h.word(tag_word(info.hash_tag));
      if constexpr (std::is_floating_point_v<F>)
        h.bytes(&v, sizeof(F));
      else
        h.word(uint64_t(v));
    }
  });
}

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
  if (env.map) {  // the texels, hashed as a vector of them (the hashes of earlier builds)
    h.word(3 * env.map->texel_count());
    h.bytes(env.map->rgb(), 3 * env.map->texel_count() * sizeof(float));
  }
  return h.hex();
}

// The settings that were hashed before gpu/render_settings_table.h (its
// FIXED ones and the resolved values: camera, lights, table size, fit) keep
// their order here, so parts rendered by earlier builds keep their hashes;
// the table's TAG settings follow their groups.
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
    add_tagged_settings(h, s, true);           // cache_lobe_spread ("lobe") ...
    if (c.bandwidth != CacheBandwidth::Off) {  // level floors change the image
      h.word(0x62616e6477696474ull);           // "bandwidt(h)"
      h.word(uint64_t(c.max_refine));
      add_floats(h, &c.feature_texels, 1);
      if (c.bandwidth == CacheBandwidth::Camera) h.word(0x63616d657261ull);  // "camera"
    }
  }
  add_tagged_settings(h, s, false);
  // Sobol parts draw other numbers than the parts of builds before the
  // sampler setting (which all used the random sampler, hashing nothing).
  if (s.sampler == PMC_SAMPLER_SOBOL) h.word(0x736f626f6cull);  // "sobol"
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
  p.adaptive = s.adaptive_threshold > 0.0;
  return p;
}

}  // namespace pmc
