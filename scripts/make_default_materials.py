#!/usr/bin/env python3
# Generates data/default/materials.mtlx: MaterialX 1.39 networks for pmc's
# default scene (data/default/room.obj, see scripts/make_default_scene.py).
# `usemtl NAME` in the OBJ binds to the surfacematerial NAME here:
#
#   floor     worn oak parquet with a checker inlay border; >100 nodes after
#             pmc's passes, every one of them driven by the UV only (the
#             whole network is cacheable in uv space)
#   walls     painted wainscot below a chair rail, faint damask wallpaper
#             above, aged towards the floor (uv only)
#   box       wooden crate: boards, gaps, a darker frame (uv only)
#   cylinder  glazed hexagonal tiles with grout (uv only)
#   sphere    veined marble from the object-space POSITION (not cacheable in
#             uv space: the pattern is solid, as in MaterialX's
#             standard_surface_marble_solid.mtlx)
#
# `ceiling` and `light` have no entry on purpose: they keep their MTL
# materials (room.mtl), so the MTL path stays exercised next to MaterialX.
#
# Units: floor and wall UVs are metres (the floor's u runs along +x and v
# away from the camera, -z; wall v runs up). Box faces are 0..1 per face
# (0.9 m), sphere and cylinder u run around the object, v up.
#
# The file is generated rather than hand-written so that the large floor
# network stays readable here; the output is deterministic and committed.
# Standard library only. Run from anywhere:
#   python3 scripts/make_default_materials.py

import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "data", "default", "materials.mtlx")


# --------------------------------------------------------------------------
# A small builder for MaterialX nodegraphs
# --------------------------------------------------------------------------

class Typed:
    """A constant with an explicit MaterialX type."""

    def __init__(self, type_, value):
        self.type = type_
        self.value = value


def v2(x, y):
    return Typed("vector2", (x, y))


def v3(x, y, z):
    return Typed("vector3", (x, y, z))


def c3(r, g, b):
    return Typed("color3", (r, g, b))


def integer(i):
    return Typed("integer", (i,))


def boolean(b):
    return Typed("boolean", b)


def filename(path, colorspace=None):
    t = Typed("filename", path)
    t.colorspace = colorspace
    return t


class Ref:
    """A reference to a node of a graph (or to an interface input)."""

    def __init__(self, graph, name, type_, interface=False):
        self.graph = graph
        self.name = name
        self.type = type_
        self.interface = interface

    def __mul__(self, k):
        """ref * constant: a multiply node (keeps the scaled terms short)."""
        return self.graph.node("multiply", self.type, in1=self, in2=k)


def fmt_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return "%.6g" % v
    if isinstance(v, str):
        return v
    return ", ".join("%.6g" % x for x in v)


class Graph:
    def __init__(self, name, doc=""):
        self.name = name
        self.doc = doc
        self.interface = []   # (name, type, value, uiname)
        self.nodes = []       # (cat, name, type, [(input, type, attrs)])
        self.outputs = []     # (name, type, node)
        self.names = set()
        self.counter = {}

    def param(self, name, value, uiname=None):
        if not isinstance(value, Typed):
            value = Typed("float", value)
        self.interface.append((name, value.type, fmt_value(value.value), uiname))
        return Ref(self, name, value.type, interface=True)

    def _name(self, cat, name):
        if name is None:
            k = self.counter.get(cat, 0) + 1
            self.counter[cat] = k
            name = "%s%d" % (cat, k)
        assert name not in self.names, name
        self.names.add(name)
        return name

    def node(self, cat, type_, name=None, **inputs):
        name = self._name(cat, name)
        ins = []
        for key, val in inputs.items():
            if val is None:
                continue
            if isinstance(val, Ref):
                if val.interface:
                    ins.append((key, val.type, 'interfacename="%s"' % val.name))
                else:
                    ins.append((key, val.type, 'nodename="%s"' % val.name))
                continue
            if not isinstance(val, Typed):
                if isinstance(val, (int, float)):
                    val = Typed("float", float(val))
                else:
                    raise TypeError("%s.%s: untyped %r" % (name, key, val))
            attrs = 'value="%s"' % fmt_value(val.value)
            cs = getattr(val, "colorspace", None)
            if cs:
                attrs += ' colorspace="%s"' % cs
            ins.append((key, val.type, attrs))
        self.nodes.append((cat, name, type_, ins))
        return Ref(self, name, type_)

    def output(self, name, ref):
        # Outputs share the nodegraph's namespace with its nodes: prefix them.
        self.outputs.append(("out_" + name, ref.type, ref.name))

    # Shorthands for the nodes used most.
    def __getattr__(self, cat):
        # g.mix("color3", fg=..., bg=..., mix=..., name=...) etc.
        if cat.startswith("_"):
            raise AttributeError(cat)

        def make(type_, name=None, **inputs):
            return self.node(cat, type_, name, **inputs)
        return make

    def xml(self):
        out = ['  <nodegraph name="%s">' % self.name]
        if self.doc:
            out.append("    <!-- %s -->" % self.doc)
        for name, type_, value, uiname in self.interface:
            ui = ' uiname="%s"' % uiname if uiname else ""
            out.append('    <input name="%s" type="%s" value="%s"%s />' % (name, type_, value, ui))
        for cat, name, type_, ins in self.nodes:
            if not ins:
                out.append('    <%s name="%s" type="%s" />' % (cat, name, type_))
                continue
            out.append('    <%s name="%s" type="%s">' % (cat, name, type_))
            for key, t, attrs in ins:
                out.append('      <input name="%s" type="%s" %s />' % (key, t, attrs))
            out.append("    </%s>" % cat)
        for name, type_, node in self.outputs:
            out.append('    <output name="%s" type="%s" nodename="%s" />' % (name, type_, node))
        out.append("  </nodegraph>")
        return "\n".join(out)


