// part_identity.h — which frame a render belongs to: the hashes and facts a part EXR records.
//
// A render of a sample range or a window (the samples and crop settings) writes them into the part
// (core/render_part.h) and `pmc merge` refuses parts whose hashes differ. The scene hash covers what the
// scene is made of once loaded (geometry, the compiled material programs, their texels, an environment map's
// texels); the settings hash covers every resolved setting that changes the image (size, frame spp, depth,
// seed, camera, lights, environment, the cache's mode and table). It leaves out what only changes speed
// (threads, device, trace mode, transfers, shade lanes) and the part's own sample range and window. Which of
// the plain settings it covers, and how, is the `hash` column of gpu/render_settings_table.h.
#pragma once

#include <string>

#include "core/render_part.h"
#include "gpu/render_session.h"

namespace pmc {

std::string scene_hash(const RenderSession& session);
std::string settings_hash(const RenderSettings& settings);
// The part description of `out`, rendered by `session` with `settings`.
PartInfo part_info(const RenderSession& session, const RenderSettings& settings, const RenderOutput& out);

}  // namespace pmc
