// denoise_command.cpp — `pmc denoise IN.exr -o OUT.exr`: a frame with albedo and normal passes in, denoised
// out.
//
// For a frame rendered elsewhere (a merged farm frame, `pmc merge`, or any
// `pmc render --aov albedo,normal`): reads the beauty (R, G, B) and the
// albedo.R/G/B and N.X/Y/Z layers, denoises them with OIDN
// (core/denoiser.h) and writes what `pmc render --denoise` writes
// (app/denoise_outputs.h): OUT.exr (denoised, with the input's pass layers)
// and OUT.png, and OUT.noisy.exr / OUT.noisy.png (the input as it was). An
// input that is not a whole frame with those channels is an error naming
// the file; nothing is written then.
#include <cstdio>
#include <memory>

#include "app/cli.h"
#include "app/commands.h"
#include "app/denoise_outputs.h"
#include "app/output_guard.h"
#include "app/render_options.h"
#include "core/denoiser.h"
#include "core/error.h"
#include "core/image_backend.h"
#include "core/render_passes.h"
#include "core/tone_map.h"

namespace pmc {
namespace {

struct DenoiseArgs {
  std::string in, exr;
  ToneMap tone_map;
};

struct LayeredFrame {
  Image color, albedo, normal;
  std::vector<ImageLayer> layers;  // every pass layer present (albedo and normal included)
};

LayeredFrame read_layered_frame(const std::string& path) {
  std::string why;
  auto in = image_backend().open(path, false, why);
  if (!in) fail(path, ": cannot read image: ", why);
  const ImageHeader& h = in->header();
  if (h.width <= 0 || h.height <= 0) fail(path, ": empty image (", h.width, "x", h.height, ")");
  if (h.full_width > 0 &&
      (h.x != h.full_x || h.y != h.full_y || h.width != h.full_width || h.height != h.full_height))
    fail(path, ": a window of ", h.width, "x", h.height, " at (", h.x, ",", h.y, ") inside a ", h.full_width,
         "x", h.full_height, " frame, not a whole frame (merge the parts first)");
  const size_t n = size_t(h.width) * size_t(h.height);
  auto read = [&](const std::vector<std::string>& names) {
    Image im;
    im.width = h.width;
    im.height = h.height;
    im.channels = int(names.size());
    im.pixels.resize(n * names.size());
    std::vector<float> channel(n);
    for (size_t c = 0; c < names.size(); ++c) {
      const int k = h.channel_index(names[c]);
      if (k < 0)
        fail(path, ": no channel ", names[c],
             " (pmc denoise needs R, G, B, albedo.R/G/B and N.X/Y/Z: render ",
             "with 'pmc render --aov albedo,normal')");
      if (!in->read(k, k + 1, PixelFormat::Float, channel.data()))
        fail(path, ": cannot decode channel ", names[c], ": ", in->error());
      for (size_t i = 0; i < n; ++i) im.pixels[i * names.size() + c] = channel[i];
    }
    return im;
  };
  LayeredFrame f;
  f.color = read({"R", "G", "B"});
  for (const PassName& p : pass_names()) {
    bool present = true;
    for (const std::string& c : p.channels) present = present && h.channel_index(c) >= 0;
    if (present || p.bit == kPassAlbedo || p.bit == kPassNormal)
      f.layers.push_back({p.channels, read(p.channels)});
    if (p.bit == kPassAlbedo) f.albedo = f.layers.back().image;
    if (p.bit == kPassNormal) f.normal = f.layers.back().image;
  }
  return f;
}

int run_denoise(const DenoiseArgs& a) {
  const DenoisePaths paths = denoise_paths(a.exr);
  check_output_path("-o", paths.exr, ".exr");
  check_output_path("-o (its PNG)", paths.png);
  std::vector<std::pair<std::string, std::string>> outputs = {{"-o", paths.exr}, {"-o (its PNG)", paths.png}};
  for (const auto& o : check_noisy_outputs(paths)) outputs.push_back(o);
  check_distinct_outputs(outputs);
  for (const auto& [option, out] : outputs) {
    std::error_code ec;
    if (std::filesystem::equivalent(a.in, out, ec)) fail(option, ": '", out, "' is also the input");
  }
  std::string why;
  if (!denoiser_available(&why)) fail("pmc denoise: ", why);

  const LayeredFrame frame = read_layered_frame(a.in);
  const DenoiseResult r = denoise({&frame.color, &frame.albedo, &frame.normal});

  OutputGuard guard;
  for (const auto& o : outputs) guard.track(o.second);
  write_exr_layers(paths.exr, r.image, frame.layers);
  write_png_display(paths.png, tone_map_image(r.image, a.tone_map));
  write_exr_layers(paths.noisy_exr, frame.color, frame.layers);
  write_png_display(paths.noisy_png, tone_map_image(frame.color, a.tone_map));
  guard.commit();
  std::fprintf(stderr, "pmc: denoised %s (%dx%d) with Open Image Denoise on %s in %.2fs -> %s\n",
               a.in.c_str(), frame.color.width, frame.color.height, r.device.c_str(), r.seconds,
               paths.exr.c_str());
  return 0;
}

}  // namespace

CommandRun add_denoise_command(CLI::App& pmc) {
  auto a = std::make_shared<DenoiseArgs>();
  CLI::App* app = pmc.add_subcommand("denoise", "denoise a frame with its albedo and normal passes (OIDN)");
  cli::formatter(pmc).usage(
      app, "pmc denoise IN.exr -o OUT.exr [options]",
      "Denoises a frame (a merged farm frame, or any pmc render --aov albedo,normal) with Intel Open\n"
      "Image Denoise, using its albedo.R/G/B and N.X/Y/Z layers. Writes OUT.exr (with the input's pass\n"
      "layers) and OUT.png denoised, OUT.noisy.exr and OUT.noisy.png as the input was. Exit codes: 0\n"
      "done, 2 bad input (nothing written), 3 unexpected failure.");
  app->option_defaults()->group("options");
  app->set_help_flag("-h,--help", "print this help and exit");
  app->add_option("IN.exr", a->in, "a whole frame with R, G, B, albedo.R/G/B and N.X/Y/Z")->required();
  app->add_option("-o", a->exr, "denoised image (linear EXR, must end in .exr); the PNG goes beside it")
      ->type_name("OUT.exr")
      ->required();
  declare_display_options(*app, a->tone_map);
  return [a] { return run_denoise(*a); };
}

}  // namespace pmc
