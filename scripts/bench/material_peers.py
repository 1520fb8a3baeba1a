"""bench.material_peers — pmc's materials against Mitsuba 3's on scenes written
for the purpose (issue 35): roughplastic, roughconductor, dielectric,
roughdielectric, thindielectric and principled, each beside the
standard_surface that means the same thing, and which differences are model
choices. Not a timing benchmark: a comparison of images (render times are
listed for scale).

Needs Mitsuba 3 (PyPI `mitsuba`) in .venv and Debian's libllvm19 for its
llvm_ad_rgb variant; scripts/setup-peers installs both (scripts/setup does
not: pmc's tests do not need them).

    scripts/python -m bench.material_peers                 every material, 128x128, 256 spp
    scripts/python -m bench.material_peers --only glass_pane_thin,conductor_a0.3
    scripts/python -m bench.material_peers --spp 64 --doc -          a quick look
    scripts/python -m bench.material_peers --keep-scenes out/peers-scenes    keep the OBJ/MTLX files
    scripts/python -m bench.material_peers --report-only   the table again from OUT_DIR/results.json

Method (also written into the section):
  scenes    written by this module into a temporary folder (--keep-scenes DIR
            to keep them): one OBJ per shape, read by both renderers (the same
            triangles and vertex normals), and for pmc one OBJ of all of them
            with `usemtl` names bound to a generated MaterialX document of
            standard_surface materials. Constant white environment (pmc
            `--env 1,1,1`, Mitsuba `constant` radiance 1).
              sphere   a unit sphere (96x48 quads, smooth normals) on a grey
                       Lambert floor (albedo 0.5): opaque materials
              glass    the same sphere and floor, an emissive backdrop
                       (radiance 4, black) behind its left half: solid glass
              pane     a 2x2 pane (a quad, or a box 0.1 thick) at an angle in
                       front of an emissive backdrop (radiance 4) covering its
                       left half: thin and solid glass
  camera    pinhole, vertical field of view (pmc's --fov; Mitsuba fov_axis y),
            the same position and target; Mitsuba's film uses a box filter
            (pmc's pixels are box-filtered).
  depth     pmc --max-depth D (surface hits) against Mitsuba's path
            integrator with max_depth D + 1 (Mitsuba counts the camera segment).
  variant   Mitsuba's llvm_ad_rgb (RGB, like pmc), scalar_rgb where LLVM is
            missing.
  metrics   over the object's pixels only (a pixel counts when 4x4 rays
            through it all hit the analytic sphere or pane, eroded by one
            pixel): mean radiance ratio pmc / Mitsuba (all channels), the
            relative RMSE (RMS of pmc - Mitsuba over Mitsuba's mean), and the
            noise floor: the relative RMSE two renders' noise alone would
            give, from Mitsuba's image rendered as two halves with different
            seeds (pmc's noise taken as equal to Mitsuba's). The pane rows also
            give the mean over the part of the pane in front of the backdrop
            and in front of the sky.
  furnace   each opaque material is also rendered on the sphere without
            the floor ("sphere alone"): a convex object under a white sky
            shows its directional albedo E(mu_o) at every pixel, so the mean
            over the sphere is the albedo averaged over the view (1 for a
            lossless white conductor). Times are for the scene with the floor.
"""
import json
import math
import os
import shutil
import sys
import tempfile
import time

from bench import common

PROG = "bench.material_peers"
SECTION = "## Materials against Mitsuba 3 (scripts/bench-material-peers)"

BACKDROP_RADIANCE = 4.0
FLOOR_ALBEDO = 0.5

# Cameras: (from, at, vertical fov in degrees).
CAMERAS = {
    "sphere": ((0.0, 2.0, 5.0), (0.0, 0.9, 0.0), 35.0),
    "glass": ((0.0, 2.0, 5.0), (0.0, 0.9, 0.0), 35.0),
    "pane": ((1.6, 1.6, 4.0), (0.0, 1.0, 0.0), 40.0),
}


def rough(alpha):
    """standard_surface's specular_roughness for a GGX alpha (alpha = r^2)."""
    return math.sqrt(alpha)


