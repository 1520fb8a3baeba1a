"""bench.node_costs — what one node of each costly pattern family costs on the
device, in units of an average node of the default scene's floor network
(the unit the cache plan's node-count threshold, materials/cache_plan.h,
implicitly assumes). Prints a table and writes the "Node costs" section of
docs/BENCHMARKS.md.

    scripts/python -m bench.node_costs                 640x360, 8 spp, 5 rounds
    scripts/python -m bench.node_costs --runs 1 --spp 2 --doc -    a quick look

Method: the shared plane (geometry/plane.obj) seen from above, white
environment, --max-depth 1 and --cache off, so every shaded hit is a camera
hit that runs its material once.
  1. Per family, a generated document whose base colour is the sum of K nodes
     of that family, each at its own scaled coordinate (position x s_i or
     uv x s_i, so deduplication keeps them apart); the baseline document sums
     K `extract`s of the same coordinates instead. A node's cost is
     (shade(family) - shade(baseline)) / (K x shaded hits): the shade stage's
     seconds per hit, against an extract (a fraction of a nanosecond).
  2. The unit: the default floor network (--material floor) against a
     constant floor (bench.materials' trivial.mtlx), divided by the floor's
     evaluated instructions per hit: the time of its average node.
  3. RUNS rounds, every render once per round, the order rotated; medians.
"""
import os
import time

from bench import common
from bench import materials as bench_materials

PROG = "bench.node_costs"
SECTION = "## Node costs (scripts/bench-node-costs)"
K = 8
PLANE = "../shared/scenes/materialx/geometry/plane.obj"
IMAGE_RGB = "../shared/scenes/sponza/textures/spnza_bricks_a_diff.png"
IMAGE_GREY = "../shared/scenes/sponza/textures/spnza_bricks_a_bump.png"
VIEW = ["--env", "1,1,1", "--camera-from", "0,-0.75,0.65", "--camera-at", "0,-0.05,0", "--fov", "45",
        "--max-depth", "1", "--cache", "off"]
# family -> (key input: position or uv, the node's XML given its name and coordinate node)
FAMILIES = {
    "noise2d": ("uv", '<noise2d name="{n}" type="float"><input name="texcoord" type="vector2" nodename="{c}" />'
                      "</noise2d>"),
    "fractal2d (1 octave)": ("uv", '<fractal2d name="{n}" type="float"><input name="texcoord" type="vector2" '
                                   'nodename="{c}" /><input name="octaves" type="integer" value="1" /></fractal2d>'),
    "cellnoise2d": ("uv", '<cellnoise2d name="{n}" type="float"><input name="texcoord" type="vector2" '
                          'nodename="{c}" /></cellnoise2d>'),
    "worleynoise2d": ("uv", '<worleynoise2d name="{n}" type="float"><input name="texcoord" type="vector2" '
                            'nodename="{c}" /></worleynoise2d>'),
    "tiledhexagons": ("uv", '<tiledhexagons name="{n}" type="color3"><input name="texcoord" type="vector2" '
                            'nodename="{c}" /><input name="uvtiling" type="vector2" value="24, 10" />'
                            "</tiledhexagons>"),
    "tiledcircles": ("uv", '<tiledcircles name="{n}" type="color3"><input name="texcoord" type="vector2" '
                           'nodename="{c}" /><input name="uvtiling" type="vector2" value="24, 10" />'
                           "</tiledcircles>"),
    "noise3d": ("position", '<noise3d name="{n}" type="float"><input name="position" type="vector3" '
                            'nodename="{c}" /></noise3d>'),
    "fractal3d (1 octave)": ("position", '<fractal3d name="{n}" type="float"><input name="position" '
                                         'type="vector3" nodename="{c}" /><input name="octaves" type="integer" '
                                         'value="1" /></fractal3d>'),
    "cellnoise3d": ("position", '<cellnoise3d name="{n}" type="float"><input name="position" type="vector3" '
                                'nodename="{c}" /></cellnoise3d>'),
    "worleynoise3d": ("position", '<worleynoise3d name="{n}" type="float"><input name="position" '
                                  'type="vector3" nodename="{c}" /></worleynoise3d>'),
    # Images: a 1024x1024 texture as Sponza's and the brick's, read through its mip chain.
    "image (1024x1024 RGB)": ("uv", '<image name="{n}" type="color3"><input name="file" type="filename" '
                                    f'value="{os.path.abspath(IMAGE_RGB)}" /><input name="texcoord" type="vector2" '
                                    'nodename="{c}" /></image>'),
    "image (1024x1024 grey)": ("uv", '<image name="{n}" type="float"><input name="file" type="filename" '
                                     f'value="{os.path.abspath(IMAGE_GREY)}" /><input name="texcoord" '
                                     'type="vector2" nodename="{c}" /></image>'),
}


