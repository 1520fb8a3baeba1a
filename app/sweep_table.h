// sweep_table.h — the rows `pmc sweep` measured, and sweep.csv.
//
// One row per render: the cacheless render, one per cache setting of the
// grid ("setting"), and cache off/on per --convergence-spp value
// ("convergence_off", "convergence_on"). A row holds the settings it was
// rendered with (cells, entries, mip bias, cache_eval; zeros and "off" for
// cacheless rows), its median time, hit rate and table size, and its error
// against the cacheless render (setting rows; the cacheless row itself has
// PSNR 999 and relMSE 0) and against the high-sample reference (every row).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pmc {

struct SweepRow {
  std::string kind;        // cacheless, setting, convergence_off, convergence_on
  std::string cache_eval;  // off, hit, center, center-nearest
  uint64_t cells = 0, entries = 0;
  float mip_bias = 0.0f;
  int spp = 0;
  double time_seconds = 0, hit_rate = 0;
  uint64_t memory_bytes = 0;
  std::optional<double> psnr_vs_cacheless, relmse_vs_cacheless;
  double relmse_vs_reference = 0;
};

// The CSV (header and one line per row); numbers as C++ streams print them.
std::string sweep_csv(const std::vector<SweepRow>& rows);

}  // namespace pmc
