"""bench.peer_scenes — the scenes bench.peers renders with pmc, Cycles and
Mitsuba 3, and the files each renderer reads.

A scene is an OBJ (or several, merged) from ../shared/scenes or data/, and
small OBJs the spec holds as text ("generated", written into the scene's
folder), a camera, lights in pmc's lights-file form and an environment.
Every material becomes a diffuse stand-in: reflectance Kd x map_Kd
(sRGB-decoded), emission Ke, cut-out map_d. Specular terms (Ks, Ns, Pr,
...) and bump maps are dropped, so the three renderers shade the same BSDF and the comparison measures light
transport and sampling; bench.material_peers compares materials.

write_scene_files(spec, folder) parses the OBJs once (this module's own small
reader: v/vt/vn/f with negative indices, polygons fanned into triangles,
usemtl) and writes, into `folder`:
  scene.obj + scene.mtl   every triangle, grouped by material (pmc and
                          Blender's OBJ importer read these; texture paths
                          absolute)
  part_N.obj              one OBJ per material, re-indexed (Mitsuba's obj
                          plugin reads one material per shape)
  scene.lights.json       pmc's lights file: the lights and the environment
and returns the renderer-neutral job description (a dict, see job_for) that
bench.peer_cycles and bench.peer_mitsuba read.
"""
import json
import math
import os

SHARED = "../shared/scenes"
MANY_LIGHTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data", "default",
                           "many.lights.json")

# A 1 m box 18 m above the default room's roof (y = 3): the stray object of issue 36,
# which grew the scene's bounding sphere and, with the pick by power, gave the
# environment most of the light samples. Written into the scene's folder.
STRAY_BOX = "".join(f"v {x} {y} {z}\n" for x in (-0.5, 0.5) for y in (21.0, 22.0) for z in (-0.5, 0.5)) + \
    "usemtl stray\n" + "".join(f"f {a} {b} {c} {d}\n" for a, b, c, d in (
        (1, 2, 4, 3), (5, 7, 8, 6), (1, 5, 6, 2), (3, 4, 8, 7), (1, 3, 7, 5), (2, 6, 8, 4)))


def _many_lights():
    """The lights and the world colour of data/default/many.lights.json."""
    with open(MANY_LIGHTS) as f:
        d = json.load(f)
    return d["lights"], d["environment"]


# ---- the scenes ----------------------------------------------------------------------
def _scenes():
    """name -> spec. Cameras: pmc's (position, target, vertical field of view
    in degrees, +Y up). Lights: pmc's lights-file entries (README.md, "Lights
    files"); "environment" is a constant radiance or a map."""
    many_lights, world_colour = _many_lights()
    return {
        "cornell": {
            "what": "Embree's Cornell box (front open), a quad light under the ceiling and a point light",
            "objs": [f"{SHARED}/cornell/cornell_box.obj"],
            "camera": ((278.0, 273.0, -800.0), (278.0, 273.0, 0.0), 37.0),
            "lights": [
                {"type": "quad", "corner": [213.0, 548.0, 227.0], "edge_u": [130.0, 0.0, 0.0],
                 "edge_v": [0.0, 0.0, 105.0], "radiance": [20.0, 20.0, 20.0]},
                {"type": "point", "position": [213.0, 300.0, 227.0], "intensity": [40000.0, 40000.0, 40000.0]},
            ],
            "environment": None,
        },
        "sponza": {
            "what": "Crytek Sponza with GPU-Raytracer's roof cover and two emissive icospheres (Ke 12), "
                    "overview camera",
            "objs": [f"{SHARED}/sponza/sponza.obj", f"{SHARED}/sponza/sponza_extras.obj"],
            "camera": ((-110.0, 20.0, 0.0), (100.0, 20.0, 0.0), 55.4),
            "lights": [],
            "environment": None,
        },
        "spider": {
            "what": "assimp's spider under the goegap HDR environment",
            "objs": [f"{SHARED}/spider/spider.obj"],
            "camera": ((90.0, 80.0, 190.0), (-17.0, -2.0, -10.0), 45.0),
            "lights": [],
            "environment": {"map": f"{SHARED}/envmaps/goegap.hdr"},
        },
        "default": {
            "what": "pmc's default room with its MTL stand-ins, the sun disk of sun.lights.json and "
                    "the table_mountain sky",
            "objs": ["data/default/room.obj"],
            "camera": ((0.0, 1.5, 4.6), (0.0, 1.3, 0.0), 45.0),
            "lights": [{"type": "directional", "direction": [-0.5, -0.45, -1.0],
                        "irradiance": [12.0, 11.0, 9.5], "angle_deg": 0.53}],
            "environment": {"map": f"{SHARED}/envmaps/table_mountain.hdr"},
        },
        "interior": {
            "what": "pmc's default room with its MTL stand-ins, the 30 lights of data/default/many.lights.json "
                    "(12 points, 8 spots, 10 quads of which 4 two-sided) and its world colour, and a 1 m box "
                    "18 m above the roof",
            "objs": ["data/default/room.obj"],
            "generated": {"stray.obj": STRAY_BOX},
            "camera": ((0.0, 1.5, 4.6), (0.0, 1.3, 0.0), 45.0),
            "lights": many_lights,
            "environment": world_colour,
        },
    }


