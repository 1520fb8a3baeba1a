// compare_command.cpp — `pmc compare`: cacheless vs cached at equal samples.
//
// Renders the scene twice with the same seed and samples, once with the
// progressive material cache off and once on, and writes both images, the
// absolute difference x5 (the paper's Fig. 1c), the hit map (Fig. 1d),
// metrics.json and report.md into --out-dir. With --reference REF.exr (or
// --reference-spp N, rendered cacheless with another seed) it also measures
// each render against the reference, so the cache's bias can be told apart
// from the noise both renders share. With --bias it renders both again with
// a second seed and estimates the cache's bias with the noise taken out
// (estimate_bias, core/image_metrics.h): what a CI gate should read, as a
// same-seed comparison counts the fireflies of paths that part (a cached
// value that differs in its last bits sends a path elsewhere) as error.
// With --denoise the cached render is
// also denoised (OIDN with its albedo and normal passes, core/denoiser.h)
// and shown, and measured against the reference, in its own column.
//
// Bad input fails before anything is rendered and leaves nothing behind:
// the options, the reference (its file and its size) and the scene are
// checked and both renders prepared before --out-dir is created; if a render
// or a write fails after that, the files written (OutputGuard) and the
// folders created (OutDir) are removed again. `compare` always renders cache
// off and on, so its --help does not list --cache and the option is refused.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.h"
#include "app/commands.h"
#include "app/output_guard.h"
#include "app/progress.h"
#include "app/render_options.h"
#include "app/stats_json.h"
#include "core/atomic_write.h"
#include "core/denoiser.h"
#include "core/error.h"
#include "core/heatmap.h"
#include "core/image_metrics.h"
#include "core/render_passes.h"
#include "core/tone_map.h"
#include "gpu/render_session.h"

