#!/usr/bin/env python3
# Generates pmc's heavy procedural scene into data/heavy/: the scene the
# progressive material cache is made for (issue 39) and its benchmark scene
# (scripts/bench-heavy). An open-fronted room (room.obj + room.mtl) whose
# every surface carries a procedural MaterialX network of 100-300 nodes
# (materials.mtlx), built the way people build them from stdlib nodes, lit
# by an area quad under the ceiling and a low sun (room.lights.json), seen
# from room.camera:
#
#   plaster  side walls and ceiling: mottled, trowelled paint with cracks,
#            peeling patches, tide marks near the floor, soot at the top (uv)
#   wood     floor: staggered planks with growth rings, pores, per-plank
#            colour, gaps, worn varnish, scratches and dirt (uv)
#   brick    back wall: stretcher bond with jittered mortar, per-brick
#            colour, chipped edges, efflorescence and grime (uv)
#   marble   plinth and the ball on it: warped veins, clouds, specks and
#            crystals from the object-space position (position)
#   metal    drum: painted metal with a stencil band, rims, chips, scratches
#            and drips (uv) over rust from the position (position); the two
#            meet in a few nodes on top, so each side is its own cache point
#   fabric   ottoman: a tartan twill of threads with fibres, worn edges, lint
#            and dirt (uv)
#
# Units: room uvs are metres (floor u along +x, v towards -z; wall v up);
# box faces are 0..1 per face, the drum's u runs around it and v up. No
# textures: every pattern is procedural, so the scene stays small. The
# builders are those of the default scene (scripts/make_default_scene.py,
# scripts/make_default_materials.py). Standard library only; the output is
# deterministic (tests/app/heavy_scene_test.cpp regenerates it and compares).
#   python3 scripts/make_heavy_scene.py [--out DIR]     (default data/heavy)

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_default_materials as mx  # noqa: E402  (the nodegraph builder)
import make_default_scene as geo     # noqa: E402  (the OBJ builder)
from make_default_materials import Typed, c3, integer, v2, v3  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_OUT = os.path.join(ROOT, "data", "heavy")

# Room extents: x in [-RX, RX], y in [0, RY], z in [-RZ, RZ]; open toward +z.
RX, RY, RZ = 2.5, 3.0, 2.5
CAMERA = {"from": (0.0, 1.55, 6.4), "at": (0.0, 1.05, 0.0), "up": (0.0, 1.0, 0.0), "fov": 45.0}
LIGHTS = {"lights": [
    {"type": "quad", "name": "ceiling panel", "corner": [-0.6, 2.95, -0.9], "edge_u": [1.2, 0.0, 0.0],
     "edge_v": [0.0, 0.0, 1.2], "radiance": [9.0, 8.6, 8.0]},
    {"type": "directional", "name": "low sun through the open front", "direction": [-0.45, -0.5, -1.0],
     "irradiance": [3.5, 3.2, 2.7], "angle_deg": 0.53},
]}
F, C, V2, V3 = "float", "color3", "vector2", "vector3"


# --------------------------------------------------------------------------
# Building blocks: the small sub-networks artists repeat in every material
# --------------------------------------------------------------------------

def f(x):
    return Typed("float", float(x))


def ss(g, x, lo, hi, name=None):
    return g.smoothstep(F, name=name, **{"in": x, "low": lo, "high": hi})


def remap(g, x, a, b, c, d, name=None, type_=F):
    return g.remap(type_, name=name, **{"in": x, "inlow": a, "inhigh": b, "outlow": c, "outhigh": d})


def inv(g, x, name=None):
    return g.invert(F, name=name, **{"in": x})


def absv(g, x, name=None):
    return g.absval(F, name=name, **{"in": x})


def clamp01(g, x, name=None):
    return g.clamp(F, name=name, **{"in": x, "low": 0.0, "high": 1.0})


def xtr(g, x, i, name=None):
    return g.extract(F, name=name, **{"in": x, "index": integer(i)})


def fbm2(g, uv, scale, octaves, name, amplitude=1.0, lacunarity=2.0, diminish=0.5):
    """fractal2d of uv scaled per axis."""
    s = g.multiply(V2, name=name + "_uv", in1=uv, in2=v2(*scale))
    return g.fractal2d(F, name=name, texcoord=s, octaves=integer(octaves), amplitude=amplitude,
                       lacunarity=lacunarity, diminish=diminish)


def fbm3(g, pos, scale, octaves, name, offset=(0.0, 0.0, 0.0), amplitude=1.0, diminish=0.5):
    """fractal3d of the position scaled and offset (an offset decorrelates layers)."""
    s = g.multiply(V3, name=name + "_p", in1=pos, in2=scale)
    o = g.add(V3, name=name + "_po", in1=s, in2=v3(*offset))
    return g.fractal3d(F, name=name, position=o, octaves=integer(octaves), amplitude=amplitude,
                       diminish=diminish)


def ramp3(g, t, c0, c1, c2, name):
    """A three-stop colour ramp over t in [0, 1] (mix of two smoothsteps)."""
    a = ss(g, t, 0.0, 0.5, name + "_a")
    b = ss(g, t, 0.5, 1.0, name + "_b")
    m = g.mix(C, name=name + "_lo", fg=c1, bg=c0, mix=a)
    return g.mix(C, name=name, fg=c2, bg=m, mix=b)


def hsv_jitter(g, col, r_h, r_s, r_v, name, hue=0.02, sat=(0.8, 1.15), val=(0.8, 1.1)):
    """Per-cell hue, saturation and value variation from three random numbers."""
    hsv = g.rgbtohsv(C, name=name + "_hsv", **{"in": col})
    dh = remap(g, r_h, 0.0, 1.0, -hue, hue, name + "_dh")
    ks = remap(g, r_s, 0.0, 1.0, sat[0], sat[1], name + "_ks")
    kv = remap(g, r_v, 0.0, 1.0, val[0], val[1], name + "_kv")
    gain = g.combine3(C, name=name + "_gain", in1=f(1.0), in2=ks, in3=kv)
    bias = g.combine3(C, name=name + "_bias", in1=dh, in2=f(0.0), in3=f(0.0))
    scaled = g.multiply(C, name=name + "_scaled", in1=hsv, in2=gain)
    shifted = g.add(C, name=name + "_shifted", in1=scaled, in2=bias)
    return g.hsvtorgb(C, name=name, **{"in": shifted})


def scratches(g, coord, scale, gate_scale, width, name):
    """Thin streaks where a stretched noise crosses zero, gated by a coarse noise."""
    n = g.noise2d(F, name=name + "_n", texcoord=g.multiply(V2, name=name + "_uv", in1=coord, in2=v2(*scale)))
    off = ss(g, absv(g, n, name + "_abs"), 0.0, width, name + "_off")
    lines = inv(g, off, name + "_lines")
    gate_n = g.noise2d(F, name=name + "_gate_n",
                       texcoord=g.multiply(V2, name=name + "_gate_uv", in1=coord, in2=v2(*gate_scale)))
    gate = ss(g, gate_n, 0.0, 0.3, name + "_gate")
    return g.multiply(F, name=name, in1=lines, in2=gate)


def edge_wear(g, edge_dist, noise, width, name):
    """1 at an edge, fading over `width` (jittered by noise in [-1, 1])."""
    w = g.multiply(F, name=name + "_w", in1=g.add(F, name=name + "_j", in1=noise, in2=1.2), in2=width)
    return inv(g, ss(g, edge_dist, 0.0, w, name + "_in"), name)


def warped_fbm3(g, pos, scale, octaves, warp, name, offset=(0.0, 0.0, 0.0)):
    """A domain-warped solid fBm (Blender's noise texture with distortion): the
    position pushed by a vector fBm, then an fBm of `octaves` octaves there."""
    p = g.add(V3, name=name + "_p", in1=g.multiply(V3, name=name + "_ps", in1=pos, in2=scale), in2=v3(*offset))
    w = g.fractal3d(V3, name=name + "_warp", position=p, octaves=integer(3))
    pw = g.add(V3, name=name + "_pw", in1=p, in2=g.multiply(V3, name=name + "_wk", in1=w, in2=warp))
    return g.fractal3d(F, name=name, position=pw, octaves=integer(octaves), diminish=0.55)


