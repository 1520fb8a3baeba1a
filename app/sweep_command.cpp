// sweep_command.cpp — `pmc sweep`: cache settings against time and error.
//
// For every combination of --cells, --entries, --mip-biases and --cache-evals it
// renders the scene cached (same seed and samples as one cacheless render)
// and writes a row of sweep.csv: time, hit rate, memory, error against the
// cacheless render and against a high-sample reference. With
// --convergence-spp it also renders cache off and on at each sample count,
// measuring relMSE against the reference: the equal-time question a user
// asks ("for the same time, is the cached image better?"). The plots come
// from scripts/plot_sweep.py.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/commands.h"
#include "app/output_guard.h"
#include "app/progress.h"
#include "app/render_job.h"
#include "app/render_options.h"
#include "core/error.h"
#include "core/image_metrics.h"

namespace pmc {
namespace {

std::vector<std::string> split_list(const std::string& s, const std::string& option) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  if (out.empty()) fail(option, ": expected a comma-separated list");
  return out;
}

template <typename T>
std::vector<T> parse_list(const std::string& s, const std::string& option) {
  std::vector<T> out;
  for (const std::string& item : split_list(s, option)) {
    std::istringstream is(item);
    T v{};
    if (!(is >> v) || !is.eof()) fail(option, ": '", item, "' is not a number");
    out.push_back(v);
  }
  return out;
}

}  // namespace

