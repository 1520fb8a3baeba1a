// sweep_test.cpp — `pmc sweep` end to end through the binary, and
// scripts/plot_sweep.py on what it writes.
//
// Checked against what the options ask for, not against recorded numbers:
// one CSV row per combination of --cells x --entries x --mip-biases x
// --cache-evals (plus the cacheless row and two rows per --convergence-spp),
// memory = cells x entries x 8 bytes, hit rates in [0, 1] and zero for the
// cacheless rows, errors finite; a coarser mip level gives more hits than a
// finer one (fewer, larger texels); center-mode rows are deterministic, so a
// second sweep with the same seed gives the same errors. The sweep draws
// its three plots into its out-dir (--plots png; none with --plots none), and
// a missing plotter fails before anything is rendered. The cache options of `pmc render` are
// aliases of the lists (--mip-bias LIST = --mip-biases LIST, ...) and give
// the same CSV; the convergence_on rows use the grid's first combination and
// their columns say so; --cache-filter and --cache-min-nodes reach every
// cached row. Bad lists, conflicting options and --cache off exit with 2,
// name the option and leave no out-dir behind.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/image_io.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

using CsvRow = std::map<std::string, std::string>;

std::vector<CsvRow> read_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> header;
  std::vector<CsvRow> rows;
  auto split = [](const std::string& l) {
    std::vector<std::string> out;
    std::stringstream ss(l);
    std::string cell;
    while (std::getline(ss, cell, ',')) out.push_back(cell);
    if (!l.empty() && l.back() == ',') out.push_back("");
    return out;
  };
  if (!std::getline(in, line)) return rows;
  header = split(line);
  while (std::getline(in, line)) {
    std::vector<std::string> cells = split(line);
    CsvRow r;
    for (size_t i = 0; i < header.size(); ++i) r[header[i]] = i < cells.size() ? cells[i] : "";
    rows.push_back(r);
  }
  return rows;
}

double num(const CsvRow& r, const std::string& k) { return std::stod(r.at(k)); }

// The brick teapot, 2 samples, no image size; its point planned by node
// count (at 2 spp it would not pay under the cost model: no cached rows).
std::string teapot_scene() {
  return test::shared_scene("materialx/geometry/teapot.obj") + " --mtlx " +
         test::shared_scene("materialx/standard_surface_brick_procedural.mtlx") +
         " --material M_BrickPattern --env 1,1,1 --camera-from 0.75,1.0,2.45 --camera-at -0.09,0.05,-0.01"
         " --spp 2 --quiet --cache-model nodes";
}

// The brick teapot, small: 64x48 pixels, 2 samples.
std::string teapot() { return teapot_scene() + " --width 64 --height 48"; }

