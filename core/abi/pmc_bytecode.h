/* pmc_bytecode.h — the material stack machine's instruction encoding.
 *
 * All materials compile into one flat buffer of 32-bit words; a material is
 * an entry offset into it. An instruction is
 *   word 0: opcode (bits 0-7) | output width - 1 (bits 8-9) | operand count
 *           (bits 10-13) | 16-bit immediate (bits 16-31)
 *   word 1: destination slot in the float stack
 *   words 2 ..: one operand word per input
 * An operand word names a value of 1-4 floats: bit 31 set means an inline
 * constant stored in the code buffer at word index (bits 0-27), else a stack
 * slot; bits 28-29 hold width - 1. A width-1 operand broadcasts to all lanes,
 * which is how MaterialX's "FA" variants (color3 * float) work. Every
 * operation computes on float4 lanes and writes `width` floats.
 *
 * PMC_OPCODES is the one list of opcodes: X(name, minimum operands, maximum
 * operands, (operand slots)), the slots named in the order the operand words
 * hold them. Its expansions are the PmcOpcode enum and, per opcode, the slot
 * indices PMC_ARG_<name>_<slot> (PMC_ARG_CLAMP_high is 2) that the
 * interpreter (core/device/pmc_interp.h) reads its operands by, and the
 * disassembler's and the parity test's name tables. Which MaterialX node
 * emits which opcode is materials/node_table.cpp's job; a node's operand
 * inputs come in the slots' order (tests/materials/node_table_test.cpp checks
 * their count against the opcode's). A slot is never named after an OpenCL
 * built-in (mix, rotate): an OpenCL implementation may define those as macros,
 * which would rename the slot's enumerator.
 */
#ifndef PMC_BYTECODE_H
#define PMC_BYTECODE_H

#include "pmc_vec.h"

