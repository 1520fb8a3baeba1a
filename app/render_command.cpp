// render_command.cpp — `pmc render`: OBJ in, EXR + tone-mapped PNG (+ stats) out.
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/output_guard.h"
#include "app/progress.h"
#include "app/render_options.h"
#include "core/error.h"
#include "core/heatmap.h"
#include "core/obj_loader.h"
#include "gpu/render_session.h"

namespace pmc {
namespace {

nlohmann::json stats_json(const RenderSettings& s, const RenderStats& st, const std::string& scene) {
  nlohmann::json j;
  j["scene"] = scene;
  j["render_seconds"] = st.render_seconds;
  j["kernel_build_seconds"] = st.kernel_build_seconds;
  j["kernel_warmup_seconds"] = st.kernel_warmup_seconds;
  j["width"] = s.width;
  j["height"] = s.height;
  j["spp"] = s.spp;
  j["max_depth"] = s.max_depth;
  j["seed"] = s.seed;
  j["paths"] = st.paths;
  j["rays"] = st.rays;
  j["shadow_rays"] = st.shadow_rays;
  j["rays_per_second"] = st.render_seconds > 0 ? double(st.rays) / st.render_seconds : 0.0;
  j["nan_pixels"] = st.nan_pixels;
  j["bad_samples"] = st.bad_samples;
  j["stage_seconds"] = {{"camera", st.stages.camera}, {"trace", st.stages.trace},
                        {"sort", st.stages.sort},     {"shade", st.stages.shade},
                        {"shadow", st.stages.shadow}, {"resolve", st.stages.resolve},
                        {"film", st.stages.film},     {"transfer", st.stages.transfer}};
  j["transfer_mode"] = st.transfer;
  j["shade_lanes"] = st.shade_lanes;
  j["device"] = st.device;
  nlohmann::json c;
  c["enabled"] = s.cache.on;
  c["eval"] = s.cache.center ? "center" : "hit";
  c["filter"] = s.cache.bilinear ? "bilinear" : "nearest";
  c["mip_bias"] = s.cache.mip_bias;
  c["lookups"] = st.cache.lookups;
  c["hits"] = st.cache.hits;
  c["misses"] = st.cache.misses;
  c["hit_rate"] = st.cache.lookups ? double(st.cache.hits) / double(st.cache.lookups) : 0.0;
  c["inserts"] = st.cache.inserts;
  c["already_present"] = st.cache.already_present;
  c["dropped_full"] = st.cache.dropped_full;
  c["not_encodable"] = st.cache.not_encodable;
  c["occupancy"] = st.cache.occupancy();
  c["memory_bytes"] = st.cache.memory_bytes;
  c["cells"] = st.cache.cells;
  c["entries"] = st.cache.ways;
  c["size_reason"] =
      s.cache.on || !s.cache.reason.empty() ? with_flags(s.cache.reason) : std::string("--cache off");
  j["cache"] = c;
  return j;
}

void write_text_atomic(const std::string& path, const std::string& text) {
  std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) fail(path, ": cannot open for writing");
    out << text;
    if (!out) fail(path, ": writing failed");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail(path, ": cannot move into place");
}

}  // namespace

