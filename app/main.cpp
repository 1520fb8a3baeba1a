// main.cpp — the pmc command line: parses the subcommand (CLI11), runs it,
// turns errors into exit codes.
//
// Exit codes: 0 success (and --help), 2 bad input or options (a CLI11 parse
// error, pmc::Error; a ConfigError is shown with the flags of its settings),
// 3 unexpected failure.
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "app/cli.h"
#include "app/commands.h"
#include "core/error.h"

namespace cli = pmc::cli;

int main(int argc, char** argv) {
  pmc::set_warning_settings(cli::flag_name);  // warnings from below app/ name flags, not settings
  CLI::App pmc("", "pmc");
  auto formatter = std::make_shared<pmc::cli::HelpFormatter>();
  pmc.formatter(formatter);
  formatter->usage(&pmc, "pmc COMMAND [options]");
  pmc.footer("\n'pmc COMMAND --help' describes each command's options.");
  pmc.require_subcommand(1);
  pmc.option_defaults()->group("options");
  pmc.set_help_flag("-h,--help", "print this help and exit");
  std::vector<std::pair<CLI::App*, pmc::CommandRun>> commands;
  for (auto add :
       {pmc::add_render_command, pmc::add_compare_command, pmc::add_sweep_command, pmc::add_merge_command,
        pmc::add_denoise_command, pmc::add_info_command, pmc::add_cache_replay_command}) {
    pmc::CommandRun run = add(pmc);
    commands.push_back({pmc.get_subcommands({}).back(), run});
  }

  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "help") {
    std::printf("%s", pmc.help().c_str());
    return args.empty() ? 2 : 0;
  }
  bool known = args[0][0] == '-';
  for (auto& [sub, run] : commands) known = known || sub->check_name(args[0]);
  if (!known) {
    std::fprintf(stderr, "pmc: error: unknown command '%s' (see 'pmc --help')\n", args[0].c_str());
    return 2;
  }
  try {
    try {
      pmc.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
      std::printf("%s", pmc.help().c_str());
      return 0;
    } catch (const CLI::ParseError& e) {
      const CLI::App* sub = nullptr;
      for (auto& [s, run] : commands)
        if (s->parsed()) sub = s;
      std::fprintf(stderr, "pmc: error: %s (see 'pmc %s--help')\n", cli::parse_error_message(e).c_str(),
                   sub ? (sub->get_name() + " ").c_str() : "");
      return 2;
    }
    for (auto& [sub, run] : commands)
      if (sub->parsed()) return run();
    return 2;
  } catch (const pmc::ConfigError& e) {  // a setting: shown as the flag that sets it
    std::fprintf(stderr, "pmc: error: %s\n", e.phrased(pmc::cli::flag_name).c_str());
    return 2;
  } catch (const pmc::Error& e) {
    std::fprintf(stderr, "pmc: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pmc: unexpected failure: %s\n", e.what());
    return 3;
  }
}
