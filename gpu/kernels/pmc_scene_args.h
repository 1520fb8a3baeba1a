/* pmc_scene_args.h — the scene's device buffers, listed once for both sides.
 *
 * PMC_SCENE_BUFFERS(X) names every read-only scene buffer the shade kernel
 * takes, in argument order, with its OpenCL C type. The kernel expands it
 * into its parameter list and into a PmcSceneData struct that the device
 * functions receive instead of a dozen positional pointers; the host
 * (gpu/scene_buffers.h) expands it into an enum that indexes its buffers, and
 * the typed launcher (gpu/wave_kernels.cpp) sets the arguments in this order.
 * Adding a scene buffer means one line here and its upload in
 * gpu/scene_buffers.cpp.
 */
#ifndef PMC_SCENE_ARGS_H
#define PMC_SCENE_ARGS_H

// clang-format off
#define PMC_SCENE_BUFFERS(X)                          \
  X(triangles, __global const PmcTriangleRecord*)     \
  X(code, __global const pmc_u32*)      /* bytecode */ \
  X(materials, __global const PmcMaterialInfo*)       \
  X(textures, __global const PmcTexture*)             \
  X(texels, __global const pmc_u32*)    /* RGBA8 */  \
  X(srgb_lut, __constant float*)                      \
  X(lights, __global const PmcLight*)   /* pmc_lights.h */ \
  X(tri_light, __global const pmc_i32*) /* per triangle: its light (-1: none) */ \
  X(light_tree, __global const PmcLightTreeNode*) /* core/light_tree.h */ \
  X(env, __global const float*)         /* map texels, CDFs */
// clang-format on

#ifdef __OPENCL_VERSION__
#define PMC_SCENE_FIELD(name, type) type name;
#define PMC_SCENE_PARAM(name, type) type name,
#define PMC_SCENE_INIT(name, type) s.name = name;
typedef struct PmcSceneData {
  PMC_SCENE_BUFFERS(PMC_SCENE_FIELD)
  uint texture_count;
  PmcLightSet light_set; /* lights + env + the frame's light header */
} PmcSceneData;
#endif

#endif /* PMC_SCENE_ARGS_H */