int run_sweep(const std::vector<std::string>& args) {
  ArgParser p(
      "pmc sweep SCENE.obj --out-dir DIR [--cells LIST] [--entries LIST] [--mip-biases LIST] [options]",
      "Renders SCENE with every combination of cache settings and writes sweep.csv (time, hit rate,\n"
      "memory, error vs cacheless and vs a reference). scripts/plot_sweep.py turns it into plots.");
  p.option("--out-dir", "DIR", "where sweep.csv goes");
  p.option("--cells", "LIST", "cache cell counts, e.g. 4096,65536,1048576", "the scene's automatic size");
  p.option("--entries", "LIST", "entries per cell, e.g. 1,4,8", "8");
  p.option("--mip-biases", "LIST", "mip biases, e.g. -1,0,1,2", "0");
  p.option("--cache-evals", "LIST",
           "cache modes: hit, center (center + bilinear filter) and/or center-nearest; the CSV's cache_eval "
           "column",
           "center");
  p.option("--reference-spp", "N", "samples of the cacheless reference", "16 x --spp");
  p.option("--convergence-spp", "LIST", "sample counts for equal-time curves, e.g. 1,2,4,8,16");
  p.option("--repeat", "N", "timing rounds; each renders every setting once (round-robin), times are medians",
           "1");
  p.flag("--quiet", "no progress bars");
  declare_render_options(p);
  if (!p.parse(args)) return 0;
  if (p.positional().size() != 1) fail("sweep: expected exactly one SCENE.obj (see --help)");
  if (!p.has("--out-dir")) fail("sweep: missing --out-dir DIR");
  const std::string obj = p.positional()[0], dir = p.get("--out-dir");
  const int repeat = p.get_int("--repeat", 1);
  if (repeat < 1) fail("--repeat: must be at least 1");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) fail("--out-dir: cannot create '", dir, "': ", ec.message());
  apply_thread_option(p);
  ClContext cl(p.get("--device"));
  const bool quiet = p.has("--quiet");

  std::unique_ptr<RenderJob> off_job = prepare_render(p, obj, cl, "off", false);
  std::unique_ptr<RenderJob> on_job = prepare_render(p, obj, cl, "on", !quiet);
  RenderSettings base = off_job->settings;
  RenderSettings ref_settings = base;
  ref_settings.spp = p.get_int("--reference-spp", base.spp * 16);
  if (ref_settings.spp <= 0) fail("--reference-spp: must be at least 1");
  ref_settings.seed = base.seed + 0x9e3779b9u;

  std::vector<long long> cells = p.has("--cells")
                                     ? parse_list<long long>(p.get("--cells"), "--cells")
                                     : std::vector<long long>{(long long)on_job->settings.cache.cells};
  std::vector<long long> entries = parse_list<long long>(p.get("--entries", "8"), "--entries");
  std::vector<float> biases = parse_list<float>(p.get("--mip-biases", "0"), "--mip-biases");
  std::vector<std::string> evals = split_list(p.get("--cache-evals", "center"), "--cache-evals");
  for (long long c : cells)
    if (c <= 0) fail("--cells: cell counts must be positive");
  for (long long e : entries)
    if (e <= 0 || e > 1024) fail("--entries: must be in 1..1024");
  for (const std::string& e : evals)
    if (e != "hit" && e != "center" && e != "center-nearest")
      fail("--cache-evals: expected hit, center and/or center-nearest, got '", e, "'");
  std::vector<int> convergence;
  if (p.has("--convergence-spp"))
    for (int spp : parse_list<int>(p.get("--convergence-spp"), "--convergence-spp")) {
      if (spp <= 0) fail("--convergence-spp: sample counts must be positive");
      convergence.push_back(spp);
    }

  // Every render of the sweep, in CSV order. Timing runs round-robin: each of
  // the --repeat rounds renders every row once (alternating direction), so
  // the machine's drift and noise fall on all rows alike; a row's time is the
  // median over the rounds, its image the first round's.
  struct Row {
    std::string kind, mode, label;  // mode: off, hit, center, center-nearest
    RenderSettings settings;
    bool cached = false;
    std::vector<double> times;
    RenderOutput out;
  };
  std::vector<Row> rows;
  rows.push_back({"cacheless", "off", "cache off", base, false, {}, {}});
  const bool on_available = on_job->settings.cache.on;
  if (!on_available) warn(obj + ": no material has a cache point; only cacheless rows are written");
  auto cached_settings = [&](const std::string& mode) {
    RenderSettings s = on_job->settings;
    s.cache.center = mode != "hit";
    s.cache.bilinear = mode == "center";
    return s;
  };
  if (on_available)
    for (long long c : cells)
      for (long long e : entries)
        for (float b : biases)
          for (const std::string& ev : evals) {
            RenderSettings s = cached_settings(ev);
            s.cache.cells = uint64_t(c);
            s.cache.ways = uint32_t(e);
            s.cache.mip_bias = b;
            std::ostringstream label;
            label << "cells " << c << " x " << e << " bias " << b << " " << ev;
            rows.push_back({"setting", ev, label.str(), s, true, {}, {}});
          }
  for (int spp : convergence)
    for (int on = 0; on < (on_available ? 2 : 1); ++on) {
      RenderSettings s = on ? on_job->settings : base;
      s.spp = spp;
      const std::string mode =
          on ? (s.cache.center ? (s.cache.bilinear ? "center" : "center-nearest") : "hit") : "off";
      rows.push_back({on ? "convergence_on" : "convergence_off",
                      mode,
                      std::string(on ? "on " : "off ") + std::to_string(spp) + " spp",
                      s,
                      on != 0,
                      {},
                      {}});
    }

  auto render_once = [&](RenderJob& job, const RenderSettings& s, const std::string& label) {
    ProgressBar bar(label, !quiet);
    RenderOutput out = job.renderer->render(s, [&](int d, int t, uint64_t n) { bar.update(d, t, n); });
    bar.finish();
    return out;
  };
  Image reference = render_once(*off_job, ref_settings, "reference").image;
  for (int r = 0; r < repeat; ++r)
    for (size_t k = 0; k < rows.size(); ++k) {
      Row& row = rows[r % 2 == 0 ? k : rows.size() - 1 - k];
      std::string label = row.label;
      if (repeat > 1) label += " (round " + std::to_string(r + 1) + "/" + std::to_string(repeat) + ")";
      RenderOutput out = render_once(row.cached ? *on_job : *off_job, row.settings, label);
      row.times.push_back(out.stats.render_seconds);
      if (row.times.size() == 1) row.out = std::move(out);
    }
  for (Row& row : rows) {
    std::sort(row.times.begin(), row.times.end());
    const size_t n = row.times.size();
    row.out.stats.render_seconds = n % 2 ? row.times[n / 2] : 0.5 * (row.times[n / 2 - 1] + row.times[n / 2]);
  }

  OutputGuard guard;
  const std::string csv_path = dir + "/sweep.csv";
  guard.track(csv_path);
  std::ofstream csv(csv_path);
  csv << "kind,cells,entries,mip_bias,cache_eval,spp,time_seconds,hit_rate,memory_bytes,psnr_vs_cacheless,"
         "relmse_vs_cacheless,relmse_vs_reference\n";
  const RenderOutput& cacheless = rows[0].out;
  for (const Row& row : rows) {
    const RenderSettings& s = row.settings;
    const CacheStats& cs = row.out.stats.cache;
    const ImageError vs_ref = compare_images(row.out.image, reference);
    const double hit_rate = cs.lookups ? double(cs.hits) / double(cs.lookups) : 0.0;
    if (row.kind == "cacheless") {
      csv << "cacheless,0,0,0,off," << s.spp << "," << row.out.stats.render_seconds << ",0,0,999,0,"
          << vs_ref.relmse << "\n";
    } else if (row.kind == "setting") {
      const ImageError vs_off = compare_images(row.out.image, cacheless.image);
      csv << "setting," << s.cache.cells << "," << s.cache.ways << "," << s.cache.mip_bias << "," << row.mode
          << "," << s.spp << "," << row.out.stats.render_seconds << "," << hit_rate << "," << cs.memory_bytes
          << "," << vs_off.psnr << "," << vs_off.relmse << "," << vs_ref.relmse << "\n";
    } else {
      csv << row.kind << "," << s.cache.cells << "," << s.cache.ways << "," << s.cache.mip_bias << ","
          << row.mode << "," << s.spp << "," << row.out.stats.render_seconds << "," << hit_rate << ","
          << cs.memory_bytes << ",,," << vs_ref.relmse << "\n";
    }
  }
  csv.close();
  if (!csv) fail(csv_path, ": writing failed");
  guard.commit();
  std::fprintf(stderr, "pmc sweep: wrote %s\n", csv_path.c_str());
  return 0;
}

}  // namespace pmc
