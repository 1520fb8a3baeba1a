// sweep_plots.h — `pmc sweep --plots png`: the sweep's figures, written into
// its --out-dir beside sweep.csv.
//
// The figures are drawn by matplotlib: pmc runs scripts/plot_sweep.py of the
// source tree it was built from with the project's Python (scripts/python,
// the .venv that scripts/setup makes; PMC_PYTHON names another interpreter).
// plot_sweep.py writes cache_size_time.png, mip_bias_error.png and
// convergence.png, each when the CSV has the rows it needs (one cache size
// gives no size plot, ...), and prints the numbers it drew. pmc checks that
// the plotter is there before it renders anything, so a sweep never runs for
// an hour to fail at its plots; if plotting fails afterwards, the plots are
// removed and sweep.csv is kept.
#pragma once

#include <string>

namespace pmc {

// The files plot_sweep.py may write into the out-dir.
inline const char* const kSweepPlots[] = {"cache_size_time.png", "mip_bias_error.png", "convergence.png"};

// Fails (pmc::Error naming --plots) when the Python or plot_sweep.py is missing.
void check_sweep_plotter();
// Runs plot_sweep.py on `csv`, writing into `dir`; its output (the numbers it
// drew) goes to stderr unless `quiet`. Fails, having removed the plots it
// wrote, when the script fails. False (with a warning) when the CSV has
// nothing to plot.
bool write_sweep_plots(const std::string& csv, const std::string& dir, bool quiet);

}  // namespace pmc