def material(name, graph, surface_inputs):
    """standard_surface + surfacematerial; surface_inputs maps an input to a
    graph output name (str) or a Typed/float constant."""
    out = ['  <standard_surface name="SR_%s" type="surfaceshader">' % name]
    types = {o[0]: o[1] for o in graph.outputs} if graph else {}
    for key, val in surface_inputs.items():
        if isinstance(val, str):
            out.append('    <input name="%s" type="%s" nodegraph="%s" output="%s" />'
                       % (key, types["out_" + val], graph.name, "out_" + val))
        else:
            if not isinstance(val, Typed):
                val = Typed("float", float(val))
            out.append('    <input name="%s" type="%s" value="%s" />' % (key, val.type, fmt_value(val.value)))
    out.append("  </standard_surface>")
    out.append('  <surfacematerial name="%s" type="material">' % name)
    out.append('    <input name="surfaceshader" type="surfaceshader" nodename="SR_%s" />' % name)
    out.append("  </surfacematerial>")
    return "\n".join(out)


WOOD = "textures/wood.png"
CHECKER = "textures/checker.png"


# --------------------------------------------------------------------------
# floor: worn oak parquet (uv only)
# --------------------------------------------------------------------------

def floor_graph():
    g = Graph("NG_floor", "worn oak planks in a random bond, checker inlay border; uv in metres")
    plank_len = g.param("plank_length", 1.1, "Plank length (m)")
    plank_w = g.param("plank_width", 0.14, "Plank width (m)")
    gap = g.param("gap_width", 0.0025, "Gap half-width (m)")
    varnish_rough = g.param("varnish_roughness", 0.32, "Varnish roughness")

    uv = g.texcoord("vector2", name="uv")
    u = g.extract("float", name="u", **{"in": uv, "index": integer(0)})
    v = g.extract("float", name="v", **{"in": uv, "index": integer(1)})

    # --- plank layout: rows along u, each row shifted by a random amount ---
    row_f = g.divide("float", name="row_f", in1=v, in2=plank_w)
    row = g.floor("float", name="row", **{"in": row_f})
    lv = g.subtract("float", name="local_v", in1=row_f, in2=row)
    row_key = g.combine2("vector2", name="row_key", in1=row, in2=Typed("float", 7.0))
    row_rand = g.cellnoise2d("float", name="row_rand", texcoord=row_key)
    stagger = g.multiply("float", name="stagger", in1=row_rand, in2=plank_len)
    us = g.add("float", name="u_shifted", in1=u, in2=stagger)
    col_f = g.divide("float", name="col_f", in1=us, in2=plank_len)
    col = g.floor("float", name="col", **{"in": col_f})
    lu = g.modulo("float", name="local_u", in1=col_f, in2=1.0)
    plank_id = g.combine2("vector2", name="plank_id", in1=col, in2=row)
    r1 = g.cellnoise2d("float", name="plank_rand1", texcoord=plank_id)
    id2 = g.add("vector2", name="plank_id2", in1=plank_id, in2=v2(17.0, 5.0))
    r2 = g.cellnoise2d("float", name="plank_rand2", texcoord=id2)
    id3 = g.subtract("vector2", name="plank_id3", in1=plank_id, in2=v2(3.0, 29.0))
    r3 = g.cellnoise2d("float", name="plank_rand3", texcoord=id3)
    local = g.combine2("vector2", name="plank_uv", in1=lu, in2=lv)

    # --- wood: the same texture three ways, offset per plank ---
    grain_uv = g.combine2("vector2", name="grain_uv", in1=us, in2=row_f)
    grain_scaled = g.multiply("vector2", name="grain_scaled", in1=grain_uv, in2=v2(0.45, 0.23))
    rand2 = g.combine2("vector2", name="plank_rand12", in1=r1, in2=r2)
    rand_off = g.multiply("vector2", name="plank_offset", in1=rand2, in2=v2(5.0, 3.0))
    wood_uv = g.add("vector2", name="wood_uv", in1=grain_scaled, in2=rand_off)
    wood = g.image("color3", name="wood", file=filename(WOOD, "srgb_texture"), texcoord=wood_uv)
    # A finer, stretched lookup of the same wood for figure (flecks/rays).
    figure = g.tiledimage("color3", name="wood_figure", file=filename(WOOD, "srgb_texture"),
                          texcoord=wood_uv, uvtiling=v2(2.7, 0.37), uvoffset=v2(0.31, 0.77))
    figure_l = g.luminance("color3", name="figure_luma", **{"in": figure})
    figure_f = g.extract("float", name="figure_f", **{"in": figure_l, "index": integer(0)})
    figure_k = g.remap("float", name="figure_gain", **{"in": figure_f, "inlow": 0.12, "inhigh": 0.45,
                                                      "outlow": 1.12, "outhigh": 0.88})
    wood_fig = g.multiply("color3", name="wood_with_figure", in1=wood, in2=figure_k)
    # A large, rotated lookup as slow colour drift across the room.
    drift_uv = g.place2d("vector2", name="drift_uv", texcoord=uv, pivot=v2(2.0, 2.0),
                         scale=v2(3.1, 1.3), rotate=Typed("float", 37.0), offset=v2(0.2, 0.1))
    drift = g.image("float", name="drift", file=filename(WOOD), texcoord=drift_uv)
    drift_k = g.remap("float", name="drift_gain", **{"in": drift, "inlow": 0.2, "inhigh": 0.6,
                                                    "outlow": 0.93, "outhigh": 1.06})
    wood_drift = g.multiply("color3", name="wood_drift", in1=wood_fig, in2=drift_k)

    # --- per-plank hue/saturation/value variation ---
    hsv = g.rgbtohsv("color3", name="wood_hsv", **{"in": wood_drift})
    hue_shift = g.remap("float", name="hue_shift", **{"in": r3, "inlow": 0.0, "inhigh": 1.0,
                                                     "outlow": -0.012, "outhigh": 0.012})
    sat_k = g.remap("float", name="sat_gain", **{"in": r1, "inlow": 0.0, "inhigh": 1.0,
                                                "outlow": 0.85, "outhigh": 1.08})
    val_k = g.remap("float", name="val_gain", **{"in": r2, "inlow": 0.0, "inhigh": 1.0,
                                                "outlow": 0.78, "outhigh": 1.08})
    # A few planks were replaced with darker stock.
    val_dark = g.ifgreater("float", name="val_replaced", value1=r3, value2=0.88,
                           in1=Typed("float", 0.62), in2=val_k)
    hsv_mul = g.combine3("color3", name="hsv_gain", in1=Typed("float", 1.0), in2=sat_k, in3=val_dark)
    hsv_add = g.combine3("color3", name="hsv_bias", in1=hue_shift, in2=Typed("float", 0.0),
                         in3=Typed("float", 0.0))
    hsv2 = g.multiply("color3", name="wood_hsv_scaled", in1=hsv, in2=hsv_mul)
    hsv3 = g.add("color3", name="wood_hsv_shifted", in1=hsv2, in2=hsv_add)
    plank_color = g.hsvtorgb("color3", name="plank_color", **{"in": hsv3})
    # Light falls off towards one long edge of each plank (old, cupped planks).
    cup = g.ramptb("float", name="cupping", valuet=0.94, valueb=1.03, texcoord=local)
    end_split = g.splitlr("float", name="end_tone", valuel=0.97, valuer=1.0, center=0.04, texcoord=local)
    tone = g.multiply("float", name="plank_tone", in1=cup, in2=end_split)
    plank_toned = g.multiply("color3", name="plank_toned", in1=plank_color, in2=tone)

    # --- gaps between planks and eased edges ---
    lu_inv = g.invert("float", name="local_u_inv", **{"in": lu})
    du = g.min("float", name="edge_u", in1=lu, in2=lu_inv)
    du_m = g.multiply("float", name="edge_u_m", in1=du, in2=plank_len)
    lv_inv = g.invert("float", name="local_v_inv", **{"in": lv})
    dv = g.min("float", name="edge_v", in1=lv, in2=lv_inv)
    dv_m = g.multiply("float", name="edge_v_m", in1=dv, in2=plank_w)
    edge = g.min("float", name="edge_dist", in1=du_m, in2=dv_m)
    gap_hi = g.multiply("float", name="gap_outer", in1=gap, in2=1.8)
    gap_mask = g.smoothstep("float", name="gap_mask", **{"in": edge, "low": gap, "high": gap_hi})
    bevel = g.smoothstep("float", name="bevel", **{"in": edge, "low": 0.0, "high": 0.012})
    bevel_k = g.remap("float", name="bevel_gain", **{"in": bevel, "inlow": 0.0, "inhigh": 1.0,
                                                    "outlow": 0.7, "outhigh": 1.0})
    gap_color = c3(0.035, 0.025, 0.018)
    beveled = g.multiply("color3", name="beveled", in1=plank_toned, in2=bevel_k)
    with_gaps = g.mix("color3", name="with_gaps", fg=beveled, bg=gap_color, mix=gap_mask)

    # --- wear: worn-through varnish along a walking path and in blotches ---
    wear_cells = g.multiply("vector2", name="wear_uv", in1=uv, in2=v2(2.2, 2.9))
    wear_w = g.worleynoise2d("float", name="wear_worley", texcoord=wear_cells, jitter=0.85)
    wear_blotch = g.smoothstep("float", name="wear_blotch", **{"in": wear_w, "low": 0.18, "high": 0.42})
    wear_blotch_i = g.invert("float", name="wear_blotch_inv", **{"in": wear_blotch})
    wear_fbm = g.fractal2d("float", name="wear_fbm", texcoord=uv, octaves=integer(4),
                           lacunarity=2.17, diminish=0.55, amplitude=1.4)
    # A diagonal walking path from the front left to the back right.
    path_d = g.dotproduct("float", name="path_d", in1=uv, in2=v2(0.7071, -0.7071))
    path_c = g.subtract("float", name="path_centered", in1=path_d, in2=-0.1)
    path_a = g.absval("float", name="path_abs", **{"in": path_c})
    path_fb = g.add("float", name="path_wobble", in1=path_a, in2=wear_fbm * 0.25)
    # MaterialX smoothstep needs low < high (1 for in >= high), so fall-offs invert it.
    path_out = g.smoothstep("float", name="path_outside", **{"in": path_fb, "low": 0.35, "high": 0.9})
    path = g.invert("float", name="path", **{"in": path_out})
    wear_sum = g.add("float", name="wear_sum", in1=path * 0.75, in2=wear_blotch_i * 0.55)
    wear_n = g.noise2d("float", name="wear_grain", texcoord=g.multiply("vector2", name="wear_grain_uv",
                                                                       in1=uv, in2=v2(41.0, 7.0)),
                       amplitude=0.35, pivot=0.0)
    wear_raw = g.add("float", name="wear_raw", in1=wear_sum, in2=wear_n)
    wear = g.clamp("float", name="wear", **{"in": wear_raw, "low": 0.0, "high": 1.0})
    worn_hsv = g.rgbtohsv("color3", name="worn_hsv", **{"in": with_gaps})
    worn_hsv2 = g.multiply("color3", name="worn_hsv_faded", in1=worn_hsv, in2=c3(1.0, 0.8, 1.12))
    worn_rgb = g.hsvtorgb("color3", name="worn_color", **{"in": worn_hsv2})
    wear_mix = g.multiply("float", name="wear_amount", in1=wear, in2=gap_mask)
    worn = g.mix("color3", name="worn", fg=worn_rgb, bg=with_gaps, mix=wear_mix)

    # --- scratches: thin streaks along the planks ---
    scr_uv = g.multiply("vector2", name="scratch_uv", in1=grain_uv, in2=v2(3.0, 61.0))
    scr_n = g.noise2d("float", name="scratch_noise", texcoord=scr_uv)
    scr_a = g.absval("float", name="scratch_abs", **{"in": scr_n})
    scr_off = g.smoothstep("float", name="scratch_off", **{"in": scr_a, "low": 0.0, "high": 0.035})
    scr = g.invert("float", name="scratch_lines", **{"in": scr_off})
    scr_gate_n = g.noise2d("float", name="scratch_gate", texcoord=g.multiply(
        "vector2", name="scratch_gate_uv", in1=uv, in2=v2(1.7, 2.3)))
    scr_gate = g.smoothstep("float", name="scratch_gate_mask", **{"in": scr_gate_n, "low": 0.05,
                                                                  "high": 0.35})
    scratches = g.multiply("float", name="scratches", in1=scr, in2=scr_gate)
    scratched = g.add("color3", name="scratched", in1=worn,
                      in2=g.multiply("float", name="scratch_bright", in1=scratches, in2=0.06))

    # --- dirt: in the gaps, towards the walls, in smears ---
    dirt_uv = g.place2d("vector2", name="dirt_uv", texcoord=uv, pivot=v2(2.0, 2.0), scale=v2(0.9, 0.45),
                        rotate=Typed("float", -23.0))
    dirt_f = g.fractal2d("float", name="dirt_fbm", texcoord=dirt_uv, octaves=integer(5),
                         lacunarity=1.93, diminish=0.6)
    dirt_s = g.smoothstep("float", name="dirt_smear", **{"in": dirt_f, "low": 0.05, "high": 0.6})
    quarter = g.multiply("vector2", name="room_uv", in1=uv, in2=0.25)
    corner = g.ramp4("float", name="room_dirt", valuetl=0.9, valuetr=0.7, valuebl=0.15,
                     valuebr=0.25, texcoord=quarter)
    wall_x = g.absval("float", name="wall_x", **{"in": g.subtract("float", name="u_centered",
                                                                  in1=u, in2=2.0)})
    wall_dist = g.subtract("float", name="wall_dist", in1=2.0, in2=wall_x)
    wall_clean = g.smoothstep("float", name="wall_clean", **{"in": wall_dist, "low": 0.05, "high": 0.45})
    wall_dirt = g.invert("float", name="wall_dirt", **{"in": wall_clean})
    dirt_a = g.multiply("float", name="dirt_area", in1=dirt_s, in2=corner)
    dirt_b = g.max("float", name="dirt_total", in1=dirt_a, in2=wall_dirt * 0.6)
    gap_dirt = g.invert("float", name="gap_dirt", **{"in": bevel})
    dirt = g.max("float", name="dirt", in1=dirt_b, in2=gap_dirt * 0.8)
    dirt_k = g.multiply("float", name="dirt_amount", in1=dirt, in2=0.42)
    dirty = g.mix("color3", name="dirty", fg=c3(0.09, 0.075, 0.06), bg=scratched, mix=dirt_k)

    # --- a few water rings (stains) ---
    st_uv = g.multiply("vector2", name="stain_uv", in1=uv, in2=1.6)
    st_d = g.worleynoise2d("float", name="stain_dist", texcoord=st_uv, jitter=0.6)
    st_in = g.smoothstep("float", name="stain_in", **{"in": st_d, "low": 0.19, "high": 0.22})
    st_out = g.smoothstep("float", name="stain_out", **{"in": st_d, "low": 0.24, "high": 0.27})
    ring = g.subtract("float", name="stain_ring", in1=st_in, in2=st_out)
    st_pick = g.cellnoise2d("float", name="stain_pick", texcoord=g.add(
        "vector2", name="stain_cell", in1=st_uv, in2=v2(0.5, 0.5)))
    st_on = g.ifgreatereq("float", name="stain_on", value1=st_pick, value2=0.75, in1=ring,
                          in2=Typed("float", 0.0))
    stained = g.multiply("color3", name="stained", in1=dirty,
                         in2=g.remap("float", name="stain_gain", **{"in": st_on, "inlow": 0.0,
                                                                   "inhigh": 1.0, "outlow": 1.0,
                                                                   "outhigh": 0.72}))

    # --- border: plain frame at the walls, checker inlay inside it ---
    left = g.splitlr("float", name="border_l", valuel=1.0, valuer=0.0, center=0.42, texcoord=uv)
    right = g.splitlr("float", name="border_r", valuel=0.0, valuer=1.0, center=3.58, texcoord=uv)
    back = g.splittb("float", name="border_b", valuet=1.0, valueb=0.0, center=3.58, texcoord=uv)
    border = g.max("float", name="border", in1=g.max("float", name="border_lr", in1=left, in2=right),
                   in2=back)
    inner_l = g.splitlr("float", name="frame_l", valuel=1.0, valuer=0.0, center=0.17, texcoord=uv)
    inner_r = g.splitlr("float", name="frame_r", valuel=0.0, valuer=1.0, center=3.83, texcoord=uv)
    inner_b = g.splittb("float", name="frame_b", valuet=1.0, valueb=0.0, center=3.83, texcoord=uv)
    frame = g.max("float", name="frame", in1=g.max("float", name="frame_lr", in1=inner_l, in2=inner_r),
                  in2=inner_b)
    inlay = g.tiledimage("color3", name="inlay", file=filename(CHECKER, "srgb_texture"), texcoord=uv,
                         uvtiling=v2(2.0, 2.0), uvoffset=v2(0.125, 0.125))
    inlay_w = g.multiply("color3", name="inlay_warm", in1=inlay, in2=c3(0.95, 0.74, 0.5))
    frame_wood = g.multiply("color3", name="frame_wood", in1=g.image(
        "color3", name="frame_grain", file=filename(WOOD, "srgb_texture"),
        texcoord=g.combine2("vector2", name="frame_grain_uv", in1=v, in2=u)),
        in2=c3(0.62, 0.5, 0.42))
    border_c = g.mix("color3", name="border_color", fg=frame_wood, bg=inlay_w, mix=frame)
    border_aged = g.mix("color3", name="border_aged", fg=c3(0.1, 0.08, 0.06), bg=border_c,
                        mix=g.multiply("float", name="border_dirt", in1=dirt_s, in2=0.25))
    base_color = g.mix("color3", name="base_color", fg=border_aged, bg=stained, mix=border)

    # --- roughness ---
    rough_n = g.fractal2d("float", name="rough_fbm", texcoord=g.multiply(
        "vector2", name="rough_uv", in1=uv, in2=v2(6.0, 9.0)), octaves=integer(3), amplitude=0.06)
    r_a = g.add("float", name="rough_varnish", in1=varnish_rough, in2=rough_n)
    r_b = g.add("float", name="rough_wear", in1=r_a, in2=wear_mix * 0.33)
    r_c = g.add("float", name="rough_scratch", in1=r_b, in2=scratches * 0.25)
    r_d = g.add("float", name="rough_dirt", in1=r_c, in2=dirt_k * 0.5)
    r_e = g.mix("float", name="rough_gap", fg=r_d, bg=0.9, mix=gap_mask)
    r_border = g.mix("float", name="rough_border", fg=0.42, bg=r_e, mix=border)
    roughness = g.clamp("float", name="roughness", **{"in": r_border, "low": 0.08, "high": 0.95})
    # Varnish reflects less where it is worn or dirty.
    spec = g.remap("float", name="specular", **{"in": g.max("float", name="spec_loss", in1=wear_mix,
                                                           in2=dirt_k),
                                               "inlow": 0.0, "inhigh": 1.0, "outlow": 1.0, "outhigh": 0.45})
    g.output("base_color", base_color)
    g.output("roughness", roughness)
    g.output("specular", spec)
    return g


