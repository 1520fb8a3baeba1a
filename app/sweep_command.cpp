// sweep_command.cpp — `pmc sweep`: cache settings against time and error.
//
// For every combination of --cells, --entries, --mip-biases and --cache-evals
// (app/sweep_grid.h) it renders the scene cached (same seed and samples as
// one cacheless render) and writes a row of sweep.csv (app/sweep_table.h):
// time, hit rate, memory, error against the cacheless render and against a
// high-sample reference. With --convergence-spp it also renders cache off
// and on at each sample count, measuring relMSE against the reference: the
// equal-time question a user asks ("for the same time, is the cached image
// better?"). The cached convergence rows use the grid's first combination.
//
// The render options of `pmc render` apply to every row; the cache options a
// sweep varies are lists here, and each row's cache settings are set on the
// cached session's settings and checked by validate_render_settings()
// (gpu/render_config.h), as the renderer checks them. --cache-filter sets the filter of every
// center-mode row; --cache-min-nodes shapes the one cached program all
// cached rows share. With --plots png the figures of sweep.csv are drawn into
// the out-dir as well (app/sweep_plots.h).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <sstream>

#include "app/cli.h"
#include "app/commands.h"
#include "app/output_guard.h"
#include "app/progress.h"
#include "app/render_options.h"
#include "app/sweep_grid.h"
#include "app/sweep_plots.h"
#include "app/sweep_table.h"
#include "core/atomic_write.h"
#include "core/cache_sizing.h"
#include "core/error.h"
#include "core/image_metrics.h"
#include "gpu/render_session.h"

