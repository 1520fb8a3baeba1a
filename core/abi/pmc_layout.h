/* pmc_layout.h — the list of shared struct fields whose layout must agree.
 *
 * PMC_LAYOUT_STRUCTS(X) names every struct of pmc_types.h; PMC_LAYOUT_FIELDS(X)
 * every field. tests/gpu/abi_layout_test.cpp expands both lists on the host
 * (sizeof/offsetof) and in a kernel, and compares the two tables. Adding a
 * field to pmc_types.h means adding it here, except PmcFrame's scalars, which
 * come from their own list (PMC_FRAME_SCALARS, pmc_types.h).
 */
#ifndef PMC_LAYOUT_H
#define PMC_LAYOUT_H

#define PMC_LAYOUT_STRUCTS(X) \
  X(PmcRay)                   \
  X(PmcHit)                   \
  X(PmcPathState)             \
  X(PmcShadowLoad)            \
  X(PmcTriangle)              \
  X(PmcTriangleRecord)        \
  X(PmcFilmPixel)             \
  X(PmcPathPasses)            \
  X(PmcPassPixel)             \
  X(PmcTexture)               \
  X(PmcMaterialInfo)          \
  X(PmcLight)                 \
  X(PmcLightHeader)           \
  X(PmcLightTreeNode)         \
  X(PmcFrame)                 \
  X(PmcCounters)

#define PMC_LAYOUT_FRAME_SCALAR_(X, type, member) X(PmcFrame, member)

// clang-format off
#define PMC_LAYOUT_FIELDS(X)       \
  X(PmcRay, org_x)                 \
  X(PmcRay, tnear)                 \
  X(PmcRay, dir_x)                 \
  X(PmcRay, time)                  \
  X(PmcRay, tfar)                  \
  X(PmcRay, mask)                  \
  X(PmcRay, id)                    \
  X(PmcRay, flags)                 \
  X(PmcHit, t)                     \
  X(PmcHit, u)                     \
  X(PmcHit, v)                     \
  X(PmcHit, prim)                  \
  X(PmcPathState, throughput)      \
  X(PmcPathState, radiance)        \
  X(PmcPathState, cone_width)      \
  X(PmcPathState, cache_cone)      \
  X(PmcPathState, pixel)           \
  X(PmcPathState, depth)           \
  X(PmcPathState, flags)           \
  X(PmcPathState, cache_hits)      \
  X(PmcPathState, light_normal)    \
  X(PmcShadowLoad, rgb)            \
  X(PmcShadowLoad, path)           \
  X(PmcTriangle, v)                \
  X(PmcTriangle, n)                \
  X(PmcTriangle, t)                \
  X(PmcTriangle, material)         \
  X(PmcTriangleRecord, p)          \
  X(PmcTriangleRecord, n)          \
  X(PmcTriangleRecord, t)          \
  X(PmcTriangleRecord, material)   \
  X(PmcTriangleRecord, flags)      \
  X(PmcTriangleRecord, tangent)    \
  X(PmcFilmPixel, sum)             \
  X(PmcFilmPixel, bad_samples)     \
  X(PmcFilmPixel, cache_hits)      \
  X(PmcFilmPixel, grey_sq_sum)     \
  X(PmcPathPasses, albedo)         \
  X(PmcPathPasses, normal)         \
  X(PmcPathPasses, position)       \
  X(PmcPathPasses, depth)          \
  X(PmcPathPasses, material)       \
  X(PmcPathPasses, state)          \
  X(PmcPassPixel, sum)             \
  X(PmcPassPixel, hit_samples)     \
  X(PmcPassPixel, material_inv)    \
  X(PmcTexture, offset)            \
  X(PmcTexture, width)             \
  X(PmcTexture, height)            \
  X(PmcTexture, levels)            \
  X(PmcTexture, flags)             \
  X(PmcMaterialInfo, entry)        \
  X(PmcMaterialInfo, flags)        \
  X(PmcMaterialInfo, emission)     \
  X(PmcMaterialInfo, cache_points) \
  X(PmcMaterialInfo, cache_position_mask) \
  X(PmcMaterialInfo, cache_level_floor_uv) \
  X(PmcMaterialInfo, cache_level_floor_position) \
  X(PmcFrame, cam_eye)             \
  X(PmcFrame, cam_spread)          \
  X(PmcFrame, cam_forward)         \
  X(PmcFrame, crop_x0)             \
  X(PmcFrame, cam_right)           \
  X(PmcFrame, crop_y0)             \
  X(PmcFrame, cam_up)              \
  X(PmcFrame, crop_width)          \
  X(PmcLight, type)                \
  X(PmcLight, flags)               \
  X(PmcLight, pmf)                 \
  X(PmcLight, cdf)                 \
  X(PmcLight, pos)                 \
  X(PmcLight, area)                \
  X(PmcLight, axis)                \
  X(PmcLight, cos_outer)           \
  X(PmcLight, edge_v)              \
  X(PmcLight, one_minus_cos)       \
  X(PmcLight, rgb)                 \
  X(PmcLight, spot_outer)          \
  X(PmcLight, normal)              \
  X(PmcLight, spot_inner)          \
  X(PmcLight, tree_trail)          \
  X(PmcLight, distant_weight)      \
  X(PmcLightTreeNode, lo)          \
  X(PmcLightTreeNode, energy)      \
  X(PmcLightTreeNode, hi)          \
  X(PmcLightTreeNode, cos_theta_o) \
  X(PmcLightTreeNode, axis)        \
  X(PmcLightTreeNode, cos_theta_e) \
  X(PmcLightTreeNode, second)      \
  X(PmcLightTreeNode, flags)       \
  X(PmcLightHeader, count)         \
  X(PmcLightHeader, at_infinity)   \
  X(PmcLightHeader, quad_end)      \
  X(PmcLightHeader, distant_end)   \
  X(PmcLightHeader, env)           \
  X(PmcLightHeader, env_width)     \
  X(PmcLightHeader, env_height)    \
  X(PmcLightHeader, env_rot_cos)   \
  X(PmcLightHeader, env_rot_sin)   \
  X(PmcLightHeader, env_inv_integral) \
  X(PmcLightHeader, env_uniform)   \
  X(PmcLightHeader, sampler)       \
  X(PmcLightHeader, tree_nodes)    \
  X(PmcLightHeader, env_scale)     \
  X(PmcFrame, lights)              \
  PMC_FRAME_SCALARS(PMC_LAYOUT_FRAME_SCALAR_, X) \
  X(PmcCounters, next_rays)
// clang-format on

#endif /* PMC_LAYOUT_H */