# --------------------------------------------------------------------------
# walls: wainscot + damask wallpaper (uv only)
# --------------------------------------------------------------------------

def walls_graph():
    g = Graph("NG_walls", "painted wainscot below a rail at 0.9 m, damask wallpaper above; uv in metres")
    paper = g.param("paper_color", c3(0.8, 0.74, 0.62), "Wallpaper")
    paint = g.param("panel_color", c3(0.16, 0.3, 0.27), "Wainscot paint")
    uv = g.texcoord("vector2", name="uv")
    # The shape and line nodes output color3 in MaterialX 1.39 (0 or 1 in every channel).
    damask = g.tiledcloverleafs("color3", name="damask", texcoord=uv, uvtiling=v2(3.0, 3.0), size=0.8,
                                staggered=boolean(True))
    dots = g.tiledcircles("color3", name="dots", texcoord=uv, uvtiling=v2(6.0, 6.0), uvoffset=v2(0.5, 0.25),
                          size=0.18)
    motif = g.extract("float", name="motif", **{"in": g.max("color3", name="motifs", in1=damask, in2=dots),
                                                 "index": integer(0)})
    paper_dark = g.multiply("color3", name="paper_print", in1=paper, in2=c3(0.86, 0.86, 0.89))
    paper_c = g.mix("color3", name="paper", fg=paper_dark, bg=paper, mix=motif)
    mottle = g.fractal2d("float", name="mottle", texcoord=g.multiply("vector2", name="mottle_uv", in1=uv,
                                                                     in2=v2(2.5, 2.5)),
                         octaves=integer(4), amplitude=0.05)
    paper_m = g.add("color3", name="paper_mottled", in1=paper_c, in2=mottle)
    panel_n = g.noise2d("float", name="brush", texcoord=g.multiply("vector2", name="brush_uv", in1=uv,
                                                                   in2=v2(3.0, 90.0)),
                        amplitude=0.025, pivot=1.0)
    panel = g.multiply("color3", name="panel", in1=paint, in2=panel_n)
    rail = g.splittb("color3", name="wainscot", valuet=paper_m, valueb=panel, center=0.9, texcoord=uv)
    v = g.extract("float", name="v", **{"in": uv, "index": integer(1)})
    rail_d = g.absval("float", name="rail_d", **{"in": g.subtract("float", name="rail_off", in1=v,
                                                                  in2=0.92)})
    off_rail = g.smoothstep("float", name="off_rail", **{"in": rail_d, "low": 0.025, "high": 0.035})
    railed = g.mix("color3", name="railed", fg=rail, bg=c3(0.82, 0.8, 0.74), mix=off_rail)
    grime = g.ramptb("float", name="grime_height", valuet=0.0, valueb=0.5,
                     texcoord=g.multiply("vector2", name="wall_uv01", in1=uv, in2=v2(0.25, 0.333)))
    grime_n = g.fractal2d("float", name="grime_fbm", texcoord=uv, octaves=integer(3), lacunarity=2.3)
    grime_k = g.clamp("float", name="grime", **{"in": g.multiply("float", name="grime_raw", in1=grime,
                                                                in2=g.add("float", name="grime_var",
                                                                          in1=grime_n, in2=0.6)),
                                               "low": 0.0, "high": 0.5})
    base = g.mix("color3", name="base_color", fg=c3(0.3, 0.27, 0.22), bg=railed, mix=grime_k)
    rough = g.mix("float", name="roughness", fg=0.35, bg=0.75, mix=g.splittb(
        "float", name="gloss_paint", valuet=0.0, valueb=1.0, center=0.9, texcoord=uv))
    g.output("base_color", base)
    g.output("roughness", rough)
    return g


