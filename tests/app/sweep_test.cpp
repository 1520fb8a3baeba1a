// sweep_test.cpp — `pmc sweep` end to end through the binary, and
// scripts/plot_sweep.py on what it writes.
//
// Checked against what the options ask for, not against recorded numbers:
// one CSV row per combination of --cells x --entries x --mip-biases x
// --cache-evals (plus the cacheless row and two rows per --convergence-spp),
// memory = cells x entries x 8 bytes, hit rates in [0, 1] and zero for the
// cacheless rows, errors finite; a coarser mip level gives more hits than a
// finer one (fewer, larger texels); center-mode rows are deterministic, so a
// second sweep with the same seed gives the same errors. The plot script
// turns the CSV into its three PNGs. Bad lists exit with 2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.h"

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

// The brick teapot, small: 64x48 pixels, 2 samples.
std::string teapot() {
  return test::shared_scene("materialx/geometry/teapot.obj") + " --mtlx " +
         test::shared_scene("materialx/standard_surface_brick_procedural.mtlx") +
         " --material M_BrickPattern --env 1,1,1 --camera-from 0.75,1.0,2.45 --camera-at -0.09,0.05,-0.01"
         " --width 64 --height 48 --spp 2 --quiet";
}

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

  // Center-mode images do not depend on insertion order: the same sweep again
  // gives the same errors for those rows.
  const std::string dir2 = dir + "/again";
  ASSERT_EQ(test::run_pmc(args + dir2, &log), 0) << log;
  std::vector<CsvRow> again = read_csv(dir2 + "/sweep.csv");
  ASSERT_EQ(again.size(), rows.size());
  for (size_t i = 0; i < rows.size(); ++i)
    if (rows[i].at("kind") == "setting" && rows[i].at("cache_eval") != "hit")
      EXPECT_EQ(rows[i].at("relmse_vs_cacheless"), again[i].at("relmse_vs_cacheless")) << i;

  // The plots.
  const std::string plots = dir + "/plots";
  const std::string cmd =
      test::source_path("scripts/plot_sweep.py") + " " + dir + "/sweep.csv " + plots + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  for (const char* f : {"cache_size_time.png", "mip_bias_error.png", "convergence.png"})
    EXPECT_TRUE(test::file_exists(plots + "/" + f)) << f;
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

}  // namespace
}  // namespace pmc
