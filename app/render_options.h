// render_options.h — the render options shared by every subcommand that renders.
//
// declare_render_options() adds --mtlx ... --shade-lanes to a subcommand,
// each bound to the RenderConfig field it sets (and named for ConfigError
// messages, app/cli.h); the plain settings' options come from the table in
// gpu/render_settings_table.h, the rest are declared here. The config is checked by RenderConfig::validate()
// (gpu/render_config.h), not here: the flags only carry values.
#pragma once

#include <CLI/CLI.hpp>

#include "core/tone_map.h"
#include "gpu/render_config.h"
#include "gpu/wavefront_renderer.h"

namespace pmc {

// Which cache options a subcommand takes as `pmc render` does.
enum class CacheFlags {
  All,          // render: --cache on|off and every cache option
  AllButCache,  // compare renders cache off and on: no --cache
  None,         // sweep declares the cache options itself (as lists)
};

void declare_render_options(CLI::App& app, RenderConfig& config, CacheFlags cache_flags);
// --exposure and --view: how the PNGs of renders are made (core/tone_map.h;
// the EXRs stay linear).
void declare_display_options(CLI::App& app, ToneMap& tone_map);
// --quiet, as every rendering subcommand has it.
CLI::Option* add_quiet_flag(CLI::App& app, bool& quiet, const std::string& what_still_prints);
// The cache table chosen for a render (or why there is none), on stderr.
void print_cache_choice(const RenderSettings& settings);

}  // namespace pmc
