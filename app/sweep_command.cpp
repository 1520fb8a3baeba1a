// sweep_command.cpp — `pmc sweep`: cache settings against time and error.
//
// For every combination of --cells, --entries, --mip-biases and --cache-evals it
// renders the scene cached (same seed and samples as one cacheless render)
// and writes a row of sweep.csv: time, hit rate, memory, error against the
// cacheless render and against a high-sample reference. With
// --convergence-spp it also renders cache off and on at each sample count,
// measuring relMSE against the reference: the equal-time question a user
// asks ("for the same time, is the cached image better?"). The cached
// convergence rows use the grid's first combination. The plots come from
// scripts/plot_sweep.py.
//
// The render options of `pmc render` are accepted and apply to every row,
// but the cache options that a sweep varies take lists here: --mip-bias,
// --cache-eval, --cache-cells and --cache-entries are aliases of the sweep's
// --mip-biases, --cache-evals, --cells and --entries. So that prepare_render()
// (which reads them as single values) never sees a list, the jobs are
// prepared from a second parse of the command line without them; the sweep
// sets each row's cache settings itself, and the CSV columns are the settings
// a row was rendered with. --cache-filter sets the filter of every
// center-mode row; --cache-min-nodes shapes the one cached program all
// cached rows share.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "app/commands.h"
#include "app/output_guard.h"
#include "app/progress.h"
#include "app/render_options.h"
#include "core/cache_sizing.h"
#include "core/error.h"
#include "core/image_metrics.h"
#include "gpu/render_session.h"

namespace pmc {
namespace {

// A list option's value and the name it was given under (for messages).
struct ListArg {
  std::string option, value;
};

// `name` or its render-option alias `alias`, not both; `fallback` when neither.
ListArg list_arg(const ArgParser& p, const std::string& name, const std::string& alias,
                 const std::string& fallback) {
  if (p.has(name) && p.has(alias))
    fail("sweep: ", alias, " is the same list as ", name, "; give one of them, not both");
  if (p.has(alias)) return {alias, p.get(alias)};
  return {name, p.get(name, fallback)};
}

// "a,b,c": items without spaces around them; empty items are errors.
std::vector<std::string> split_list(const ListArg& a, const char* example) {
  std::vector<std::string> out;
  std::string item;
  std::stringstream ss(a.value);
  bool bad = a.value.empty() || a.value.back() == ',';
  while (!bad && std::getline(ss, item, ',')) {
    const size_t b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b == std::string::npos)
      bad = true;
    else
      out.push_back(item.substr(b, e - b + 1));
  }
  if (bad) fail(a.option, ": '", a.value, "' is not a comma-separated list (e.g. ", example, ")");
  return out;
}

// "'x'" or, in a longer list, "'x' in 'a,x,b'".
std::string quoted_item(const ListArg& a, const std::string& item) {
  return "'" + item + "'" + (item == a.value ? "" : " in '" + a.value + "'");
}

template <typename T>
void refuse_duplicates(const ListArg& a, const std::vector<T>& values,
                       const std::vector<std::string>& items) {
  for (size_t i = 0; i < values.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (values[i] == values[j])
        fail(a.option, ": '", items[i], "' is listed twice in '", a.value, "' (each value gives one row)");
}

std::vector<long long> int_list(const ListArg& a, const char* example) {
  const std::vector<std::string> items = split_list(a, example);
  std::vector<long long> out;
  for (const std::string& item : items) {
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(item.c_str(), &end, 10);
    if (*end != '\0' || errno == ERANGE)
      fail(a.option, ": ", quoted_item(a, item), " is not an integer (expected a comma-separated list, e.g. ",
           example, ")");
    out.push_back(v);
  }
  refuse_duplicates(a, out, items);
  return out;
}

std::vector<double> number_list(const ListArg& a, const char* example) {
  const std::vector<std::string> items = split_list(a, example);
  std::vector<double> out;
  for (const std::string& item : items) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (*end != '\0' || !std::isfinite(v))
      fail(a.option, ": ", quoted_item(a, item),
           " is not a finite number (expected a comma-separated list, e.g. ", example, ")");
    out.push_back(v);
  }
  refuse_duplicates(a, out, items);
  return out;
}

// A cached row's evaluation mode, named as in the CSV's cache_eval column.
struct Mode {
  bool center = true, bilinear = true;
  std::string name() const { return center ? (bilinear ? "center" : "center-nearest") : "hit"; }
};

// --cache-evals after --cache-filter: the filter applies to every center-mode row.
std::vector<Mode> modes_from(const ListArg& a, const ArgParser& p) {
  const std::vector<std::string> items = split_list(a, "hit,center");
  const std::string filter = p.get("--cache-filter");
  if (p.has("--cache-filter") && filter != "nearest" && filter != "bilinear")
    fail("--cache-filter: expected nearest or bilinear, got '", filter, "'");
  std::vector<Mode> out;
  std::vector<std::string> names;
  for (const std::string& item : items) {
    Mode m;
    if (item == "hit")
      m = {false, false};
    else if (item == "center")
      m = {true, true};
    else if (item == "center-nearest")
      m = {true, false};
    else
      fail(a.option, ": expected hit, center and/or center-nearest, got '", item, "'");
    if (filter == "bilinear" && !(item == "center"))
      fail("--cache-filter bilinear: applies to center-mode rows only, but ", a.option, " lists '", item,
           "' (a hit-mode texel has no centre value to interpolate; center-nearest is the nearest filter)");
    if (filter == "nearest") m.bilinear = false;
    out.push_back(m);
    names.push_back(m.name());
  }
  for (size_t i = 0; i < names.size(); ++i)
    if (std::count(names.begin(), names.begin() + i, names[i]))
      fail(a.option, ": '", a.value, "' gives two ", names[i], " rows",
           p.has("--cache-filter") ? " (--cache-filter nearest makes center rows center-nearest)" : "");
  return out;
}

// The command line without the options the sweep reads as lists, for
// prepare_render(); the sweep sets those per row. (A value that looks like
// an option name is not expected here: the full parse accepted `args`.)
std::vector<std::string> without_sweep_lists(const std::vector<std::string>& args) {
  static const std::set<std::string> lists = {"--mip-bias",      "--cache-eval",   "--cache-cells",
                                              "--cache-entries", "--cache-filter", "--cache"};
  std::vector<std::string> out;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string name = args[i].substr(0, args[i].find('='));
    if (!lists.count(name)) {
      out.push_back(args[i]);
    } else if (name.size() == args[i].size()) {
      ++i;  // its value
    }
  }
  return out;
}

}  // namespace