// clang-format off
#define PMC_OPCODES(X)                                                                                                 \
  X(END, 0, 0, ())                                        /* stop */                                                   \
  X(OUTPUT, 1, 1, (in))                                   /* surface parameter `imm` */                                \
  X(MOVE, 1, 1, (in))                                     /* broadcast/truncate to width */                            \
  X(SWIZZLE, 1, 1, (in))                                  /* imm: 3 bits per lane: 0-3 xyzw, 4 = 0, 5 = 1 */           \
  X(COMBINE, 2, 4, (in1, in2, in3, in4))                  /* dst lanes = first lane of each operand */                 \
  X(TEXCOORD, 0, 0, ())                                   /* uv */                                                     \
  X(POSITION, 0, 0, ())                                   /* world (= object) position */                              \
  X(NORMAL, 0, 0, ())                                     /* shading normal, world */                                  \
  X(TANGENT, 0, 0, ())                                    /* tangent, world */                                         \
  X(BITANGENT, 0, 0, ())                                  /* bitangent, world */                                       \
  X(ADD, 2, 2, (in1, in2))                                                                                             \
  X(SUB, 2, 2, (in1, in2))                                                                                             \
  X(MUL, 2, 2, (in1, in2))                                                                                             \
  X(DIV, 2, 2, (in1, in2))                                                                                             \
  X(MOD, 2, 2, (in1, in2))                                                                                             \
  X(POW, 2, 2, (in1, in2))                                                                                             \
  X(MIN, 2, 2, (in1, in2))                                                                                             \
  X(MAX, 2, 2, (in1, in2))                                                                                             \
  X(DOT, 2, 2, (in1, in2))                                /* imm = operand width */                                    \
  X(ABS, 1, 1, (in))                                                                                                   \
  X(FLOOR, 1, 1, (in))                                                                                                 \
  X(CEIL, 1, 1, (in))                                                                                                  \
  X(SIN, 1, 1, (in))                                                                                                   \
  X(COS, 1, 1, (in))                                                                                                   \
  X(SQRT, 1, 1, (in))                                                                                                  \
  X(NORMALIZE, 1, 1, (in))                                                                                             \
  X(CLAMP, 3, 3, (in, low, high))                                                                                      \
  X(SMOOTHSTEP, 3, 3, (in, low, high))                                                                                 \
  X(MIX, 3, 3, (fg, bg, weight))                          /* MaterialX mix: bg + (fg - bg) * weight */                 \
  X(REMAP, 5, 5, (in, inlow, inhigh, outlow, outhigh))                                                                 \
  X(IFGREATER, 4, 4, (value1, value2, in1, in2))                                                                       \
  X(IFGREATEREQ, 4, 4, (value1, value2, in1, in2))                                                                     \
  X(LUMINANCE, 2, 2, (in, lumacoeffs))                                                                                 \
  X(RGBTOHSV, 1, 1, (in))                                                                                              \
  X(HSVTORGB, 1, 1, (in))                                                                                              \
  X(IMAGE, 3, 3, (texcoord, default, mode))               /* imm = texture index */                                    \
  X(PLACE2D, 6, 6, (texcoord, pivot, scale, degrees, offset, operationorder))                                          \
  X(NOISE2D, 3, 3, (texcoord, amplitude, pivot))                                                                       \
  X(NOISE3D, 3, 3, (position, amplitude, pivot))                                                                       \
  X(FRACTAL2D, 5, 5, (texcoord, amplitude, octaves, lacunarity, diminish))                                             \
  X(FRACTAL3D, 5, 5, (position, amplitude, octaves, lacunarity, diminish))                                             \
  X(CELLNOISE2D, 1, 1, (texcoord))                                                                                     \
  X(CELLNOISE3D, 1, 1, (position))                                                                                     \
  X(WORLEY2D, 3, 3, (texcoord, jitter, style))                                                                         \
  X(WORLEY3D, 3, 3, (position, jitter, style))                                                                         \
  X(RAMPLR, 3, 3, (valuel, valuer, texcoord))                                                                          \
  X(RAMPTB, 3, 3, (valuet, valueb, texcoord))                                                                          \
  X(RAMP4, 5, 5, (valuetl, valuetr, valuebl, valuebr, texcoord))                                                       \
  X(SPLITLR, 4, 4, (valuel, valuer, center, texcoord))                                                                 \
  X(SPLITTB, 4, 4, (valuet, valueb, center, texcoord))                                                                 \
  X(TILEDSHAPE, 5, 5, (texcoord, uvtiling, uvoffset, size, staggered)) /* imm = shape */                               \
  X(LINEPATTERN, 5, 5, (texcoord, uvtiling, uvoffset, thickness, staggered)) /* imm = kind */                          \
  X(NORMALMAP, 4, 4, (in, scale, normal, tangent))                                                                     \
  X(TAN, 1, 1, (in))                                                                                                   \
  X(ASIN, 1, 1, (in))                                                                                                  \
  X(ACOS, 1, 1, (in))                                                                                                  \
  X(ATAN2, 2, 2, (iny, inx))                                                                                           \
  X(EXP, 1, 1, (in))                                                                                                   \
  X(LN, 1, 1, (in))                                                                                                    \
  X(SIGN, 1, 1, (in))                                                                                                  \
  X(ROUND, 1, 1, (in))                                    /* halves away from zero */                                  \
  X(FRACT, 1, 1, (in))                                    /* x - floor(x) */                                           \
  X(LENGTH, 1, 1, (in))                                   /* imm = operand width */                                    \
  X(CROSS, 2, 2, (in1, in2))                                                                                           \
  X(NOT, 1, 1, (in))                                      /* a == 0 ? 1 : 0 */                                         \
  X(IFEQUAL, 4, 4, (value1, value2, in1, in2))            /* values compared on their first component */               \
  X(BLEND, 3, 3, (fg, bg, weight))                        /* imm = PMC_BLEND_* */                                      \
  X(ROTATE2D, 2, 2, (in, amount))                         /* amount in degrees */                                      \
  X(ROTATE3D, 3, 3, (in, amount, axis))                   /* amount in degrees */                                      \
  X(COMPOSITE, 3, 3, (fg, bg, weight))                    /* imm = PMC_COMP_* (color4 merge nodes) */                  \
  X(PREMULT, 1, 1, (in))                                  /* imm 0: RGB * alpha, 1: RGB / alpha (or as is at 0) */     \
  X(OUTSIDE, 2, 2, (in, mask))                            /* in * (1 - mask) */                                        \
  X(FLAKE, 7, 7, (size, roughness, coverage, position, normal, tangent, bitangent))                                    \
                                                          /* imm = PMC_FLAKE_* (pmc_flake.h) */                        \
  X(ROUGHNESS_ANISO, 2, 2, (roughness, anisotropy))       /* pmc_pbr_data.h */                                         \
  X(ROUGHNESS_DUAL, 1, 1, (roughness))                    /* vector2 */                                                \
  X(ARTISTIC_IOR, 2, 2, (reflectivity, edge_color))       /* imm 0: ior, 1: extinction */                              \
  X(BLACKBODY, 1, 1, (temperature))                       /* kelvin -> linear Rec.709 */                               \
  X(HAIR_ROUGHNESS, 4, 4, (longitudinal, azimuthal, scale_TT, scale_TRT)) /* imm = PMC_HAIR_* */                       \
  X(HAIR_MELANIN, 4, 4, (melanin_concentration, melanin_redness, eumelanin_color, pheomelanin_color))                  \
  X(HAIR_COLOR, 2, 2, (color, azimuthal_roughness))       /* pmc_hair_data.h */                                        \
  X(HEXIMAGE, 13, 13, (texcoord, tiling, rotation, rotationrange, scale, scalerange, offset,                           \
                       offsetrange, falloff, default, mode, falloffcontrast, lumacoeffs))                              \
                                                          /* mode as IMAGE's; imm = texture index */                   \
  X(HEXNORMALMAP, 15, 15, (texcoord, tiling, rotation, rotationrange, scale, scalerange, offset,                       \
                           offsetrange, falloff, default, mode, strength, flip_g, normal, tangent))                    \
  X(CACHE_LOOKUP, 1, 1, (skip))                           /* dst = cached value; imm = node | enc << 14 */             \
  X(CACHE_STORE, 1, 1, (value))                           /* dst = value where lookup k missed; insert */
