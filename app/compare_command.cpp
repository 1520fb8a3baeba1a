// compare_command.cpp — `pmc compare`: cacheless vs cached at equal samples.
//
// Renders the scene twice with the same seed and samples, once with the
// progressive material cache off and once on, and writes both images, the
// absolute difference x5 (the paper's Fig. 1c), the hit map (Fig. 1d),
// metrics.json and report.md into --out-dir. With --reference REF.exr (or
// --reference-spp N, rendered cacheless with another seed) it also measures
// each render against the reference, so the cache's bias can be told apart
// from the noise both renders share.
//
// Bad input fails before anything is rendered and leaves nothing behind:
// the options, the reference (its file and its size) and the scene are
// checked and both renders prepared before --out-dir is created; if a render
// or a write fails after that, the files written (OutputGuard) and the
// folders created (OutDir) are removed again. `compare` always renders cache
// off and on, so its --help does not list --cache and the option is refused.
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/commands.h"
#include "app/output_guard.h"
#include "app/progress.h"
#include "app/render_options.h"
#include "core/error.h"
#include "core/heatmap.h"
#include "core/image_metrics.h"
#include "gpu/render_session.h"

namespace pmc {
namespace {

nlohmann::json error_json(const ImageError& e) {
  return {{"rmse", e.rmse}, {"relmse", e.relmse}, {"psnr", e.psnr}, {"max_abs_error", e.max_abs}};
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
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower((unsigned char)c));
  if (ext != ".exr")
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
  if (img.channels > 3) {
    std::vector<float> rgb(size_t(width) * size_t(height) * 3);
    for (size_t i = 0; i < size_t(width) * size_t(height); ++i)
      for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = img.pixels[i * size_t(img.channels) + c];
    img.pixels = std::move(rgb);
    img.channels = 3;
  }
  return img;
}

}  // namespace