namespace pmc {
namespace {

nlohmann::json error_json(const ImageError& e) {
  return {{"rmse", e.rmse},
          {"relmse", e.relmse},
          {"psnr", e.psnr},
          {"max_abs_error", e.max_abs},
          {"worst_tile_psnr", e.worst_tile_psnr},
          {"worst_tile", {e.worst_tile_x, e.worst_tile_y, kMetricTile}},
          {"worst_trimmed_tile_psnr", e.worst_trimmed_tile_psnr},
          {"worst_trimmed_tile", {e.worst_trimmed_tile_x, e.worst_trimmed_tile_y, kMetricTile}}};
}

// Reads --reference and checks it against the render's size, before
// anything is rendered. An alpha channel is dropped; fewer than three
// channels are refused.
Image read_reference(const std::string& path, int width, int height) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail("--reference: '", path, "' does not exist");
  if (std::filesystem::is_directory(path, ec)) fail("--reference: '", path, "' is a directory, not an image");
  // The errors are measured on linear radiance: an 8-bit PNG (tone-mapped,
  // sRGB) would compare display values with radiance and look hugely wrong.
  if (!has_extension(path, ".exr"))
    fail("--reference: '", path,
         "' is not an EXR: compare measures linear radiance, so give it the .exr "
         "of a render (a PNG holds tone-mapped display values)");
  Image img;
  try {
    img = read_image(path);
  } catch (const Error& e) {
    fail("--reference: ", e.what());
  }
  if (img.channels < 3)
    fail("--reference: '", path, "' has ", img.channels, " channel", img.channels == 1 ? "" : "s",
         "; expected an RGB image");
  if (img.width != width || img.height != height)
    fail("--reference: '", path, "' is ", img.width, "x", img.height, " but the renders are ", width, "x",
         height, " (--width/--height)");
  return img.channels > 3 ? first_channels(img, 3) : img;
}

// report.md: the four images side by side and the numbers of metrics.json.
std::string report_markdown(const nlohmann::json& m, const std::string& obj, const std::string& device) {
  const bool denoised = m.contains("denoise");
  std::ostringstream r;
  r << "# pmc compare: " << obj << "\n\n"
    << m["width"].get<int>() << "x" << m["height"].get<int>() << ", " << m["spp"].get<int>() << " spp, seed "
    << m["seed"].get<uint32_t>() << ", device " << device << "\n\n"
    << "| cache off | cache on | difference x" << m["diff_scale"].get<float>()
    << " | cache hits per sample (0-20) |" << (denoised ? " cache on, denoised |" : "") << "\n"
    << "|---|---|---|---|" << (denoised ? "---|" : "") << "\n"
    << "| ![](cache_off.png) | ![](cache_on.png) | ![](difference.png) | ![](hitmap.png) |"
    << (denoised ? " ![](cache_on_denoised.png) |" : "") << "\n\n"
    << "| metric | value |\n|---|---|\n"
    << "| time without cache (s) | " << m["time_off_seconds"].get<double>() << " |\n"
    << "| time with cache (s) | " << m["time_on_seconds"].get<double>() << " |\n"
    << "| speed ratio (off / on) | " << m["speed_ratio"].get<double>() << " |\n"
    << "| PSNR cached vs cacheless (dB) | " << m["psnr"].get<double>() << " |\n"
    << "| worst 16x16 tile PSNR (dB) | " << m["cached_vs_cacheless"]["worst_tile_psnr"].get<double>()
    << " |\n"
    << "| worst 16x16 tile PSNR without each tile's " << kTrimPixels << " largest pixel errors (dB) | "
    << m["cached_vs_cacheless"]["worst_trimmed_tile_psnr"].get<double>() << " |\n"
    << "| RMSE | " << m["rmse"].get<double>() << " |\n"
    << "| relMSE | " << m["relmse"].get<double>() << " |\n"
    << "| max abs error | " << m["max_abs_error"].get<double>() << " |\n"
    << "| cache hit rate | " << m["hit_rate"].get<double>() << " |\n"
    << "| cache memory (MiB) | " << m["cache_memory_bytes"].get<double>() / double(1 << 20) << " |\n";
  if (m.contains("cache_bias")) {
    const nlohmann::json& b = m["cache_bias"];
    r << "| the cache's bias, noise taken out (two seeds; dB) | " << b["psnr"].get<double>() << " |\n"
      << "| its worst 16x16 tile (dB) | " << b["worst_tile_psnr"].get<double>() << " |\n"
      << "| noise floor: cacheless seed 1 vs seed 2 (dB) | " << b["noise_psnr"].get<double>() << " |\n";
  }
  if (m.contains("reference")) {
    const nlohmann::json &on_ref = m["cached_vs_reference"], &off_ref = m["cacheless_vs_reference"];
    r << "| relMSE cached vs reference | " << on_ref["relmse"].get<double>() << " |\n"
      << "| relMSE cacheless vs reference | " << off_ref["relmse"].get<double>() << " |\n"
      << "| PSNR cached vs reference (dB) | " << on_ref["psnr"].get<double>() << " |\n"
      << "| PSNR cacheless vs reference (dB) | " << off_ref["psnr"].get<double>() << " |\n";
    if (denoised)
      r << "| relMSE cached and denoised vs reference | "
        << m["denoised_vs_reference"]["relmse"].get<double>() << " |\n";
    r << "\nReference: ";
    const nlohmann::json& ref = m["reference"];
    if (!ref.contains("spp"))
      r << ref["file"].get<std::string>() << "\n";
    else
      r << "reference.exr, cacheless, " << ref["spp"].get<int>() << " spp, seed "
        << ref["seed"].get<uint32_t>() << "\n";
  }
  return r.str();
}

struct CompareArgs {
  RenderConfig config;
  ToneMap tone_map;  // --exposure, --view: the two renders' PNGs
  std::string dir, reference, cache;
  int reference_spp = 0;
  float diff_scale = 5.0f;
  bool quiet = false;
  bool denoise = false;
  bool bias = false;  // also both renders with a second seed: the cache's bias apart from the noise
};

// The second seed of the bias estimate: independent of the first and of the
// reference's (seed + 0x9e3779b9).
uint32_t bias_seed(uint32_t seed) { return seed + 0x632be5abu; }

nlohmann::json bias_json(const BiasEstimate& b, uint32_t seed2) {
  return {{"seed2", seed2},
          {"psnr", b.psnr},
          {"worst_tile_psnr", b.worst_tile_psnr},
          {"worst_tile", {b.worst_tile_x, b.worst_tile_y, kMetricTile}},
          {"noise_psnr", b.noise_psnr}};
}

int run_compare(CompareArgs& a) {
  if (!a.reference.empty() && a.reference_spp > 0)
    fail("compare: give --reference or --reference-spp, not both");
  if (!a.cache.empty())
    fail("compare: --cache is not an option of compare (it always renders cache off and on)");
  const std::string &obj = a.config.scene, &dir = a.dir;
  OutDir out_dir(dir);  // checked now, created once the renders are prepared
  const float diff_scale = a.diff_scale;
  const int reference_spp = a.reference_spp;
  const bool quiet = a.quiet;
  RenderConfig config = a.config;
  if (a.denoise) {
    config.passes = kPassAlbedo | kPassNormal;
    std::string why;
    if (!denoiser_available(&why)) fail("--denoise: ", why);
  }
  config.validate();
  Image reference;
  const bool have_reference = !a.reference.empty() || reference_spp > 0;
  if (!a.reference.empty()) reference = read_reference(a.reference, config.width, config.height);
  std::unique_ptr<ClContext> cl = open_device(config);

  auto render = [&](RenderSession& session, const RenderSettings& s, const char* label) {
    ProgressBar bar(label, !quiet);
    RenderOutput out = session.render(s, [&](int d, int t, uint64_t r) { bar.update(d, t, r); });
    bar.finish();
    if (out.stats.nan_pixels)
      warn(std::string(label) + ": " + std::to_string(out.stats.nan_pixels) + " non-finite pixels");
    return out;
  };
  config.cache = false;
  RenderSession off_session(config, *cl);
  config.cache = true;
  RenderSession on_session(config, *cl);
  if (!quiet) print_cache_choice(on_session.settings());

  // Every input is valid: from here on a failure removes what was created.
  out_dir.create();
  RenderOutput off = render(off_session, off_session.settings(), "cache off");
  RenderOutput on = render(on_session, on_session.settings(), "cache on ");
  if (reference_spp > 0) {
    RenderSettings rs = off_session.settings();
    rs.spp = reference_spp;
    rs.seed = rs.seed + 0x9e3779b9u;  // independent noise
    reference = render(off_session, rs, "reference").image;
  }
  RenderOutput off2, on2;  // --bias: the same renders with the second seed
  if (a.bias) {
    RenderSettings s_off = off_session.settings(), s_on = on_session.settings();
    s_off.seed = s_on.seed = bias_seed(s_off.seed);
    off2 = render(off_session, s_off, "cache off, seed 2");
    on2 = render(on_session, s_on, "cache on,  seed 2");
  }

  DenoiseResult clean;
  if (a.denoise) clean = denoise({&on.image, &on.passes.albedo, &on.passes.normal});

  OutputGuard guard;
  auto path = [&](const std::string& name) {
    std::string full = dir + "/" + name;
    guard.track(full);
    return full;
  };
  write_exr(path("cache_off.exr"), off.image);
  write_png_display(path("cache_off.png"), tone_map_image(off.image, a.tone_map));
  write_exr(path("cache_on.exr"), on.image);
  write_png_display(path("cache_on.png"), tone_map_image(on.image, a.tone_map));
  write_png_display(path("difference.png"), difference_image(on.image, off.image, diff_scale));
  write_png_display(path("hitmap.png"), heatmap_with_colorbar(on.hitmap));
  write_exr(path("hitmap.exr"), on.hitmap);
  if (reference_spp > 0) write_exr(path("reference.exr"), reference);
  if (a.bias) {
    write_exr(path("cache_off_seed2.exr"), off2.image);
    write_exr(path("cache_on_seed2.exr"), on2.image);
  }
  if (a.denoise) {
    write_exr(path("cache_on_denoised.exr"), clean.image);
    write_png_display(path("cache_on_denoised.png"), tone_map_image(clean.image, a.tone_map));
  }

  const RenderSettings& on_settings = on_session.settings();
  const ImageError e = compare_images(on.image, off.image);
  const CacheStats& cs = on.stats.cache;
  const double t_off = off.stats.render_seconds, t_on = on.stats.render_seconds;
  nlohmann::json m;
  m["scene"] = obj;
  m["width"] = on_settings.width;
  m["height"] = on_settings.height;
  m["spp"] = on_settings.spp;
  m["seed"] = on_settings.seed;
  m["time_off_seconds"] = t_off;
  m["time_on_seconds"] = t_on;
  m["speed_ratio"] = t_on > 0 ? t_off / t_on : 0.0;
  m["cached_vs_cacheless"] = error_json(e);
  m["rmse"] = e.rmse;
  m["relmse"] = e.relmse;
  m["psnr"] = e.psnr;
  m["max_abs_error"] = e.max_abs;
  m["hit_rate"] = hit_rate(cs);
  m["cache_memory_bytes"] = cs.memory_bytes;
  m["cache"] = cache_json(on_settings, cs);
  m["diff_scale"] = diff_scale;
  m["nan_pixels"] = {{"off", off.stats.nan_pixels}, {"on", on.stats.nan_pixels}};
  if (a.denoise)
    m["denoise"] = {{"seconds", clean.seconds}, {"device", clean.device}, {"prefiltered_aux", true}};
  if (have_reference) {
    if (!a.reference.empty())
      m["reference"] = {{"file", a.reference}};
    else
      m["reference"] = {{"file", "reference.exr"},
                        {"spp", reference_spp},
                        {"seed", off_session.settings().seed + 0x9e3779b9u}};
    m["cached_vs_reference"] = error_json(compare_images(on.image, reference));
    m["cacheless_vs_reference"] = error_json(compare_images(off.image, reference));
    if (a.denoise) m["denoised_vs_reference"] = error_json(compare_images(clean.image, reference));
  }
  if (a.bias)
    m["cache_bias"] =
        bias_json(estimate_bias(off.image, on.image, off2.image, on2.image), bias_seed(on_settings.seed));
  write_text_file(path("metrics.json"), m.dump(2) + "\n");
  write_text_file(path("report.md"), report_markdown(m, obj, on.stats.device));
  guard.commit();
  out_dir.commit();
  std::fprintf(
      stderr,
      "pmc compare: off %.2fs, on %.2fs (x%.2f), PSNR %.2f dB, hit rate %.1f%%, cache %.1f MiB -> %s\n",
      t_off, t_on, t_on > 0 ? t_off / t_on : 0.0, e.psnr, 100.0 * m["hit_rate"].get<double>(),
      double(cs.memory_bytes) / double(1 << 20), dir.c_str());
  return 0;
}

}  // namespace

