// render_command.cpp — `pmc render`: OBJ in, EXR + tone-mapped PNG (+ stats, hit map) out.
//
// The flags fill a RenderConfig (app/render_options.h) and the paths of the
// outputs; every output path is checked before the scene is loaded, then a
// RenderSession renders and the outputs are written atomically, removed
// again (OutputGuard) if a later one fails. --aov adds render passes as EXR
// layers (core/render_passes.h); --denoise runs OIDN (core/denoiser.h) on the
// beauty with the albedo and normal passes and writes the noisy image beside
// the denoised one (app/denoise_outputs.h).
#include <tbb/parallel_invoke.h>

#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/cli.h"
#include "app/commands.h"
#include "app/denoise_outputs.h"
#include "app/output_guard.h"
#include "app/part_options.h"
#include "app/progress.h"
#include "app/render_options.h"
#include "app/stats_json.h"
#include "core/atomic_write.h"
#include "core/denoiser.h"
#include "core/error.h"
#include "core/heatmap.h"
#include "core/texture_cache.h"
#include "core/tone_map.h"
#include "gpu/part_identity.h"
#include "gpu/render_session.h"

namespace pmc {
namespace {

struct RenderArgs {
  RenderConfig config;
  ToneMap tone_map;  // --exposure, --view
  std::string exr, stats, hitmap;
  std::string aov;  // --aov LIST
  bool denoise = false;
  bool quiet = false;
};

// The passes --aov and --denoise ask for (ConfigError on a bad list or a
// denoised part).
uint32_t requested_passes(const RenderArgs& a) {
  uint32_t bits = 0;
  std::string error;
  if (!parse_pass_list(a.aov, bits, error)) fail_config(setting("passes"), ": ", error);
  if (a.denoise) {
    if (a.config.samples || a.config.crop)
      fail_config(setting("denoise"), ": a part of a frame (", setting("samples"), ", ", setting("crop"),
                  ") is not denoised; merge the parts, then run 'pmc denoise' on the merged frame");
    bits |= kPassAlbedo | kPassNormal;  // OIDN's auxiliary images
  }
  return bits;
}

std::string with_extension(const std::string& path, const char* extension) {
  return std::filesystem::path(path).replace_extension(extension).string();
}

int run_render(const RenderArgs& args) {
  RenderArgs a = args;
  a.config.passes = requested_passes(a);
  const RenderConfig& config = a.config;
  config.validate();
  const std::string& obj = config.scene;
  const std::string& exr = a.exr;
  const std::string png = with_extension(exr, ".png");
  const std::string hitmap_exr = a.hitmap.empty() ? "" : with_extension(a.hitmap, ".exr");
  // Every output is checked before the scene is even loaded.
  check_output_path("-o", exr, ".exr");
  check_output_path("-o (its PNG)", png);
  std::vector<std::pair<std::string, std::string>> outputs = {{"-o", exr}, {"-o (its PNG)", png}};
  if (!a.hitmap.empty()) {
    check_output_path("--hitmap", a.hitmap, ".png");
    check_output_path("--hitmap (its EXR)", hitmap_exr);
    outputs.push_back({"--hitmap", a.hitmap});
    outputs.push_back({"--hitmap (its EXR)", hitmap_exr});
  }
  if (!a.stats.empty()) {
    check_output_path("--stats", a.stats);
    outputs.push_back({"--stats", a.stats});
  }
  const DenoisePaths denoised = denoise_paths(exr);
  if (a.denoise) {
    for (const auto& o : check_noisy_outputs(denoised)) outputs.push_back(o);
    std::string why;
    if (!denoiser_available(&why)) fail_config(setting("denoise"), ": ", why);
  }
  check_distinct_outputs(outputs);

  RenderSession session(config);  // opens the device beside the scene's loading
  const RenderSettings& settings = session.settings();
  if (!a.quiet) print_cache_choice(settings);
  ProgressBar bar("render", !a.quiet);
  RenderOutput out =
      session.render([&](int done, int total, uint64_t rays) { bar.update(done, total, rays); });
  bar.finish();
  DenoiseResult clean;
  if (a.denoise) {
    clean = denoise({&out.image, &out.passes.albedo, &out.passes.normal});
    std::fprintf(stderr,
                 "pmc: denoised with Open Image Denoise on %s in %.2fs (albedo and normal prefiltered)\n",
                 clean.device.c_str(), clean.seconds);
  }
  const std::vector<ImageLayer> layers =
      config.passes ? pass_layers(out.passes, config.passes) : std::vector<ImageLayer>{};

  OutputGuard guard;
  guard.track(exr);
  guard.track(png);
  if (a.denoise) {
    guard.track(denoised.noisy_exr);
    guard.track(denoised.noisy_png);
  }
  if (!a.hitmap.empty()) {
    guard.track(a.hitmap);
    guard.track(hitmap_exr);
  }
  // The files are independent, and each one's encoder (zlib) runs on one
  // core: they are written side by side. The EXR records which part of which
  // frame it is (core/render_part.h; the scene's content hash takes a pass
  // over every texel); a part (--samples, --crop) also carries the exact sums
  // `pmc merge` adds.
  const bool part = config.samples || config.crop;
  PartInfo info = part_info(session, settings, out);
  info.passes = config.passes;
  const Image& final_image = a.denoise ? clean.image : out.image;
  tbb::parallel_invoke(
      [&] {
        write_part_exr(exr, final_image, info, part ? &out.film : nullptr, layers);
        if (a.denoise) write_part_exr(denoised.noisy_exr, out.image, info, nullptr, layers);
      },
      [&] {
        write_png_display(png, tone_map_image(final_image, a.tone_map));
        if (a.denoise) write_png_display(denoised.noisy_png, tone_map_image(out.image, a.tone_map));
        if (!a.hitmap.empty()) {
          write_png_display(a.hitmap, heatmap_with_colorbar(out.hitmap));
          write_exr(hitmap_exr, out.hitmap);
        }
      });
  if (!a.stats.empty()) {
    guard.track(a.stats);
    nlohmann::json j = render_json(settings, out.stats, obj);
    j["setup_seconds"] = setup_json(session.setup_seconds());
    j["cache"]["model"] = cache_model_json(session, out.stats);
    if (settings.cache.on)
      j["cache"]["supersample"] = {{"uv", session.cache_supersample().uv},
                                   {"position", session.cache_supersample().position}};
    j["texture_cache"] = texture_cache_json(TextureCache::instance());
    j["memory_bytes"] = memory_json(session, out.stats);
    j["passes"] = pass_list_text(config.passes);
    if (a.denoise)
      j["denoise"] = {{"seconds", clean.seconds}, {"device", clean.device}, {"prefiltered_aux", true}};
    write_text_file(a.stats, j.dump(2) + "\n");
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
        (unsigned long long)st.cache.lookups, 100.0 * hit_rate(st.cache),
        (unsigned long long)st.cache.inserts, (unsigned long long)st.cache.dropped_full,
        100.0 * st.cache.occupancy());
  if (settings.adaptive_threshold > 0.0)
    std::fprintf(stderr,
                 "pmc: adaptive sampling: %.1f samples per pixel on average, %llu pixels stopped before %d\n",
                 st.adaptive_mean_spp, (unsigned long long)st.adaptive_stopped_pixels, settings.spp);
  if (st.nan_pixels > 0 || st.bad_samples > 0)
    warn(std::to_string(st.bad_samples) + " NaN/Inf samples dropped, " + std::to_string(st.nan_pixels) +
         " non-finite pixels");
  return 0;
}

}  // namespace

CommandRun add_render_command(CLI::App& pmc) {
  auto a = std::make_shared<RenderArgs>();
  CLI::App* app = pmc.add_subcommand("render", "render an OBJ scene (EXR + PNG)");
  cli::formatter(pmc).usage(
      app, "pmc render SCENE.obj -o OUT.exr [options]",
      "Renders an OBJ scene: Embree traces rays on the host, OpenCL shades them.\n"
      "Writes linear OUT.exr and an sRGB OUT.png beside it (--exposure, --view). Exit codes: 0 done,\n"
      "2 bad input or options (nothing written), 3 unexpected failure.");
  app->option_defaults()->group("options");
  app->set_help_flag("-h,--help", "print this help and exit");
  app->add_option("SCENE.obj", a->config.scene, "the OBJ scene (a SCENE.camera beside it sets the camera)")
      ->required();
  app->add_option("-o", a->exr,
                  "output image (linear EXR, must end in .exr); the PNG (--exposure, --view) goes beside it")
      ->type_name("OUT.exr")
      ->required();
  app->add_option("--stats", a->stats, "write render statistics as JSON")->type_name("OUT.json");
  app->add_option(
         "--hitmap", a->hitmap,
         "cache points found per sample as a viridis heat map (0..20) + raw MAP.exr (must end in .png)")
      ->type_name("MAP.png");
  add_quiet_flag(*app, a->quiet, "the summary and warnings still print");
  declare_render_options(*app, a->config, CacheFlags::All);
  // A part of the frame (farm chunks; README, Farm rendering): checked against
  // --spp and the image size by RenderConfig::validate.
  app->add_option_function<std::string>(
         "--samples", [a](const std::string& v) { a->config.samples = parse_sample_range(v); },
         "render only the sample indices [A, B) of the frame's --spp (a farm chunk); the EXR then also "
         "holds the exact sums 'pmc merge' adds up")
      ->type_name("A:B")
      ->default_str("0:spp")
      ->group("image");
  app->add_option_function<std::string>(
         "--crop", [a](const std::string& v) { a->config.crop = parse_crop_window(v); },
         "render only pixels [x0,x1) x [y0,y1) of the frame (a tile; pixels keep their frame coordinates); "
         "the EXR's data window is the tile, and it holds the exact sums 'pmc merge' adds up")
      ->type_name("x0,y0,x1,y1")
      ->default_str("the whole frame")
      ->group("image");
  cli::name_setting("passes", "--aov");
  app->add_option(
         "--aov", a->aov,
         "render passes written as layers of OUT.exr, from: albedo (albedo.R/G/B), normal (N.X/Y/Z), "
         "depth (Z), position (P.X/Y/Z), material (material.id), hits (cache_hits.V), or all; with "
         "--samples/--crop parts carry their exact sums and 'pmc merge' adds them")
      ->type_name("LIST")
      ->group("image");
  cli::name_setting("denoise", "--denoise");
  app->add_flag(
         "--denoise", a->denoise,
         "denoise with Intel Open Image Denoise (beauty + albedo + normal; scripts/setup installs it): "
         "OUT.exr/OUT.png are denoised, OUT.noisy.exr/OUT.noisy.png the render as it came")
      ->group("image");
  declare_display_options(*app, a->tone_map);
  return [a] { return run_render(*a); };
}

}  // namespace pmc
