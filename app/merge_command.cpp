// merge_command.cpp — `pmc merge PARTS... -o OUT.exr`: parts of a frame in, the frame out.
//
// Reads part EXRs (core/render_part.h: sample ranges and/or crop windows of
// one frame, written by `pmc render --samples/--crop`), refuses parts that do
// not belong together (core/render_part.cpp says which checks), adds their
// exact film sums and writes the sample-weighted mean: each pixel is the sum
// of all its samples over all parts divided by its sample count, the same
// division of the same integer sum a one-process render does, so the result
// is bit for bit that render's. Writes OUT.exr (itself a part of the whole
// frame, so merges can be merged), OUT.png beside it and, with --stats,
// merged statistics. Outputs are checked before any part is read and removed
// again if anything fails (OutputGuard; every file is written atomically).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "app/cli.h"
#include "app/commands.h"
#include "app/output_guard.h"
#include "app/render_options.h"
#include "core/atomic_write.h"
#include "core/error.h"
#include "core/film_sum.h"
#include "core/render_part.h"
#include "core/render_passes.h"
#include "core/tone_map.h"

namespace pmc {
namespace {

struct MergeArgs {
  std::vector<std::string> parts;
  std::string exr, stats;
  bool allow_partial = false;
  ToneMap tone_map;
};

nlohmann::json counters_json(const PartCacheCounters& c) {
  return {{"lookups", c.lookups},
          {"hits", c.hits},
          {"misses", c.misses},
          {"inserts", c.inserts},
          {"dropped_full", c.dropped_full},
          {"hit_rate", c.lookups ? double(c.hits) / double(c.lookups) : 0.0}};
}

nlohmann::json merge_stats(const std::vector<RenderPart>& parts, const MergedFrame& m) {
  nlohmann::json j;
  j["scene"] = m.info.scene;
  j["scene_hash"] = m.info.scene_hash;
  j["settings_hash"] = m.info.settings_hash;
  j["width"] = m.info.frame_width;
  j["height"] = m.info.frame_height;
  j["spp"] = m.info.spp;
  j["seed"] = m.info.seed;
  j["partial"] = m.info.partial;
  j["missing_pixel_samples"] = m.missing_pixel_samples;
  j["render_seconds_sum"] = m.info.render_seconds;
  uint64_t bad = 0;
  for (uint32_t b : m.film.bad) bad += b;
  j["bad_samples"] = bad;
  nlohmann::json list = nlohmann::json::array();
  for (const RenderPart& p : parts)
    list.push_back({{"file", p.path},
                    {"samples", {p.info.sample_begin, p.info.sample_end}},
                    {"crop", p.info.crop},
                    {"render_seconds", p.info.render_seconds},
                    {"cache", counters_json(p.info.cache_counters)}});
  j["parts"] = list;
  nlohmann::json c = counters_json(m.info.cache_counters);
  c["enabled"] = m.info.cache;
  j["cache"] = c;
  return j;
}

int run_merge(const MergeArgs& a) {
  const std::string& exr = a.exr;
  const std::string png = std::filesystem::path(exr).replace_extension(".png").string();
  check_output_path("-o", exr, ".exr");
  check_output_path("-o (its PNG)", png);
  std::vector<std::pair<std::string, std::string>> outputs = {{"-o", exr}, {"-o (its PNG)", png}};
  if (!a.stats.empty()) {
    check_output_path("--stats", a.stats);
    outputs.push_back({"--stats", a.stats});
  }
  check_distinct_outputs(outputs);
  for (const std::string& in : a.parts)
    for (const auto& [option, out] : outputs) {
      std::error_code ec;
      if (std::filesystem::equivalent(in, out, ec)) fail(option, ": '", out, "' is also one of the parts");
    }

  std::vector<RenderPart> parts;
  for (const std::string& in : a.parts) parts.push_back(read_part_exr(in));
  const MergedFrame merged = merge_parts(parts, a.allow_partial);
  const Image image = film_mean(merged.film);

  OutputGuard guard;
  guard.track(exr);
  guard.track(png);
  // Parts with passes carry their sums: the merged frame's pass layers come from the merged sums.
  const std::vector<ImageLayer> layers = merged.film.has_passes()
                                             ? pass_layers(film_passes(merged.film), merged.info.passes)
                                             : std::vector<ImageLayer>{};
  write_part_exr(exr, image, merged.info, &merged.film, layers);
  write_png_display(png, tone_map_image(image, a.tone_map));
  if (!a.stats.empty()) {
    guard.track(a.stats);
    write_text_file(a.stats, merge_stats(parts, merged).dump(2) + "\n");
  }
  guard.commit();
  std::string missing;
  if (merged.info.partial)
    missing = " with " + std::to_string(merged.missing_pixel_samples) + " pixel samples missing";
  std::fprintf(stderr, "pmc: merged %zu parts of %s (%dx%d, %d spp)%s -> %s\n", parts.size(),
               merged.info.scene.c_str(), merged.info.frame_width, merged.info.frame_height, merged.info.spp,
               missing.c_str(), exr.c_str());
  return 0;
}

}  // namespace

CommandRun add_merge_command(CLI::App& pmc) {
  auto a = std::make_shared<MergeArgs>();
  CLI::App* app = pmc.add_subcommand("merge", "add up parts of a frame (render --samples A:B, --crop)");
  cli::formatter(pmc).usage(
      app, "pmc merge PART.exr... -o OUT.exr [options]",
      "Adds up parts of one frame (pmc render --samples A:B and/or --crop) into the frame: each pixel\n"
      "is the mean of all its samples, bit for bit the one-process render. Refuses parts of another\n"
      "scene, settings or frame, parts that overlap and missing samples, naming the file. Exit codes:\n"
      "0 done, 2 bad input (nothing written), 3 unexpected failure.");
  app->option_defaults()->group("options");
  app->set_help_flag("-h,--help", "print this help and exit");
  app->add_option("PART.exr", a->parts, "parts of one frame (EXRs written by pmc render --samples/--crop)")
      ->required();
  app->add_option("-o", a->exr, "merged image (linear EXR, must end in .exr); the PNG goes beside it")
      ->type_name("OUT.exr")
      ->required();
  app->add_option("--stats", a->stats,
                  "merged statistics as JSON: the parts, their times, summed cache counters")
      ->type_name("OUT.json");
  app->add_flag(
      "--allow-partial", a->allow_partial,
      "merge even if samples are missing (each pixel: the mean of the samples it has; none: black)");
  declare_display_options(*app, a->tone_map);
  cli::name_setting("passes", "--aov");
  return [a] { return run_merge(*a); };
}

}  // namespace pmc