# Each material: key, scene, the object's shape ("box" only for the solid pane),
# pmc's standard_surface inputs (besides base 1), Mitsuba's BSDF, a short label.
def materials():
    ss = lambda **kw: kw  # noqa: E731
    grey = lambda v: {"type": "rgb", "value": [v, v, v]}  # noqa: E731
    m = []
    for alpha, kd in ((0.1, 0.5), (0.3, 0.8)):
        m.append(dict(key=f"plastic_a{alpha}_d{kd}", scene="sphere",
                      label=f"roughplastic GGX alpha {alpha}, diffuse {kd}, ior 1.5",
                      pmc=ss(base_color=(kd,) * 3, specular=1.0, specular_IOR=1.5, specular_roughness=rough(alpha)),
                      mi={"type": "roughplastic", "distribution": "ggx", "alpha": alpha, "int_ior": 1.5,
                          "ext_ior": 1.0, "diffuse_reflectance": grey(kd)}))
    for alpha in (0.3, 0.6):
        m.append(dict(key=f"conductor_a{alpha}", scene="sphere",
                      label=f"roughconductor GGX alpha {alpha}, white (material none)",
                      pmc=ss(base_color=(1.0,) * 3, metalness=1.0, specular_roughness=rough(alpha)),
                      mi={"type": "roughconductor", "distribution": "ggx", "alpha": alpha, "material": "none",
                          "specular_reflectance": grey(1.0)}))
    m.append(dict(key="glass_sphere_smooth", scene="glass", label="dielectric, ior 1.5 (solid sphere)",
                  pmc=ss(transmission=1.0, specular_IOR=1.5, specular_roughness=0.0),
                  mi={"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}))
    for alpha in (0.1, 0.3):
        m.append(dict(key=f"glass_sphere_a{alpha}", scene="glass",
                      label=f"roughdielectric GGX alpha {alpha}, ior 1.5 (solid sphere)",
                      pmc=ss(transmission=1.0, specular_IOR=1.5, specular_roughness=rough(alpha)),
                      mi={"type": "roughdielectric", "distribution": "ggx", "alpha": alpha, "int_ior": 1.5,
                          "ext_ior": 1.0}))
    m.append(dict(key="glass_pane_solid", scene="pane", shape="box", label="dielectric, ior 1.5 (pane 0.1 thick)",
                  pmc=ss(transmission=1.0, specular_IOR=1.5, specular_roughness=0.0),
                  mi={"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}))
    m.append(dict(key="glass_pane_thin", scene="pane", label="thindielectric, ior 1.5 (one quad) vs thin_walled",
                  pmc=ss(transmission=1.0, specular_IOR=1.5, specular_roughness=0.0, thin_walled=True),
                  mi={"type": "thindielectric", "int_ior": 1.5, "ext_ior": 1.0}))
    principled = lambda **kw: {"type": "principled", "roughness": 0.3, "specular": 0.5, "spec_tint": 0.0,  # noqa
                               "sheen_tint": 0.0, **kw}
    m.append(dict(key="principled_dielectric", scene="sphere", label="principled metallic 0, roughness 0.3, grey 0.5",
                  pmc=ss(base_color=(0.5,) * 3, specular=1.0, specular_IOR=1.5, specular_roughness=0.3),
                  mi=principled(base_color=grey(0.5), metallic=0.0)))
    gold = (0.9, 0.6, 0.3)
    m.append(dict(key="principled_metal", scene="sphere", label="principled metallic 1, roughness 0.3, (0.9, 0.6, 0.3)",
                  pmc=ss(base_color=gold, metalness=1.0, specular_roughness=0.3),
                  mi=principled(base_color={"type": "rgb", "value": list(gold)}, metallic=1.0)))
    m.append(dict(key="principled_clearcoat", scene="sphere",
                  label="principled metallic 0, roughness 0.3, grey 0.5, clearcoat 1, clearcoat_gloss 1",
                  pmc=ss(base_color=(0.5,) * 3, specular=1.0, specular_IOR=1.5, specular_roughness=0.3, coat=1.0,
                         coat_IOR=1.5, coat_roughness=math.sqrt(0.001)),
                  mi=principled(base_color=grey(0.5), metallic=0.0, clearcoat=1.0, clearcoat_gloss=1.0)))
    m.append(dict(key="principled_sheen", scene="sphere",
                  label="principled metallic 0, roughness 0.3, grey 0.5, sheen 1 (white)",
                  pmc=ss(base_color=(0.5,) * 3, specular=1.0, specular_IOR=1.5, specular_roughness=0.3, sheen=1.0,
                         sheen_color=(1.0,) * 3, sheen_roughness=0.3),
                  mi=principled(base_color=grey(0.5), metallic=0.0, sheen=1.0)))
    return m


def parse(argv=None):
    p = common.make_parser("material_peers", __doc__)
    common.add_pmc(p)
    common.add_image_size(p, 128, 128, 256)
    p.add_argument("--max-depth", type=common.positive_int, default=16, metavar="D",
                   help="pmc's --max-depth (surface hits); Mitsuba gets max_depth D + 1 (default 16)")
    p.add_argument("--variant", default="llvm_ad_rgb", metavar="NAME",
                   help="Mitsuba variant (default llvm_ad_rgb; scalar_rgb is used when it cannot be set)")
    p.add_argument("--only", type=lambda s: [k for k in s.split(",") if k], default=None, metavar="KEYS",
                   help="comma-separated material keys (default: all: " + ", ".join(m["key"] for m in materials()) + ")")
    p.add_argument("--keep-scenes", metavar="DIR", default=None,
                   help="write the scenes here and keep them (default: a temporary folder, removed afterwards)")
    common.add_out_dir(p, "out/bench-material-peers", "EXR images of both renderers, logs, results.json")
    common.add_doc(p)
    common.add_report_only(p)
    a = common.parse_args(p, "material_peers", None, argv)
    known = {m["key"] for m in materials()}
    for k in a.only or []:
        if k not in known:
            p.error(f"--only: unknown material '{k}' (known: {', '.join(sorted(known))})")
    return a


# ---- geometry ----------------------------------------------------------------------
class Mesh:
    def __init__(self):
        self.v, self.n, self.f = [], [], []  # f: triangles of (vertex, normal) index pairs, 0-based

    def quad(self, corners, normal):
        """A planar quad, corners counter-clockwise seen from where `normal` points."""
        base_v, base_n = len(self.v), len(self.n)
        self.v += [tuple(c) for c in corners]
        self.n.append(tuple(normal))
        i = [(base_v + k, base_n) for k in range(4)]
        self.f += [(i[0], i[1], i[2]), (i[0], i[2], i[3])]
        return self

    def obj_text(self, name=None):
        out = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in self.v]
        out += [f"vn {x:.6f} {y:.6f} {z:.6f}" for x, y, z in self.n]
        if name:
            out.append(f"usemtl {name}")
        out += ["f " + " ".join(f"{a + 1}//{b + 1}" for a, b in tri) for tri in self.f]
        return "\n".join(out) + "\n"


def sphere_mesh(center, radius, nu=96, nv=48):
    m = Mesh()
    cx, cy, cz = center
    for j in range(nv + 1):
        th = math.pi * j / nv
        for i in range(nu + 1):
            ph = 2 * math.pi * i / nu
            d = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            m.v.append((cx + radius * d[0], cy + radius * d[1], cz + radius * d[2]))
            m.n.append(d)
    row = nu + 1
    for j in range(nv):
        for i in range(nu):
            a, b, c, d = j * row + i, (j + 1) * row + i, (j + 1) * row + i + 1, j * row + i + 1
            # counter-clockwise seen from outside (theta down, phi turning from +x to -z)
            if j > 0:
                m.f.append(((a, a), (b, b), (d, d)))
            if j < nv - 1:
                m.f.append(((b, b), (c, c), (d, d)))
    return m


def box_mesh(lo, hi):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    m = Mesh()
    m.quad([(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)], (0, 0, 1))
    m.quad([(x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0)], (0, 0, -1))
    m.quad([(x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1)], (1, 0, 0))
    m.quad([(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)], (-1, 0, 0))
    m.quad([(x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (x0, y1, z0)], (0, 1, 0))
    m.quad([(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)], (0, -1, 0))
    return m


SPHERE = ((0.0, 1.0, 0.0), 1.0)
PANE = ((-1.0, 0.0, -0.05), (1.0, 2.0, 0.05))  # the solid pane's box; the thin pane is its z = 0 section


def floor_mesh():
    return Mesh().quad([(-20, 0, 20), (20, 0, 20), (20, 0, -20), (-20, 0, -20)], (0, 1, 0))


def scene_shapes(scene, shape, floor=True):
    """[(name, Mesh, role)] of a scene; role is 'object', 'floor' or 'light'."""
    if scene in ("sphere", "glass"):
        shapes = [("object", sphere_mesh(*SPHERE), "object")] + ([("floor", floor_mesh(), "floor")] if floor else [])
        if scene == "glass":
            shapes.append(("backdrop", Mesh().quad([(-8, 0, -3), (0.3, 0, -3), (0.3, 6, -3), (-8, 6, -3)], (0, 0, 1)),
                           "light"))
        return shapes
    (x0, y0, z0), (x1, y1, z1) = PANE
    pane = box_mesh(PANE[0], PANE[1]) if shape == "box" else \
        Mesh().quad([(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0)], (0, 0, 1))
    backdrop = Mesh().quad([(-6, -2, -2.5), (0.0, -2, -2.5), (0.0, 5, -2.5), (-6, 5, -2.5)], (0, 0, 1))
    return [("object", pane, "object"), ("backdrop", backdrop, "light")]


def mtlx_value(v):
    if isinstance(v, bool):
        return "boolean", "true" if v else "false"
    if isinstance(v, tuple):
        return "color3", ", ".join(f"{c:g}" for c in v)
    return "float", f"{v:g}"


def write_mtlx(path, mats):
    """mats: {name: standard_surface inputs}."""
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n')
        for name, inputs in mats.items():
            f.write(f'  <standard_surface name="SR_{name}" type="surfaceshader">\n')
            for k, v in {"base": 1.0, **inputs}.items():
                t, text = mtlx_value(v)
                f.write(f'    <input name="{k}" type="{t}" value="{text}" />\n')
            f.write("  </standard_surface>\n")
            f.write(f'  <surfacematerial name="{name}" type="material">\n'
                    f'    <input name="surfaceshader" type="surfaceshader" nodename="SR_{name}" />\n'
                    "  </surfacematerial>\n")
        f.write("</materialx>\n")


def write_scene(folder, m, floor=True):
    """Writes m's scene (floor=False: without the floor, prefixed furnace_);
    returns (pmc OBJ, pmc MTLX, [(shape OBJ, role)])."""
    os.makedirs(folder, exist_ok=True)
    shapes = scene_shapes(m["scene"], m.get("shape"), floor)
    if not floor:
        m = dict(m, key="furnace_" + m["key"])
    parts, combined, offset_v, offset_n = [], [], 0, 0
    for name, mesh, role in shapes:
        path = os.path.join(folder, f"{m['key']}.{name}.obj")
        with open(path, "w") as f:
            f.write(mesh.obj_text())
        parts.append((path, role))
        combined.append((name, mesh, offset_v, offset_n))
        offset_v += len(mesh.v)
        offset_n += len(mesh.n)
    obj = os.path.join(folder, f"{m['key']}.pmc.obj")
    with open(obj, "w") as f:
        for _, mesh, _, _ in combined:
            f.write("".join(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in mesh.v))
        for _, mesh, _, _ in combined:
            f.write("".join(f"vn {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in mesh.n))
        for name, mesh, ov, on in combined:
            f.write(f"o {name}\nusemtl {name}\n")
            f.write("".join("f " + " ".join(f"{a + 1 + ov}//{b + 1 + on}" for a, b in tri) + "\n" for tri in mesh.f))
    mtlx = os.path.join(folder, f"{m['key']}.mtlx")
    mats = {"object": m["pmc"]}
    roles = {name: role for name, _, role in shapes}
    if "floor" in roles:
        mats["floor"] = {"base_color": (FLOOR_ALBEDO,) * 3, "specular": 0.0}
    if "backdrop" in roles:
        mats["backdrop"] = {"base_color": (0.0,) * 3, "specular": 0.0, "emission": 1.0,
                            "emission_color": (BACKDROP_RADIANCE,) * 3}
    write_mtlx(mtlx, mats)
    return obj, mtlx, parts


# ---- the object's pixels -----------------------------------------------------------
def camera_rays(camera, w, h, sub=4):
    """Ray directions (h, w, sub*sub, 3) of a pinhole camera with a vertical fov,
    image rows from the top."""
    import numpy as np
    eye, at, fov = np.array(camera[0], float), np.array(camera[1], float), camera[2]
    fwd = at - eye
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    t = math.tan(math.radians(fov) / 2)
    offs = (np.arange(sub) + 0.5) / sub
    xs = (np.arange(w)[:, None] + offs[None, :]).reshape(-1)  # w*sub
    ys = (np.arange(h)[:, None] + offs[None, :]).reshape(-1)
    px = (2 * xs / w - 1) * t * w / h
    py = (1 - 2 * ys / h) * t
    d = fwd[None, None] + px[None, :, None] * right[None, None] + py[:, None, None] * up[None, None]
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    return eye, d  # d: (h*sub, w*sub, 3)


def object_masks(m, camera, w, h, sub=4):
    """(object, over backdrop, over sky) boolean masks (h, w): pixels whose
    sub x sub rays all hit the object (eroded by one pixel); for panes, those
    of them whose straight rays all meet the backdrop's plane left of its
    edge, and those whose rays all pass right of it."""
    import numpy as np
    eye, d = camera_rays(camera, w, h, sub)
    if m["scene"] in ("sphere", "glass"):
        c, r = np.array(SPHERE[0]), SPHERE[1]
        oc = eye - c
        b = d @ oc
        disc = b * b - (oc @ oc - r * r)
        hit = disc > 0
        side = np.zeros_like(hit)
    else:
        (x0, y0, _), (x1, y1, _) = PANE
        tz = (0.0 - eye[2]) / d[..., 2]  # the pane's mid plane z = 0
        p = eye + tz[..., None] * d
        hit = (tz > 0) & (p[..., 0] > x0) & (p[..., 0] < x1) & (p[..., 1] > y0) & (p[..., 1] < y1)
        # where the straight ray meets the backdrop plane (z = -2.5): left of x = 0 is the backdrop
        tb = (-2.5 - eye[2]) / d[..., 2]
        side = (eye[0] + tb * d[..., 0]) < 0.0
    full = hit.reshape(h, sub, w, sub).all(axis=(1, 3))
    left = side.reshape(h, sub, w, sub).all(axis=(1, 3))
    eroded = full.copy()
    eroded[1:] &= full[:-1]
    eroded[:-1] &= full[1:]
    eroded[:, 1:] &= full[:, :-1]
    eroded[:, :-1] &= full[:, 1:]
    return eroded, eroded & left, eroded & ~side.reshape(h, sub, w, sub).any(axis=(1, 3))


# ---- Mitsuba -----------------------------------------------------------------------
def load_mitsuba(variant):
    try:
        import mitsuba as mi
    except ImportError:
        sys.exit(f"{PROG}: Mitsuba 3 is not installed in .venv: run scripts/setup-peers")
    try:
        mi.set_variant(variant)
    except Exception as e:  # no LLVM: the scalar variant needs nothing else
        print(f"{PROG}: Mitsuba variant {variant} unavailable ({str(e).splitlines()[0][:100]}); using scalar_rgb",
              flush=True)
        mi.set_variant("scalar_rgb")
    return mi


def mitsuba_scene(mi, m, parts, camera, a):
    eye, at, fov = camera
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": a.max_depth + 1},
        "sensor": {"type": "perspective", "fov": fov, "fov_axis": "y",
                   "to_world": mi.ScalarTransform4f().look_at(origin=list(eye), target=list(at), up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": a.width, "height": a.height, "pixel_format": "rgb",
                            "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent", "sample_count": a.spp}},
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [1.0, 1.0, 1.0]}},
    }
    black = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.0, 0.0, 0.0]}}
    for i, (path, role) in enumerate(parts):
        shape = {"type": "obj", "filename": path, "face_normals": False}
        if role == "object":
            shape["bsdf"] = m["mi"]
        elif role == "floor":
            shape["bsdf"] = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [FLOOR_ALBEDO] * 3}}
        else:
            shape["bsdf"] = black
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": [BACKDROP_RADIANCE] * 3}}
        scene[f"shape{i}_{role}"] = shape
    return scene


