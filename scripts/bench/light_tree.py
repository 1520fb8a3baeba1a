"""bench.light_tree — next-event estimation's light pick: the light tree
(`--light-tree on`, the default) against the pick by power (`off`, the old
selection), at equal samples and at equal time. For each scene it renders a
reference with many samples (tree, cache off), then in interleaved rounds
both samplers at SPP (cache off, a new seed per round), and measures the
relMSE of each image against the reference (pmc's definition:
mean of (x - ref)^2 / (ref^2 + 0.01) over pixels and channels) and the
render time. Efficiency is 1 / (relMSE x seconds). Prints a table and writes
the "Light selection" section of docs/BENCHMARKS.md.

    scripts/python -m bench.light_tree                     the default sizes (about 10 minutes on 2 cores)
    scripts/python -m bench.light_tree --runs 1 --spp 4 --ref-spp 64 --width 80 --height 45 --doc -   a quick look

Scenes: the default room with the 30 mixed lights and the sky of
data/default/many.lights.json; the default room as it is (its emissive
ceiling panel); the default room with its low sun (data/default/sun.lights.json);
and a hall this module writes (write_hall): four glowing spheres of 6,300
triangles each (24,480 of them with area) under 300 point lights, the scale
issue 36 asks the tree to hold up at.
The reference's own noise adds about SPP/REF_SPP to every relMSE alike.
"""
import json
import math
import os
import random
import sys
import time

from bench import common

PROG = "bench.light_tree"
SECTION = "## Light selection: the light tree against the pick by power (scripts/bench-light-tree)"
ROOM = ["data/default/room.obj", "--mtlx", "data/default/materials.mtlx"]
SCENES = [
    ("many lights", [*ROOM, "--lights", "data/default/many.lights.json"]),
    ("default", ROOM),
    ("default + sun", [*ROOM, "--lights", "data/default/sun.lights.json"]),
]
SAMPLERS = ["off", "on"]


def write_hall(folder):
    """A 10 x 4 x 10 m hall (a grey floor, a ceiling and three walls, open
    towards the camera), four
    emissive spheres of radius 0.4 m (90 x 35 quads, split into triangles,
    each sphere its own colour) and 300 point lights of random intensity
    under the ceiling: tens of thousands of emissive triangles and hundreds
    of lights. Returns its render arguments (scene, lights, camera)."""
    os.makedirs(folder, exist_ok=True)
    rng = random.Random(3)
    verts, faces = [], []  # faces: (material, vertex numbers from 1)

    def quad(corners, material):
        first = len(verts) + 1
        verts.extend(corners)
        faces.append((material, (first, first + 1, first + 2, first + 3)))

    w, h = 10.0, 4.0
    quad([(0, 0, 0), (w, 0, 0), (w, 0, w), (0, 0, w)], "floor")
    quad([(0, h, 0), (0, h, w), (w, h, w), (w, h, 0)], "wall")
    quad([(0, 0, 0), (0, 0, w), (0, h, w), (0, h, 0)], "wall")
    quad([(w, 0, 0), (w, h, 0), (w, h, w), (w, 0, w)], "wall")
    quad([(0, 0, w), (w, 0, w), (w, h, w), (0, h, w)], "wall")
    rings, segments = 35, 90
    for s in range(4):
        cx, cy, cz, r = 2.0 + 2.0 * s, 1.0, 5.0 + 2.0 * (s % 2), 0.4
        base = len(verts) + 1
        for j in range(rings + 1):
            th = math.pi * j / rings
            for i in range(segments):
                ph = 2.0 * math.pi * i / segments
                verts.append((cx + r * math.sin(th) * math.cos(ph), cy + r * math.cos(th),
                              cz + r * math.sin(th) * math.sin(ph)))
        for j in range(rings):
            for i in range(segments):
                a, b = base + j * segments + i, base + j * segments + (i + 1) % segments
                c, d = b + segments, a + segments
                faces += [(f"glow{s}", (a, b, c)), (f"glow{s}", (a, c, d))]
    with open(os.path.join(folder, "hall.obj"), "w") as f:
        f.write("mtllib hall.mtl\n")
        f.writelines(f"v {x:.6g} {y:.6g} {z:.6g}\n" for x, y, z in verts)
        current = None
        for material, vs in faces:
            if material != current:
                f.write(f"usemtl {material}\n")
                current = material
            f.write("f " + " ".join(map(str, vs)) + "\n")
    with open(os.path.join(folder, "hall.mtl"), "w") as f:
        f.write("newmtl floor\nKd 0.6 0.6 0.6\nnewmtl wall\nKd 0.7 0.7 0.7\n")
        f.writelines(f"newmtl glow{s}\nKd 0.1 0.1 0.1\nKe {1 + s} 2 {4 - s}\n" for s in range(4))
    points = [{"type": "point", "position": [rng.uniform(0.5, 9.5), rng.uniform(2.5, 3.8), rng.uniform(0.5, 9.5)],
               "intensity": [rng.uniform(0.05, 0.5)] * 3} for _ in range(300)]
    with open(os.path.join(folder, "hall.lights.json"), "w") as f:
        json.dump({"lights": points}, f)
    return [os.path.join(folder, "hall.obj"), "--lights", os.path.join(folder, "hall.lights.json"),
            "--camera-from", "5,2,-3", "--camera-at", "5,1.5,5", "--fov", "60"]


