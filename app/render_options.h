// render_options.h — the render options shared by every subcommand that renders.
//
// declare_render_options() adds --width ... --env to a parser and
// render_settings_from() validates them (positive sizes, sane depths) into
// RenderSettings, resolving the camera: flags, else SCENE.camera, else
// framing the scene's bounds.
#pragma once

#include "app/cli_args.h"
#include "gpu/wavefront_renderer.h"
#include "materials/material_set.h"

namespace pmc {

void declare_render_options(ArgParser& p);
MaterialOptions material_options_from(const ArgParser& p);
RenderSettings render_settings_from(const ArgParser& p, const Scene& scene, const std::string& obj_path);
// Decides the cache table size (--cache-cells/--cache-entries, else from the
// scene) once the materials are compiled; turns the cache off when no
// material has a cache point. Prints the choice when `verbose`.
void size_cache(const ArgParser& p, const MaterialSet& materials, RenderSettings& s, bool cache_on,
                bool verbose);
uint64_t available_memory_bytes();
// Applies --threads (TBB and PoCL thread counts); call before any OpenCL use.
void apply_thread_option(const ArgParser& p);

}  // namespace pmc