def crack_lines(g, coord, kind, width, name):
    """Cell borders of a Worley noise (F2 - F1 small): craquelure, crystal
    boundaries, flake edges. `kind` is "2d" (coord: vector2) or "3d"."""
    w = g.node("worleynoise" + kind, V2, name + "_f12", **{"texcoord" if kind == "2d" else "position": coord,
                                                           "jitter": 0.85})
    gap = g.subtract(F, name=name + "_gap", in1=xtr(g, w, 1, name + "_f2"), in2=xtr(g, w, 0, name + "_f1"))
    return inv(g, ss(g, gap, 0.0, width, name + "_s"), name)


def weathering(g, pos, name, scale=1.0, grime=(c3(0.1, 0.085, 0.07), c3(0.3, 0.27, 0.22), c3(0.2, 0.22, 0.16))):
    """Weathering from the position, the layer artists put over every
    material: a domain-warped grime mask, blotches, grime in hairline cracks,
    and the grime's own colour. Returns (amount, colour), both position-only."""
    big = warped_fbm3(g, pos, 0.8 * scale, 7, 0.7, name + "_big", offset=(1.7, 4.1, 2.9))
    mid = fbm3(g, pos, 3.3 * scale, 5, name + "_mid", offset=(7.3, 1.1, 5.5))
    blot = inv(g, g.worleynoise3d(F, name=name + "_blot_d", position=g.multiply(
        V3, name=name + "_blot_p", in1=pos, in2=1.9 * scale), jitter=0.9), name + "_blot")
    cracks = crack_lines(g, g.multiply(V3, name=name + "_crack_p", in1=pos, in2=5.0 * scale), "3d", 0.04,
                         name + "_cracks")
    t = g.add(F, name=name + "_t", in1=g.add(F, name=name + "_t0", in1=big, in2=g.multiply(
        F, name=name + "_bk", in1=blot, in2=0.45)), in2=g.multiply(F, name=name + "_mk", in1=mid, in2=0.25))
    mask = ss(g, t, 0.35, 0.85, name + "_mask")
    amount = clamp01(g, g.max(F, name=name + "_amt0", in1=mask, in2=g.multiply(
        F, name=name + "_ck", in1=cracks, in2=0.6)), name + "_amount")
    grit = g.noise3d(F, name=name + "_grit", position=g.multiply(V3, name=name + "_grit_p", in1=pos,
                                                                 in2=30.0 * scale), amplitude=0.5, pivot=0.5)
    tone = clamp01(g, g.add(F, name=name + "_tone0", in1=g.multiply(F, name=name + "_tm", in1=mid, in2=0.8),
                            in2=grit), name + "_tone")
    colour = ramp3(g, tone, grime[0], grime[1], grime[2], name + "_color")
    return amount, colour


def weathered(g, base, rough, amount, colour, strength, rough_to):
    """The uv layers under the position's weathering: the few nodes that read both keys."""
    k = g.multiply(F, name="weather_k", in1=amount, in2=strength)
    out_base = g.mix(C, name="weathered", fg=colour, bg=base, mix=k)
    out_rough = g.mix(F, name="weathered_rough", fg=rough_to, bg=rough, mix=k)
    return out_base, out_rough


def box_edge_dist(g, u, v, name):
    """Distance in face units to the nearest border of a 0..1 face."""
    du = g.min(F, name=name + "_u", in1=u, in2=inv(g, u, name + "_ui"))
    dv = g.min(F, name=name + "_v", in1=v, in2=inv(g, v, name + "_vi"))
    return g.min(F, name=name, in1=du, in2=dv)


def uv_parts(g):
    uv = g.texcoord(V2, name="uv")
    return uv, xtr(g, uv, 0, "u"), xtr(g, uv, 1, "v")


# --------------------------------------------------------------------------
# plaster: side walls and ceiling (uv only)
# --------------------------------------------------------------------------