def parse(argv=None):
    p = common.make_parser("light_tree", __doc__)
    common.add_pmc(p)
    common.add_runs(p, 5)
    common.add_image_size(p, 160, 90, 16)
    p.add_argument("--ref-spp", type=common.positive_int, default=1024, metavar="N",
                   help="samples per pixel of each scene's reference (default 1024)")
    common.add_out_dir(p, "out/bench-light-tree")
    common.add_doc(p)
    return common.parse_args(p, "light_tree", None, argv)


def read_image(path):
    import mitsuba as mi
    import numpy as np
    mi.set_variant("scalar_rgb")
    return np.array(mi.Bitmap(path), dtype=np.float64)[..., :3]


def rel_mse(img, ref):
    import numpy as np
    return float(np.mean((img - ref) ** 2 / (ref * ref + 0.01)))


def main(argv=None):
    a = parse(argv)
    common.chdir_root()
    OUT, RUNS, SPP, W, H = a.out_dir, a.runs, a.spp, a.width, a.height
    os.makedirs(OUT, exist_ok=True)
    pmc = common.find_pmc(a.pmc, PROG)

    def render(scene, tree, name, spp, seed):
        exr, js = f"{OUT}/{name}.exr", f"{OUT}/{name}.json"
        cmd = [pmc, "render", *scene, "--light-tree", tree, "--cache", "off", "--seed", str(seed), "-o", exr,
               "--stats", js, *common.size_args(W, H, spp)]
        try:
            s, _ = common.run_pmc(cmd, js, f"{OUT}/{name}.log")
        except common.RunFailed as e:
            sys.exit(f"{PROG}: {name} failed with {e}")
        return exr, s

    print(f"{PROG}: {pmc}; {RUNS} rounds, {W}x{H}, {SPP} spp against {a.ref_spp} spp references", flush=True)
    loads = common.LoadSampler()
    t0 = time.time()
    rows, results, device = [], {}, "?"
    hall = ("300 points, 24,480 emissive triangles (written)", write_hall(os.path.join(OUT, "hall")))
    scenes = SCENES + [hall]
    for si, (label, scene) in enumerate(scenes):
        tag = f"scene{si}"
        ref_exr, st = render(scene, "on", f"{tag}_reference", a.ref_spp, 7919)
        device = st.get("device", device)
        lights = st.get("lights", {})
        ref = read_image(ref_exr)
        for tree in SAMPLERS:  # untimed: PoCL's kernel cache, the OS file cache
            render(scene, tree, f"{tag}_{tree}_warmup", 1, 1)
        res = {t: {"relmse": [], "seconds": []} for t in SAMPLERS}
        for r in range(RUNS):
            for tree in common.round_order(SAMPLERS, r):
                exr, s = render(scene, tree, f"{tag}_{tree}_{r}", SPP, r + 1)
                res[tree]["relmse"].append(rel_mse(read_image(exr), ref))
                res[tree]["seconds"].append(s["render_seconds"])
                loads.sample()
            print(f"  {label}: round {r + 1}/{RUNS}  " + "  ".join(
                f"{t}: relMSE {res[t]['relmse'][-1]:.4g} in {res[t]['seconds'][-1]:.2f}s" for t in SAMPLERS),
                flush=True)
        med = {t: {k: common.median(v) for k, v in res[t].items()} for t in SAMPLERS}
        # Per-round ratios (the two renders of a round share the machine's load), medians and ranges.
        noise = common.median_range(common.round_ratios(res["off"]["relmse"], res["on"]["relmse"]))
        cost = common.median_range(common.round_ratios(res["on"]["seconds"], res["off"]["seconds"]))
        eff = common.median_range([n / c for n, c in zip(common.round_ratios(res["off"]["relmse"], res["on"]["relmse"]),
                                                         common.round_ratios(res["on"]["seconds"],
                                                                             res["off"]["seconds"]))])
        results[label] = dict(med=med, noise=noise, cost=cost, efficiency=eff, all=res)
        tree_text = (f"{lights['count']}, {lights['tree_depth']} levels, "
                     f"{1e3 * lights['tree_build_seconds']:.0f} ms" if lights else "-")
        rows.append([label, tree_text, f"{med['off']['relmse']:.4g}", f"{med['on']['relmse']:.4g}",
                     f"**{noise[0]:.2f}x** ({noise[1]:.2f}-{noise[2]:.2f})",
                     f"{med['off']['seconds']:.2f}", f"{med['on']['seconds']:.2f}",
                     f"{cost[0]:.2f} ({cost[1]:.2f}-{cost[2]:.2f})",
                     f"**{eff[0]:.2f}x** ({eff[1]:.2f}-{eff[2]:.2f})"])
    elapsed = time.time() - t0
    table = common.md_table(["scene", "lights, tree depth, tree build", "relMSE, power", "relMSE, tree",
                             "relMSE power / tree (range)",
                             "seconds, power", "seconds, tree", "time tree / power (range)",
                             "efficiency tree / power (range)"], rows)
    scene_lines = "\n".join(f"    build/pmc render {' '.join(s)} --light-tree on|off --cache off "
                            f"{' '.join(common.size_args(W, H, SPP))}" for _, s in scenes)
    section = f"""{SECTION}

Produced by `{a.command}` on {common.utc_now()} ({elapsed / 60:.1f} minutes, references included).
Machine: {common.machine(device)}; load average {loads.before():.1f} before the runs,
{loads.median():.1f} median and {loads.max():.1f} max between them. pmc: {common.git_rev(ignore=["docs"])}.
{RUNS} interleaved rounds (a new seed each), {W}x{H}, {SPP} spp, cache off; relMSE against a
{a.ref_spp}-spp reference of the same scene (tree, another seed); render seconds (wall); ratios are
medians (and ranges) of per-round ratios; efficiency = 1 / (relMSE x seconds), so its ratio is the
relMSE ratio over the time ratio, i.e. how much less error the tree reaches at equal time:

{scene_lines}

{table}

"Power" is the old pick: one global pmf by power, the environment and suns weighted by the scene's
bounding sphere. The tree picks a light at infinity or the light tree by an irradiance estimate at the
shading point, then descends the tree by each child's importance (core/light_tree.h,
core/device/pmc_lights.h). The default room's only emitter is its ceiling panel, two triangles
with the same box, normal and energy, which the tree splits 1/2 : 1/2 as power does: the images are
identical, so its row shows the cost of the pick alone, and how much the load of a shared machine
moves a time ratio. In the sun scene a few fireflies (the sun through the open front, then the
walls) decide each image's relMSE, which spans 0.14 to 35 over the rounds with either pick: there
the range of the ratio says more than its median. The hall (`write_hall` in
scripts/bench/light_tree.py, written into the output folder) has four glowing spheres of 6,300
triangles (24,480 with area) and 300 point lights: the tree's build is part of each render's time.
"""
    print()
    print(table)
    print(f"{PROG}: {elapsed:.0f}s; images and logs in {OUT}/")
    with open(os.path.join(OUT, "results.json"), "w") as f:
        json.dump(results, f, indent=1)
    common.write_section(a.doc, SECTION, section, PROG)


if __name__ == "__main__":
    main()