def parse(argv=None):
    p = common.make_parser("node_costs", __doc__)
    common.add_pmc(p)
    common.add_runs(p, 5)
    common.add_image_size(p, 640, 360, 8)
    common.add_out_dir(p, "out/bench-node-costs", "the generated documents, images, stats and logs")
    common.add_doc(p)
    common.add_report_only(p)
    return common.parse_args(p, "node_costs", None, argv)


def slug(name):
    """A family's file name: its first word, and for images the kind in brackets (image_rgb, image_grey)."""
    words = name.split(" ")
    return words[0] if words[0] != "image" else f"image_{words[-1].strip(')').lower()}"


def document(key, node_xml):
    """K nodes (node_xml, or an extract when None) at coordinates key x (1 + 0.37 i), summed into base_color."""
    coord_type = "vector3" if key == "position" else "vector2"
    body = [f'<{key if key == "position" else "texcoord"} name="key" type="{coord_type}" />']
    total = None
    for i in range(K):
        body.append(f'<multiply name="c{i}" type="{coord_type}"><input name="in1" type="{coord_type}" '
                    f'nodename="key" /><input name="in2" type="float" value="{1 + 0.37 * i:.2f}" /></multiply>')
        if node_xml is None:
            body.append(f'<extract name="v{i}" type="float"><input name="in" type="{coord_type}" nodename="c{i}" />'
                        '<input name="index" type="integer" value="0" /></extract>')
        elif 'type="float"' in node_xml.split(">")[0]:
            body.append(node_xml.format(n=f"v{i}", c=f"c{i}"))
        else:  # a colour3 pattern contributes its first channel
            body.append(node_xml.format(n=f"n{i}", c=f"c{i}"))
            body.append(f'<extract name="v{i}" type="float"><input name="in" type="color3" nodename="n{i}" />'
                        '<input name="index" type="integer" value="0" /></extract>')
        if total is None:
            total = f"v{i}"
        else:
            body.append(f'<add name="s{i}" type="float"><input name="in1" type="float" nodename="{total}" />'
                        f'<input name="in2" type="float" nodename="v{i}" /></add>')
            total = f"s{i}"
    body.append(f'<multiply name="scaled" type="float"><input name="in1" type="float" nodename="{total}" />'
                '<input name="in2" type="float" value="0.05" /></multiply>')
    body.append('<convert name="colour" type="color3"><input name="in" type="float" nodename="scaled" /></convert>')
    lines = "\n    ".join(body)
    return f"""<?xml version="1.0"?>
<materialx version="1.39">
  <nodegraph name="NG">
    {lines}
    <output name="out" type="color3" nodename="colour" />
  </nodegraph>
  <standard_surface name="SR" type="surfaceshader">
    <input name="base_color" type="color3" nodegraph="NG" output="out" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR" />
  </surfacematerial>
</materialx>
"""


class Measure:
    def __init__(self, args):
        self.a = args
        self.out = args.out_dir
        self.log = os.path.join(self.out, "log.txt")
        open(self.log, "w").close()
        self.size = common.size_args(args.width, args.height, args.spp)

    def configs(self):
        """name -> (mtlx, material)."""
        c = {}
        for key in ("uv", "position"):
            path = os.path.join(self.out, f"baseline_{key}.mtlx")
            with open(path, "w") as f:
                f.write(document(key, None))
            c[f"baseline_{key}"] = (path, "M")
        for name, (key, xml) in FAMILIES.items():
            path = os.path.join(self.out, f"{slug(name)}.mtlx")
            with open(path, "w") as f:
                f.write(document(key, xml))
            c[slug(name)] = (path, "M")
        trivial = os.path.join(self.out, "trivial.mtlx")
        bench_materials.write_trivial(trivial)
        c["floor"] = ("data/default/materials.mtlx", "floor")
        c["const_floor"] = (trivial, "floor")
        return c

    def render(self, name, mtlx, material):
        exr, js = f"{self.out}/{name}.exr", f"{self.out}/{name}.json"
        cmd = [self.a.pmc, "render", PLANE, "--mtlx", mtlx, "--material", material, *VIEW, "-o", exr, "--stats", js,
               *self.size]
        return common.run_pmc(cmd, js, self.log, f"render {name}", append=True)[0]

    def all(self):
        t0 = time.time()
        configs = self.configs()
        code = bench_materials.parse_bytecode(common.run(
            [self.a.pmc, "info", "--scene", PLANE, "--mtlx", "data/default/materials.mtlx", "--material", "floor",
             "--dump-bytecode", "--cache-min-nodes", "1000000000"], self.log, "pmc info", append=True).output)
        for name, (mtlx, material) in configs.items():  # untimed: PoCL's kernel cache, the OS file cache
            self.render(name, mtlx, material)
        load = common.LoadSampler()
        shade = {name: [] for name in configs}
        hits = {}
        device = ""
        for r in range(self.a.runs):
            print(f"{PROG}: round {r + 1} of {self.a.runs}", flush=True)
            for name in common.round_order(list(configs), r):
                s = self.render(name, *configs[name])
                shade[name].append(s["stage_seconds"]["shade"])
                hits[name] = s["rays"] - s["shadow_rays"]
                device = s["device"]
                load.sample()
        return dict(command=self.a.command, now=common.utc_now(), rev=common.git_rev(ignore=["docs/BENCHMARKS.md"]),
                    machine=common.machine(device), load=load.note(), elapsed=time.time() - t0,
                    width=self.a.width, height=self.a.height, spp=self.a.spp, runs=self.a.runs, shade=shade,
                    hits=hits, floor_evaluated=code["floor"]["evaluated"])