def plaster_graph():
    g = mx.Graph("NG_plaster", "aged painted plaster: mottling, trowel marks, cracks, peeling, tide marks, soot")
    paint = g.param("paint_color", c3(0.78, 0.74, 0.66), "Paint")
    bare = g.param("plaster_color", c3(0.55, 0.47, 0.38), "Bare plaster")
    uv, u, v = uv_parts(g)
    # Mottled paint: a large fbm and a sandy fine one.
    mottle = fbm2(g, uv, (0.6, 0.6), 8, "mottle", diminish=0.55)
    mottle_k = remap(g, mottle, -0.6, 0.6, 0.9, 1.06, "mottle_gain")
    sand = fbm2(g, uv, (22.0, 22.0), 3, "sand", amplitude=0.5)
    sand_k = remap(g, sand, -0.5, 0.5, 0.96, 1.03, "sand_gain")
    # Trowel marks: a noise stretched along a rotated axis.
    trowel_uv = g.place2d(V2, name="trowel_uv", texcoord=uv, scale=v2(0.35, 2.4), rotate=f(28.0),
                          pivot=v2(0.0, 0.0))
    trowel = g.noise2d(F, name="trowel", texcoord=trowel_uv)
    trowel_k = remap(g, ss(g, trowel, -0.2, 0.35, "trowel_s"), 0.0, 1.0, 0.97, 1.03, "trowel_gain")
    tone = g.multiply(F, name="paint_tone", in1=g.multiply(F, name="paint_tone2", in1=mottle_k, in2=sand_k),
                      in2=trowel_k)
    painted = g.multiply(C, name="painted", in1=paint, in2=tone)
    # Cracks: ridges of a warped fractal, only in some areas.
    warp = fbm2(g, uv, (1.7, 1.7), 3, "crack_warp", amplitude=0.2)
    crack_uv = g.add(V2, name="crack_uv", in1=g.multiply(V2, name="crack_uv0", in1=uv, in2=v2(1.3, 1.1)),
                     in2=g.combine2(V2, name="crack_shift", in1=warp, in2=warp))
    ridge = absv(g, g.fractal2d(F, name="crack_fbm", texcoord=crack_uv, octaves=integer(4)), "crack_abs")
    crack_line = inv(g, ss(g, ridge, 0.0, 0.018, "crack_s"), "crack_line")
    crack_area = ss(g, fbm2(g, uv, (0.45, 0.45), 2, "crack_area_n"), 0.05, 0.3, "crack_area")
    cracks = g.multiply(F, name="cracks", in1=crack_line, in2=crack_area)
    # Peeling: worley blotches, warped, with a dark rim where the paint lifts.
    peel_n = fbm2(g, uv, (3.0, 3.0), 3, "peel_warp", amplitude=0.12)
    peel_uv = g.add(V2, name="peel_uv", in1=g.multiply(V2, name="peel_uv0", in1=uv, in2=v2(1.4, 1.4)),
                    in2=g.combine2(V2, name="peel_shift", in1=peel_n, in2=peel_n))
    peel_d = g.worleynoise2d(F, name="peel_worley", texcoord=peel_uv, jitter=0.9)
    peel_pick = g.cellnoise2d(F, name="peel_pick", texcoord=peel_uv)
    peel_r = g.ifgreater(F, name="peel_radius", value1=peel_pick, value2=0.72, in1=f(0.22), in2=f(0.0))
    peel_in = inv(g, ss(g, peel_d, g.multiply(F, name="peel_r0", in1=peel_r, in2=0.8), peel_r, "peel_s"),
                  "peel")
    rim_out = inv(g, ss(g, peel_d, peel_r, g.add(F, name="peel_r1", in1=peel_r, in2=0.03), "rim_s"), "rim_out")
    rim = g.subtract(F, name="peel_rim", in1=rim_out, in2=peel_in)
    bare_n = fbm2(g, uv, (9.0, 9.0), 3, "bare_grain")
    bare_c = g.multiply(C, name="bare", in1=bare, in2=remap(g, bare_n, -0.5, 0.5, 0.85, 1.1, "bare_gain"))
    peeled = g.mix(C, name="peeled", fg=bare_c, bg=painted, mix=peel_in)
    rimmed = g.multiply(C, name="rimmed", in1=peeled,
                        in2=remap(g, rim, 0.0, 1.0, 1.0, 0.7, "rim_gain"))
    craq = g.max(F, name="craquelure", in1=crack_lines(g, g.multiply(V2, name="craq_uv", in1=crack_uv, in2=3.5),
                                                           "2d", 0.03, "craq_coarse"),
                 in2=g.multiply(F, name="craq_fine_k", in1=crack_lines(g, g.multiply(
                     V2, name="craq_fine_uv", in1=uv, in2=v2(11.0, 11.0)), "2d", 0.05, "craq_fine"), in2=0.5))
    craq_m = g.multiply(F, name="craq_masked", in1=craq, in2=crack_area)
    pits = ss(g, g.worleynoise2d(F, name="pits_d", texcoord=g.multiply(V2, name="pits_uv", in1=uv,
                                                                     in2=v2(35.0, 35.0)), jitter=1.0),
              0.0, 0.12, "pits")
    all_cracks = g.max(F, name="all_cracks", in1=cracks, in2=craq_m)
    cracked = g.multiply(C, name="cracked", in1=g.multiply(C, name="pitted", in1=rimmed, in2=remap(
        g, pits, 0.0, 1.0, 0.85, 1.0, "pits_gain")), in2=remap(g, all_cracks, 0.0, 1.0, 1.0, 0.45, "crack_gain"))
    # Tide marks of old damp near the floor, wobbling along the wall.
    tide_n = fbm2(g, uv, (1.2, 0.3), 3, "tide_n", amplitude=0.15)
    tide_h = g.add(F, name="tide_h", in1=v, in2=tide_n)
    damp = inv(g, ss(g, tide_h, 0.25, 0.55, "damp_s"), "damp")
    tide_line = g.subtract(F, name="tide_line", in1=ss(g, tide_h, 0.5, 0.54, "tide_a"),
                           in2=ss(g, tide_h, 0.56, 0.62, "tide_b"))
    damp_c = g.mix(C, name="damp_color", fg=c3(0.5, 0.44, 0.34), bg=cracked,
                   mix=g.multiply(F, name="damp_k", in1=damp, in2=0.45))
    tided = g.mix(C, name="tided", fg=c3(0.42, 0.34, 0.24), bg=damp_c,
                  mix=g.multiply(F, name="tide_k", in1=tide_line, in2=0.6))
    # Soot towards the ceiling, dirt along the skirting.
    soot_n = fbm2(g, uv, (0.8, 2.0), 4, "soot_n", amplitude=0.3)
    soot = ss(g, g.add(F, name="soot_h", in1=v, in2=soot_n), 2.3, 3.0, "soot")
    dirt_n = fbm2(g, uv, (4.0, 1.0), 4, "dirt_n")
    dirt = g.multiply(F, name="dirt", in1=inv(g, ss(g, v, 0.0, 0.25, "dirt_h"), "dirt_low"),
                      in2=remap(g, dirt_n, -0.5, 0.5, 0.2, 1.0, "dirt_var"))
    sooted = g.mix(C, name="sooted", fg=c3(0.12, 0.11, 0.1), bg=tided,
                   mix=g.multiply(F, name="soot_k", in1=soot, in2=0.5))
    base = g.mix(C, name="base_uv", fg=c3(0.16, 0.13, 0.1), bg=sooted,
                 mix=g.multiply(F, name="dirt_k", in1=dirt, in2=0.6))
    # Roughness: satin paint, chalky bare plaster, rougher soot and damp.
    r0 = g.mix(F, name="rough_peel", fg=0.92, bg=0.55, mix=peel_in)
    r1 = g.add(F, name="rough_sand", in1=r0, in2=g.multiply(F, name="rough_sand_k", in1=sand, in2=0.1))
    r2 = g.add(F, name="rough_soot", in1=r1, in2=g.multiply(F, name="rough_soot_k", in1=soot, in2=0.2))
    r3 = g.add(F, name="rough_damp", in1=r2, in2=g.multiply(F, name="rough_damp_k", in1=damp, in2=0.15))
    rough = g.clamp(F, name="rough_uv", **{"in": r3, "low": 0.3, "high": 1.0})
    amount, grime = weathering(g, g.position(V3, name="pos"), "weather", 0.8)
    base, rough = weathered(g, base, rough, amount, grime, 0.45, 0.95)
    g.output("base_color", base)
    g.output("roughness", rough)
    return g


# --------------------------------------------------------------------------
# wood: floor planks with rings and pores (uv only)
# --------------------------------------------------------------------------

def plank_layout(g, uv, u, v, plank_len, plank_w):
    """Rows of planks along u, each row shifted at random: per-plank ids and local coordinates."""
    row_f = g.divide(F, name="row_f", in1=v, in2=plank_w)
    row = g.floor(F, name="row", **{"in": row_f})
    lv = g.subtract(F, name="local_v", in1=row_f, in2=row)
    stagger = g.multiply(F, name="stagger", in1=g.cellnoise2d(
        F, name="row_rand", texcoord=g.combine2(V2, name="row_key", in1=row, in2=f(11.0))), in2=plank_len)
    us = g.add(F, name="u_shifted", in1=u, in2=stagger)
    col_f = g.divide(F, name="col_f", in1=us, in2=plank_len)
    col = g.floor(F, name="col", **{"in": col_f})
    lu = g.subtract(F, name="local_u", in1=col_f, in2=col)
    pid = g.combine2(V2, name="plank_id", in1=col, in2=row)
    rands = [g.cellnoise2d(F, name="plank_rand%d" % i, texcoord=g.add(V2, name="plank_key%d" % i, in1=pid,
                                                                       in2=v2(7.0 * i, 13.0 * i)))
             for i in range(1, 4)]
    return us, lu, lv, rands