int run_compare(const std::vector<std::string>& args) {
  ArgParser p(
      "pmc compare SCENE.obj --out-dir DIR [render options] [--reference REF.exr | --reference-spp N]",
      "Renders SCENE cacheless and cached with the same seed and samples and writes both images,\n"
      "their difference (x --diff-scale), the cache hit map, metrics.json and report.md to DIR.\n"
      "It always renders both, so --cache is not an option here; the other cache options set up\n"
      "the cached render.");
  p.option("--out-dir", "DIR",
           "where the images, metrics.json and report.md go (created when the inputs are valid)");
  p.option(
      "--reference", "REF.exr",
      "also measure both renders against this image (--width x --height, RGB; checked before rendering)");
  p.option("--reference-spp", "N", "render a cacheless reference with N samples (another seed)");
  p.option("--diff-scale", "S", "scale of the difference image (positive)", "5");
  p.flag("--quiet", "no progress bars and no cache-size lines (the summary and warnings still print)");
  declare_render_options(p);
  declare_display_options(p);
  p.hide("--cache");  // refused below: compare always renders both
  if (!p.parse(args)) return 0;
  if (p.positional().size() != 1) fail("compare: expected exactly one SCENE.obj (see --help)");
  if (!p.has("--out-dir")) fail("compare: missing --out-dir DIR");
  if (p.has("--reference") && p.has("--reference-spp"))
    fail("compare: give --reference or --reference-spp, not both");
  if (p.has("--cache"))
    fail("compare: --cache is not an option of compare (it always renders cache off and on)");
  const std::string obj = p.positional()[0], dir = p.get("--out-dir");
  OutDir out_dir(dir);  // checked now, created once the renders are prepared
  const float diff_scale = p.get_float("--diff-scale", 5.0f);
  if (!(diff_scale > 0.0f)) fail("--diff-scale: must be positive, got ", p.get("--diff-scale"));
  const int reference_spp = p.get_int("--reference-spp", 0);
  if (p.has("--reference-spp") && reference_spp <= 0)
    fail("--reference-spp: must be at least 1, got ", reference_spp);
  const bool quiet = p.has("--quiet");
  const DisplaySettings display = display_settings_from(p);
  RenderConfig config = render_config_from(p, obj);
  Image reference;
  const bool have_reference = p.has("--reference") || p.has("--reference-spp");
  if (p.has("--reference")) reference = read_reference(p.get("--reference"), config.width, config.height);
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
  if (p.has("--reference-spp")) {
    RenderSettings rs = off_session.settings();
    rs.spp = reference_spp;
    rs.seed = rs.seed + 0x9e3779b9u;  // independent noise
    reference = render(off_session, rs, "reference").image;
  }

  OutputGuard guard;
  auto path = [&](const std::string& name) {
    std::string full = dir + "/" + name;
    guard.track(full);
    return full;
  };
  write_exr(path("cache_off.exr"), off.image);
  write_png_tonemapped(path("cache_off.png"), off.image, display);
  write_exr(path("cache_on.exr"), on.image);
  write_png_tonemapped(path("cache_on.png"), on.image, display);
  write_png_display(path("difference.png"), difference_image(on.image, off.image, diff_scale));
  write_png_display(path("hitmap.png"), heatmap_with_colorbar(on.hitmap));
  write_exr(path("hitmap.exr"), on.hitmap);
  if (p.has("--reference-spp")) write_exr(path("reference.exr"), reference);

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
  m["cache"] = {{"enabled", on_settings.cache.on},
                {"lookups", cs.lookups},
                {"hits", cs.hits},
                {"misses", cs.misses},
                {"inserts", cs.inserts},
                {"already_present", cs.already_present},
                {"dropped_full", cs.dropped_full},
                {"not_encodable", cs.not_encodable},
                {"memory_bytes", cs.memory_bytes},
                {"size_reason", with_flags(on_settings.cache.reason)},
                {"occupancy", cs.occupancy()},
                {"cells", cs.cells},
                {"entries", cs.ways},
                {"mip_bias", on_settings.cache.mip_bias},
                {"eval", on_settings.cache.center ? "center" : "hit"},
                {"filter", on_settings.cache.bilinear ? "bilinear" : "nearest"}};
  m["diff_scale"] = diff_scale;
  m["nan_pixels"] = {{"off", off.stats.nan_pixels}, {"on", on.stats.nan_pixels}};
  if (have_reference) {
    if (p.has("--reference"))
      m["reference"] = {{"file", p.get("--reference")}};
    else
      m["reference"] = {{"file", "reference.exr"},
                        {"spp", reference_spp},
                        {"seed", off_session.settings().seed + 0x9e3779b9u}};
    m["cached_vs_reference"] = error_json(compare_images(on.image, reference));
    m["cacheless_vs_reference"] = error_json(compare_images(off.image, reference));
  }
  {
    std::ofstream out(path("metrics.json"));
    out << m.dump(2) << "\n";
    if (!out) fail(dir, "/metrics.json: writing failed");
  }
  {
    std::ofstream r(path("report.md"));
    r << "# pmc compare: " << obj << "\n\n"
      << on_settings.width << "x" << on_settings.height << ", " << on_settings.spp << " spp, seed "
      << on_settings.seed << ", device " << on.stats.device << "\n\n"
      << "| cache off | cache on | difference x" << diff_scale << " | cache hits per sample (0-20) |\n"
      << "|---|---|---|---|\n"
      << "| ![](cache_off.png) | ![](cache_on.png) | ![](difference.png) | ![](hitmap.png) |\n\n"
      << "| metric | value |\n|---|---|\n"
      << "| time without cache (s) | " << t_off << " |\n| time with cache (s) | " << t_on << " |\n"
      << "| speed ratio (off / on) | " << m["speed_ratio"].get<double>() << " |\n"
      << "| PSNR cached vs cacheless (dB) | " << e.psnr << " |\n| RMSE | " << e.rmse << " |\n"
      << "| relMSE | " << e.relmse << " |\n| max abs error | " << e.max_abs << " |\n"
      << "| cache hit rate | " << m["hit_rate"].get<double>() << " |\n"
      << "| cache memory (MiB) | " << double(cs.memory_bytes) / double(1 << 20) << " |\n";
    if (have_reference) {
      const nlohmann::json &on_ref = m["cached_vs_reference"], &off_ref = m["cacheless_vs_reference"];
      r << "| relMSE cached vs reference | " << on_ref["relmse"].get<double>() << " |\n"
        << "| relMSE cacheless vs reference | " << off_ref["relmse"].get<double>() << " |\n"
        << "| PSNR cached vs reference (dB) | " << on_ref["psnr"].get<double>() << " |\n"
        << "| PSNR cacheless vs reference (dB) | " << off_ref["psnr"].get<double>() << " |\n\n"
        << "Reference: ";
      if (p.has("--reference"))
        r << p.get("--reference") << "\n";
      else
        r << "reference.exr, cacheless, " << reference_spp << " spp, seed "
          << m["reference"]["seed"].get<uint32_t>() << "\n";
    }
    if (!r) fail(dir, "/report.md: writing failed");
  }
  guard.commit();
  out_dir.commit();
  std::fprintf(
      stderr,
      "pmc compare: off %.2fs, on %.2fs (x%.2f), PSNR %.2f dB, hit rate %.1f%%, cache %.1f MiB -> %s\n",
      t_off, t_on, t_on > 0 ? t_off / t_on : 0.0, e.psnr, 100.0 * m["hit_rate"].get<double>(),
      double(cs.memory_bytes) / double(1 << 20), dir.c_str());
  return 0;
}

}  // namespace pmc