// clang-format on

#define PMC_OP_ENUM(name, lo, hi, slots) PMC_OP_##name,
enum PmcOpcode { PMC_OPCODES(PMC_OP_ENUM) PMC_OP_COUNT };
#undef PMC_OP_ENUM

/* Slot indices: enum { PMC_ARG_CLAMP_in = 0, PMC_ARG_CLAMP_low = 1,
 * PMC_ARG_CLAMP_high = 2, PMC_OPERANDS_<name> = 3 } for each row. The helper
 * is chosen by the row's maximum operand count, so a slot list of another
 * length fails to compile. */
#define PMC_SLOTS_0(op, unused)
#define PMC_SLOTS_1(op, a) PMC_ARG_##op##_##a,
#define PMC_SLOTS_2(op, a, b) PMC_SLOTS_1(op, a) PMC_ARG_##op##_##b,
#define PMC_SLOTS_3(op, a, b, c) PMC_SLOTS_2(op, a, b) PMC_ARG_##op##_##c,
#define PMC_SLOTS_4(op, a, b, c, d) PMC_SLOTS_3(op, a, b, c) PMC_ARG_##op##_##d,
#define PMC_SLOTS_5(op, a, b, c, d, e) PMC_SLOTS_4(op, a, b, c, d) PMC_ARG_##op##_##e,
#define PMC_SLOTS_6(op, a, b, c, d, e, f) PMC_SLOTS_5(op, a, b, c, d, e) PMC_ARG_##op##_##f,
#define PMC_SLOTS_7(op, a, b, c, d, e, f, g) PMC_SLOTS_6(op, a, b, c, d, e, f) PMC_ARG_##op##_##g,
#define PMC_SLOTS_13(op, a, b, c, d, e, f, g, h, i, j, k, l, m) \
  PMC_SLOTS_7(op, a, b, c, d, e, f, g) PMC_SLOTS_6(op, h, i, j, k, l, m)
#define PMC_SLOTS_15(op, a, b, c, d, e, f, g, h, i, j, k, l, m, n, o) \
  PMC_SLOTS_7(op, a, b, c, d, e, f, g) PMC_SLOTS_7(op, h, i, j, k, l, m, n) PMC_ARG_##op##_##o,