def wood_graph():
    g = mx.Graph("NG_wood", "oak floor planks: growth rings, pores, per-plank colour, gaps, worn varnish, dirt")
    light = g.param("light_wood", c3(0.62, 0.42, 0.24), "Earlywood")
    dark = g.param("dark_wood", c3(0.3, 0.17, 0.08), "Latewood")
    plank_len, plank_w = 1.25, 0.16
    uv, u, v = uv_parts(g)
    us, lu, lv, (r1, r2, r3) = plank_layout(g, uv, u, v, plank_len, plank_w)
    across = g.multiply(F, name="across_m", in1=lv, in2=plank_w)
    # Growth rings: distance from the pith, off the plank, warped along it.
    pith = remap(g, r1, 0.0, 1.0, -0.25, 0.35, "pith")
    depth = remap(g, r2, 0.0, 1.0, 0.03, 0.12, "pith_depth")
    dy = g.subtract(F, name="pith_dy", in1=across, in2=pith)
    radius = g.magnitude(F, name="pith_r", **{"in": g.combine2(V2, name="pith_vec", in1=dy, in2=depth)})
    ring_warp = fbm2(g, g.combine2(V2, name="grain_uv", in1=us, in2=across), (0.9, 5.0), 4, "ring_warp",
                     amplitude=0.012)
    ring_r = g.add(F, name="ring_r", in1=radius, in2=ring_warp)
    ring_f = g.modulo(F, name="ring_f", in1=g.multiply(F, name="ring_n", in1=ring_r, in2=55.0), in2=1.0)
    late = g.power(F, name="latewood", in1=ss(g, ring_f, 0.45, 0.95, "ring_s"), in2=2.0)
    grain_uv = g.combine2(V2, name="fibre_uv", in1=us, in2=across)
    fibres = fbm2(g, grain_uv, (3.0, 90.0), 3, "fibres", amplitude=0.5)
    wood_t = clamp01(g, g.add(F, name="wood_t0", in1=late, in2=g.multiply(F, name="fibre_k", in1=fibres,
                                                                         in2=0.3)), "wood_t")
    wood = g.mix(C, name="wood", fg=dark, bg=light, mix=wood_t)
    # Pores: short dark streaks along the grain, denser in the earlywood.
    pores_n = g.worleynoise2d(F, name="pores_d", texcoord=g.multiply(V2, name="pores_uv", in1=grain_uv,
                                                                     in2=v2(14.0, 160.0)), jitter=1.0)
    pores = g.multiply(F, name="pores", in1=inv(g, ss(g, pores_n, 0.05, 0.25, "pores_s"), "pores_in"),
                       in2=inv(g, late, "earlywood"))
    # Ray flecks: short, lighter lenses across the grain (quarter-sawn oak).
    fleck_d = g.worleynoise2d(F, name="fleck_d", texcoord=g.multiply(V2, name="fleck_uv", in1=grain_uv,
                                                                     in2=v2(6.0, 45.0)), jitter=0.9)
    flecks = g.multiply(F, name="flecks", in1=inv(g, ss(g, fleck_d, 0.1, 0.3, "fleck_s"), "fleck_in"),
                        in2=ss(g, r2, 0.6, 0.8, "fleck_planks"))
    # Knots: a few dark cells per plank run.
    knot_d = g.worleynoise2d(F, name="knot_d", texcoord=g.multiply(V2, name="knot_uv", in1=grain_uv,
                                                                   in2=v2(1.6, 9.0)), jitter=0.7)
    knot = g.multiply(F, name="knot", in1=inv(g, ss(g, knot_d, 0.02, 0.12, "knot_s"), "knot_in"),
                      in2=ss(g, r3, 0.55, 0.65, "knot_planks"))
    pored0 = g.multiply(C, name="pored0", in1=wood, in2=remap(g, pores, 0.0, 1.0, 1.0, 0.55, "pores_gain"))
    flecked = g.mix(C, name="flecked", fg=c3(0.7, 0.52, 0.32), bg=pored0,
                    mix=g.multiply(F, name="fleck_k", in1=flecks, in2=0.5))
    pored = g.mix(C, name="pored", fg=c3(0.12, 0.06, 0.03), bg=flecked, mix=knot)
    # Per-plank colour: some boards redder, some greyer, a few replaced.
    planked = hsv_jitter(g, pored, r3, r1, r2, "plank_color", hue=0.015, sat=(0.8, 1.1), val=(0.75, 1.1))
    replaced = g.ifgreater(F, name="replaced", value1=r3, value2=0.9, in1=f(0.6), in2=f(1.0))
    boards = g.multiply(C, name="boards", in1=planked, in2=replaced)
    # Gaps and eased edges.
    du = g.multiply(F, name="edge_u", in1=g.min(F, name="edge_u0", in1=lu, in2=inv(g, lu, "lu_inv")),
                    in2=plank_len)
    dv = g.multiply(F, name="edge_v", in1=g.min(F, name="edge_v0", in1=lv, in2=inv(g, lv, "lv_inv")),
                    in2=plank_w)
    edge = g.min(F, name="edge_dist", in1=du, in2=dv)
    gap = ss(g, edge, 0.0015, 0.003, "gap")
    bevel = remap(g, ss(g, edge, 0.0, 0.01, "bevel_s"), 0.0, 1.0, 0.75, 1.0, "bevel")
    gapped = g.mix(C, name="gapped", fg=g.multiply(C, name="beveled", in1=boards, in2=bevel),
                   bg=c3(0.03, 0.02, 0.015), mix=gap)
    # Worn varnish along a path from the front to the back, and in blotches.
    path_d = absv(g, g.subtract(F, name="path_c", in1=u, in2=g.add(
        F, name="path_x", in1=f(2.2), in2=g.multiply(F, name="path_bend", in1=v, in2=0.25))), "path_d")
    path_n = fbm2(g, uv, (1.5, 1.5), 3, "path_n", amplitude=0.35)
    path = inv(g, ss(g, g.add(F, name="path_w", in1=path_d, in2=path_n), 0.2, 0.8, "path_s"), "path")
    blotch = inv(g, ss(g, g.worleynoise2d(F, name="wear_worley", texcoord=g.multiply(
        V2, name="wear_uv", in1=uv, in2=v2(2.5, 3.1)), jitter=0.8), 0.15, 0.4, "blotch_s"), "blotch")
    wear = clamp01(g, g.add(F, name="wear0", in1=g.multiply(F, name="path_k", in1=path, in2=0.7),
                            in2=g.multiply(F, name="blotch_k", in1=blotch, in2=0.4)), "wear")
    wear_g = g.multiply(F, name="wear_gapped", in1=wear, in2=gap)
    faded = hsv_jitter(g, gapped, f(0.5), f(0.0), f(1.0), "faded", hue=0.0, sat=(0.75, 0.75), val=(1.15, 1.15))
    worn = g.mix(C, name="worn", fg=faded, bg=gapped, mix=wear_g)
    scr = scratches(g, grain_uv, (2.0, 45.0), (1.3, 1.9), 0.03, "scratches")
    scratched = g.add(C, name="scratched", in1=worn, in2=g.multiply(F, name="scratch_bright", in1=scr, in2=0.05))
    # Dirt along the walls and in the gaps.
    wall_d = g.min(F, name="wall_d", in1=g.min(F, name="wall_dx", in1=u, in2=g.subtract(
        F, name="wall_dx1", in1=f(2 * RX), in2=u)), in2=g.subtract(F, name="wall_dz", in1=f(2 * RZ), in2=v))
    dirt_n = fbm2(g, uv, (2.0, 2.0), 4, "dirt_n", diminish=0.6)
    wall_dirt = inv(g, ss(g, g.add(F, name="wall_dn", in1=wall_d, in2=g.multiply(
        F, name="wall_dnk", in1=dirt_n, in2=0.2)), 0.0, 0.45, "wall_s"), "wall_dirt")
    dirt = g.max(F, name="dirt", in1=wall_dirt, in2=g.multiply(F, name="gap_dirt", in1=inv(g, bevel, "bevel_inv"),
                                                                in2=2.0))
    dirty = g.mix(C, name="base_uv", fg=c3(0.07, 0.055, 0.04), bg=scratched,
                  mix=g.multiply(F, name="dirt_k", in1=clamp01(g, dirt, "dirt_c"), in2=0.5))
    # Varnish roughness and the coat that wears off.
    rough = clamp01(g, g.add(F, name="rough2", in1=g.add(F, name="rough1", in1=g.add(
        F, name="rough0", in1=f(0.3), in2=g.multiply(F, name="rough_wear", in1=wear_g, in2=0.35)),
        in2=g.multiply(F, name="rough_scr", in1=scr, in2=0.2)), in2=g.multiply(F, name="rough_pore", in1=pores,
                                                                               in2=0.15)), "rough_uv")
    coat = g.multiply(F, name="coat", in1=inv(g, wear_g, "unworn"), in2=gap)
    amount, grime = weathering(g, g.position(V3, name="pos"), "weather", 1.2)
    base, rough = weathered(g, dirty, rough, amount, grime, 0.3, 0.7)
    g.output("base_color", base)
    g.output("roughness", rough)
    g.output("coat", coat)
    return g


# --------------------------------------------------------------------------
# brick: back wall (uv only)
# --------------------------------------------------------------------------