TEST(Sweep, WritesOneRowPerSettingAndThePlotsFollow) {
  const std::string dir = test::temp_dir();
  const std::string args =
      "sweep " + teapot() +
      " --cells 64,4096 --entries 2 --mip-biases -2,1 --cache-evals hit,center,center-nearest"
      " --convergence-spp 1,2 --reference-spp 8 --repeat 2 --out-dir ";
  std::string log;
  ASSERT_EQ(test::run_pmc(args + dir, &log), 0) << log;
  std::vector<CsvRow> rows = read_csv(dir + "/sweep.csv");
  ASSERT_EQ(rows.size(), 1u + 2 * 2 * 3 + 2 * 2)
      << "cacheless + cells x biases x modes + 2 per convergence spp";

  std::map<std::string, int> kinds;
  for (const CsvRow& r : rows) {
    kinds[r.at("kind")] += 1;
    const double hit = num(r, "hit_rate"), t = num(r, "time_seconds");
    EXPECT_TRUE(t > 0.0 && std::isfinite(t)) << r.at("kind");
    EXPECT_GE(hit, 0.0);
    EXPECT_LE(hit, 1.0);
    EXPECT_TRUE(std::isfinite(num(r, "relmse_vs_reference")));
    if (r.at("kind") == "setting") {
      EXPECT_EQ(num(r, "entries"), 2.0);
      EXPECT_EQ(num(r, "memory_bytes"), num(r, "cells") * 2 * 8) << "cells x entries x 8 bytes";
      EXPECT_TRUE(std::isfinite(num(r, "psnr_vs_cacheless")));
      EXPECT_GT(hit, 0.0) << "the brick network is cached";
    }
    if (r.at("kind") == "cacheless" || r.at("kind") == "convergence_off") {
      EXPECT_EQ(hit, 0.0);
      EXPECT_EQ(r.at("cache_eval"), "off");
    }
  }
  EXPECT_EQ(kinds["cacheless"], 1);
  EXPECT_EQ(kinds["setting"], 12);
  EXPECT_EQ(kinds["convergence_on"], 2);
  EXPECT_EQ(kinds["convergence_off"], 2);

  // Coarser virtual texels (bias -2) are shared by more samples than finer ones (+1).
  auto hit_of = [&](const std::string& cells, const std::string& bias, const std::string& mode) {
    for (const CsvRow& r : rows)
      if (r.at("kind") == "setting" && r.at("cells") == cells &&
          std::stod(r.at("mip_bias")) == std::stod(bias) && r.at("cache_eval") == mode)
        return num(r, "hit_rate");
    ADD_FAILURE() << "no row " << cells << " " << bias << " " << mode;
    return -1.0;
  };
  for (const char* mode : {"hit", "center", "center-nearest"})
    EXPECT_GT(hit_of("4096", "-2", mode), hit_of("4096", "1", mode)) << mode;

  // The sweep drew its plots into its out-dir (--plots png, the default):
  // PNG images of the size plot_sweep.py draws (110 dpi figures).
  for (const char* f : {"cache_size_time.png", "mip_bias_error.png", "convergence.png"}) {
    ASSERT_TRUE(test::file_exists(dir + "/" + f)) << f << "\n" << log;
    const Image png = read_image(dir + "/" + f);
    EXPECT_GT(png.width, 400) << f;
    EXPECT_GT(png.height, 300) << f;
    EXPECT_GT(test::image_mean(png), 0.5) << f << ": a plot on a white page";
    EXPECT_LT(test::image_mean(png), 1.0) << f << ": something is drawn";
  }

  // Center-mode images do not depend on insertion order: the same sweep again
  // gives the same errors for those rows. With --plots none: only sweep.csv.
  const std::string dir2 = dir + "/again";
  ASSERT_EQ(test::run_pmc(args + dir2 + " --plots none", &log), 0) << log;
  for (const char* f : {"cache_size_time.png", "mip_bias_error.png", "convergence.png"})
    EXPECT_FALSE(test::file_exists(dir2 + "/" + f)) << f;
  std::vector<CsvRow> again = read_csv(dir2 + "/sweep.csv");
  ASSERT_EQ(again.size(), rows.size());
  for (size_t i = 0; i < rows.size(); ++i)
    if (rows[i].at("kind") == "setting" && rows[i].at("cache_eval") != "hit")
      EXPECT_EQ(rows[i].at("relmse_vs_cacheless"), again[i].at("relmse_vs_cacheless")) << i;
}

// A small, fast sweep: 32x24, reference at 2 samples.
std::string small_teapot() { return teapot_scene() + " --width 32 --height 24 --reference-spp 2"; }

std::vector<CsvRow> rows_of(const std::vector<CsvRow>& rows, const std::string& kind) {
  std::vector<CsvRow> out;
  for (const CsvRow& r : rows)
    if (r.at("kind") == kind) out.push_back(r);
  return out;
}

