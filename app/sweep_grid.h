// sweep_grid.h — the cache settings `pmc sweep` renders, from its list options.
//
// --cells, --entries, --mip-biases and --cache-evals take comma-separated
// lists (their `pmc render` names --cache-cells, --cache-entries, --mip-bias
// and --cache-eval are CLI11 aliases of them); --convergence-spp lists sample
// counts. parse_sweep_grid() checks every list before anything is loaded:
// items are numbers (or modes) in range, none is listed twice (each value
// gives one row), and a list is given once under either of its names.
// Messages name the option by both names ("--cells/--cache-cells").
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace pmc {

// A list option as given on the command line: its names for messages and
// each occurrence's text (more than one is an error).
struct ListOption {
  std::string names;
  std::vector<std::string> given;
};
// Declares `list` on `app` under `cli_names` ("--cells,--cache-cells").
CLI::Option* add_list_option(CLI::App& app, const std::string& cli_names, ListOption& list,
                             const std::string& help);

// A cached row's evaluation mode, named as in the CSV's cache_eval column.
struct SweepMode {
  bool center = true, bilinear = true;
  std::string name() const { return center ? (bilinear ? "center" : "center-nearest") : "hit"; }
};

struct SweepLists {
  ListOption cells, entries, biases, evals, convergence;
  std::string filter;  // --cache-filter: "", nearest or bilinear
};

struct SweepGrid {
  std::vector<long long> cells;  // empty: the scene's automatic size per entries value
  std::vector<long long> entries;
  std::vector<double> biases;
  std::vector<SweepMode> modes;
  std::vector<int> convergence;  // sample counts of the convergence rows
};

SweepGrid parse_sweep_grid(const SweepLists& lists);

}  // namespace pmc