int run_sweep(const std::vector<std::string>& args) {
  auto declare = [](ArgParser& p) {
    p.option("--out-dir", "DIR", "where sweep.csv goes");
    p.option("--cells", "LIST", "cache cell counts, e.g. 4096,65536,1048576 (alias: --cache-cells)",
             "the scene's automatic size: per --entries value, the cells that keep its total entries, as "
             "pmc render --cache-entries does");
    p.option("--entries", "LIST", "entries per cell, e.g. 1,4,8 (alias: --cache-entries)", "8");
    p.option("--mip-biases", "LIST", "mip biases, e.g. -1,0,1,2 (alias: --mip-bias)", "0");
    p.option(
        "--cache-evals", "LIST",
        "cache modes: hit, center (center + bilinear filter) and/or center-nearest; the CSV's cache_eval "
        "column (alias: --cache-eval)",
        "center");
    p.option("--reference-spp", "N", "samples of the cacheless reference", "16 x --spp");
    p.option("--convergence-spp", "LIST",
             "sample counts for equal-time curves, e.g. 1,2,4,8,16: cache off and on (with the grid's first "
             "combination) at each");
    p.option("--repeat", "N",
             "timing rounds; each renders every setting once (round-robin), times are medians", "1");
    p.flag("--quiet", "no progress bars and no cache-size lines (warnings still print)");
    declare_render_options(p);
  };
  ArgParser p(
      "pmc sweep SCENE.obj --out-dir DIR [--cells LIST] [--entries LIST] [--mip-biases LIST] "
      "[--cache-evals LIST] [options]",
      "Renders SCENE cacheless once and cached with every combination of --cells x --entries x\n"
      "--mip-biases x --cache-evals (same seed and samples) and writes sweep.csv: time, hit rate,\n"
      "memory, error vs cacheless and vs a reference. Each row's cells, entries, mip_bias and\n"
      "cache_eval columns are the settings it was rendered with. The convergence_on rows of\n"
      "--convergence-spp use the grid's first combination (the first value of each list).\n"
      "The render options apply to every row; the cache options that the sweep varies take\n"
      "lists here. scripts/plot_sweep.py turns sweep.csv into plots.");
  declare(p);
  p.redescribe(
      "--cache", "on",
      "sweep always renders the cacheless rows and the cached ones: 'on' changes nothing, 'off' is an "
      "error");
  p.redescribe("--cache-cells", "LIST", "same as --cells (give one of the two)");
  p.redescribe("--cache-entries", "LIST", "same as --entries (give one of the two)");
  p.redescribe("--mip-bias", "LIST", "same as --mip-biases (give one of the two)");
  p.redescribe("--cache-eval", "LIST", "same as --cache-evals (give one of the two)");
  p.redescribe("--cache-filter", "nearest|bilinear",
               "filter of every center-mode row, convergence_on included: nearest turns 'center' rows into "
               "center-nearest ones; bilinear refuses 'hit' and 'center-nearest'",
               "as --cache-evals names it");
  p.redescribe("--cache-min-nodes", "N", "smallest sub-graph worth a cache point, for every cached row",
               std::to_string(kDefaultCacheMinNodes));
  if (!p.parse(args)) return 0;
  if (p.positional().size() != 1) fail("sweep: expected exactly one SCENE.obj (see --help)");
  if (!p.has("--out-dir")) fail("sweep: missing --out-dir DIR");
  const std::string obj = p.positional()[0], dir = p.get("--out-dir");
  OutDir out_dir(dir);  // checked now, created once the renders are prepared
  const int repeat = p.get_int("--repeat", 1);
  if (repeat < 1) fail("--repeat: must be at least 1");
  if (p.has("--reference-spp") && p.get_int("--reference-spp", 0) <= 0)
    fail("--reference-spp: must be at least 1");
  if (p.has("--cache")) {
    const std::string cache = p.get("--cache");
    if (cache == "off")
      fail("--cache off: sweep compares cache settings; the cacheless rows are always rendered");
    if (cache != "on") fail("--cache: expected on or off, got '", cache, "'");
  }

  // The lists, checked before anything is loaded or rendered.
  const ListArg cells_arg = list_arg(p, "--cells", "--cache-cells", "");
  const ListArg entries_arg = list_arg(p, "--entries", "--cache-entries", "8");
  const ListArg bias_arg = list_arg(p, "--mip-biases", "--mip-bias", "0");
  const ListArg eval_arg = list_arg(p, "--cache-evals", "--cache-eval", "center");
  std::vector<long long> cells;
  if (p.has("--cells") || p.has("--cache-cells")) cells = int_list(cells_arg, "4096,65536");
  for (long long c : cells)
    if (c <= 0) fail(cells_arg.option, ": cell counts must be positive, got ", c);
  const std::vector<long long> entries = int_list(entries_arg, "1,4,8");
  for (long long e : entries)
    if (e <= 0 || e > 1024) fail(entries_arg.option, ": entries per cell must be in 1..1024, got ", e);
  const std::vector<double> biases = number_list(bias_arg, "-1,0,1,2");
  for (double b : biases)
    if (std::fabs(b) > 32.0) fail(bias_arg.option, ": mip biases must be within -32..32, got ", b);
  const std::vector<Mode> modes = modes_from(eval_arg, p);
  std::vector<int> convergence;
  if (p.has("--convergence-spp")) {
    const ListArg conv_arg{"--convergence-spp", p.get("--convergence-spp")};
    for (long long spp : int_list(conv_arg, "1,2,4,8,16")) {
      if (spp <= 0 || spp > 2147483647LL)
        fail("--convergence-spp: sample counts must be positive, got ", spp);
      convergence.push_back(int(spp));
    }
  }

  // The render options as prepare_render() reads them: single values only.
  ArgParser render_args("", "");
  declare(render_args);
  render_args.parse(without_sweep_lists(args));
  RenderConfig config = render_config_from(render_args, obj);
  std::unique_ptr<ClContext> cl = open_device(config);
  const bool quiet = p.has("--quiet");
  config.cache = false;
  RenderSession off_session(config, *cl);
  config.cache = true;
  RenderSession on_session(config, *cl);
  if (!quiet) print_cache_choice(on_session.settings());
  RenderSettings base = off_session.settings();
  RenderSettings ref_settings = base;
  ref_settings.spp = p.get_int("--reference-spp", base.spp * 16);
  if (ref_settings.spp <= 0) fail("--reference-spp: must be at least 1");
  ref_settings.seed = base.seed + 0x9e3779b9u;
  // Without --cells, each entries value gets the cell count that keeps the
  // automatic table's total entries (what `pmc render --cache-entries E` picks).
  const uint64_t auto_total =
      on_session.settings().cache.cells * std::max<uint64_t>(1, on_session.settings().cache.ways);
  auto cells_for = [&](long long c, long long e) -> long long {
    return c > 0 ? c : (long long)cells_for_total_entries(auto_total, uint64_t(e));
  };
  if (cells.empty()) cells.push_back(-1);  // automatic
  for (long long c0 : cells)
    for (long long e : entries)
      if (std::string problem = table_memory_problem(uint64_t(cells_for(c0, e)), uint64_t(e));
          !problem.empty())
        fail(cells_arg.option, "/", entries_arg.option, ": ", problem);

  out_dir.create();

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
  const bool on_available = on_session.settings().cache.on;
  if (!on_available) warn(obj + ": no material has a cache point; only cacheless rows are written");
  auto cached_settings = [&](long long c, long long e, double b, const Mode& m) {
    RenderSettings s = on_session.settings();
    s.cache.cells = uint64_t(cells_for(c, e));
    s.cache.ways = uint32_t(e);
    s.cache.mip_bias = float(b);
    s.cache.center = m.center;
    s.cache.bilinear = m.bilinear;
    return s;
  };
  auto describe = [](const RenderSettings& s, const Mode& m) {
    std::ostringstream label;
    label << "cells " << s.cache.cells << " x " << s.cache.ways << " bias " << s.cache.mip_bias << " "
          << m.name();
    return label.str();
  };
  if (on_available)
    for (long long c : cells)
      for (long long e : entries)
        for (double b : biases)
          for (const Mode& m : modes) {
            RenderSettings s = cached_settings(c, e, b, m);
            rows.push_back({"setting", m.name(), describe(s, m), s, true, {}, {}});
          }
  // The cached convergence rows: the grid's first combination.
  const RenderSettings convergence_on = cached_settings(cells[0], entries[0], biases[0], modes[0]);
  for (int spp : convergence)
    for (int on = 0; on < (on_available ? 2 : 1); ++on) {
      RenderSettings s = on ? convergence_on : base;
      s.spp = spp;
      const std::string label = on ? "on " + std::to_string(spp) + " spp, " + describe(s, modes[0])
                                   : "off " + std::to_string(spp) + " spp";
      rows.push_back({on ? "convergence_on" : "convergence_off",
                      on ? modes[0].name() : "off",
                      label,
                      s,
                      on != 0,
                      {},
                      {}});
    }

  auto render_once = [&](RenderSession& session, const RenderSettings& s, const std::string& label) {
    ProgressBar bar(label, !quiet);
    RenderOutput out = session.render(s, [&](int d, int t, uint64_t n) { bar.update(d, t, n); });
    bar.finish();
    return out;
  };
  Image reference = render_once(off_session, ref_settings, "reference").image;
  for (int r = 0; r < repeat; ++r)
    for (size_t k = 0; k < rows.size(); ++k) {
      Row& row = rows[r % 2 == 0 ? k : rows.size() - 1 - k];
      std::string label = row.label;
      if (repeat > 1) label += " (round " + std::to_string(r + 1) + "/" + std::to_string(repeat) + ")";
      RenderOutput out = render_once(row.cached ? on_session : off_session, row.settings, label);
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
    if (!row.cached) {
      csv << row.kind << ",0,0,0,off," << s.spp << "," << row.out.stats.render_seconds << ",0,0,"
          << (row.kind == "cacheless" ? "999,0," : ",,") << vs_ref.relmse << "\n";
      continue;
    }
    csv << row.kind << "," << s.cache.cells << "," << s.cache.ways << "," << s.cache.mip_bias << ","
        << row.mode << "," << s.spp << "," << row.out.stats.render_seconds << "," << hit_rate(cs) << ","
        << cs.memory_bytes << ",";
    if (row.kind == "setting") {
      const ImageError vs_off = compare_images(row.out.image, cacheless.image);
      csv << vs_off.psnr << "," << vs_off.relmse << ",";
    } else {
      csv << ",,";
    }
    csv << vs_ref.relmse << "\n";
  }
  csv.close();
  if (!csv) fail(csv_path, ": writing failed");
  guard.commit();
  out_dir.commit();
  std::fprintf(stderr, "pmc sweep: wrote %s\n", csv_path.c_str());
  return 0;
}

}  // namespace pmc