TEST(Sweep, RenderCacheOptionsAreAliasesOfTheLists) {
  const std::string dir = test::temp_dir();
  const std::string common = "sweep " + small_teapot() + " --convergence-spp 1 --out-dir ";
  std::string log;
  ASSERT_EQ(test::run_pmc(common + dir +
                              "/alias --mip-bias -2,1 --cache-eval center,hit --cache-cells 64 "
                              "--cache-entries 2",
                          &log),
            0)
      << log;
  ASSERT_EQ(test::run_pmc(common + dir +
                              "/lists --mip-biases -2,1 --cache-evals center,hit --cells 64 "
                              "--entries 2",
                          &log),
            0)
      << log;
  const std::vector<CsvRow> alias = read_csv(dir + "/alias/sweep.csv"),
                            lists = read_csv(dir + "/lists/sweep.csv");
  ASSERT_EQ(alias.size(), 1u + 2 * 2 + 2) << "cacheless + biases x modes + convergence off and on";
  ASSERT_EQ(alias.size(), lists.size());
  for (size_t i = 0; i < alias.size(); ++i) {
    for (const char* k : {"kind", "cells", "entries", "mip_bias", "cache_eval", "spp", "memory_bytes"})
      EXPECT_EQ(alias[i].at(k), lists[i].at(k)) << i << " " << k;
    if (alias[i].at("cache_eval") == "center")  // deterministic
      EXPECT_EQ(alias[i].at("relmse_vs_reference"), lists[i].at("relmse_vs_reference")) << i;
  }
  std::map<std::string, int> seen;
  for (const CsvRow& r : rows_of(alias, "setting")) {
    EXPECT_EQ(r.at("cells"), "64");
    EXPECT_EQ(r.at("entries"), "2");
    EXPECT_EQ(num(r, "memory_bytes"), 64 * 2 * 8);
    seen[r.at("mip_bias") + " " + r.at("cache_eval")] += 1;
  }
  EXPECT_EQ(seen,
            (std::map<std::string, int>{{"-2 center", 1}, {"-2 hit", 1}, {"1 center", 1}, {"1 hit", 1}}));
  // convergence_on: the first combination (64 cells x 2, bias -2, center), and its columns say so.
  const std::vector<CsvRow> on = rows_of(alias, "convergence_on");
  ASSERT_EQ(on.size(), 1u);
  EXPECT_EQ(on[0].at("cells"), "64");
  EXPECT_EQ(on[0].at("entries"), "2");
  EXPECT_EQ(num(on[0], "mip_bias"), -2.0);
  EXPECT_EQ(on[0].at("cache_eval"), "center");
  EXPECT_EQ(num(on[0], "memory_bytes"), 64 * 2 * 8) << "the table it actually used";
  EXPECT_GT(num(on[0], "hit_rate"), 0.0);
}

TEST(Sweep, CacheFilterAndMinNodesReachEveryCachedRow) {
  const std::string dir = test::temp_dir();
  std::string log;
  // --cache-filter nearest: center rows read the nearest texel, the convergence rows too.
  ASSERT_EQ(
      test::run_pmc("sweep " + small_teapot() +
                        " --cache-evals center,hit --cache-filter nearest --convergence-spp 1 --out-dir " +
                        dir + "/nearest",
                    &log),
      0)
      << log;
  const std::vector<CsvRow> rows = read_csv(dir + "/nearest/sweep.csv");
  const std::vector<CsvRow> settings = rows_of(rows, "setting"), on = rows_of(rows, "convergence_on");
  ASSERT_EQ(settings.size(), 2u);
  EXPECT_EQ(settings[0].at("cache_eval"), "center-nearest");
  EXPECT_EQ(settings[1].at("cache_eval"), "hit");
  ASSERT_EQ(on.size(), 1u);
  EXPECT_EQ(on[0].at("cache_eval"), "center-nearest");
  // Without lists the grid is the defaults: the automatic size, 8 entries, bias 0.
  EXPECT_EQ(on[0].at("cells"), settings[0].at("cells"));
  EXPECT_EQ(on[0].at("entries"), "8");
  EXPECT_EQ(num(on[0], "mip_bias"), 0.0);
  EXPECT_GT(num(on[0], "cells"), 0.0);

  // --cache-min-nodes above any sub-graph: no cache point, so no cached row at all.
  ASSERT_EQ(test::run_pmc("sweep " + small_teapot() +
                              " --cache-min-nodes 100000 --convergence-spp 1 --out-dir " + dir + "/nocache",
                          &log),
            0)
      << log;
  EXPECT_NE(log.find("no material has a cache point"), std::string::npos) << log;
  std::map<std::string, int> kinds;
  for (const CsvRow& r : read_csv(dir + "/nocache/sweep.csv")) kinds[r.at("kind")] += 1;
  EXPECT_EQ(kinds, (std::map<std::string, int>{{"cacheless", 1}, {"convergence_off", 1}}));
}

