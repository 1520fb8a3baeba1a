// sweep_plots.cpp — runs scripts/plot_sweep.py on a sweep's CSV.
#include "app/sweep_plots.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "core/error.h"

#ifndef PMC_SOURCE_DIR
#error "PMC_SOURCE_DIR must name the source tree (CMakeLists.txt sets it)"
#endif

namespace pmc {
namespace {

std::string python() {
  const char* env = std::getenv("PMC_PYTHON");
  return env && *env ? env : std::string(PMC_SOURCE_DIR) + "/scripts/python";
}

std::string script() { return std::string(PMC_SOURCE_DIR) + "/scripts/plot_sweep.py"; }

std::string quoted(const std::string& s) {  // one word for /bin/sh
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

void check_sweep_plotter() {
  const std::string py = python();
  const bool on_path = py.find('/') == std::string::npos;  // PMC_PYTHON=python3
  if (!on_path && access(py.c_str(), X_OK) != 0)
    fail("--plots png: the Python that draws the plots, '", py,
         "', is missing (run scripts/setup, set PMC_PYTHON, or give --plots none)");
  if (!on_path && !std::getenv("PMC_PYTHON") &&
      access((std::string(PMC_SOURCE_DIR) + "/.venv/bin/python").c_str(), X_OK) != 0)
    fail("--plots png: the project's Python (", PMC_SOURCE_DIR,
         "/.venv) is missing: run scripts/setup, or give --plots none");
  if (access(script().c_str(), R_OK) != 0)
    fail("--plots png: '", script(), "' is missing (give --plots none)");
}

bool write_sweep_plots(const std::string& csv, const std::string& dir, bool quiet) {
  const std::string cmd = quoted(python()) + " " + quoted(script()) + " --allow-empty " + quoted(csv) + " " +
                          quoted(dir) + " 2>&1";
  std::string output;
  int status = -1;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[4096];
    while (size_t n = std::fread(buf, 1, sizeof buf, p)) output.append(buf, n);
    status = pclose(p);
  }
  if (status != 0) {
    std::error_code ec;
    for (const char* f : kSweepPlots) std::filesystem::remove(std::filesystem::path(dir) / f, ec);
    if (output.size() > 4000) output = "..." + output.substr(output.size() - 4000);
    fail("--plots png: scripts/plot_sweep.py failed (", csv, " is complete; run scripts/python ",
         "scripts/plot_sweep.py ", csv, " ", dir, " again once it works):\n", output);
  }
  if (!quiet) std::fprintf(stderr, "%s", output.c_str());
  std::error_code ec;
  for (const char* f : kSweepPlots)
    if (std::filesystem::exists(std::filesystem::path(dir) / f, ec)) return true;
  warn("--plots png: nothing to plot in " + csv + " (one cache size, one mip bias and mode, no " +
       "--convergence-spp, or no cached rows)" + (quiet ? ":\n" + output : std::string()));
  return false;
}

}  // namespace pmc
