/* pmc_types.h — every struct that crosses the host/OpenCL boundary.
 *
 * Compiled by both C++ (host) and OpenCL C (kernels). Layouts use only 4-byte
 * scalars and arrays of them, so both compilers agree on sizes and offsets
 * without packing pragmas; tests/gpu/abi_layout_test.cpp checks every struct
 * here on both sides. Data flows:
 *   camera kernel   -> PmcRay queue + PmcPathState
 *   host (Embree)   -> PmcHit per ray (and occlusion bytes for shadow rays)
 *   shade kernel    -> runs PmcMaterialInfo.entry's bytecode, writes the next PmcRay queue, shadow PmcRay
 * queue + PmcShadowLoad resolve kernel  -> PmcPathState.radiance; film kernel -> PmcFilmPixel
 */
#ifndef PMC_TYPES_H
#define PMC_TYPES_H

#include "pmc_vec.h"

/* A ray in exactly the layout of Embree 3's RTCRay (48 bytes), so the host
 * can hand a queue to rtcIntersect/rtcOccluded without reshuffling fields.
 * `id` is the path index the ray belongs to. */
typedef struct PmcRay {
  float org_x, org_y, org_z, tnear;
  float dir_x, dir_y, dir_z, time;
  float tfar;
  pmc_u32 mask, id, flags;
} PmcRay;

/* What Embree found for one ray: distance, barycentrics, triangle (-1: miss). */
typedef struct PmcHit {
  float t, u, v;
  pmc_i32 prim;
} PmcHit;

/* An empty slot of the shade kernel's material-sorted order (padding that
 * rounds each material's run up to a whole batch). */
#define PMC_NO_RAY 0xffffffffu

/* Path flags. */
#define PMC_PATH_SPECULAR 1u /* last bounce was near-specular: no MIS on emitters */
#define PMC_PATH_EMISSION_ONLY                                         \
  2u /* the ray leaves a path's last hit (max_depth): the hit it meets \
      * adds the emission it sees, by MIS, and ends the path */

/* The state a path carries between bounces (one per path slot). */
typedef struct PmcPathState {
  float throughput[3];
  float radiance[3];
  float cone_width;   /* ray-cone width at the ray origin (world units); its spread is the
                         camera's pixel angle, PmcFrame.cam_spread */
  pmc_u32 cache_cone; /* position cells' cone beyond the texture's (cache_lobe_spread): extra
                         width at the ray origin and extra spread, as two bfloat16s
                         (pmc_pack_cone, core/device/pmc_raycone.h) */
  float bsdf_pdf;     /* solid-angle pdf of the direction that produced the ray */
  pmc_u32 pixel;      /* linear pixel index y*width+x */
  pmc_u32 depth;      /* number of surface hits so far */
  pmc_u32 flags;
  pmc_u32 cache_hits;    /* cache points found along the path (hit map) */
  float light_normal[3]; /* the shading normal the last vertex picked its light sample with:
                            with the ray's origin it recomputes that pick's probability for
                            MIS (pmc_lights.h). Stored whole, not octahedral: 64 bytes in all,
                            so a state fills one cache line, and the shade kernel neither
                            encodes nor decodes it (that cost 7% of its time) */
} PmcPathState;

/* Unoccluded contribution of a shadow ray, added to its path if the host
 * finds the segment free. */
typedef struct PmcShadowLoad {
  float rgb[3];
  pmc_u32 path;
} PmcShadowLoad;

/* One triangle: indices into the position, normal and uv arrays (-1: absent),
 * and its material. */
typedef struct PmcTriangle {
  pmc_i32 v[3];
  pmc_i32 n[3];
  pmc_i32 t[3];
  pmc_i32 material;
} PmcTriangle;

/* One triangle's shading data in one record: its corners' positions, normals
 * and uvs side by side, so a hit reads two cache lines instead of the ten
 * that the indexed arrays scatter it over (triangle, 3 positions, 3 normals,
 * 3 uvs). 128 bytes: the shared buffer is 64-byte aligned, so every record
 * fills exactly two lines. `flags`: PMC_TRI_NORMALS, PMC_TRI_UVS (absent
 * normals and uvs are zeros). */
#define PMC_TRI_NORMALS 1u
#define PMC_TRI_UVS 2u
#define PMC_TRI_TANGENTS 4u /* `tangent` holds the corners' smooth uv tangents (core/vertex_tangents.h) */
typedef struct __attribute__((aligned(64))) PmcTriangleRecord {
  float p[9];
  float n[9];
  float t[6];
  pmc_i32 material;
  pmc_u32 flags;
  pmc_u32 tangent[3]; /* corners' unit tangents, octahedral (core/device/pmc_octahedral.h) */
  float pad[3];
} PmcTriangleRecord;