CommandRun add_compare_command(CLI::App& pmc) {
  auto a = std::make_shared<CompareArgs>();
  CLI::App* app =
      pmc.add_subcommand("compare", "render cache off and on; images, difference, hit map, metrics");
  cli::formatter(pmc).usage(
      app, "pmc compare SCENE.obj --out-dir DIR [render options] [--reference REF.exr | --reference-spp N]",
      "Renders SCENE cacheless and cached with the same seed and samples and writes both images,\n"
      "their difference (x --diff-scale), the cache hit map, metrics.json and report.md to DIR.\n"
      "It always renders both, so --cache is not an option here; the other cache options set up\n"
      "the cached render.");
  app->option_defaults()->group("options");
  app->set_help_flag("-h,--help", "print this help and exit");
  app->add_option("SCENE.obj", a->config.scene, "the OBJ scene")->required();
  app->add_option("--out-dir", a->dir,
                  "where the images, metrics.json and report.md go (created when the inputs are valid)")
      ->type_name("DIR")
      ->required();
  app->add_option("--reference", a->reference,
                  "also measure both renders against this image (--width x --height, RGB; checked before "
                  "rendering)")
      ->type_name("REF.exr");
  app->add_option("--reference-spp", a->reference_spp,
                  "render a cacheless reference with N samples (another seed)")
      ->type_name("N")
      ->check(cli::at_least(1));
  app->add_option("--diff-scale", a->diff_scale, "scale of the difference image (positive)")
      ->type_name("S")
      ->check(cli::positive())
      ->capture_default_str();
  add_quiet_flag(*app, a->quiet, "the summary and warnings still print");
  app->add_flag("--bias", a->bias,
                "also render both with a second seed and estimate the cache's bias with the noise taken "
                "out (the mean of (on1 - off1)(on2 - off2) per tile, a same-seed comparison's fireflies "
                "cancelled): metrics.json cache_bias, cache_off_seed2.exr, cache_on_seed2.exr; twice the "
                "render time");
  app->add_flag("--denoise", a->denoise,
                "also denoise the cached render (Intel Open Image Denoise with albedo and normal passes): "
                "cache_on_denoised.exr/.png, its own column and, with a reference, its relMSE");
  declare_render_options(*app, a->config, CacheFlags::AllButCache);
  declare_display_options(*app, a->tone_map);
  app->add_option("--cache", a->cache, "refused: compare always renders both")->group("");
  return [a] { return run_compare(*a); };
}

}  // namespace pmc