int run_render(const std::vector<std::string>& args) {
  ArgParser p("pmc render SCENE.obj -o OUT.exr [options]",
              "Renders an OBJ scene: Embree traces rays on the host, OpenCL shades them.\n"
              "Writes linear OUT.exr and an sRGB OUT.png beside it (--exposure, --view).");
  p.option("-o", "OUT.exr",
           "output image (linear EXR, must end in .exr); the PNG (--exposure, --view) goes beside it");
  p.option("--stats", "OUT.json", "write render statistics as JSON");
  p.option("--hitmap", "MAP.png",
           "cache points found per sample as a viridis heat map (0..20) + raw MAP.exr (must end in .png)");
  p.flag("--quiet", "no progress bar and no cache-size line (the summary and warnings still print)");
  declare_render_options(p);
  declare_display_options(p);
  if (!p.parse(args)) return 0;
  if (p.positional().size() != 1) fail("render: expected exactly one SCENE.obj (see --help)");
  if (!p.has("-o")) fail("render: missing -o OUT.exr");
  const std::string obj = p.positional()[0];
  const std::string exr = p.get("-o");
  const std::string png = replace_extension(exr, ".png");
  // Every output is checked before the scene is even loaded.
  check_output_path("-o", exr, ".exr");
  check_output_path("-o (its PNG)", png);
  std::vector<std::pair<std::string, std::string>> outputs = {{"-o", exr}, {"-o (its PNG)", png}};
  if (p.has("--hitmap")) {
    check_output_path("--hitmap", p.get("--hitmap"), ".png");
    check_output_path("--hitmap (its EXR)", replace_extension(p.get("--hitmap"), ".exr"));
    outputs.push_back({"--hitmap", p.get("--hitmap")});
    outputs.push_back({"--hitmap (its EXR)", replace_extension(p.get("--hitmap"), ".exr")});
  }
  if (p.has("--stats")) {
    check_output_path("--stats", p.get("--stats"));
    outputs.push_back({"--stats", p.get("--stats")});
  }
  check_distinct_outputs(outputs);
  const DisplaySettings display = display_settings_from(p);

  const RenderConfig config = render_config_from(p, obj);
  std::unique_ptr<ClContext> cl = open_device(config);
  RenderSession session(config, *cl);
  const RenderSettings& settings = session.settings();
  if (!p.has("--quiet")) print_cache_choice(settings);
  ProgressBar bar("render", !p.has("--quiet"));
  RenderOutput out =
      session.render([&](int done, int total, uint64_t rays) { bar.update(done, total, rays); });
  bar.finish();

  OutputGuard guard;
  guard.track(exr);
  guard.track(png);
  write_exr(exr, out.image);
  write_png_tonemapped(png, out.image, display);
  if (p.has("--hitmap")) {
    const std::string map = p.get("--hitmap");
    const std::string raw = replace_extension(map, ".exr");
    guard.track(map);
    guard.track(raw);
    write_png_display(map, heatmap_with_colorbar(out.hitmap));
    write_exr(raw, out.hitmap);
  }
  if (p.has("--stats")) {
    guard.track(p.get("--stats"));
    write_text_atomic(p.get("--stats"), stats_json(settings, out.stats, obj).dump(2) + "\n");
  }
  guard.commit();
  const RenderStats& st = out.stats;
  std::fprintf(
      stderr,
      "pmc: %s: %dx%d, %d spp in %.2fs (%.2f Mrays/s; trace %.2fs, shade %.2fs, shadow %.2fs) on %s -> %s\n",
      obj.c_str(), settings.width, settings.height, settings.spp, st.render_seconds,
      st.render_seconds > 0 ? st.rays / st.render_seconds * 1e-6 : 0.0, st.stages.trace, st.stages.shade,
      st.stages.shadow, st.device.c_str(), exr.c_str());
  if (settings.cache.on)
    std::fprintf(
        stderr,
        "pmc: cache: %llu lookups, %.1f%% hits, %llu inserts, %llu dropped (cell full), %.1f%% occupied\n",
        (unsigned long long)st.cache.lookups,
        st.cache.lookups ? 100.0 * double(st.cache.hits) / double(st.cache.lookups) : 0.0,
        (unsigned long long)st.cache.inserts, (unsigned long long)st.cache.dropped_full,
        100.0 * st.cache.occupancy());
  if (st.nan_pixels > 0 || st.bad_samples > 0)
    warn(std::to_string(st.bad_samples) + " NaN/Inf samples dropped, " + std::to_string(st.nan_pixels) +
         " non-finite pixels");
  return 0;
}

}  // namespace pmc