# --------------------------------------------------------------------------
# box: wooden crate (uv only; each face 0..1)
# --------------------------------------------------------------------------

def box_graph():
    g = Graph("NG_box", "crate: four boards per face inside a frame; uv 0..1 per face")
    uv = g.texcoord("vector2", name="uv")
    u = g.extract("float", name="u", **{"in": uv, "index": integer(0)})
    v = g.extract("float", name="v", **{"in": uv, "index": integer(1)})
    board_f = g.multiply("float", name="board_f", in1=v, in2=4.0)
    board = g.floor("float", name="board", **{"in": board_f})
    board_r = g.cellnoise2d("float", name="board_rand", texcoord=g.combine2(
        "vector2", name="board_key", in1=board, in2=Typed("float", 3.0)))
    wood_uv = g.combine2("vector2", name="wood_uv", in1=g.multiply("float", name="wood_s", in1=u, in2=0.3),
                         in2=g.add("float", name="wood_t", in1=g.multiply("float", name="board_t",
                                                                          in1=v, in2=1.1),
                                   in2=board_r))
    wood = g.image("color3", name="wood", file=filename(WOOD, "srgb_texture"), texcoord=wood_uv)
    tint = g.remap("float", name="board_tint", **{"in": board_r, "outlow": 0.8, "outhigh": 1.1})
    boards = g.multiply("color3", name="boards", in1=wood, in2=tint)
    gaps = g.extract("float", name="gaps", **{"in": g.grid("color3", name="grid", texcoord=uv,
                                                          uvtiling=v2(1.0, 4.0), thickness=0.035),
                                             "index": integer(0)})
    frame_u = g.absval("float", name="frame_u", **{"in": g.subtract("float", name="u_c", in1=u, in2=0.5)})
    frame_v = g.absval("float", name="frame_v", **{"in": g.subtract("float", name="v_c", in1=v, in2=0.5)})
    frame_d = g.max("float", name="frame_d", in1=frame_u, in2=frame_v)
    frame = g.ifgreater("float", name="frame", value1=frame_d, value2=0.41, in1=Typed("float", 1.0),
                        in2=Typed("float", 0.0))
    frame_wood = g.tiledimage("color3", name="frame_wood", file=filename(WOOD, "srgb_texture"),
                              texcoord=g.combine2("vector2", name="uv_vu", in1=v, in2=u),
                              uvtiling=v2(0.6, 0.9), uvoffset=v2(0.4, 0.0))
    frame_c = g.multiply("color3", name="frame_color", in1=frame_wood, in2=c3(0.55, 0.45, 0.4))
    gapped = g.mix("color3", name="gapped", fg=c3(0.04, 0.03, 0.02), bg=boards, mix=gaps)
    framed = g.mix("color3", name="framed", fg=frame_c, bg=gapped, mix=frame)
    edge = g.smoothstep("float", name="edge_wear", **{"in": frame_d, "low": 0.47, "high": 0.5})
    base = g.mix("color3", name="base_color", fg=c3(0.62, 0.5, 0.36), bg=framed, mix=edge)
    luma = g.extract("float", name="wood_luma_f", **{"in": g.luminance("color3", name="wood_luma",
                                                                        **{"in": wood}),
                                                      "index": integer(0)})
    rough = g.remap("float", name="roughness", **{"in": luma, "outlow": 0.75, "outhigh": 0.5})
    g.output("base_color", base)
    g.output("roughness", rough)
    return g


