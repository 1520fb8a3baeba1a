// commands.h — the pmc subcommands.
//
// Each add_*_command() declares its subcommand's options on `pmc` (CLI11)
// and returns what runs it once the command line is parsed; that returns the
// process exit code. main.cpp turns errors into exit codes.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace pmc {

using CommandRun = std::function<int()>;

CommandRun add_render_command(CLI::App& pmc);
CommandRun add_compare_command(CLI::App& pmc);
CommandRun add_sweep_command(CLI::App& pmc);
CommandRun add_info_command(CLI::App& pmc);
CommandRun add_merge_command(CLI::App& pmc);
CommandRun add_denoise_command(CLI::App& pmc);
CommandRun add_cache_replay_command(CLI::App& pmc);

}  // namespace pmc