def render_mitsuba(mi, scene_dict, spp):
    """Two halves of spp with different seeds: (mean image, half A, half B, seconds)."""
    import numpy as np
    t0 = time.perf_counter()
    scene = mi.load_dict(scene_dict)
    half = max(1, spp // 2)
    a = np.array(mi.render(scene, spp=half, seed=1), dtype=np.float64)
    b = np.array(mi.render(scene, spp=spp - half if spp > 1 else 1, seed=2), dtype=np.float64)
    return (a + b) / 2, a, b, time.perf_counter() - t0


def read_exr(mi, path):
    import numpy as np
    img = np.array(mi.Bitmap(path), dtype=np.float64)
    return img[..., :3]


def write_exr(mi, path, img):
    import numpy as np
    mi.Bitmap(np.ascontiguousarray(img, dtype=np.float32)).write(path)


# ---- measuring ---------------------------------------------------------------------
def fmt3(v):
    return ",".join(f"{c:g}" for c in v)


def measure(a):
    import numpy as np
    mi = load_mitsuba(a.variant)
    out = os.path.abspath(a.out_dir)
    folder = os.path.abspath(a.keep_scenes) if a.keep_scenes else tempfile.mkdtemp(prefix="pmc-material-peers-")
    log = os.path.join(out, "pmc.log")
    if os.path.exists(log):
        os.remove(log)
    rows, t_start = [], time.perf_counter()
    try:
        for m in materials():
            if a.only and m["key"] not in a.only:
                continue
            camera = CAMERAS[m["scene"]]

            def render_pair(floor=True):
                """pmc's image, Mitsuba's (and its halves), both times; the pmc command."""
                obj, mtlx, parts = write_scene(folder, m, floor)
                key = m["key"] if floor else "furnace_" + m["key"]
                exr = os.path.join(out, f"{key}.pmc.exr")
                cmd = [a.pmc, "render", obj, "-o", exr, "--mtlx", mtlx, "--lights", "none", "--env", "1,1,1",
                       "--camera-from", fmt3(camera[0]), "--camera-at", fmt3(camera[1]), "--fov", f"{camera[2]:g}",
                       "--max-depth", str(a.max_depth), "--cache", "off",
                       *common.size_args(a.width, a.height, a.spp)]
                print(f"{PROG}: {key}: pmc, then Mitsuba ({mi.variant()})", flush=True)
                done = common.run(cmd, log, f"pmc {key}", append=True)
                ref, ha, hb, t_mi = render_mitsuba(mi, mitsuba_scene(mi, m, parts, camera, a), a.spp)
                write_exr(mi, os.path.join(out, f"{key}.mitsuba.exr"), ref)
                return read_exr(mi, exr), ref, ha, hb, done.wall, t_mi, " ".join(cmd)

            row = dict(key=m["key"], label=m["label"], scene=m["scene"])
            try:
                p, ref, ha, hb, t_pmc, t_mi, row["pmc_command"] = render_pair()
                if m["scene"] == "sphere":  # the sphere alone: its directional albedo, averaged over the view
                    fp, fref, _, _, _, _, _ = render_pair(floor=False)
            except common.RunFailed as e:
                rows.append(dict(row, ok=False, error=str(e) + "\n" + e.tail))
                continue
            mask, over_light, over_sky = object_masks(m, camera, a.width, a.height)
            np.save(os.path.join(out, f"{m['key']}.mask.npy"), mask)
            pm, rm = p[mask], ref[mask]
            mean_ref = float(rm.mean())
            row.update(ok=True, pixels=int(mask.sum()), t_pmc=t_pmc, t_mitsuba=t_mi,
                       mean_pmc=float(pm.mean()), mean_mitsuba=mean_ref, ratio=float(pm.mean()) / mean_ref,
                       rel_rmse=float(np.sqrt(((pm - rm) ** 2).mean())) / mean_ref,
                       noise=float(np.sqrt(((ha[mask] - hb[mask]) ** 2).mean() / 2)) / mean_ref,
                       ratio_rgb=[float(pm[:, c].mean() / rm[:, c].mean()) for c in range(3)],
                       image_ratio=float(p.mean() / ref.mean()))
            if m["scene"] == "sphere":
                row.update(furnace_pmc=float(fp[mask].mean()), furnace_mitsuba=float(fref[mask].mean()))
            for name, sub in (("light", over_light), ("sky", over_sky)):
                if m["scene"] == "pane" and sub.any():
                    row[f"{name}_pmc"] = float(p[sub].mean())
                    row[f"{name}_mitsuba"] = float(ref[sub].mean())
                    row[f"{name}_pixels"] = int(sub.sum())
            print(f"{PROG}: {m['key']}: ratio {row['ratio']:.3f}, relRMSE {row['rel_rmse']:.3f} "
                  f"(noise {row['noise']:.3f}), pmc {t_pmc:.1f} s, Mitsuba {t_mi:.1f} s", flush=True)
            rows.append(row)
    finally:
        if not a.keep_scenes:
            shutil.rmtree(folder, ignore_errors=True)
    return dict(rows=rows, command=a.command, now=common.utc_now(), rev=common.git_rev(),
                machine=f"{os.cpu_count()} cores ({common.cpu_model()})", variant=mi.variant(),
                mitsuba=mi.__version__, width=a.width, height=a.height, spp=a.spp, max_depth=a.max_depth,
                elapsed=time.perf_counter() - t_start)


# ---- the report --------------------------------------------------------------------
# What each row's difference is, written after looking at the numbers of the
# run recorded in docs/BENCHMARKS.md (a new run that moves them needs a new look).
NOTES = {
    "plastic_a0.1_d0.5": "model choice. pmc is standard_surface's albedo scaling: Schlick specular (F0 0.04, "
    "multiple-scattering compensated) over Lambert weighted by 1 - E_spec, so the sphere alone shows "
    "0.04 + 0.5 x 0.96 = 0.52 at its centre. Mitsuba's roughplastic sees the diffuse base through the rough "
    "interface (tabulated single-scattering transmittance in and out, / eta^2, internal reflection folded in); "
    "its own BSDF sampling gives a normal-incidence albedo of 0.474 here. pmc is 9% brighter, uniformly "
    "(relative RMSE 0.095 is nearly all the mean).",
    "plastic_a0.3_d0.8": "model choice, and the largest one: pmc 0.81 alone (0.04 + 0.8 x 0.96), Mitsuba's "
    "roughplastic 0.55 (its BSDF sampled at normal incidence: 0.56, only 0.65 of the diffuse 0.8 gets out "
    "through the alpha 0.3 interface). Mitsuba's darkening grows with alpha (0.87 of the diffuse at alpha "
    "0.1); standard_surface's does not depend on the base's roughness beyond 1 - E.",
    "conductor_a0.3": "model choice: multiple-scattering compensation. pmc's white conductor alone reflects "
    "1.000 of the sky (exactly energy-conserving, no gain); Mitsuba's single-scattering GGX 0.843 (0.88 at "
    "the centre, as its E(mu = 1) = 0.877 at alpha 0.3 predicts).",
    "conductor_a0.6": "model choice, as above: pmc 1.000 alone, Mitsuba 0.610 (single-scattering GGX at "
    "alpha 0.6 loses 41% at normal incidence); hence pmc / Mitsuba 1.66 on the floor scene.",
    "glass_sphere_smooth": "agree within noise (+0.4%): exact Fresnel, refraction and radiance / eta^2 in both.",
    "glass_sphere_a0.1": "agree within noise (+0.5%): both are Walter et al.'s single-scattering rough "
    "dielectric.",
    "glass_sphere_a0.3": "agree (+0.9%, relative RMSE 0.091 against a noise floor of 0.084).",
    "glass_pane_solid": "agree: in front of the backdrop 3.759 vs 3.758, which is what an incoherent slab "
    "predicts at this pane's 23 degree incidence (4 (1 - R) / (1 + R) + 2R / (1 + R) = 3.758 with R = 0.042).",
    "glass_pane_thin": "agree in the mean (3.760 vs 3.762 in front of the backdrop): pmc's slab Fresnel "
    "R + T^2 R / (1 - R^2) is Mitsuba's thindielectric. In front of the sky pmc reads 1.009 against 1.002: all "
    "of it in the pixel columns next to the backdrop's edge (up to 1.3 where Mitsuba has 1.0), where pmc "
    "blurs the edge by about a pixel; pmc has no delta lobes (roughness 0 is GGX alpha 0.0014, whose long "
    "tail scatters a few per cent of the light off the straight line), the likely cause, not confirmed.",
    "principled_dielectric": "model choice: Mitsuba's principled is Disney's (Burley diffuse with its "
    "roughness-dependent retro-reflection, not weighted by the specular's 1 - E); pmc's standard_surface "
    "albedo-scales Lambert under the specular. Alone: pmc 0.530, Mitsuba 0.562; pmc 5.7% darker.",
    "principled_metal": "agree within 1.3%: Schlick with F0 = base colour in both; pmc's compensation adds "
    "little at roughness 0.3 (alpha 0.09).",
    "principled_clearcoat": "model choice: the coats add about the same (alone: pmc +0.028 over the uncoated "
    "0.530, Mitsuba +0.021 over 0.562; Disney's GTR1 clearcoat at gloss 1 against pmc's GGX coat of alpha "
    "0.001 with 1 - E_coat taken off the base); the ratio is the base's (0.952 vs 0.943).",
    "principled_sheen": "model choice: pmc's Charlie sheen (roughness 0.3, Neubelt visibility) adds +0.073 "
    "alone over the unsheened 0.530, mostly towards the rim; Disney's sheen ((1 - cos theta_d)^5, white) "
    "adds +0.009. No energy gain: pmc's sphere alone stays at 0.60.",
}


def report(data):
    header = ["material (Mitsuba)", "pixels", "pmc / Mitsuba mean", "per channel", "relative RMSE",
              "noise floor", "sphere alone: pmc", "Mitsuba", "pmc (s)", "Mitsuba (s)"]
    rows = []
    for r in data["rows"]:
        if not r.get("ok"):
            rows.append([f"`{r['key']}`: {r['label']}", "failed: " + r["error"].splitlines()[0]] + [""] * 8)
            continue
        rows.append([f"`{r['key']}`: {r['label']}", str(r["pixels"]), f"**{r['ratio']:.3f}**",
                     "/".join(f"{c:.3f}" for c in r["ratio_rgb"]), f"{r['rel_rmse']:.3f}", f"{r['noise']:.3f}",
                     f"{r['furnace_pmc']:.3f}" if "furnace_pmc" in r else "",
                     f"{r['furnace_mitsuba']:.3f}" if "furnace_mitsuba" in r else "",
                     f"{r['t_pmc']:.1f}", f"{r['t_mitsuba']:.1f}"])
    table = common.md_table(header, rows)
    panes = [r for r in data["rows"] if r.get("ok") and "light_pmc" in r]
    pane_table = ""
    if panes:
        pane_table = "\n\nPanes, mean radiance over the part in front of the backdrop (radiance " \
                     f"{BACKDROP_RADIANCE:g}) and in front of the sky (1):\n\n" + common.md_table(
                         ["pane", "backdrop: pmc", "Mitsuba", "ratio", "sky: pmc", "Mitsuba", "ratio"],
                         [[f"`{r['key']}`", f"{r['light_pmc']:.3f}", f"{r['light_mitsuba']:.3f}",
                           f"{r['light_pmc'] / r['light_mitsuba']:.3f}", f"{r.get('sky_pmc', float('nan')):.3f}",
                           f"{r.get('sky_mitsuba', float('nan')):.3f}",
                           f"{r.get('sky_pmc', float('nan')) / r.get('sky_mitsuba', float('nan')):.3f}"]
                          for r in panes])
    notes = "\n".join(f"- `{k}`: {v}" for k, v in NOTES.items() if any(r["key"] == k for r in data["rows"]))
    method = __doc__.split("Method (also written into the section):\n", 1)[1].rstrip()
    section = (f"{SECTION}\n\n`{data['command']}`\n\n"
               f"{data['now']}, {data['rev']}; {data['machine']}; Mitsuba {data['mitsuba']} ({data['variant']}); "
               f"{data['width']}x{data['height']}, {data['spp']} spp, pmc --max-depth {data['max_depth']} "
               f"(Mitsuba max_depth {data['max_depth'] + 1}); {data['elapsed'] / 60:.1f} minutes. Images: "
               f"`out/bench-material-peers/KEY.{{pmc,mitsuba}}.exr`.\n\n"
               f"{table}{pane_table}\n\n"
               + (f"Which differences are model choices:\n\n{notes}\n\n" if notes else "")
               + f"Method:\n\n```\n{textwrap_dedent(method)}\n```\n")
    return section, table + pane_table


def textwrap_dedent(text):
    import textwrap
    return textwrap.dedent(text)


def main(argv=None):
    a = parse(argv)
    common.measure_and_report(a, PROG, SECTION, measure, report)


if __name__ == "__main__":
    main()