// Without --cells each --entries value keeps the automatic table's total
// entries (as `pmc render --cache-entries E` does): 1 entry per cell gets 8x
// the cells of 8 entries per cell.
TEST(Sweep, EntriesWithoutCellsKeepTheAutomaticTotal) {
  const std::string dir = test::temp_dir();
  std::string log;
  ASSERT_EQ(test::run_pmc("sweep " + small_teapot() + " --entries 8,1 --out-dir " + dir + "/e", &log), 0)
      << log;
  const std::vector<CsvRow> settings = rows_of(read_csv(dir + "/e/sweep.csv"), "setting");
  ASSERT_EQ(settings.size(), 2u);
  EXPECT_EQ(settings[0].at("entries"), "8");
  EXPECT_EQ(settings[1].at("entries"), "1");
  EXPECT_EQ(num(settings[1], "cells"), 8.0 * num(settings[0], "cells"));
  EXPECT_EQ(num(settings[1], "memory_bytes"), num(settings[0], "memory_bytes"));
}

TEST(Sweep, ConflictingOrMalformedCacheOptionsAreRefused) {
  const std::string tmp = test::temp_dir(), dir = tmp + "/new/out";
  const struct {
    std::string args;
    std::vector<std::string> says;
  } cases[] = {
      {"--mip-bias 0,1 --mip-biases 1", {"--mip-bias", "--mip-biases"}},
      {"--cache-eval hit --cache-evals center", {"--cache-eval", "--cache-evals"}},
      {"--cache-cells 64 --cells 128", {"--cache-cells", "--cells"}},
      {"--cache-entries 2 --entries 4", {"--cache-entries", "--entries"}},
      {"--mip-bias '0;1'", {"--mip-bias", "'0;1'", "comma-separated"}},
      {"--mip-biases 0,x", {"--mip-biases", "'x'", "comma-separated"}},
      {"--mip-bias 1,,2", {"--mip-bias", "comma-separated"}},
      {"--cells 64,", {"--cells", "comma-separated"}},
      {"--cache-cells 6.5", {"--cache-cells", "not an integer"}},
      {"--cache-entries 0", {"--cache-entries", "1..1024"}},
      {"--mip-bias 40", {"--mip-bias", "-32..32"}},
      {"--cells 64,64", {"--cells", "twice"}},
      {"--convergence-spp 1,two", {"--convergence-spp"}},
      {"--cache off", {"--cache off", "the cacheless rows are always rendered"}},
      {"--cache maybe", {"--cache"}},
      {"--cache-evals hit --cache-filter bilinear", {"--cache-filter", "hit"}},
      {"--cache-evals center,center-nearest --cache-filter nearest", {"--cache-evals", "center-nearest"}},
      {"--cache-filter blurry", {"--cache-filter"}},
      {"--reference-spp 0", {"--reference-spp"}},
      {"--plots svg", {"--plots", "png or none"}},
  };
  for (const auto& c : cases) {
    std::string log;
    EXPECT_EQ(test::run_pmc("sweep " + small_teapot() + " " + c.args + " --out-dir " + dir, &log), 2)
        << c.args << "\n"
        << log;
    for (const std::string& s : c.says)
      EXPECT_NE(log.find(s), std::string::npos) << c.args << ": " << s << "\n" << log;
    EXPECT_FALSE(test::file_exists(tmp + "/new")) << c.args << ": out-dir created";
  }
}

