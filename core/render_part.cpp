// render_part.cpp — part EXRs (through the image backend), and the checks and sums of a merge.
#include "core/render_part.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "core/atomic_write.h"
#include "core/error.h"
#include "core/image_backend.h"
#include "core/render_passes.h"

namespace pmc {
namespace {

constexpr int kRgb = 3;
// The film's channels after R, G, B: the twelve sum words, then these.
const char* const kCountChannels[] = {"pmc.samples", "pmc.bad", "pmc.hits"};
constexpr int kFilmChannels = FilmSums::kWords + 3;

std::string sum_channel(int k) { return "pmc.sum" + std::to_string(k); }
std::string pass_channel(int k) { return "pmc.pass" + std::to_string(k); }
const char* const kPassCountChannels[] = {"pmc.pass_hits", "pmc.pass_material"};
constexpr int kPassFilmChannels = FilmSums::kPassWords + 2;

std::string u64s(uint64_t v) { return std::to_string(v); }

uint64_t parse_u64(const std::string& path, const std::string& name, const std::string& text) {
  try {
    size_t used = 0;
    const unsigned long long v = std::stoull(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {
  }
  fail(path, ": attribute ", name, " is not an unsigned integer ('", text, "')");
}

std::string ranges_text(int a, int b) { return std::to_string(a) + ":" + std::to_string(b); }

std::string window_text(const std::array<int, 4>& w) {
  std::ostringstream os;
  os << w[0] << "," << w[1] << "," << w[2] << "," << w[3];
  return os.str();
}

bool overlap(int a0, int a1, int b0, int b1) { return a0 < b1 && b0 < a1; }

}  // namespace

void write_part_exr(const std::string& path, const Image& image, const PartInfo& info, const FilmSums* film,
                    const std::vector<ImageLayer>& layers) {
  const int w = info.crop[2] - info.crop[0], h = info.crop[3] - info.crop[1];
  PMC_CHECK(image.width == w && image.height == h && image.channels == kRgb, "part image size");
  PMC_CHECK(!film || (film->width == w && film->height == h), "part film size");
  int layer_channels = 0;
  for (const ImageLayer& l : layers) {
    PMC_CHECK(l.image.width == w && l.image.height == h && size_t(l.image.channels) == l.channels.size(),
              "part layer size");
    layer_channels += l.image.channels;
  }
  const bool pass_sums = film && film->has_passes();
  const int nch = kRgb + layer_channels + (film ? kFilmChannels : 0) + (pass_sums ? kPassFilmChannels : 0);
  ImageWrite out;
  ImageHeader& spec = out.header;
  spec.width = w;
  spec.height = h;
  spec.channels = nch;
  spec.x = info.crop[0];
  spec.y = info.crop[1];
  spec.full_x = 0;
  spec.full_y = 0;
  spec.full_width = info.frame_width;
  spec.full_height = info.frame_height;
  spec.channel_names = {"R", "G", "B"};
  for (const ImageLayer& l : layers)
    spec.channel_names.insert(spec.channel_names.end(), l.channels.begin(), l.channels.end());
  out.format = PixelFormat::Float;
  if (film) {
    out.channel_formats.assign(size_t(kRgb + layer_channels), PixelFormat::Float);
    for (int k = 0; k < FilmSums::kWords; ++k) spec.channel_names.push_back(sum_channel(k));
    for (const char* c : kCountChannels) spec.channel_names.push_back(c);
    if (pass_sums) {
      for (int k = 0; k < FilmSums::kPassWords; ++k) spec.channel_names.push_back(pass_channel(k));
      for (const char* c : kPassCountChannels) spec.channel_names.push_back(c);
    }
    out.channel_formats.resize(size_t(nch), PixelFormat::U32);
  }
  auto attribute = [&out](const char* name, auto value) {
    out.attributes.push_back(ImageAttribute::of(name, value));
  };
  attribute("compression", std::string("zip"));
  attribute("pmc:scene_hash", info.scene_hash);
  attribute("pmc:settings_hash", info.settings_hash);
  attribute("pmc:scene", info.scene);
  attribute("pmc:spp", info.spp);
  attribute("pmc:sample_begin", info.sample_begin);
  attribute("pmc:sample_end", info.sample_end);
  attribute("pmc:seed", u64s(info.seed));
  attribute("pmc:cache", info.cache ? 1 : 0);
  attribute("pmc:cache:lookups", u64s(info.cache_counters.lookups));
  attribute("pmc:cache:hits", u64s(info.cache_counters.hits));
  attribute("pmc:cache:misses", u64s(info.cache_counters.misses));
  attribute("pmc:cache:inserts", u64s(info.cache_counters.inserts));
  attribute("pmc:cache:dropped_full", u64s(info.cache_counters.dropped_full));
  attribute("pmc:render_seconds", float(info.render_seconds));
  attribute("pmc:partial", info.partial ? 1 : 0);
  attribute("pmc:adaptive", info.adaptive ? 1 : 0);
  attribute("pmc:passes", pass_list_text(info.passes));

  // Interleaved native data: every channel is 4 bytes (float or uint32).
  std::vector<uint32_t> data(size_t(w) * size_t(h) * size_t(nch));
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i) {
    uint32_t* px = &data[i * size_t(nch)];
    std::memcpy(px, &image.pixels[i * kRgb], kRgb * sizeof(float));
    px += kRgb;
    for (const ImageLayer& l : layers) {
      const size_t c = size_t(l.image.channels);
      std::memcpy(px, &l.image.pixels[i * c], c * sizeof(float));
      px += c;
    }
    if (!film) continue;
    std::copy_n(&film->sum[i * FilmSums::kWords], FilmSums::kWords, px);
    px += FilmSums::kWords;
    *px++ = film->samples[i];
    *px++ = film->bad[i];
    *px++ = film->hits[i];
    if (!pass_sums) continue;
    std::copy_n(&film->pass_sum[i * FilmSums::kPassWords], FilmSums::kPassWords, px);
    px += FilmSums::kPassWords;
    *px++ = film->pass_hits[i];
    *px++ = film->pass_material_inv[i];
  }

  out.pixels = data.data();
  ImageBackend& backend = image_backend();
  write_atomically(path, [&](const std::string& tmp) {
    std::string why;
    if (!backend.write(tmp, path, out, why)) fail(path, ": ", why);
  });
}

RenderPart read_part_exr(const std::string& path) {
  std::string why;
  auto in = image_backend().open(path, false, why);
  if (!in) fail(path, ": cannot read image: ", why);
  const ImageHeader& spec = in->header();
  RenderPart part;
  part.path = path;
  PartInfo& info = part.info;
  info.settings_hash = in->string_attribute("pmc:settings_hash");
  if (info.settings_hash.empty())
    fail_config(path,
                ": not a pmc render part (no pmc:settings_hash attribute; render parts with "
                "'pmc render ",
                setting("samples"), " A:B' and/or '", setting("crop"), "')");
  info.scene_hash = in->string_attribute("pmc:scene_hash");
  info.scene = in->string_attribute("pmc:scene");
  info.spp = in->int_attribute("pmc:spp");
  info.sample_begin = in->int_attribute("pmc:sample_begin");
  info.sample_end = in->int_attribute("pmc:sample_end");
  info.seed = uint32_t(parse_u64(path, "pmc:seed", in->string_attribute("pmc:seed", "0")));
  info.cache = in->int_attribute("pmc:cache") != 0;
  auto counter = [&](const char* name) { return parse_u64(path, name, in->string_attribute(name, "0")); };
  info.cache_counters.lookups = counter("pmc:cache:lookups");
  info.cache_counters.hits = counter("pmc:cache:hits");
  info.cache_counters.misses = counter("pmc:cache:misses");
  info.cache_counters.inserts = counter("pmc:cache:inserts");
  info.cache_counters.dropped_full = counter("pmc:cache:dropped_full");
  info.render_seconds = in->float_attribute("pmc:render_seconds");
  info.partial = in->int_attribute("pmc:partial") != 0;
  info.adaptive = in->int_attribute("pmc:adaptive") != 0;
  std::string pass_error;
  if (!parse_pass_list(in->string_attribute("pmc:passes"), info.passes, pass_error))
    fail(path, ": attribute pmc:passes: ", pass_error);
  info.frame_width = spec.full_width;
  info.frame_height = spec.full_height;
  info.crop = {spec.x, spec.y, spec.x + spec.width, spec.y + spec.height};
  if (info.partial)
    fail(path, ": a partial merge (samples missing) cannot be merged again; merge its parts instead");
  if (info.spp <= 0 || info.sample_begin < 0 || info.sample_begin >= info.sample_end ||
      info.sample_end > info.spp)
    fail(path, ": bad sample range ", ranges_text(info.sample_begin, info.sample_end), " of ", info.spp,
         " samples");
  if (spec.full_x != 0 || spec.full_y != 0 || spec.x < 0 || spec.y < 0 || info.crop[2] > info.frame_width ||
      info.crop[3] > info.frame_height || spec.width <= 0 || spec.height <= 0)
    fail(path, ": data window ", window_text(info.crop), " is not inside the frame ", info.frame_width, "x",
         info.frame_height);

  FilmSums& f = part.film;
  const bool pass_sums = spec.channel_index(pass_channel(0)) >= 0;
  f = FilmSums::zero(spec.width, spec.height, pass_sums);
  std::vector<uint32_t> channel(f.pixels());
  auto read_channel = [&](const std::string& name) {
    const int c = spec.channel_index(name);
    if (c < 0)
      fail_config(path, ": no channel ", name, " (a part needs the film's sums: render it with 'pmc render ",
                  setting("samples"), " A:B')");
    if (!in->read(c, c + 1, PixelFormat::U32, channel.data()))
      fail(path, ": cannot decode channel ", name, ": ", in->error());
  };
  for (int k = 0; k < FilmSums::kWords; ++k) {
    read_channel(sum_channel(k));
    for (size_t i = 0; i < f.pixels(); ++i) f.sum[i * FilmSums::kWords + size_t(k)] = channel[i];
  }
  read_channel(kCountChannels[0]);
  f.samples = channel;
  read_channel(kCountChannels[1]);
  f.bad = channel;
  read_channel(kCountChannels[2]);
  f.hits = channel;
  if (pass_sums) {
    for (int k = 0; k < FilmSums::kPassWords; ++k) {
      read_channel(pass_channel(k));
      for (size_t i = 0; i < f.pixels(); ++i) f.pass_sum[i * FilmSums::kPassWords + size_t(k)] = channel[i];
    }
    read_channel(kPassCountChannels[0]);
    f.pass_hits = channel;
    read_channel(kPassCountChannels[1]);
    f.pass_material_inv = channel;
  }
  const uint32_t range = uint32_t(info.sample_end - info.sample_begin);
  if (info.adaptive && range != uint32_t(info.spp))
    fail(path, ": an adaptive part holds samples ", ranges_text(info.sample_begin, info.sample_end), " of ",
         info.spp, "; adaptive parts hold every sample of their window");
  for (size_t i = 0; i < f.pixels(); ++i) {
    const bool count_ok = info.adaptive ? f.samples[i] >= 1 && f.samples[i] <= range : f.samples[i] == range;
    if (!count_ok || f.bad[i] > f.samples[i])
      fail(path, ": pixel ", i, " of the window holds ", f.samples[i], " samples (", f.bad[i],
           " bad), its range ", ranges_text(info.sample_begin, info.sample_end), " has ", range,
           info.adaptive ? " at most" : "");
  }
  return part;
}

MergedFrame merge_parts(const std::vector<RenderPart>& parts, bool allow_partial) {
  if (parts.empty()) fail("merge: no parts given");
  const PartInfo& a = parts[0].info;
  const std::string& a_path = parts[0].path;
  for (size_t i = 1; i < parts.size(); ++i) {
    const PartInfo& b = parts[i].info;
    const std::string& p = parts[i].path;
    if (b.scene_hash != a.scene_hash)
      fail(p, ": a different scene from ", a_path, " (scene hash ", b.scene_hash, " vs ", a.scene_hash,
           "; scenes ", b.scene, " and ", a.scene, ")");
    if (b.settings_hash != a.settings_hash)
      fail(p, ": different render settings from ", a_path, " (settings hash ", b.settings_hash, " vs ",
           a.settings_hash, ")");
    if (b.adaptive != a.adaptive)
      fail(p, ": ", b.adaptive ? "adaptive" : "not adaptive", " where ", a_path, " is ",
           a.adaptive ? "adaptive" : "not adaptive", " (", setting("adaptive_threshold"), ")");
    if (b.frame_width != a.frame_width || b.frame_height != a.frame_height || b.spp != a.spp ||
        b.seed != a.seed)
      fail(p, ": a different frame from ", a_path, " (", b.frame_width, "x", b.frame_height, ", ", b.spp,
           " spp, seed ", b.seed, " vs ", a.frame_width, "x", a.frame_height, ", ", a.spp, " spp, seed ",
           a.seed, ")");
  }
  // Pass sums in every part or in none, with the same pass layers.
  for (size_t i = 1; i < parts.size(); ++i) {
    const RenderPart& b = parts[i];
    if (b.film.has_passes() != parts[0].film.has_passes()) {
      const RenderPart& without = b.film.has_passes() ? parts[0] : b;
      const RenderPart& with = b.film.has_passes() ? b : parts[0];
      fail_config(without.path, ": a part without render passes, but ", with.path, " has passes (",
                  pass_list_text(with.info.passes), "); render every part with the same ", setting("passes"));
    }
    if (b.info.passes != a.passes)
      fail_config(b.path, ": render passes ", pass_list_text(b.info.passes), " differ from ", a_path, "'s (",
                  pass_list_text(a.passes), "); render every part with the same ", setting("passes"));
  }
  // No pixel sample drawn by two parts.
  for (size_t i = 0; i < parts.size(); ++i)
    for (size_t j = i + 1; j < parts.size(); ++j) {
      const PartInfo& x = parts[i].info;
      const PartInfo& y = parts[j].info;
      if (overlap(x.sample_begin, x.sample_end, y.sample_begin, y.sample_end) &&
          overlap(x.crop[0], x.crop[2], y.crop[0], y.crop[2]) &&
          overlap(x.crop[1], x.crop[3], y.crop[1], y.crop[3]))
        fail(parts[j].path, ": samples ", ranges_text(y.sample_begin, y.sample_end), " of window ",
             window_text(y.crop), " overlap ", parts[i].path, " (samples ",
             ranges_text(x.sample_begin, x.sample_end), " of window ", window_text(x.crop), ")");
    }

  MergedFrame m;
  m.info = a;
  m.info.crop = {0, 0, a.frame_width, a.frame_height};
  m.info.sample_begin = 0;
  m.info.sample_end = a.spp;
  m.info.cache_counters = {};
  m.info.render_seconds = 0.0;
  m.film = FilmSums::zero(a.frame_width, a.frame_height, parts[0].film.has_passes());
  for (const RenderPart& part : parts) {
    add_film(m.film, part.film, part.info.crop[0], part.info.crop[1]);
    const PartCacheCounters& c = part.info.cache_counters;
    m.info.cache_counters.lookups += c.lookups;
    m.info.cache_counters.hits += c.hits;
    m.info.cache_counters.misses += c.misses;
    m.info.cache_counters.inserts += c.inserts;
    m.info.cache_counters.dropped_full += c.dropped_full;
    m.info.render_seconds += part.info.render_seconds;
  }
  // Every pixel's samples complete (with no overlap, a count of spp means all of 0..spp-1;
  // adaptive: any count, all from the one part that holds the pixel).
  for (size_t i = 0; i < m.film.pixels(); ++i) {
    const uint32_t have = m.film.samples[i];
    if (have == uint32_t(a.spp) || (a.adaptive && have > 0)) continue;
    m.missing_pixel_samples += uint64_t(a.spp) - have;
    if (allow_partial) continue;
    const int x = int(i % size_t(a.frame_width)), y = int(i / size_t(a.frame_width));
    std::string covered;
    for (const RenderPart& part : parts) {
      const PartInfo& p = part.info;
      if (x >= p.crop[0] && x < p.crop[2] && y >= p.crop[1] && y < p.crop[3])
        covered += " " + ranges_text(p.sample_begin, p.sample_end) + " (" + part.path + ")";
    }
    fail_config("merge: samples missing: pixel (", x, ",", y, ") has ", have, " of ", a.spp,
                " samples; covered by", covered.empty() ? std::string(" no part") : covered, " (pass ",
                setting("allow_partial"), " to merge what there is)");
  }
  m.info.partial = m.missing_pixel_samples > 0;
  return m;
}

}  // namespace pmc
