// sweep_table.cpp — sweep.csv from the rows.
#include "app/sweep_table.h"

#include <sstream>

namespace pmc {

std::string sweep_csv(const std::vector<SweepRow>& rows) {
  std::ostringstream csv;
  csv << "kind,cells,entries,mip_bias,cache_eval,spp,time_seconds,hit_rate,memory_bytes,psnr_vs_cacheless,"
         "relmse_vs_cacheless,relmse_vs_reference\n";
  auto optional = [&](const std::optional<double>& v) {
    if (v) csv << *v;
    csv << ",";
  };
  for (const SweepRow& r : rows) {
    csv << r.kind << "," << r.cells << "," << r.entries << "," << r.mip_bias << "," << r.cache_eval << ","
        << r.spp << "," << r.time_seconds << "," << r.hit_rate << "," << r.memory_bytes << ",";
    optional(r.psnr_vs_cacheless);
    optional(r.relmse_vs_cacheless);
    csv << r.relmse_vs_reference << "\n";
  }
  return csv.str();
}

}  // namespace pmc