def report(data):
    med = {n: common.median(v) for n, v in data["shade"].items()}
    ns = lambda seconds, n: 1e9 * seconds / n
    unit = ns(med["floor"] - med["const_floor"], data["floor_evaluated"] * data["hits"]["floor"])
    rows, printed = [], []
    for name, (key, _) in FAMILIES.items():
        s = slug(name)
        cost = ns(med[s] - med[f"baseline_{key}"], K * data["hits"][s])
        rows.append([f"`{name}`", key, f"{cost:.1f}", f"{cost / unit:.1f}"])
        printed.append(f"{name:24s} {cost:7.1f} ns   {cost / unit:6.1f} average floor nodes")
    table = common.md_table(["node", "key", "ns per node and shaded hit", "in average floor nodes"], rows)
    head = (f"Produced by `{data['command']}` on {data['now']} ({data['elapsed'] / 60:.1f} minutes).\n"
            f"Machine: {data['machine']}; checkout {data['rev']}; {data['load']}.\n")
    section = f"""{SECTION}

{head}
Method (`scripts/bench/node_costs.py`): the shared plane seen from above, white environment,
`--max-depth 1 --cache off`, {data['width']}x{data['height']}, {data['spp']} spp, so every shaded hit is a
camera hit that runs its material once. Per family a generated document sums {K} nodes of it, each at
its own scaled coordinate; the baseline sums {K} `extract`s of the same coordinates. A node's cost
is the shade stage's extra seconds over {K} x the shaded hits. The unit is the default floor network's
average node: (floor network - constant floor) / ({data['floor_evaluated']} evaluated instructions x
hits) = {unit:.2f} ns. {common.rounds_text(data['runs'])}, every render once per round, the order
rotated; medians of the shade stage. Shade-stage seconds are wall time on 2 cores, so a node's
nanoseconds here are per hit of the whole device, not of one core.

    build/pmc render {PLANE} --mtlx DOC.mtlx --material M {' '.join(VIEW)} -o OUT.exr --stats OUT.json --width {data['width']} --height {data['height']} --spp {data['spp']} --quiet

{table}

What this is for: the cache plan's threshold (`--cache-min-nodes`, 8, `materials/cache_plan.h`)
counts a sub-graph's nodes, as if every node cost the same, while one 3D Perlin noise costs about
ten average nodes and a 3D Worley noise seventy. Weighing each node by this table was built and
measured on 2026-11-27 (bench.cache_position, the solid-texture room, where it made the floor's
roughness, position -> multiply -> a 4-octave `fractal3d` -> remap, 4 nodes, a cache point; no
plan of the default scene or of the shared MaterialX documents changed): 1.24x -> 1.27x over the
cacheless render, but 49.7 -> 47.2 dB over the image and 37.9 -> 36.5 dB in the worst tile at
256 spp, and 42.9 -> 39.4 dB against the same seed at 16 spp. A cached roughness is one value per
cell, which moves highlights and lobe choices; the threshold measures only what a lookup saves,
not what the cached value costs in accuracy. It was not kept: `--cache-min-nodes 4` gives the
same plan to whoever wants it.
"""
    return section, "\n".join(printed) + f"\nunit: {unit:.2f} ns per average floor node"


def main(argv=None):
    args = parse(argv)
    common.measure_and_report(args, PROG, SECTION, lambda a: Measure(a).all(), report,
                              inputs=(PLANE, "data/default/materials.mtlx"))


if __name__ == "__main__":
    main()