def brick_graph():
    g = mx.Graph("NG_brick", "stretcher bond: jittered mortar, per-brick colour, chipped edges, efflorescence")
    mortar_c = g.param("mortar_color", c3(0.52, 0.5, 0.46), "Mortar")
    length, height = 0.225, 0.075
    uv, u, v = uv_parts(g)
    row_f = g.divide(F, name="row_f", in1=v, in2=height)
    row = g.floor(F, name="row", **{"in": row_f})
    lv = g.subtract(F, name="local_v", in1=row_f, in2=row)
    half = g.multiply(F, name="half_shift", in1=g.modulo(F, name="row_odd", in1=row, in2=2.0), in2=0.5)
    col_f = g.add(F, name="col_f", in1=g.divide(F, name="col_f0", in1=u, in2=length), in2=half)
    col = g.floor(F, name="col", **{"in": col_f})
    lu = g.subtract(F, name="local_u", in1=col_f, in2=col)
    bid = g.combine2(V2, name="brick_id", in1=col, in2=row)
    r1, r2, r3, r4 = [g.cellnoise2d(F, name="brick_rand%d" % i, texcoord=g.add(
        V2, name="brick_key%d" % i, in1=bid, in2=v2(3.0 * i, 17.0 * i))) for i in range(1, 5)]
    # Mortar: distance to the brick's border in metres, its width jittered.
    edge = box_edge_dist(g, lu, lv, "edge01")
    du = g.multiply(F, name="edge_u_m", in1=g.min(F, name="eu", in1=lu, in2=inv(g, lu, "lui")), in2=length)
    dv = g.multiply(F, name="edge_v_m", in1=g.min(F, name="ev", in1=lv, in2=inv(g, lv, "lvi")), in2=height)
    edge_m = g.min(F, name="edge_m", in1=du, in2=dv)
    jitter = g.noise2d(F, name="mortar_jitter", texcoord=g.multiply(V2, name="mj_uv", in1=uv, in2=v2(30.0, 30.0)),
                       amplitude=0.003, pivot=0.006)
    brick_mask = ss(g, edge_m, jitter, g.add(F, name="mortar_hi", in1=jitter, in2=0.004), "brick_mask")
    # Brick colour: a ramp of clays picked per brick, varied, surface noise.
    clay = ramp3(g, r1, c3(0.42, 0.16, 0.09), c3(0.55, 0.24, 0.13), c3(0.62, 0.38, 0.24), "clay")
    varied = hsv_jitter(g, clay, r2, r3, r4, "brick_color", hue=0.02, sat=(0.8, 1.15), val=(0.75, 1.1))
    burnt = g.ifgreater(F, name="burnt", value1=r4, value2=0.88, in1=f(0.55), in2=f(1.0))
    surf = fbm2(g, uv, (25.0, 25.0), 4, "brick_surf")
    speck = inv(g, ss(g, g.worleynoise2d(F, name="speck_d", texcoord=g.multiply(V2, name="speck_uv", in1=uv,
                                                                               in2=v2(60.0, 60.0)), jitter=1.0),
                      0.05, 0.15, "speck_s"), "speck")
    pebbles = crack_lines(g, g.multiply(V2, name="pebble_uv", in1=uv, in2=v2(45.0, 45.0)), "2d", 0.08, "pebbles")
    surf_k = g.multiply(F, name="surf_k", in1=remap(g, surf, -0.5, 0.5, 0.8, 1.12, "surf_gain"),
                        in2=remap(g, speck, 0.0, 1.0, 1.0, 0.6, "speck_gain"))
    bricks = g.multiply(C, name="bricks", in1=g.multiply(C, name="bricks0", in1=varied, in2=burnt), in2=surf_k)
    # Chipped edges show lighter inner clay.
    chip_n = fbm2(g, uv, (18.0, 18.0), 3, "chip_n")
    chips = g.multiply(F, name="chips", in1=edge_wear(g, edge, chip_n, 0.06, "chip_edge"),
                       in2=ss(g, chip_n, 0.0, 0.3, "chip_gate"))
    chipped = g.mix(C, name="chipped", fg=c3(0.7, 0.5, 0.36), bg=bricks, mix=chips)
    # Mortar with sand grain.
    sand = fbm2(g, uv, (60.0, 60.0), 2, "mortar_sand")
    mortar0 = g.multiply(C, name="mortar0", in1=mortar_c, in2=remap(g, sand, -0.5, 0.5, 0.8, 1.1, "sand_gain"))
    mortar = g.multiply(C, name="mortar", in1=mortar0, in2=remap(g, pebbles, 0.0, 1.0, 1.0, 0.75, "pebble_gain"))
    wall = g.mix(C, name="wall", fg=chipped, bg=mortar, mix=brick_mask)
    # Efflorescence: white bloom rising from the floor; grime from the top.
    eff_n = fbm2(g, uv, (1.6, 2.2), 5, "eff_n")
    eff_h = inv(g, ss(g, v, 0.0, 1.1, "eff_h"), "eff_low")
    eff = g.multiply(F, name="eff", in1=ss(g, g.add(F, name="eff_t", in1=eff_n, in2=g.multiply(
        F, name="eff_hk", in1=eff_h, in2=0.6)), 0.35, 0.8, "eff_s"), in2=0.7)
    bloomed = g.mix(C, name="bloomed", fg=c3(0.82, 0.8, 0.76), bg=wall, mix=eff)
    grime_n = fbm2(g, uv, (0.7, 3.0), 4, "grime_n", amplitude=0.4)
    grime = ss(g, g.add(F, name="grime_h", in1=v, in2=grime_n), 1.9, 3.0, "grime")
    base = g.mix(C, name="base_uv", fg=c3(0.1, 0.08, 0.07), bg=bloomed,
                 mix=g.multiply(F, name="grime_k", in1=grime, in2=0.55))
    rough = g.mix(F, name="rough_b", fg=g.add(F, name="rough_brick", in1=f(0.78), in2=g.multiply(
        F, name="rough_surf", in1=surf, in2=0.15)), bg=0.95, mix=brick_mask)
    rough_e = g.add(F, name="rough_eff", in1=rough, in2=g.multiply(F, name="rough_effk", in1=eff, in2=0.1))
    amount, grime = weathering(g, g.position(V3, name="pos"), "weather", 1.0,
                               (c3(0.06, 0.05, 0.045), c3(0.2, 0.2, 0.18), c3(0.12, 0.16, 0.08)))
    base, rough = weathered(g, base, clamp01(g, rough_e, "rough_uv"), amount, grime, 0.5, 0.95)
    g.output("base_color", base)
    g.output("roughness", rough)
    return g


# --------------------------------------------------------------------------
# marble: plinth and ball (position only: a solid texture)
# --------------------------------------------------------------------------

def vein(g, pos, direction, freq, warp, warp_amp, sharp, name):
    """1 - |sin| of a warped plane wave, sharpened: thin veins where it crosses zero."""
    d = g.dotproduct(F, name=name + "_d", in1=pos, in2=v3(*direction))
    phase = g.add(F, name=name + "_ph", in1=g.multiply(F, name=name + "_f", in1=d, in2=freq),
                  in2=g.multiply(F, name=name + "_w", in1=warp, in2=warp_amp))
    s = absv(g, g.sin(F, name=name + "_sin", **{"in": phase}), name + "_abs")
    return g.power(F, name=name, in1=inv(g, s, name + "_inv"), in2=sharp)


