// sweep_grid.cpp — list options of `pmc sweep`, parsed and checked.
#include "app/sweep_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "app/cli.h"
#include "core/error.h"

namespace pmc {
namespace {

// The list's text: its one occurrence, else `fallback`.
std::string text_of(const ListOption& l, const std::string& fallback) {
  if (l.given.size() > 1) fail(l.names, ": given twice; ", l.names, " name one list, give it once");
  return l.given.empty() ? fallback : l.given[0];
}

// "'x'" or, in a longer list, "'x' in 'a,x,b'".
std::string quoted_item(const std::string& list, const std::string& item) {
  return "'" + item + "'" + (item == list ? "" : " in '" + list + "'");
}

template <typename T>
void refuse_duplicates(const std::string& names, const std::string& list, const std::vector<T>& values,
                       const std::vector<std::string>& items) {
  for (size_t i = 0; i < values.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (values[i] == values[j])
        fail(names, ": '", items[i], "' is listed twice in '", list, "' (each value gives one row)");
}

std::vector<long long> int_list(const std::string& names, const std::string& list, const char* example) {
  const std::vector<std::string> items = cli::split_list(names, list, example);
  std::vector<long long> out;
  for (const std::string& item : items) {
    if (!cli::integer_problem(item, std::numeric_limits<long long>::min(),
                              std::numeric_limits<long long>::max())
             .empty())
      fail(names, ": ", quoted_item(list, item), " is not an integer (expected a comma-separated list, e.g. ",
           example, ")");
    out.push_back(std::strtoll(item.c_str(), nullptr, 10));
  }
  refuse_duplicates(names, list, out, items);
  return out;
}

std::vector<double> number_list(const std::string& names, const std::string& list, const char* example) {
  const std::vector<std::string> items = cli::split_list(names, list, example);
  std::vector<double> out;
  for (const std::string& item : items) {
    if (!cli::number_problem(item).empty())
      fail(names, ": ", quoted_item(list, item),
           " is not a finite number (expected a comma-separated list, e.g. ", example, ")");
    out.push_back(std::strtod(item.c_str(), nullptr));
  }
  refuse_duplicates(names, list, out, items);
  return out;
}

// --cache-evals after --cache-filter: the filter applies to every center-mode row.
std::vector<SweepMode> modes_from(const ListOption& evals, const std::string& filter) {
  const std::string list = text_of(evals, "center");
  const std::vector<std::string> items = cli::split_list(evals.names, list, "hit,center");
  std::vector<SweepMode> out;
  std::vector<std::string> names;
  for (const std::string& item : items) {
    SweepMode m;
    if (item == "hit")
      m = {false, false};
    else if (item == "center")
      m = {true, true};
    else if (item == "center-nearest")
      m = {true, false};
    else
      fail(evals.names, ": expected hit, center and/or center-nearest, got '", item, "'");
    if (filter == "bilinear" && item != "center")
      fail("--cache-filter bilinear: applies to center-mode rows only, but ", evals.names, " lists '", item,
           "' (a hit-mode texel has no centre value to interpolate; center-nearest is the nearest filter)");
    if (filter == "nearest") m.bilinear = false;
    out.push_back(m);
    names.push_back(m.name());
  }
  for (size_t i = 0; i < names.size(); ++i)
    if (std::count(names.begin(), names.begin() + long(i), names[i]))
      fail(evals.names, ": '", list, "' gives two ", names[i], " rows",
           filter == "nearest" ? " (--cache-filter nearest makes center rows center-nearest)" : "");
  return out;
}

}  // namespace

CLI::Option* add_list_option(CLI::App& app, const std::string& cli_names, ListOption& list,
                             const std::string& help) {
  list.names = cli_names;
  std::replace(list.names.begin(), list.names.end(), ',', '/');
  return app.add_option(cli_names, list.given, help)
      ->type_name("LIST")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

SweepGrid parse_sweep_grid(const SweepLists& l) {
  SweepGrid g;
  if (!l.cells.given.empty()) g.cells = int_list(l.cells.names, text_of(l.cells, ""), "4096,65536");
  for (long long c : g.cells)
    if (c <= 0) fail(l.cells.names, ": cell counts must be positive, got ", c);
  g.entries = int_list(l.entries.names, text_of(l.entries, "8"), "1,4,8");
  for (long long e : g.entries)
    if (e <= 0 || e > 1024) fail(l.entries.names, ": entries per cell must be in 1..1024, got ", e);
  g.biases = number_list(l.biases.names, text_of(l.biases, "0"), "-1,0,1,2");
  for (double b : g.biases)
    if (std::fabs(b) > 32.0) fail(l.biases.names, ": mip biases must be within -32..32, got ", b);
  g.modes = modes_from(l.evals, l.filter);
  if (!l.convergence.given.empty())
    for (long long spp : int_list(l.convergence.names, text_of(l.convergence, ""), "1,2,4,8,16")) {
      if (spp <= 0 || spp > 2147483647LL)
        fail(l.convergence.names, ": sample counts must be positive, got ", spp);
      g.convergence.push_back(int(spp));
    }
  return g;
}

}  // namespace pmc