# --------------------------------------------------------------------------
# cylinder: glazed hexagon tiles (uv only)
# --------------------------------------------------------------------------

def cylinder_graph():
    g = Graph("NG_cylinder", "glazed hexagonal tiles with grout; u around (1.9 m), v up (1.4 m)")
    uv = g.texcoord("vector2", name="uv")
    tiling = v2(24.0, 10.0)
    hexes = g.extract("float", name="hexes", **{"in": g.tiledhexagons(
        "color3", name="hexagons", texcoord=uv, uvtiling=tiling, size=0.92, staggered=boolean(True)),
        "index": integer(0)})
    glaze_n = g.fractal2d("float", name="glaze_var", texcoord=g.multiply("vector2", name="glaze_uv",
                                                                         in1=uv, in2=v2(9.0, 7.0)),
                          octaves=integer(3))
    glaze_k = g.remap("float", name="glaze_mix", **{"in": glaze_n, "inlow": -0.5, "inhigh": 0.5})
    glaze = g.mix("color3", name="glaze", fg=c3(0.05, 0.22, 0.42), bg=c3(0.12, 0.36, 0.55),
                  mix=g.clamp("float", name="glaze_t", **{"in": glaze_k}))
    band = g.ramptb("color3", name="band", valuet=c3(0.9, 0.95, 1.0), valueb=c3(1.05, 1.0, 0.95),
                    texcoord=uv)
    tiles = g.multiply("color3", name="tiles", in1=glaze, in2=band)
    base = g.mix("color3", name="base_color", fg=tiles, bg=c3(0.6, 0.58, 0.54), mix=hexes)
    rough = g.mix("float", name="roughness", fg=0.12, bg=0.8, mix=hexes)
    g.output("base_color", base)
    g.output("roughness", rough)
    return g


