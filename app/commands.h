// commands.h — the pmc subcommands; each returns the process exit code.
#pragma once

#include <string>
#include <vector>

namespace pmc {

int run_render(const std::vector<std::string>& args);
int run_info(const std::vector<std::string>& args);
int run_compare(const std::vector<std::string>& args);
int run_sweep(const std::vector<std::string>& args);

}  // namespace pmc
