// cache_replay_command.cpp — `pmc cache-replay TRACE`: a render's cache
// lookups replayed under other policies, table sizes and orders.
//
// The trace is what `pmc render` writes with PMC_CACHE_TRACE=FILE in the
// environment (gpu/cache_trace.h). For each table (a fraction of the render's
// cells, the entries per cell kept) it prints the hit rate, all lookups and
// camera-ray lookups, of keep-first and priority (the renderer's policies:
// they reproduce its own counts up to the order of lookups within a launch),
// LRU, and Belady's MIN (the most hits any policy can get from that many
// entries in that order), in the render's order and region-major
// (core/cache_replay.h). --json writes the same numbers for scripts.
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "app/cli.h"
#include "app/commands.h"
#include "app/output_guard.h"
#include "core/atomic_write.h"
#include "core/cache_replay.h"
#include "core/error.h"

namespace pmc {
namespace {

struct ReplayArgs {
  std::string trace, tables = "1,4,16,64", json;
  uint32_t regions = 4;
  bool no_min = false;
};

std::vector<uint64_t> parse_divisors(const std::string& text) {
  std::vector<uint64_t> out;
  for (const std::string& item : cli::split_list("--tables", text, "1,4,16,64")) {
    const std::string problem = cli::integer_problem(item, 1, 1ll << 40);
    if (!problem.empty()) fail("--tables: '", item, "': ", problem);
    out.push_back(uint64_t(std::stoll(item)));
  }
  return out;
}

nlohmann::json counts_json(const ReplayCounts& c) {
  return {{"lookups", c.lookups},         {"hits", c.hits},
          {"hit_rate", c.hit_rate()},     {"camera_lookups", c.camera_lookups},
          {"camera_hits", c.camera_hits}, {"camera_hit_rate", c.camera_hit_rate()}};
}

int run_replay(const ReplayArgs& a) {
  const std::vector<uint64_t> divisors = parse_divisors(a.tables);
  if (!a.json.empty()) check_output_path("--json", a.json);
  const LookupTrace trace = read_lookup_trace(a.trace);
  if (trace.cells == 0 || trace.ways == 0) fail("cache trace '", a.trace, "': the render had no cache table");
  for (uint64_t d : divisors)
    if (trace.cells / d == 0)
      fail("--tables: 1/", d, " of the trace's ", trace.cells, " cells is less than one cell");
  std::printf("%s: %dx%d, %llu lookups (%zu kept), table %llu cells x %u entries\n", a.trace.c_str(),
              int(trace.width), int(trace.height), (unsigned long long)trace.lookups, trace.records.size(),
              (unsigned long long)trace.cells, trace.ways);
  if (trace.records.size() < trace.lookups)
    std::printf("warning: the trace kept the first %zu lookups only (PMC_CACHE_TRACE_RECORDS)\n",
                trace.records.size());
  struct Order {
    std::string name;
    std::vector<TraceLookup> lookups;
  };
  std::vector<Order> orders;
  orders.push_back({"render", trace.records});
  if (a.regions > 0)
    orders.push_back({"region-major " + std::to_string(a.regions) + "x" + std::to_string(a.regions),
                      region_major(trace.records, trace.width, trace.height, a.regions)});
  nlohmann::json rows = nlohmann::json::array();
  std::printf("%-22s %-8s %-10s %-12s %14s %14s\n", "order", "table", "cells", "policy", "hit rate",
              "camera");
  for (const Order& o : orders)
    for (uint64_t d : divisors) {
      const uint64_t cells = trace.cells / d;
      std::vector<std::pair<std::string, ReplayCounts>> results = {
          {"keep-first", replay_keep_first(o.lookups, cells, trace.ways)},
          {"priority", replay_priority(o.lookups, cells, trace.ways)},
          {"lru", replay_lru(o.lookups, cells, trace.ways)}};
      if (!a.no_min) results.push_back({"min", replay_belady(o.lookups, cells * trace.ways)});
      for (const auto& [policy, c] : results) {
        std::printf("%-22s 1/%-6llu %-10llu %-12s %13.1f%% %13.1f%%\n", o.name.c_str(), (unsigned long long)d,
                    (unsigned long long)cells, policy.c_str(), 100.0 * c.hit_rate(),
                    100.0 * c.camera_hit_rate());
        nlohmann::json row = counts_json(c);
        row["order"] = o.name;
        row["divisor"] = d;
        row["cells"] = cells;
        row["entries"] = cells * trace.ways;
        row["policy"] = policy;
        rows.push_back(row);
      }
      std::fflush(stdout);
    }
  if (!a.json.empty()) {
    OutputGuard guard;
    guard.track(a.json);
    const nlohmann::json j = {{"trace", a.trace},
                              {"width", trace.width},
                              {"height", trace.height},
                              {"cells", trace.cells},
                              {"ways", trace.ways},
                              {"lookups", trace.lookups},
                              {"kept", trace.records.size()},
                              {"rows", rows}};
    write_text_file(a.json, j.dump(2) + "\n");
    guard.commit();
  }
  return 0;
}

}  // namespace

CommandRun add_cache_replay_command(CLI::App& pmc) {
  auto a = std::make_shared<ReplayArgs>();
  CLI::App* app = pmc.add_subcommand("cache-replay",
                                     "replay a render's cache lookups under other policies and table sizes");
  cli::formatter(pmc).usage(
      app, "pmc cache-replay TRACE [options]",
      "Replays the cache lookups of one render (written by 'PMC_CACHE_TRACE=TRACE pmc render ...')\n"
      "under keep-first and priority (the renderer's policies), LRU and Belady's MIN (the most hits\n"
      "any policy can get from a table of that many entries), for tables of a fraction of the render's\n"
      "cells, in the render's order and region-major (each wave all samples of one region). Prints\n"
      "hit rates over all lookups and over camera-ray lookups. Exit codes: 0 done, 2 bad input, 3\n"
      "unexpected failure.");
  app->option_defaults()->group("options");
  app->set_help_flag("-h,--help", "print this help and exit");
  app->add_option("TRACE", a->trace, "lookup trace (PMC_CACHE_TRACE=TRACE pmc render ...)")->required();
  app->add_option("--tables", a->tables,
                  "tables to replay, as divisors of the trace's cells: 4 is a quarter of the render's table")
      ->type_name("D,D,...")
      ->capture_default_str();
  app->add_option(
         "--regions", a->regions,
         "also replay region-major with the frame cut into N x N regions; 0: the render's order only")
      ->type_name("N")
      ->check(cli::integer<uint32_t>())
      ->capture_default_str();
  app->add_flag("--no-min", a->no_min, "leave out Belady's MIN (the slowest replay)");
  app->add_option("--json", a->json, "the same numbers as JSON")->type_name("OUT.json");
  return [a] { return run_replay(*a); };
}

}  // namespace pmc
