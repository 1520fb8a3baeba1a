// scene_buffers.h — the scene's read-only device buffers, uploaded once.
//
// Everything the shade kernel reads about the scene (geometry as one record
// per triangle, materials' bytecode and textures, the light table) lives
// here, one buffer per entry of PMC_SCENE_BUFFERS
// (gpu/kernels/pmc_scene_args.h), in the kernel's argument order. The wave loop never touches them after the
// upload (the lights once per render); the shade launcher passes them as a block. The scene's and materials'
// buffers are ClContext::shared_buffer()s: on CPU devices and integrated GPUs they are the host vectors
// themselves (no copy of the texel pool, often the largest thing in the process), so the Scene and
// MaterialSet must outlive the buffers unchanged (the RenderSession holds
// both for its renderer's lifetime); on discrete GPUs they are copies. The
// light buffers are uploaded per render, as copies.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/lights.h"
#include "core/scene.h"
#include "gpu/cl_context.h"
#include "gpu/kernels/pmc_scene_args.h"
#include "materials/material_set.h"

namespace pmc {

enum SceneBuffer : unsigned {
#define PMC_SCENE_ENUM(name, type) kScene_##name,
  PMC_SCENE_BUFFERS(PMC_SCENE_ENUM)
#undef PMC_SCENE_ENUM
      kSceneBufferCount
};

// The scene's triangles as PmcTriangleRecords (corners copied out of the
// indexed position, normal and uv arrays).
std::vector<PmcTriangleRecord> triangle_records_of(const Scene& scene);

struct SceneBuffers {
  // One record per scene triangle (PmcTriangleRecord); before `buffers`,
  // which may be this vector itself (shared) and must be released first.
  std::vector<PmcTriangleRecord> triangle_records;
  std::array<ClBuffer, kSceneBufferCount> buffers;
  LightTable lights;            // set by upload_lights()
  std::vector<float> emission;  // per material, rgb: its emissive triangles are lights
  uint32_t texture_count = 0;
  std::vector<int32_t> triangle_material;  // host copy: the material sort reads it per hit
  int material_count = 0;

  SceneBuffers(const ClContext& cl, const Scene& scene, const MaterialSet& materials);
  // The light table depends on the render's settings (lights file,
  // environment): each render uploads its own (lights, tri_light, light_tree, env).
  void upload_lights(const ClContext& cl, LightTable table);
  const ClBuffer& operator[](SceneBuffer b) const { return buffers[b]; }
};

}  // namespace pmc