#define PMC_SLOTS_EXPAND(macro, args) macro args
#define PMC_SLOTS_UNPAREN(...) __VA_ARGS__
#define PMC_OP_SLOT_ENUM(name, lo, hi, slots) \
  enum { PMC_SLOTS_EXPAND(PMC_SLOTS_##hi, (name, PMC_SLOTS_UNPAREN slots)) PMC_OPERANDS_##name = hi };
PMC_OPCODES(PMC_OP_SLOT_ENUM)
#undef PMC_OP_SLOT_ENUM

#define PMC_OPERAND_CONST 0x80000000u
#define PMC_OPERAND_INDEX_MASK 0x0fffffffu

PMC_FN pmc_u32 pmc_op_header(pmc_u32 op, pmc_u32 width, pmc_u32 nargs, pmc_u32 imm) {
  return op | ((width - 1u) << 8) | (nargs << 10) | (imm << 16);
}
PMC_FN pmc_u32 pmc_op_code(pmc_u32 h) { return h & 0xffu; }
PMC_FN pmc_u32 pmc_op_width(pmc_u32 h) { return ((h >> 8) & 3u) + 1u; }
PMC_FN pmc_u32 pmc_op_nargs(pmc_u32 h) { return (h >> 10) & 15u; }
PMC_FN pmc_u32 pmc_op_imm(pmc_u32 h) { return h >> 16; }
PMC_FN pmc_u32 pmc_operand(int is_const, pmc_u32 index, pmc_u32 width) {
  return (is_const ? PMC_OPERAND_CONST : 0u) | ((width - 1u) << 28) | index;
}
PMC_FN pmc_u32 pmc_operand_width(pmc_u32 o) { return ((o >> 28) & 3u) + 1u; }

/* Image address modes and filters, packed into the IMAGE `mode` constant:
 * u mode | v mode << 2 | filter << 4 | PMC_IMAGE_ANISO. The compiler sets
 * PMC_IMAGE_ANISO where the lookup's uv is the mesh's uv under a uniform
 * scale and a shift (materials/emit.cpp): there the footprint's ellipse keeps
 * its direction and the lookup filters anisotropically; elsewhere (turned,
 * mirrored or unevenly stretched uvs, computed ones) it is isotropic. */
#define PMC_ADDR_CONSTANT 0u
#define PMC_ADDR_CLAMP 1u
#define PMC_ADDR_PERIODIC 2u
#define PMC_ADDR_MIRROR 3u
#define PMC_FILTER_CLOSEST 0u
#define PMC_FILTER_LINEAR 1u
#define PMC_IMAGE_ANISO 256u

/* Tiled shapes and line patterns (imm of TILEDSHAPE / LINEPATTERN). */
#define PMC_SHAPE_CIRCLES 0u
#define PMC_SHAPE_CLOVERLEAFS 1u
#define PMC_SHAPE_HEXAGONS 2u
#define PMC_LINES_GRID 0u
#define PMC_LINES_CROSSHATCH 1u

/* Blend modes (imm of BLEND), MaterialX's compositing nodes:
 * mix * f(fg, bg) + (1 - mix) * bg, lane-wise. */
#define PMC_BLEND_PLUS 0u       /* fg + bg */
#define PMC_BLEND_MINUS 1u      /* bg - fg */
#define PMC_BLEND_DIFFERENCE 2u /* |bg - fg| */
#define PMC_BLEND_BURN 3u       /* 1 - (1 - bg) / fg; 0 where |fg| < 1e-6 */
#define PMC_BLEND_DODGE 4u      /* bg / (1 - fg); 0 where |1 - fg| < 1e-6 */
#define PMC_BLEND_SCREEN 5u     /* 1 - (1 - fg) (1 - bg) */

/* Merge nodes (imm of COMPOSITE), MaterialX's color4 compositing nodes
 * (core/device/pmc_compositing.h has the formulas). */
#define PMC_COMP_DISJOINTOVER 0u
#define PMC_COMP_IN 1u
#define PMC_COMP_MASK 2u
#define PMC_COMP_MATTE 3u
#define PMC_COMP_OUT 4u
#define PMC_COMP_OVER 5u

/* Surface parameters a material program writes with OUTPUT (float offsets
 * into the parameter block). Unwritten parameters keep the defaults set by
 * pmc_surface_defaults(). */
#define PMC_P_MODEL                                                         \
  0 /* 0: standard_surface and the shading models mapped onto it (MTL too); \
       1: a flattened closure graph (diffuse albedo and Schlick F0 as given) */
#define PMC_P_BASE 1
#define PMC_P_BASE_COLOR 2 /* 3 floats */
#define PMC_P_METALNESS 5
#define PMC_P_SPECULAR 6
#define PMC_P_SPECULAR_COLOR 7 /* 3 */
#define PMC_P_SPECULAR_ROUGHNESS 10
#define PMC_P_SPECULAR_IOR 11
#define PMC_P_EMISSION 12
#define PMC_P_EMISSION_COLOR 13 /* 3 */
#define PMC_P_NORMAL 16         /* 3, world; (0,0,0) = keep the shading normal */
#define PMC_P_OPACITY 19        /* 3 */
#define PMC_P_COAT 22
#define PMC_P_COAT_COLOR 23 /* 3 */
#define PMC_P_COAT_ROUGHNESS 26
#define PMC_P_COAT_IOR 27
#define PMC_P_TRANSMISSION 28
#define PMC_P_TRANSMISSION_COLOR 29 /* 3 */
#define PMC_P_TRANSMISSION_DEPTH 32 /* scene units; 0: the colour tints each crossing */
#define PMC_P_THIN_WALLED 33        /* 0 or 1 */
#define PMC_P_SHEEN 34
#define PMC_P_SHEEN_COLOR 35 /* 3 */
#define PMC_P_SHEEN_ROUGHNESS 38
#define PMC_P_SPECULAR_ANISOTROPY 39
#define PMC_P_SPECULAR_ROTATION 40 /* turns (MaterialX: 1 = 360 degrees) */
#define PMC_P_COUNT 41

/* standard_surface inputs pmc models, each with its parameter, width and
 * MaterialX 1.39 default: X(input, param, width, x, y, z). The device's
 * pmc_surface_defaults() and the node table's standard_surface entry both
 * expand this one list. */
// clang-format off
#define PMC_STANDARD_SURFACE(X)                                          \
  X(base, PMC_P_BASE, 1, 1.0f, 0.0f, 0.0f)                               \
  X(base_color, PMC_P_BASE_COLOR, 3, 0.8f, 0.8f, 0.8f)                   \
  X(metalness, PMC_P_METALNESS, 1, 0.0f, 0.0f, 0.0f)                     \
  X(specular, PMC_P_SPECULAR, 1, 1.0f, 0.0f, 0.0f)                       \
  X(specular_color, PMC_P_SPECULAR_COLOR, 3, 1.0f, 1.0f, 1.0f)           \
  X(specular_roughness, PMC_P_SPECULAR_ROUGHNESS, 1, 0.2f, 0.0f, 0.0f)   \
  X(specular_IOR, PMC_P_SPECULAR_IOR, 1, 1.5f, 0.0f, 0.0f)               \
  X(specular_anisotropy, PMC_P_SPECULAR_ANISOTROPY, 1, 0.0f, 0.0f, 0.0f) \
  X(specular_rotation, PMC_P_SPECULAR_ROTATION, 1, 0.0f, 0.0f, 0.0f)     \
  X(transmission, PMC_P_TRANSMISSION, 1, 0.0f, 0.0f, 0.0f)               \
  X(transmission_color, PMC_P_TRANSMISSION_COLOR, 3, 1.0f, 1.0f, 1.0f)   \
  X(transmission_depth, PMC_P_TRANSMISSION_DEPTH, 1, 0.0f, 0.0f, 0.0f)   \
  X(sheen, PMC_P_SHEEN, 1, 0.0f, 0.0f, 0.0f)                             \
  X(sheen_color, PMC_P_SHEEN_COLOR, 3, 1.0f, 1.0f, 1.0f)                 \
  X(sheen_roughness, PMC_P_SHEEN_ROUGHNESS, 1, 0.3f, 0.0f, 0.0f)         \
  X(emission, PMC_P_EMISSION, 1, 0.0f, 0.0f, 0.0f)                       \
  X(emission_color, PMC_P_EMISSION_COLOR, 3, 1.0f, 1.0f, 1.0f)           \
  X(normal, PMC_P_NORMAL, 3, 0.0f, 0.0f, 0.0f)                           \
  X(opacity, PMC_P_OPACITY, 3, 1.0f, 1.0f, 1.0f)                         \
  X(coat, PMC_P_COAT, 1, 0.0f, 0.0f, 0.0f)                               \
  X(coat_color, PMC_P_COAT_COLOR, 3, 1.0f, 1.0f, 1.0f)                   \
  X(coat_roughness, PMC_P_COAT_ROUGHNESS, 1, 0.1f, 0.0f, 0.0f)           \
  X(coat_IOR, PMC_P_COAT_IOR, 1, 1.5f, 0.0f, 0.0f)                       \
  X(thin_walled, PMC_P_THIN_WALLED, 1, 0.0f, 0.0f, 0.0f)
// clang-format on

/* Floats of stack per shading point: the compiler's limit. Kernels are built
 * with -DPMC_STACK_SIZE=<the scene's peak rounded up to a power of two, at
 * least 16> (wave_program_options, gpu/wave_kernels.cpp), so private memory is about as large
 * as the loaded materials need while few distinct kernel builds exist. */
#ifndef PMC_STACK_SIZE
#define PMC_STACK_SIZE 128
#endif

#endif /* PMC_BYTECODE_H */