/* Accumulated film pixel: the exact sum of its samples' rgb (per channel a
 * 128-bit fixed-point number in four 32-bit words, core/device/pmc_film.h),
 * the number of samples dropped as NaN/Inf/huge, the cache points found
 * by its samples (the hit map), and the sum of its good samples' squared
 * grey value ((r + g + b) / 3)^2, added in sample order (one work-item per
 * pixel), which adaptive sampling's error estimate reads
 * (gpu/adaptive_sampling.h). */
typedef struct PmcFilmPixel {
  pmc_u32 sum[12]; /* channel c: sum[4c .. 4c+3], least significant word first */
  pmc_u32 bad_samples;
  pmc_u32 cache_hits;
  float grey_sq_sum;
  pmc_u32 pad;
} PmcFilmPixel;

/* Render passes (AOVs; core/device/pmc_passes.h). Per path slot, what the
 * path's first hits leave for the pass film: the albedo and world-space
 * shading normal of its first non-specular hit (found through mirrors and
 * glass), and the camera ray's hit: its world position, its distance from
 * the camera (Z) and its material. Written only when PmcFrame.passes_on. */
#define PMC_PASS_NO_MATERIAL 0xffffffffu /* the camera ray escaped */
#define PMC_PASS_FOUND 1u                /* state: albedo and normal are recorded */
typedef struct PmcPathPasses {
  float albedo[3];
  float normal[3];
  float position[3];
  float depth;
  pmc_u32 material; /* PMC_PASS_NO_MATERIAL: no camera hit */
  pmc_u32 state;
  pmc_u32 pad[4];
} PmcPathPasses;

/* The pass film: exact sums like PmcFilmPixel's (4 words per channel) of
 * PMC_PASS_CHANNELS channels: albedo rgb, normal xyz, position xyz, depth;
 * the samples whose camera ray hit a surface (position and depth are their
 * mean), and the smallest material id any sample's camera ray hit, stored
 * as its complement's maximum (0: none hit, so a zeroed film is empty; a
 * max merges exactly, as a sum does). */
#define PMC_PASS_CHANNELS 10u
#define PMC_PASS_ALBEDO 0u
#define PMC_PASS_NORMAL 3u
#define PMC_PASS_POSITION 6u
#define PMC_PASS_DEPTH 9u
typedef struct PmcPassPixel {
  pmc_u32 sum[40]; /* channel c: sum[4c .. 4c+3] */
  pmc_u32 hit_samples;
  pmc_u32 material_inv; /* ~(smallest material id); 0: none hit */
  pmc_u32 pad[2];
} PmcPassPixel;

/* A texture in the shared texel pool: mip level l has size
 * max(1, width >> l) x max(1, height >> l) and starts at
 * offset + sum of the sizes of the levels before it. */
#define PMC_TEX_SRGB 1u
typedef struct PmcTexture {
  pmc_u32 offset; /* first texel (RGBA8) of level 0 in the pool */
  pmc_i32 width, height, levels;
  pmc_u32 flags;
  pmc_u32 pad[3];
} PmcTexture;

/* Per material: where its program starts, its constant emission (the
 * light table and next-event estimation use it) and how many cache points
 * its program looks up (0 with the cache off), and which of them are keyed on
 * the position cell rather than the uv texel. */
#define PMC_MAT_CUTOUT 1u
#define PMC_MAT_FOOTPRINT                                               \
  2u /* its program filters images by the ray cone's footprint (image,  \
      * hex-tiled image or normal map): only then does the shade kernel \
      * compute the footprint's width and ellipse at its hits */
#define PMC_MAT_UNIFORM                                                  \
  4u /* its program reads nothing of the shading point and keeps its     \
      * normal: every point gets the same parameters, so a batch runs it \
      * for one point and shares the BSDF (pmc_eval_material_lanes) */
#define PMC_MAT_EMITS                                                   \
  8u /* its program writes the emission: only such a material's hits    \
      * past a path's last one (PMC_PATH_EMISSION_ONLY) run it; others' \
      * add nothing and skip it (pmc_shade_batch) */
typedef struct PmcMaterialInfo {
  pmc_u32 entry;
  pmc_u32 flags;
  float emission[3];
  pmc_u32 cache_points;
  pmc_u32 cache_position_mask;        /* bit p: its p-th cache point is keyed on position */
  pmc_i32 cache_level_floor_uv;       /* lowest virtual level of its uv points (pmc_cache_floored_level) */
  pmc_i32 cache_level_floor_position; /* ... of its position points; PMC_LAMBDA_MIN: no floor */
  pmc_u32 pad[3];
} PmcMaterialInfo;

/* Light types (PmcLight.type); core/device/pmc_lights.h samples and
 * evaluates them, core/lights.cpp builds the table. Units: intensity W/sr,
 * irradiance W/m^2, radiance W/(m^2 sr), distances in scene units. */
