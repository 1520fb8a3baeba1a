// render_options.h — the render options shared by every subcommand that renders.
//
// declare_render_options() adds --width ... --chunk-rays to a parser and
// render_config_from() maps them onto a RenderConfig (validated). Lower
// layers name settings by their RenderConfig names (core/error.h);
// flag_name() and with_flags() show them as the flags that set them.
#pragma once

#include "app/cli_args.h"
#include "core/image_io.h"
#include "gpu/render_config.h"

namespace pmc {

void declare_render_options(ArgParser& p);
RenderConfig render_config_from(const ArgParser& p, const std::string& obj);
// --exposure and --view: how the PNGs of renders are made (the EXRs stay linear).
void declare_display_options(ArgParser& p);
DisplaySettings display_settings_from(const ArgParser& p);
// "cache_entries" -> "--cache-entries".
std::string flag_name(const std::string& setting);
// Text with marked settings (ConfigError messages, the cache size's reason) in flag names.
std::string with_flags(const std::string& marked);
// The cache table chosen for a render (or why there is none), on stderr.
void print_cache_choice(const RenderSettings& settings);

}  // namespace pmc
