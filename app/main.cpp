// main.cpp — the pmc command line: dispatches subcommands, turns errors into exit codes.
//
// Exit codes: 0 success, 2 bad input or options (pmc::Error), 3 unexpected failure.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/render_options.h"
#include "core/error.h"

namespace {

void usage() {
  std::printf(
      "usage: pmc COMMAND [options]\n\n"
      "commands:\n"
      "  render SCENE.obj -o OUT.exr   render an OBJ scene (EXR + PNG)\n"
      "  compare SCENE.obj --out-dir D render cache off and on; images, difference, hit map, metrics\n"
      "  sweep SCENE.obj --out-dir D   cache sizes, mip biases, eval modes -> sweep.csv\n"
      "  info --devices                list OpenCL devices\n"
      "  info --scene SCENE.obj        summarise a scene\n\n"
      "'pmc COMMAND --help' describes each command's options.\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    usage();
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  try {
    if (command == "render") return pmc::run_render(args);
    if (command == "info") return pmc::run_info(args);
    if (command == "compare") return pmc::run_compare(args);
    if (command == "sweep") return pmc::run_sweep(args);
    std::fprintf(stderr, "pmc: unknown command '%s'\n", command.c_str());
    usage();
    return 2;
  } catch (const pmc::ConfigError& e) {  // a setting: shown as the flag that sets it
    std::fprintf(stderr, "pmc: error: %s\n", e.phrased(pmc::flag_name).c_str());
    return 2;
  } catch (const pmc::Error& e) {
    std::fprintf(stderr, "pmc: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pmc: unexpected failure: %s\n", e.what());
    return 3;
  }
}