SCENES = _scenes()


# ---- reading OBJ and MTL -------------------------------------------------------------
class Mesh:
    """Triangles grouped by material: positions, uvs and normals as read, and
    per material a list of triangles of three (v, vt or -1, vn or -1) corners."""

    def __init__(self):
        self.v, self.vt, self.vn = [], [], []
        self.groups = {}  # material -> [((v, t, n), (v, t, n), (v, t, n)), ...]
        self.mtllibs = []  # absolute MTL paths, in order


def _index(tok, count):
    i = int(tok)
    return i - 1 if i > 0 else count + i


def read_obj(path, mesh):
    """Appends the OBJ at `path` to `mesh` (indices re-based)."""
    v0, t0, n0 = len(mesh.v), len(mesh.vt), len(mesh.vn)
    folder = os.path.dirname(os.path.abspath(path))
    material = "default"
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            key = parts[0]
            if key == "v":
                mesh.v.append(tuple(float(x) for x in parts[1:4]))
            elif key == "vt":
                mesh.vt.append((float(parts[1]), float(parts[2]) if len(parts) > 2 else 0.0))
            elif key == "vn":
                mesh.vn.append(tuple(float(x) for x in parts[1:4]))
            elif key == "usemtl":
                material = parts[1] if len(parts) > 1 else "default"
            elif key == "mtllib":
                lib = os.path.join(folder, " ".join(parts[1:]))
                if lib not in mesh.mtllibs:
                    mesh.mtllibs.append(lib)
            elif key == "f":
                corners = []
                for c in parts[1:]:
                    s = c.split("/")
                    vi = _index(s[0], len(mesh.v) - v0) + v0
                    ti = _index(s[1], len(mesh.vt) - t0) + t0 if len(s) > 1 and s[1] else -1
                    ni = _index(s[2], len(mesh.vn) - n0) + n0 if len(s) > 2 and s[2] else -1
                    corners.append((vi, ti, ni))
                tris = mesh.groups.setdefault(material, [])
                for k in range(1, len(corners) - 1):
                    tris.append((corners[0], corners[k], corners[k + 1]))


def _map_path(folder, parts):
    """The file of a map_* statement (options such as -bm skipped; Windows
    separators and a leading .\\ accepted)."""
    name = parts[-1].replace("\\", "/")
    if name.startswith("./"):
        name = name[2:]
    return os.path.normpath(os.path.join(folder, name))


def read_mtl(path):
    """name -> {"kd", "ke", "map_kd", "map_d"} of the diffuse stand-in."""
    folder = os.path.dirname(os.path.abspath(path))
    out, cur = {}, None
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts or parts[0].startswith("#"):
                continue
            key = parts[0]
            if key == "newmtl":
                cur = out.setdefault(parts[1], {"kd": [0.8, 0.8, 0.8], "ke": [0.0, 0.0, 0.0],
                                                "map_kd": None, "map_d": None})
            elif cur is None:
                continue
            elif key == "Kd":
                cur["kd"] = [float(x) for x in parts[1:4]]
            elif key == "Ke":
                cur["ke"] = [float(x) for x in parts[1:4]]
            elif key == "map_Kd":
                cur["map_kd"] = _map_path(folder, parts)
            elif key == "map_d":
                cur["map_d"] = _map_path(folder, parts)
    return out


# ---- writing the renderers' inputs ---------------------------------------------------
def _fmt(xs):
    return " ".join(f"{x:.9g}" for x in xs)


def _write_mtl(path, materials):
    with open(path, "w") as f:
        f.write("# bench.peer_scenes: diffuse stand-ins\n")
        for name, m in materials.items():
            f.write(f"\nnewmtl {name}\nKd {_fmt(m['kd'])}\nKs 0 0 0\nNs 0\nillum 1\n")
            if any(m["ke"]):
                f.write(f"Ke {_fmt(m['ke'])}\n")
            if m["map_kd"]:
                f.write(f"map_Kd {m['map_kd']}\n")
            if m["map_d"]:
                f.write(f"map_d {m['map_d']}\n")


def _valid_normal(n):
    return all(math.isfinite(x) for x in n) and sum(x * x for x in n) > 1e-20