namespace pmc {
namespace {

struct SweepArgs {
  RenderConfig config;  // the render options; its cache fields other than min nodes are unused
  SweepLists lists;
  std::string dir, cache, plots = "png";
  int reference_spp = 0, repeat = 1;
  bool quiet = false;
};

// A render of the sweep. Timing runs round-robin: each of the --repeat rounds
// renders every row once (alternating direction), so the machine's drift and
// noise fall on all rows alike; a row's time is the median over the rounds,
// its image the first round's.
struct Run {
  SweepRow row;
  std::string label;
  RenderSettings settings;
  bool cached = false;
  std::vector<double> times;
  RenderOutput out;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int run_sweep(SweepArgs& a) {
  if (a.cache == "off")
    fail("--cache off: sweep compares cache settings; the cacheless rows are always rendered");
  // The lists, checked before anything is loaded or rendered.
  SweepGrid grid = parse_sweep_grid(a.lists);
  if (a.plots == "png") check_sweep_plotter();
  const std::string &obj = a.config.scene, &dir = a.dir;
  OutDir out_dir(dir);  // checked now, created once the renders are prepared
  RenderConfig config = a.config;
  config.validate();
  std::unique_ptr<ClContext> cl = open_device(config);
  config.cache = false;
  RenderSession off_session(config, *cl);
  config.cache = true;
  RenderSession on_session(config, *cl);
  if (!a.quiet) print_cache_choice(on_session.settings());
  const RenderSettings base = off_session.settings();
  RenderSettings ref_settings = base;
  ref_settings.spp = a.reference_spp > 0 ? a.reference_spp : base.spp * 16;
  ref_settings.seed = base.seed + 0x9e3779b9u;
  // Without --cells, each entries value gets the cell count that keeps the
  // automatic table's total entries (what `pmc render --cache-entries E` picks).
  const CacheSettings& auto_size = on_session.settings().cache;
  const uint64_t auto_total = auto_size.cells * std::max<uint64_t>(1, auto_size.ways);
  auto cells_for = [&](long long c, long long e) {
    return c > 0 ? uint64_t(c) : cells_for_total_entries(auto_total, uint64_t(e));
  };
  if (grid.cells.empty()) grid.cells.push_back(-1);  // automatic
  for (long long c : grid.cells)
    for (long long e : grid.entries)
      if (std::string problem = table_memory_problem(cells_for(c, e), uint64_t(e)); !problem.empty())
        fail(a.lists.cells.names, "/", a.lists.entries.names, ": ", problem);

  out_dir.create();

  std::vector<Run> runs;
  auto cacheless = [&](const std::string& kind, int spp, const std::string& label) {
    Run r;
    r.row.kind = kind;
    r.row.cache_eval = "off";
    r.settings = base;
    r.settings.spp = r.row.spp = spp;
    validate_render_settings(r.settings);  // as every render's (gpu/render_config.h)
    r.label = label;
    runs.push_back(r);
  };
  auto cached = [&](const std::string& kind, long long c, long long e, double b, const SweepMode& m,
                    int spp) {
    Run r;
    r.settings = on_session.settings();
    r.settings.cache.cells = cells_for(c, e);
    r.settings.cache.ways = uint32_t(e);
    r.settings.cache.mip_bias = float(b);
    r.settings.cache.center = m.center;
    r.settings.cache.bilinear = m.bilinear;
    r.settings.spp = spp;
    validate_render_settings(r.settings);  // the row's edits, checked as every render's (gpu/render_config.h)
    r.cached = true;
    r.row.kind = kind;
    r.row.cache_eval = m.name();
    r.row.cells = r.settings.cache.cells;
    r.row.entries = r.settings.cache.ways;
    r.row.mip_bias = r.settings.cache.mip_bias;
    r.row.spp = spp;
    std::ostringstream label;
    if (kind == "convergence_on") label << "on " << spp << " spp, ";
    label << "cells " << r.row.cells << " x " << r.row.entries << " bias " << r.row.mip_bias << " "
          << m.name();
    r.label = label.str();
    runs.push_back(r);
  };
  cacheless("cacheless", base.spp, "cache off");
  const bool on_available = on_session.settings().cache.on;
  if (!on_available) warn(obj + ": no material has a cache point; only cacheless rows are written");
  if (on_available)
    for (long long c : grid.cells)
      for (long long e : grid.entries)
        for (double b : grid.biases)
          for (const SweepMode& m : grid.modes) cached("setting", c, e, b, m, base.spp);
  // The cached convergence rows: the grid's first combination.
  for (int spp : grid.convergence) {
    cacheless("convergence_off", spp, "off " + std::to_string(spp) + " spp");
    if (on_available)
      cached("convergence_on", grid.cells[0], grid.entries[0], grid.biases[0], grid.modes[0], spp);
  }

  auto render_once = [&](RenderSession& session, const RenderSettings& s, const std::string& label) {
    ProgressBar bar(label, !a.quiet);
    RenderOutput out = session.render(s, [&](int d, int t, uint64_t n) { bar.update(d, t, n); });
    bar.finish();
    return out;
  };
  const Image reference = render_once(off_session, ref_settings, "reference").image;
  for (int round = 0; round < a.repeat; ++round)
    for (size_t k = 0; k < runs.size(); ++k) {
      Run& run = runs[round % 2 == 0 ? k : runs.size() - 1 - k];
      std::string label = run.label;
      if (a.repeat > 1)
        label += " (round " + std::to_string(round + 1) + "/" + std::to_string(a.repeat) + ")";
      RenderOutput out = render_once(run.cached ? on_session : off_session, run.settings, label);
      run.times.push_back(out.stats.render_seconds);
      if (run.times.size() == 1) run.out = std::move(out);
    }

  std::vector<SweepRow> rows;
  for (Run& run : runs) {
    SweepRow& row = run.row;
    row.time_seconds = median(run.times);
    row.relmse_vs_reference = compare_images(run.out.image, reference).relmse;
    if (run.cached) {
      row.hit_rate = hit_rate(run.out.stats.cache);
      row.memory_bytes = run.out.stats.cache.memory_bytes;
    }
    if (row.kind == "cacheless") {
      row.psnr_vs_cacheless = 999.0;
      row.relmse_vs_cacheless = 0.0;
    } else if (row.kind == "setting") {
      const ImageError vs_off = compare_images(run.out.image, runs[0].out.image);
      row.psnr_vs_cacheless = vs_off.psnr;
      row.relmse_vs_cacheless = vs_off.relmse;
    }
    rows.push_back(row);
  }

  OutputGuard guard;
  const std::string csv_path = dir + "/sweep.csv";
  guard.track(csv_path);
  write_text_file(csv_path, sweep_csv(rows));
  guard.commit();
  out_dir.commit();
  std::fprintf(stderr, "pmc sweep: wrote %s\n", csv_path.c_str());
  if (a.plots == "png") {
    if (write_sweep_plots(csv_path, dir, a.quiet))
      std::fprintf(stderr, "pmc sweep: plots in %s\n", dir.c_str());
  }
  return 0;
}

}  // namespace

CommandRun add_sweep_command(CLI::App& pmc) {
  auto a = std::make_shared<SweepArgs>();
  CLI::App* app = pmc.add_subcommand("sweep", "cache sizes, mip biases, eval modes -> sweep.csv");
  cli::formatter(pmc).usage(
      app,
      "pmc sweep SCENE.obj --out-dir DIR [--cells LIST] [--entries LIST] "
      "[--mip-biases LIST] [--cache-evals LIST] [options]",
      "Renders SCENE cacheless once and cached with every combination of --cells x --entries x\n"
      "--mip-biases x --cache-evals (same seed and samples) and writes sweep.csv: time, hit rate,\n"
      "memory, error vs cacheless and vs a reference. Each row's cells, entries, mip_bias and\n"
      "cache_eval columns are the settings it was rendered with. The convergence_on rows of\n"
      "--convergence-spp use the grid's first combination (the first value of each list).\n"
      "The render options apply to every row; the cache options that the sweep varies take\n"
      "lists here (their pmc render names are aliases). With --plots png (the default) the\n"
      "figures go into DIR too: scripts/plot_sweep.py draws them with matplotlib.");
  app->option_defaults()->group("options");
  app->set_help_flag("-h,--help", "print this help and exit");
  app->add_option("SCENE.obj", a->config.scene, "the OBJ scene")->required();
  app->add_option("--out-dir", a->dir, "where sweep.csv and the plots go (created when the inputs are valid)")
      ->type_name("DIR")
      ->required();
  app->add_option("--plots", a->plots,
                  "png: matplotlib PNGs of sweep.csv in DIR, drawn by the source tree's "
                  "scripts/plot_sweep.py with its Python (scripts/python; PMC_PYTHON overrides): "
                  "cache_size_time.png (2+ cache sizes), mip_bias_error.png (2+ biases or modes), "
                  "convergence.png (--convergence-spp); none: only sweep.csv")
      ->type_name("png|none")
      ->check(cli::one_of({"png", "none"}))
      ->capture_default_str();
  add_list_option(*app, "--cells,--cache-cells", a->lists.cells, "cache cell counts, e.g. 4096,65536,1048576")
      ->default_str(
          "the scene's automatic size: per --entries value, the cells that keep its total entries, as pmc "
          "render --cache-entries does");
  add_list_option(*app, "--entries,--cache-entries", a->lists.entries,
                  "entries per cell, 1..1024, e.g. 1,4,8")
      ->default_str("8");
  add_list_option(*app, "--mip-biases,--mip-bias", a->lists.biases, "mip biases, -32..32, e.g. -1,0,1,2")
      ->default_str("0");
  add_list_option(*app, "--cache-evals,--cache-eval", a->lists.evals,
                  "cache modes: hit, center (center + bilinear filter) and/or center-nearest; the CSV's "
                  "cache_eval column")
      ->default_str("center");
  app->add_option(
         "--cache-filter", a->lists.filter,
         "filter of every center-mode row, convergence_on included: nearest turns 'center' rows into "
         "center-nearest ones; bilinear refuses 'hit' and 'center-nearest'")
      ->type_name("nearest|bilinear")
      ->check(cli::one_of({"nearest", "bilinear"}))
      ->default_str("as --cache-evals names it");
  cli::name_setting("cache_model", "--cache-model");
  app->add_option_function<std::string>(
         "--cache-model",
         [a](const std::string& v) {
           a->config.cache_model = v == "nodes" ? CacheModel::Nodes : CacheModel::Cost;
         },
         "which sub-graphs become cache points, for every cached row: cost: those that pay on this device "
         "for "
         "this frame; nodes: the node count alone (see pmc render --help)")
      ->type_name("cost|nodes")
      ->check(cli::one_of({"cost", "nodes"}))
      ->default_str("cost");
  cli::name_setting("cache_min_nodes", "--cache-min-nodes");
  app->add_option("--cache-min-nodes", a->config.cache_min_nodes,
                  "smallest sub-graph (in nodes) worth a cache point, for every cached row")
      ->type_name("N")
      ->check(cli::integer<int>())
      ->capture_default_str();
  app->add_option(
         "--cache", a->cache,
         "sweep always renders the cacheless rows and the cached ones: 'on' changes nothing, 'off' is "
         "an error")
      ->type_name("on")
      ->check(cli::one_of({"on", "off"}));
  app->add_option("--reference-spp", a->reference_spp, "samples per pixel of the cacheless reference")
      ->type_name("N")
      ->check(cli::at_least(1))
      ->default_str("16 x --spp");
  add_list_option(*app, "--convergence-spp", a->lists.convergence,
                  "sample counts for equal-time curves, e.g. 1,2,4,8,16: cache off and on (with the grid's "
                  "first combination) at each");
  app->add_option("--repeat", a->repeat,
                  "timing rounds; each renders every setting once (round-robin), times are medians")
      ->type_name("N")
      ->check(cli::at_least(1))
      ->capture_default_str();
  add_quiet_flag(*app, a->quiet, "warnings still print");
  declare_render_options(*app, a->config, CacheFlags::None);
  return [a] { return run_sweep(*a); };
}

}  // namespace pmc