def marble_graph():
    g = mx.Graph("NG_marble", "veined marble from the object-space position: warped veins, clouds, specks")
    stone = g.param("stone_color", c3(0.88, 0.87, 0.84), "Stone")
    vein_c = g.param("vein_color", c3(0.2, 0.22, 0.24), "Veins")
    pos = g.position(V3, name="pos")
    warp1 = warped_fbm3(g, pos, 2.2, 8, 0.5, "warp1")
    warp2 = fbm3(g, pos, 5.5, 5, "warp2", offset=(3.1, 7.7, 1.3))
    warp3 = fbm3(g, pos, 1.1, 3, "warp3", offset=(11.0, 2.0, 5.0))
    big = vein(g, pos, (0.8, 0.45, 0.4), 6.0, warp1, 3.5, 18.0, "vein_main")
    small = vein(g, pos, (-0.3, 0.9, 0.3), 17.0, warp2, 2.5, 40.0, "vein_fine")
    branch = vein(g, pos, (0.2, -0.4, 0.9), 9.0, g.add(F, name="warp13", in1=warp1, in2=warp3), 4.0, 28.0,
                  "vein_branch")
    branch_gate = ss(g, warp3, -0.1, 0.25, "branch_gate")
    veins = clamp01(g, g.add(F, name="veins0", in1=big, in2=g.add(
        F, name="veins1", in1=g.multiply(F, name="fine_k", in1=small, in2=0.5),
        in2=g.multiply(F, name="branch_k", in1=branch, in2=branch_gate))), "veins")
    # Clouds: soft colour variation in the stone and in the veins.
    cloud = g.noise3d(F, name="cloud", position=g.multiply(V3, name="cloud_p", in1=pos, in2=3.0),
                      amplitude=0.5, pivot=0.5)
    stone_c = ramp3(g, cloud, c3(0.8, 0.79, 0.76), stone, c3(0.93, 0.9, 0.86), "stone_ramp")
    vein_t = g.noise3d(F, name="vein_tone", position=g.multiply(V3, name="vein_tone_p", in1=pos, in2=4.5),
                       amplitude=0.5, pivot=0.5)
    vein_col = g.mix(C, name="vein_col", fg=c3(0.33, 0.38, 0.34), bg=vein_c, mix=vein_t)
    halo = g.multiply(F, name="halo", in1=ss(g, veins, 0.02, 0.5, "halo_s"), in2=0.25)
    haloed = g.mix(C, name="haloed", fg=c3(0.7, 0.68, 0.62), bg=stone_c, mix=halo)
    veined0 = g.mix(C, name="veined0", fg=vein_col, bg=haloed, mix=veins)
    # A few golden veins across the others (Calacatta oro).
    gold = vein(g, pos, (0.5, 0.2, -0.8), 3.5, g.add(F, name="warp12", in1=warp1, in2=warp2), 3.0, 60.0,
                "vein_gold")
    gold_gate = ss(g, g.noise3d(F, name="gold_gate_n", position=g.multiply(V3, name="gold_gate_p", in1=pos,
                                                                           in2=1.7)), 0.0, 0.3, "gold_gate")
    gold_col = ramp3(g, vein_t, c3(0.55, 0.42, 0.2), c3(0.7, 0.55, 0.3), c3(0.6, 0.5, 0.38), "gold_color")
    veined = g.mix(C, name="veined", fg=gold_col, bg=veined0,
                   mix=g.multiply(F, name="gold_k", in1=gold, in2=gold_gate))
    # Crystals and specks.
    crystal = g.worleynoise3d(F, name="crystal", position=g.multiply(V3, name="crystal_p", in1=pos, in2=24.0),
                              jitter=0.9)
    grains = crack_lines(g, g.multiply(V3, name="grain_p", in1=pos, in2=40.0), "3d", 0.05, "grain_bounds")
    crystal_k = g.multiply(F, name="crystal_k", in1=remap(g, crystal, 0.0, 0.8, 1.04, 0.97, "crystal_gain"),
                           in2=remap(g, grains, 0.0, 1.0, 1.0, 0.93, "grain_gain"))
    speck = ss(g, g.cellnoise3d(F, name="speck_cells", position=g.multiply(V3, name="speck_p", in1=pos,
                                                                          in2=70.0)), 0.95, 1.0, "speck")
    specked = g.mix(C, name="specked", fg=c3(0.15, 0.14, 0.13), bg=g.multiply(
        C, name="crystalled", in1=veined, in2=crystal_k), mix=speck)
    # Dust settles low on the plinth; a warm patina overall.
    y = xtr(g, pos, 1, "height")
    dust_n = fbm3(g, pos, 8.0, 3, "dust_n", offset=(5.0, 5.0, 5.0))
    dust = g.multiply(F, name="dust", in1=inv(g, ss(g, g.add(F, name="dust_h", in1=y, in2=g.multiply(
        F, name="dust_hk", in1=dust_n, in2=0.1)), 0.0, 0.3, "dust_s"), "dust_low"), in2=0.4)
    patina_n = fbm3(g, pos, 1.5, 3, "patina_n", offset=(1.0, 9.0, 4.0))
    patina = g.mix(C, name="patina", fg=c3(0.86, 0.8, 0.68), bg=specked,
                   mix=g.multiply(F, name="patina_k", in1=ss(g, patina_n, 0.0, 0.5, "patina_s"), in2=0.25))
    base = g.mix(C, name="base_color", fg=c3(0.55, 0.5, 0.44), bg=patina, mix=dust)
    # Polish: glossy, duller in the veins, in dust and where the surface is etched.
    etch = fbm3(g, pos, 12.0, 4, "etch", offset=(2.0, 4.0, 8.0), amplitude=0.06)
    r = g.add(F, name="rough_etch", in1=f(0.07), in2=absv(g, etch, "etch_abs"))
    r = g.add(F, name="rough_veins", in1=r, in2=g.multiply(F, name="rough_vk", in1=veins, in2=0.12))
    r = g.add(F, name="rough_dust", in1=r, in2=g.multiply(F, name="rough_dk", in1=dust, in2=0.8))
    g.output("base_color", base)
    g.output("roughness", clamp01(g, r, "roughness"))
    return g


# --------------------------------------------------------------------------
# metal: a painted drum (uv) rusting through (position)
# --------------------------------------------------------------------------