# --------------------------------------------------------------------------
# sphere: solid marble from the position (not uv)
# --------------------------------------------------------------------------

def sphere_graph():
    g = Graph("NG_sphere", "veined marble from the object-space position (solid texture)")
    c1 = g.param("color_1", c3(0.86, 0.85, 0.82), "Stone")
    c2 = g.param("color_2", c3(0.16, 0.17, 0.22), "Veins")
    pos = g.position("vector3", name="pos")
    d = g.dotproduct("float", name="along", in1=pos, in2=v3(1.0, 0.6, 0.35))
    d_s = g.multiply("float", name="along_scaled", in1=d, in2=7.0)
    p_s = g.multiply("vector3", name="pos_scaled", in1=pos, in2=3.5)
    n = g.fractal3d("float", name="turbulence", position=p_s, octaves=integer(5))
    s = g.sin("float", name="veins_sin", **{"in": g.add("float", name="veins_phase", in1=d_s,
                                                      in2=g.multiply("float", name="turb_scaled",
                                                                     in1=n, in2=4.0))})
    bias = g.remap("float", name="veins_01", **{"in": s, "inlow": -1.0, "inhigh": 1.0})
    veins = g.power("float", name="veins", in1=bias, in2=12.0)
    col = g.mix("color3", name="base_color", fg=c2, bg=c1, mix=veins)
    g.output("base_color", col)
    return g