def _face_normal(mesh, tri):
    a, b, c = (mesh.v[corner[0]] for corner in tri)
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    length = math.sqrt(sum(x * x for x in n))
    return [x / length for x in n] if length > 0.0 else [0.0, 0.0, 0.0]


def _write_obj(path, mesh, names, mtllib=None, fix_normals=False):
    """The triangles of materials `names`, re-indexed to what they use. With
    fix_normals, triangles without area are left out and a zero or
    non-finite vertex normal is replaced by its triangle's geometric normal
    (Mitsuba rejects such meshes; pmc and Blender cope themselves)."""
    remap = ({}, {}, {})
    lines_v, lines_t, lines_n, faces = [], [], [], []
    sources = (mesh.v, mesh.vt, mesh.vn)
    out_lines = (lines_v, lines_t, lines_n)
    tags = ("v", "vt", "vn")
    for name in names:
        faces.append(f"o part_{len(faces)}\nusemtl {name}")
        for tri in mesh.groups[name]:
            if fix_normals and not _valid_normal(_face_normal(mesh, tri)):
                continue  # no area: nothing to render
            words = []
            for corner in tri:
                idx = []
                for k in range(3):
                    i = corner[k]
                    if i < 0:
                        idx.append("")
                        continue
                    if k == 2 and fix_normals and not _valid_normal(mesh.vn[i]):
                        lines_n.append(f"vn {_fmt(_face_normal(mesh, tri))}")
                        idx.append(str(len(lines_n)))
                        continue
                    j = remap[k].get(i)
                    if j is None:
                        j = remap[k][i] = len(out_lines[k]) + 1
                        out_lines[k].append(f"{tags[k]} {_fmt(sources[k][i])}")
                    idx.append(str(j))
                words.append("/".join(idx).rstrip("/") if not idx[2] else "/".join(idx))
            faces.append("f " + " ".join(words))
    with open(path, "w") as f:
        if mtllib:
            f.write(f"mtllib {mtllib}\n")
        for block in (lines_v, lines_t, lines_n, faces):
            if block:
                f.write("\n".join(block) + "\n")


def render_args(job):
    """pmc render's scene arguments for a job of write_scene_files: the OBJ, its lights file and camera."""
    cam = job["camera"]
    return [job["obj"], "--lights", job["lights_file"], "--camera-from", ",".join(map(str, cam["from"])),
            "--camera-at", ",".join(map(str, cam["at"])), "--fov", str(cam["vfov"])]


def write_scene_files(name, folder, spec=None):
    """Writes scene `name`'s files (or those of `spec`, a scene of SCENES'
    form) into `folder` (see the module comment) and returns its job
    description."""
    spec = spec or SCENES[name]
    os.makedirs(folder, exist_ok=True)
    mesh = Mesh()
    objs = list(spec["objs"])
    for file_name, text in spec.get("generated", {}).items():
        objs.append(os.path.join(folder, file_name))
        with open(objs[-1], "w") as f:
            f.write(text)
    for obj in objs:
        read_obj(obj, mesh)
    materials = {}
    for lib in mesh.mtllibs:
        materials.update(read_mtl(lib))
    names = [n for n in mesh.groups if mesh.groups[n]]
    for n in names:
        materials.setdefault(n, {"kd": [0.8, 0.8, 0.8], "ke": [0.0, 0.0, 0.0], "map_kd": None, "map_d": None})
    used = {n: materials[n] for n in names}
    _write_mtl(os.path.join(folder, "scene.mtl"), used)
    _write_obj(os.path.join(folder, "scene.obj"), mesh, names, mtllib="scene.mtl")
    parts = []
    for i, n in enumerate(names):
        part = os.path.join(folder, f"part_{i}.obj")
        _write_obj(part, mesh, [n], fix_normals=True)
        parts.append({"obj": os.path.abspath(part), "material": n})
    env = spec["environment"]
    lights_file = {"lights": spec["lights"]}
    if env and "map" in env:
        lights_file["environment"] = {"map": os.path.abspath(env["map"]), "scale": env.get("scale", 1.0)}
    elif env:
        lights_file["environment"] = {"radiance": env["radiance"]}
    with open(os.path.join(folder, "scene.lights.json"), "w") as f:
        json.dump(lights_file, f, indent=1)
    eye, target, fov = spec["camera"]
    return {
        "scene": name,
        "what": spec["what"],
        "obj": os.path.abspath(os.path.join(folder, "scene.obj")),
        "lights_file": os.path.abspath(os.path.join(folder, "scene.lights.json")),
        "parts": parts,
        "materials": used,
        "camera": {"from": list(eye), "at": list(target), "up": [0.0, 1.0, 0.0], "vfov": fov},
        "lights": spec["lights"],
        "environment": lights_file.get("environment"),
        "triangles": sum(len(mesh.groups[n]) for n in names),
    }