def metal_graph():
    g = mx.Graph("NG_metal", "painted steel drum: stencil band, rims, chips, scratches, drips (uv); rust (position)")
    paint = g.param("paint_color", c3(0.08, 0.26, 0.3), "Paint")
    uv, u, v = uv_parts(g)
    # Paint: brush noise, a yellow band, dark rolled rims.
    brush = fbm2(g, uv, (3.0, 40.0), 3, "brush", amplitude=0.3)
    painted = g.multiply(C, name="painted", in1=paint, in2=remap(g, brush, -0.3, 0.3, 0.9, 1.08, "brush_gain"))
    band = g.multiply(F, name="band", in1=ss(g, v, 0.55, 0.56, "band_lo"), in2=inv(g, ss(
        g, v, 0.69, 0.70, "band_hi0"), "band_hi"))
    banded = g.mix(C, name="banded", fg=c3(0.75, 0.55, 0.08), bg=painted, mix=band)
    rims = [absv(g, g.subtract(F, name="rim_c%d" % i, in1=v, in2=h), "rim_d%d" % i)
            for i, h in enumerate((0.18, 0.82))]
    rim_d = g.min(F, name="rim_d", in1=rims[0], in2=rims[1])
    rim = inv(g, ss(g, rim_d, 0.008, 0.016, "rim_s"), "rim")
    rimmed = g.multiply(C, name="rimmed", in1=banded, in2=remap(g, rim, 0.0, 1.0, 1.0, 0.6, "rim_gain"))
    # Chips: edge wear at the rims and the drum's ends, bare steel showing.
    end_d = g.min(F, name="end_d", in1=v, in2=inv(g, v, "v_inv"))
    wear_d = g.min(F, name="wear_d", in1=g.multiply(F, name="rim_dk", in1=rim_d, in2=2.0), in2=end_d)
    chip_n = fbm2(g, uv, (14.0, 6.0), 4, "chip_n")
    chips = g.multiply(F, name="chips", in1=edge_wear(g, wear_d, chip_n, 0.05, "chip_edge"),
                       in2=ss(g, chip_n, -0.1, 0.2, "chip_gate"))
    scr = scratches(g, uv, (60.0, 2.0), (3.0, 2.0), 0.025, "scratches")
    bare = clamp01(g, g.max(F, name="bare0", in1=chips, in2=scr), "bare")
    # Drips running down from the top rim.
    drip_n = g.noise2d(F, name="drip_n", texcoord=g.multiply(V2, name="drip_uv", in1=uv, in2=v2(70.0, 1.5)))
    drip_len = g.multiply(F, name="drip_len", in1=ss(g, drip_n, 0.1, 0.5, "drip_s"), in2=0.5)
    drips = g.multiply(F, name="drips", in1=ss(g, v, g.subtract(F, name="drip_top", in1=f(1.0), in2=drip_len),
                                               f(1.0), "drip_h"), in2=ss(g, drip_n, 0.05, 0.3, "drip_g"))
    paint_c = g.mix(C, name="paint_color_out", fg=c3(0.2, 0.14, 0.09), bg=rimmed,
                    mix=g.multiply(F, name="drip_k", in1=drips, in2=0.6))
    steel = g.multiply(C, name="steel", in1=c3(0.62, 0.62, 0.6), in2=remap(
        g, fbm2(g, uv, (80.0, 4.0), 2, "steel_n"), -0.5, 0.5, 0.85, 1.05, "steel_gain"))
    blister_d = g.worleynoise2d(F, name="blister_d", texcoord=g.multiply(V2, name="blister_uv", in1=uv,
                                                                         in2=v2(30.0, 12.0)), jitter=0.9)
    blisters = g.multiply(F, name="blisters", in1=inv(g, ss(g, blister_d, 0.1, 0.3, "blister_s"), "blister_in"),
                          in2=ss(g, fbm2(g, uv, (4.0, 2.0), 4, "blister_area"), 0.1, 0.4, "blister_gate"))
    blistered = g.multiply(C, name="blistered", in1=paint_c, in2=remap(g, blisters, 0.0, 1.0, 1.0, 0.7,
                                                                       "blister_gain"))
    surface = g.mix(C, name="surface", fg=steel, bg=blistered, mix=bare)
    # Rust from the position: blotches, heavier low down, a colour ramp of its own.
    pos = g.position(V3, name="pos")
    rust_n = warped_fbm3(g, pos, 3.5, 7, 0.4, "rust_n")
    blot = inv(g, g.worleynoise3d(F, name="rust_worley", position=g.multiply(V3, name="rust_wp", in1=pos,
                                                                             in2=7.0), jitter=0.9), "rust_blot")
    low = inv(g, ss(g, xtr(g, pos, 1, "height"), 0.05, 0.7, "rust_hs"), "rust_low")
    rust_t = g.add(F, name="rust_t", in1=g.add(F, name="rust_t0", in1=rust_n, in2=g.multiply(
        F, name="rust_bk", in1=blot, in2=0.5)), in2=g.multiply(F, name="rust_lk", in1=low, in2=0.45))
    rust_mask = ss(g, rust_t, 0.45, 0.75, "rust_mask")
    rust_tone = fbm3(g, pos, 25.0, 3, "rust_tone", offset=(4.0, 1.0, 7.0), amplitude=0.5)
    rust_col = ramp3(g, remap(g, rust_tone, -0.5, 0.5, 0.0, 1.0, "rust_tone01"), c3(0.18, 0.07, 0.03),
                     c3(0.45, 0.18, 0.06), c3(0.62, 0.33, 0.12), "rust_color")
    pits = ss(g, g.cellnoise3d(F, name="pit_cells", position=g.multiply(V3, name="pit_p", in1=pos, in2=90.0)),
              0.9, 1.0, "pits")
    flakes = crack_lines(g, g.multiply(V3, name="flake_p", in1=pos, in2=18.0), "3d", 0.06, "flakes")
    rust_c = g.multiply(C, name="rust", in1=g.multiply(C, name="rust0", in1=rust_col, in2=remap(
        g, pits, 0.0, 1.0, 1.0, 0.5, "pit_gain")), in2=remap(g, flakes, 0.0, 1.0, 1.0, 0.55, "flake_gain"))
    rust_rough = g.add(F, name="rust_rough", in1=f(0.75), in2=g.multiply(F, name="rust_rk", in1=rust_tone,
                                                                          in2=0.3))
    # Where they meet: rust eats the paint first where it is chipped.
    eaten = g.max(F, name="rust_where", in1=rust_mask, in2=g.multiply(F, name="chip_rust", in1=bare, in2=0.5))
    base = g.mix(C, name="base_color", fg=rust_c, bg=surface, mix=eaten)
    metal = g.multiply(F, name="metalness", in1=bare, in2=inv(g, eaten, "unrusted"))
    paint_rough = g.mix(F, name="paint_rough", fg=0.3, bg=g.add(F, name="paint_r0", in1=f(0.42), in2=g.multiply(
        F, name="brush_rk", in1=brush, in2=0.2)), mix=bare)
    rough = g.mix(F, name="roughness", fg=rust_rough, bg=paint_rough, mix=eaten)
    g.output("base_color", base)
    g.output("metalness", metal)
    g.output("roughness", rough)
    return g


# --------------------------------------------------------------------------
# fabric: ottoman (uv only; each face 0..1, 0.7 m)
# --------------------------------------------------------------------------

def thread_profile(g, x, name):
    """The rounded height of a thread across its width: 1 - (2 frac(x) - 1)^2."""
    t = g.subtract(F, name=name + "_c", in1=g.multiply(F, name=name + "_2", in1=g.modulo(
        F, name=name + "_fr", in1=x, in2=1.0), in2=2.0), in2=1.0)
    return inv(g, g.multiply(F, name=name + "_sq", in1=t, in2=t), name)


def fabric_graph():
    g = mx.Graph("NG_fabric", "tartan twill upholstery: threads, fibres, worn edges, lint and dirt")
    n_threads = 56.0
    uv, u, v = uv_parts(g)
    tu = g.multiply(F, name="thread_u", in1=u, in2=n_threads)
    tv = g.multiply(F, name="thread_v", in1=v, in2=n_threads)
    warp_h = thread_profile(g, tu, "warp_h")
    weft_h = thread_profile(g, tv, "weft_h")
    # Twill: which thread is on top steps along the diagonal.
    step = g.modulo(F, name="twill", in1=g.add(F, name="twill_s", in1=g.floor(F, name="fu", **{"in": tu}),
                                                in2=g.floor(F, name="fv", **{"in": tv})), in2=3.0)
    warp_up = g.ifgreater(F, name="warp_up", value1=step, value2=0.5, in1=f(1.0), in2=f(0.0))
    fibre_u = g.noise2d(F, name="fibre_u", texcoord=g.multiply(V2, name="fibre_uv_u", in1=uv,
                                                               in2=v2(6.0, 240.0)), amplitude=0.5, pivot=0.5)
    fibre_v = g.noise2d(F, name="fibre_v", texcoord=g.multiply(V2, name="fibre_uv_v", in1=uv,
                                                               in2=v2(240.0, 6.0)), amplitude=0.5, pivot=0.5)
    height = g.mix(F, name="weave_h", fg=g.multiply(F, name="warp_hf", in1=warp_h, in2=fibre_u),
                   bg=g.multiply(F, name="weft_hf", in1=weft_h, in2=fibre_v), mix=warp_up)
    # Tartan: stripes of three colours in each direction.
    def sett(x, name):
        s = g.modulo(F, name=name + "_m", in1=g.multiply(F, name=name + "_x", in1=x, in2=5.0), in2=1.0)
        a = g.multiply(F, name=name + "_a", in1=ss(g, s, 0.1, 0.12, name + "_a0"),
                       in2=inv(g, ss(g, s, 0.3, 0.32, name + "_a1i"), name + "_a1"))
        b = g.multiply(F, name=name + "_b", in1=ss(g, s, 0.55, 0.57, name + "_b0"),
                       in2=inv(g, ss(g, s, 0.6, 0.62, name + "_b1i"), name + "_b1"))
        c = g.mix(C, name=name + "_ca", fg=c3(0.08, 0.15, 0.1), bg=c3(0.45, 0.06, 0.05), mix=a)
        return g.mix(C, name=name, fg=c3(0.75, 0.65, 0.3), bg=c, mix=b)
    warp_c = sett(u, "sett_u")
    weft_c = sett(v, "sett_v")
    thread_c = g.mix(C, name="thread_color", fg=warp_c, bg=weft_c, mix=warp_up)
    shaded = g.multiply(C, name="shaded", in1=thread_c, in2=remap(g, height, 0.0, 1.0, 0.45, 1.0, "weave_gain"))
    # Worn, faded edges of the cushion; lint specks; dirt where it is sat on.
    ed = box_edge_dist(g, u, v, "edge")
    wear_n = fbm2(g, uv, (9.0, 9.0), 3, "wear_n")
    worn = g.multiply(F, name="worn", in1=edge_wear(g, ed, wear_n, 0.06, "edge_wear"), in2=0.7)
    faded = hsv_jitter(g, shaded, f(0.5), f(0.0), f(1.0), "faded", hue=0.0, sat=(0.5, 0.5), val=(1.25, 1.25))
    weared = g.mix(C, name="weared", fg=faded, bg=shaded, mix=worn)
    lint = inv(g, ss(g, g.worleynoise2d(F, name="lint_d", texcoord=g.multiply(V2, name="lint_uv", in1=uv,
                                                                             in2=v2(40.0, 40.0)), jitter=1.0),
                     0.02, 0.07, "lint_s"), "lint")
    pill_d = g.worleynoise2d(F, name="pill_d", texcoord=g.multiply(V2, name="pill_uv", in1=uv, in2=v2(25.0, 25.0)),
                             jitter=0.8)
    pills = g.multiply(F, name="pills", in1=inv(g, ss(g, pill_d, 0.05, 0.2, "pill_s"), "pill_in"), in2=worn)
    linted0 = g.mix(C, name="linted0", fg=c3(0.8, 0.78, 0.74), bg=weared, mix=lint)
    linted = g.mix(C, name="linted", fg=g.multiply(C, name="pill_color", in1=thread_c, in2=1.2), bg=linted0,
                   mix=g.multiply(F, name="pill_k", in1=pills, in2=0.6))
    dirt_n = fbm2(g, uv, (2.5, 2.5), 4, "dirt_n", diminish=0.6)
    centre = inv(g, ss(g, ed, 0.1, 0.4, "centre_s"), "not_centre")
    dirt = g.multiply(F, name="dirt", in1=ss(g, dirt_n, 0.05, 0.5, "dirt_s"), in2=inv(g, centre, "centre"))
    base = g.mix(C, name="base_uv", fg=c3(0.1, 0.08, 0.06), bg=linted,
                 mix=g.multiply(F, name="dirt_k", in1=dirt, in2=0.35))
    rough = remap(g, height, 0.0, 1.0, 0.95, 0.7, "rough_uv")
    amount, grime = weathering(g, g.position(V3, name="pos"), "weather", 2.0,
                               (c3(0.08, 0.06, 0.05), c3(0.25, 0.2, 0.16), c3(0.35, 0.3, 0.25)))
    base, rough = weathered(g, base, rough, amount, grime, 0.3, 1.0)
    sheen = g.multiply(C, name="sheen_color", in1=thread_c, in2=remap(g, worn, 0.0, 1.0, 1.0, 1.6, "sheen_gain"))
    g.output("base_color", base)
    g.output("roughness", rough)
    g.output("sheen_color", sheen)
    return g