#define PMC_LIGHT_TRIANGLE 0u    /* emissive scene triangle (two-sided) */
#define PMC_LIGHT_POINT 1u       /* pos, rgb = intensity */
#define PMC_LIGHT_SPOT 2u        /* pos, axis (where it points), rgb = intensity on the axis */
#define PMC_LIGHT_DIRECTIONAL 3u /* axis = direction of travel, rgb = irradiance at normal incidence */
#define PMC_LIGHT_SUN 4u         /* directional with an angle: a disk of radiance rgb around -axis */
#define PMC_LIGHT_QUAD 5u        /* parallelogram pos + s edge_u + t edge_v, rgb = radiance */
#define PMC_LIGHT_ENV 6u         /* the environment: constant radiance rgb, or the map */

#define PMC_LIGHT_TWO_SIDED 1u /* quad: emits from both sides (triangles always do) */
#define PMC_LIGHT_RECTANGLE 2u /* quad: its edges are perpendicular (sampled by solid angle) */

/* One light of the table. Triangles and quads are parallelograms/triangles
 * spanned at `pos` by `axis` and `edge_v` with unit `normal` (quads emit
 * toward it). Lights are stored in table order: the environment (if any),
 * sun disks, quads, directional deltas, then the rest (PmcLightHeader). */
typedef struct PmcLight {
  pmc_u32 type;
  pmc_u32 flags;
  float pmf; /* power sampler: probability that light sampling picks this light (by power) */
  float cdf; /* power sampler: running sum of pmf in table order, the last light's is 1 */
  float pos[3];
  float area; /* triangle, quad */
  float axis[3];
  float cos_outer; /* spot: cos(cone/2); sun: cos(angle/2) */
  float edge_v[3];
  float one_minus_cos; /* sun: 1 - cos(angle/2), exact for tiny disks */
  float rgb[3];
  float spot_outer; /* spot: half opening angle (radians) */
  float normal[3];
  float spot_inner;      /* spot: the angle where the fade starts (radians) */
  pmc_u32 tree_trail[2]; /* tree sampler, finite lights: the way from the light tree's root to
                            this light's leaf, bit d (of the 64) = 1 where depth d takes the
                            second child (core/light_tree.h) */
  float distant_weight;  /* tree sampler, lights at infinity: irradiance luminance at normal
                            incidence, the weight of its pick (pmc_lights.h) */
  pmc_u32 pad;
} PmcLight;

/* A node of the light tree (core/light_tree.h), depth first: an interior
 * node's first child follows it, `second` is the other; a leaf holds one
 * light (`second` = its table index). The bounds of everything below:
 * box [lo, hi], intensity `energy` (luminance, W/sr: what the lights emit
 * at most in one direction, summed), and the orientation cone: emission
 * leaves within theta_o of `axis`, spreading at most theta_e beyond it.
 * The shade kernel reads the first 48 bytes as three float4 (lo + energy,
 * hi + cos_theta_o, axis + cos_theta_e: pmc_tree_importance_lanes), so
 * their order is part of the layout. */
#define PMC_TREE_LEAF 1u
#define PMC_TREE_TWO_SIDED 2u /* some light emits on both sides of its normal */
typedef struct PmcLightTreeNode {
  float lo[3];
  float energy;
  float hi[3];
  float cos_theta_o;
  float axis[3];
  float cos_theta_e;
  pmc_u32 second;
  pmc_u32 flags; /* PMC_TREE_* */
  pmc_u32 pad[2];
} PmcLightTreeNode;

/* How next-event estimation picks a light (PmcLightHeader.sampler). */
#define PMC_LIGHT_SAMPLER_POWER 0u /* by power alone (the cdf over the table) */
#define PMC_LIGHT_SAMPLER_TREE 1u  /* lights at infinity by irradiance, the light tree for the rest */

/* Environment kinds (PmcLightHeader.env). */
#define PMC_ENV_NONE 0u
#define PMC_ENV_CONSTANT 1u /* light 0, radiance rgb; sampled cosine-weighted around the normal */
#define PMC_ENV_MAP 2u      /* light 0, the lat-long map; sampled by luminance x sin(theta) */

/* The light table's shape (part of PmcFrame). */
typedef struct PmcLightHeader {
  pmc_i32 count;       /* lights in the table (0: no next-event estimation) */
  pmc_i32 at_infinity; /* [0, at_infinity): seen by escaped rays (environment first, suns) */
  pmc_i32 quad_end;    /* [at_infinity, quad_end): quads, tested against every ray */
  pmc_i32 distant_end; /* [quad_end, distant_end): directional deltas; the rest is finite */
  pmc_u32 env;         /* PMC_ENV_* */
  pmc_i32 env_width, env_height;
  float env_rot_cos, env_rot_sin; /* the map turned about +Y: world = R_y(angle) map */
  float env_inv_integral;         /* 1 / sum over texels of luminance x sin(theta) */
  pmc_u32 env_uniform;            /* sample the map uniformly over the sphere (comparisons) */
  pmc_u32 sampler;                /* PMC_LIGHT_SAMPLER_* */
  pmc_i32 tree_nodes;             /* nodes of the light tree (0: no finite light) */
  float env_scale;                /* the map's texels times this (its brightness setting) */
  pmc_u32 pad[2];
} PmcLightHeader;