TEST(Sweep, HelpDescribesTheListsAndTheConvergenceSetting) {
  std::string help;
  ASSERT_EQ(test::run_pmc("sweep --help", &help), 0) << help;
  for (const char* s :
       {"--mip-bias LIST", "--cache-eval LIST", "--cache-cells LIST", "--cache-entries LIST", "--cells LIST",
        "--mip-biases LIST", "first combination", "--cache-filter", "--cache-min-nodes", "'off' is an error"})
    EXPECT_NE(help.find(s), std::string::npos) << s << "\n" << help;
  for (const char* s : {"--mip-bias B", "--cache-eval hit|center", "--cache-cells N", "--cache on|off"})
    EXPECT_EQ(help.find(s), std::string::npos) << s << " is the render option's line\n" << help;
}

TEST(Sweep, BadListsAreRefused) {
  const std::string dir = test::temp_dir();
  std::string log;
  EXPECT_EQ(test::run_pmc("sweep " + teapot() + " --cache-evals hit,middle --out-dir " + dir, &log), 2)
      << log;
  EXPECT_NE(log.find("--cache-evals"), std::string::npos) << log;
  EXPECT_EQ(test::run_pmc("sweep " + teapot() + " --cells 64,zero --out-dir " + dir, &log), 2) << log;
  EXPECT_NE(log.find("--cells"), std::string::npos) << log;
  EXPECT_EQ(test::run_pmc("sweep " + teapot() + " --mip-biases 0 --repeat 0 --out-dir " + dir, &log), 2)
      << log;
  EXPECT_NE(log.find("--repeat"), std::string::npos) << log;
  EXPECT_FALSE(test::file_exists(dir + "/sweep.csv")) << "no partial output";
}

// Plots need the Python that draws them: missing, the sweep fails before it
// renders anything (exit 2, naming --plots, no out-dir), unless --plots none.
TEST(Sweep, MissingPlotterFailsBeforeRendering) {
  const std::string tmp = test::temp_dir(), dir = tmp + "/new/out";
  ASSERT_EQ(setenv("PMC_PYTHON", (tmp + "/no-such-python").c_str(), 1), 0);
  std::string log;
  const int rc = test::run_pmc("sweep " + small_teapot() + " --out-dir " + dir, &log);
  const int rc_none = test::run_pmc("sweep " + small_teapot() + " --plots none --out-dir " + tmp + "/none");
  unsetenv("PMC_PYTHON");
  EXPECT_EQ(rc, 2) << log;
  EXPECT_NE(log.find("--plots"), std::string::npos) << log;
  EXPECT_NE(log.find("no-such-python"), std::string::npos) << log;
  EXPECT_FALSE(test::file_exists(tmp + "/new")) << "out-dir created: it failed after loading the scene";
  EXPECT_EQ(rc_none, 0);
  EXPECT_TRUE(test::file_exists(tmp + "/none/sweep.csv"));
}

// One cache size, one mip bias and mode, no convergence rows: nothing to
// plot, which is a warning, not a failure (sweep.csv is the result).
TEST(Sweep, NothingToPlotIsAWarning) {
  const std::string dir = test::temp_dir() + "/out";
  std::string log;
  ASSERT_EQ(test::run_pmc("sweep " + small_teapot() + " --out-dir " + dir, &log), 0) << log;
  EXPECT_TRUE(test::file_exists(dir + "/sweep.csv"));
  EXPECT_NE(log.find("nothing to plot"), std::string::npos) << log;
  for (const char* f : {"cache_size_time.png", "mip_bias_error.png", "convergence.png"})
    EXPECT_FALSE(test::file_exists(dir + "/" + f)) << f;
}

}  // namespace
}  // namespace pmc