# --------------------------------------------------------------------------
# Geometry, MTL, camera, lights
# --------------------------------------------------------------------------

def build_geometry():
    obj = geo.Obj()
    cy = RY * 0.5
    obj.begin("floor", "wood")
    obj.quad((0.0, 0.0, 0.0), (RX, 0, 0), (0, 0, -RZ), (2 * RX, 2 * RZ))
    obj.begin("back_wall", "brick")
    obj.quad((0.0, cy, -RZ), (RX, 0, 0), (0, cy, 0), (2 * RX, RY))
    obj.begin("left_wall", "plaster")
    obj.quad((-RX, cy, 0.0), (0, 0, -RZ), (0, cy, 0), (2 * RZ, RY))
    obj.begin("right_wall", "plaster")
    obj.quad((RX, cy, 0.0), (0, 0, RZ), (0, cy, 0), (2 * RZ, RY))
    obj.begin("ceiling", "plaster")
    obj.quad((0.0, RY, 0.0), (RX, 0, 0), (0, 0, RZ), (2 * RX, 2 * RZ))
    geo.build_box(obj, (-1.1, -0.9), 0.9, 18.0, "plinth", "marble")
    geo.build_sphere(obj, (-1.1, 1.18, -0.9), 0.28, 48, 24, "ball", "marble")
    geo.build_cylinder(obj, (1.35, 0.0, -0.9), 0.38, 0.95, 48, "drum", "metal")
    geo.build_box(obj, (-0.05, 0.75), 0.7, -25.0, "ottoman", "fabric")
    return obj


# Fallbacks for renderers that read only the MTL (pmc binds the MaterialX ones).
MTL = """\
# pmc heavy scene materials, generated by scripts/make_heavy_scene.py
# (data/heavy/materials.mtlx holds the procedural networks of the same names)

newmtl plaster
Kd 0.74 0.7 0.62

newmtl wood
Kd 0.45 0.3 0.17

newmtl brick
Kd 0.5 0.25 0.15

newmtl marble
Kd 0.85 0.84 0.8
Ks 0.3 0.3 0.3
Ns 300

newmtl metal
Kd 0.1 0.25 0.28
Ks 0.2 0.2 0.2
Ns 60

newmtl fabric
Kd 0.4 0.08 0.06
"""


def materials_xml():
    graphs = [("plaster", plaster_graph(), {"base_color": "base_color", "specular": 0.4,
                                            "specular_roughness": "roughness"}),
              ("wood", wood_graph(), {"base_color": "base_color", "specular": 0.3, "specular_roughness": "roughness",
                                      "coat": "coat", "coat_roughness": 0.08}),
              ("brick", brick_graph(), {"base_color": "base_color", "specular": 0.25,
                                        "specular_roughness": "roughness"}),
              ("marble", marble_graph(), {"base_color": "base_color", "specular_roughness": "roughness",
                                          "coat": 0.5, "coat_roughness": 0.04}),
              ("metal", metal_graph(), {"base_color": "base_color", "metalness": "metalness",
                                        "specular_roughness": "roughness"}),
              ("fabric", fabric_graph(), {"base_color": "base_color", "specular": 0.2,
                                          "specular_roughness": "roughness", "sheen": 0.7,
                                          "sheen_color": "sheen_color", "sheen_roughness": 0.4})]
    parts = ['<?xml version="1.0"?>',
             "<!-- pmc heavy procedural scene materials, generated by scripts/make_heavy_scene.py - do not edit -->",
             '<materialx version="1.39" colorspace="lin_rec709">']
    for name, graph, inputs in graphs:
        parts += [graph.xml(), mx.material(name, graph, inputs)]
    parts.append("</materialx>")
    return "\n".join(parts) + "\n", [(name, len(graph.nodes)) for name, graph, _ in graphs]


def write_text(path, text):
    with open(path, "w", newline="\n") as fh:
        fh.write(text)


def main(argv=None):
    p = argparse.ArgumentParser(description="Generates the heavy procedural scene (data/heavy).")
    p.add_argument("--out", default=DEFAULT_OUT, metavar="DIR", help="output folder (default data/heavy)")
    out = p.parse_args(argv).out
    os.makedirs(out, exist_ok=True)
    obj = build_geometry()
    tris = geo.verify(obj)
    obj_path = os.path.join(out, "room.obj")
    obj.write(obj_path, "room.mtl")
    with open(obj_path) as fh:  # the builder's first line names the default scene's generator
        body = fh.read().split("\n", 1)[1]
    write_text(obj_path, "# pmc heavy scene, generated by scripts/make_heavy_scene.py - do not edit\n" + body)
    write_text(os.path.join(out, "room.mtl"), MTL)
    write_text(os.path.join(out, "room.camera"), "".join(
        "%s %s\n" % (k, " ".join("%g" % x for x in (v if isinstance(v, tuple) else (v,))))
        for k, v in CAMERA.items()))
    write_text(os.path.join(out, "room.lights.json"), json.dumps(LIGHTS, indent=1) + "\n")
    xml, counts = materials_xml()
    write_text(os.path.join(out, "materials.mtlx"), xml)
    print("wrote %s: %d triangles" % (os.path.relpath(out, os.getcwd()), tris))
    for name, n in counts:
        print("  %-8s %3d nodes as written" % (name, n))
    return 0


if __name__ == "__main__":
    sys.exit(main())