/* The frame's scalars after its light header, in their order in PmcFrame:
 * M(A, type, member) for each (A passes through). PmcFrame declares them from
 * this list and pmc_layout.h lists them for the layout check from it, so a
 * new one (a render setting's kernel copy, gpu/render_settings_table.h) is
 * one line here. path_count = wave_pixels x wave_samples. */
/* clang-format off */
#define PMC_FRAME_SCALARS(M, A)                                                                   \
  M(A, pmc_i32, width)                                                                            \
  M(A, pmc_i32, height)                                                                           \
  M(A, pmc_u32, seed)                                                                             \
  M(A, pmc_u32, sample)                                                                           \
  M(A, pmc_u32, pixel_offset)                                                                     \
  M(A, pmc_u32, path_count)                                                                       \
  M(A, pmc_i32, max_depth)                                                                        \
  M(A, pmc_u32, texture_count)                                                                    \
  M(A, pmc_u32, cache_on)          /* the programs contain cache instructions */                  \
  M(A, pmc_u32, cache_center)      /* cache_eval center */                                        \
  M(A, pmc_u32, cache_ways)        /* entries per cell */                                         \
  M(A, pmc_u32, cache_cells_lo)                                                                   \
  M(A, pmc_u32, cache_cells_hi)                                                                   \
  M(A, float, mip_bias)                                                                           \
  M(A, pmc_u32, cache_bilinear)    /* cache_filter bilinear: jittered texel selection */          \
  M(A, pmc_u32, cache_policy)      /* PMC_CACHE_KEEP_FIRST or PMC_CACHE_PRIORITY (pmc_cache.h) */ \
  M(A, pmc_i32, cache_max_refine)  /* level floors above the footprint's before bypass */         \
  M(A, float, cache_lobe_spread)   /* position cells widen per bounce (pmc_lobe_spread) */        \
  M(A, pmc_u32, cache_bandwidth)   /* level floors: 0 none, 1 at every hit, 2 at camera hits */   \
  M(A, pmc_u32, passes_on)         /* render passes: fill PmcPathPasses and the pass film */      \
  M(A, pmc_u32, wave_pixels)       /* path i of the wave: pixel pixel_offset + i % wave_pixels */ \
  M(A, pmc_u32, wave_samples)      /* of the window, sample `sample` + i / wave_pixels */         \
  M(A, pmc_u32, sampler)           /* PMC_SAMPLER_SOBOL or PMC_SAMPLER_RANDOM (pmc_rng.h) */  \
  M(A, pmc_u32, active_list)       /* 1: the wave's pixels are active[pixel_offset + i % wave_pixels] */ \
  M(A, float, clamp_direct)        /* largest light sample through the first hit (0: off) */    \
  M(A, float, clamp_indirect)      /* through later hits (pmc_clamp_light) */                   \
  M(A, pmc_u32, cache_camera_samples) /* a pixel's samples whose camera-ray hits use the cache */
/* clang-format on */
#define PMC_FRAME_MEMBER_(unused, type, member) type member;

/* PmcFrame.cache_bandwidth: where the materials' level floors apply
 * (CacheBandwidth; 0: nowhere, their floors are not computed). */
#define PMC_CACHE_FLOORS_EVERY_HIT 1u
#define PMC_CACHE_FLOORS_CAMERA 2u

/* Everything a wave's kernels need to know about the frame. */
typedef struct PmcFrame {
  float cam_eye[3];
  float cam_spread; /* spread angle of one pixel (radians) */
  float cam_forward[3];
  pmc_u32 crop_x0;    /* the window rendered (crop): path k of the render is */
  float cam_right[3]; /* scaled by tan(fov/2) * aspect */
  pmc_u32 crop_y0;    /* pixel (crop_x0 + k % crop_width, crop_y0 + k / crop_width) */
  float cam_up[3];    /* scaled by tan(fov/2) */
  pmc_u32 crop_width; /* of the full frame; the film holds the window only */
  PmcLightHeader lights;
  PMC_FRAME_SCALARS(PMC_FRAME_MEMBER_, ~)
} PmcFrame;

/* Queue counters written by the shade kernel with atomics. */
typedef struct PmcCounters {
  pmc_u32 next_rays;
  pmc_u32 shadow_rays;
  pmc_u32 pad[2];
} PmcCounters;

#endif /* PMC_TYPES_H */