def main():
    floor = floor_graph()
    walls = walls_graph()
    box = box_graph()
    cyl = cylinder_graph()
    sph = sphere_graph()
    parts = [
        '<?xml version="1.0"?>',
        "<!-- pmc default scene materials, generated by scripts/make_default_materials.py"
        " - do not edit -->",
        '<materialx version="1.39" colorspace="lin_rec709">',
        floor.xml(),
        material("floor", floor, {"base": 1.0, "base_color": "base_color", "specular": "specular",
                                  "specular_roughness": "roughness"}),
        walls.xml(),
        material("walls", walls, {"base_color": "base_color", "specular": 0.5,
                                  "specular_roughness": "roughness"}),
        box.xml(),
        material("box", box, {"base_color": "base_color", "specular": 0.3,
                               "specular_roughness": "roughness"}),
        cyl.xml(),
        material("cylinder", cyl, {"base_color": "base_color", "specular_roughness": "roughness",
                                   "coat": 0.6, "coat_roughness": 0.05}),
        sph.xml(),
        material("sphere", sph, {"base_color": "base_color", "specular_roughness": 0.12,
                                 "coat": 1.0, "coat_roughness": 0.03}),
        "</materialx>",
    ]
    with open(OUT, "w", newline="\n") as fh:
        fh.write("\n".join(parts) + "\n")
    print("wrote %s" % os.path.relpath(OUT, os.getcwd()))
    for g in (floor, walls, box, cyl, sph):
        print("  %-12s %3d nodes" % (g.name, len(g.nodes)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
