"""bench.heavy — the progressive material cache on the heavy procedural scene
(data/heavy, scripts/make_heavy_scene.py: six procedural materials of
100-300 nodes, uv- and position-driven), the scene it is made for. Prints the
paper's table (time, hit rate, whole-image and worst-tile PSNR, memory) and
the cache plan, and writes the "Heavy procedural scene" section of
docs/BENCHMARKS.md.

    scripts/python -m bench.heavy                     640x360, 16 spp, 3 rounds; PSNR at 320x180, 256 spp
    scripts/python -m bench.heavy --runs 1 --width 160 --height 90 --spp 4 --psnr-spp 16 --doc -    a quick look
    scripts/python -m bench.heavy --report-only       the table and section from --out-dir's results.json

Method:
  1. one 1-spp render of every configuration, not timed (they fill PoCL's
     kernel cache and the OS file cache; kernel compiles are never in
     render_seconds);
  2. RUNS rounds of `pmc render --cache off`, `--cache on`, `--cache on
     --cache-bandwidth on` (texels no coarser than the patterns: the answer
     to patterns finer than a pixel) and `--cache-bandwidth camera` (those
     floors at camera-ray hits only) at WIDTHxHEIGHT and SPP with --stats,
     of the networks' own shaders with every input a network drives set to a
     constant (flat_materials, --cache off: the networks free, the BSDF's
     lobes the same: the ceiling of any cache), and of the room with room.mtl's
     constant materials instead (simpler shaders: no coat, sheen or metal),
     the order rotated every round; the median render_seconds of each, off / each
     over the medians and the range of the per-round ratios. Hit rates (all
     lookups, uv keys, position keys) and the table's memory come from the
     cached renders' stats (the same every round: centre mode is
     deterministic);
  3. per cached configuration one `pmc compare` (against off, same seed and
     samples) at PSNR_WIDTHxPSNR_HEIGHT and PSNR_SPP: PSNR over the image and
     in its worst 16x16 tile (pmc compare's metrics.json, as bench.cache and
     bench.cache_position read them), and the worst tile with each tile's 2
     largest pixel errors left out;
  3a. one more `pmc compare` of the default cache and of `--cache-bandwidth
     camera` with another seed, which
     parts the cache's bias from the noise (bias_estimate): the two cacheless
     renders' difference is noise alone (the noise floor of any same-seed
     figure), and the mean of (on_1 - off_1)(on_2 - off_2) over a tile is an
     unbiased estimate of its squared bias, the noise of the two seeds being
     independent: the same PSNR, worst tile included, with the noise taken out;
  3b. with --supersample K,...: per K one more `pmc compare` at the PSNR size with
     `--cache-supersample K` (0: auto): PSNR, worst tile and trimmed worst tile, and
     the compare's own off/on time ratio (one run each: the speed at those samples,
     not the timed rounds' medians);
  4. `pmc info --dump-cache-plan`: per material its nodes after pmc's passes,
     its cache points (node, sub-graph size, key) and the nodes that read uv
     and position together (not cacheable: the few nodes where the two
     kinds of layers meet).
Goals (issue 39): cache on at least 2.0x at 640x360, 16 spp; the worst 16x16
tile at least 40 dB at 256 spp.
"""
import os
import re
import time

from bench import common

PROG = "bench.heavy"
SECTION = "## Heavy procedural scene: the cache's own benchmark (scripts/bench-heavy)"
SCENE = ["data/heavy/room.obj", "--mtlx", "data/heavy/materials.mtlx"]
# Timed configurations: name, scene, pmc options. "flat": the networks' shaders with constant
# inputs (flat_materials; scene None: written into --out-dir), cacheless: what any cache could
# reach. "free": room.mtl's constant materials, whose simpler shaders also drop the coat, sheen
# and metal lobes. The cached ones (CACHED) are also compared with the cacheless render for their bias.
CONFIGS = [("off", SCENE, ["--cache", "off"]), ("on", SCENE, ["--cache", "on"]),
           ("bandwidth", SCENE, ["--cache", "on", "--cache-bandwidth", "on"]),
           ("camera", SCENE, ["--cache", "on", "--cache-bandwidth", "camera"]),
           ("flat", None, ["--cache", "off"]), ("free", SCENE[:1], ["--cache", "off"])]
FLAT_MTLX = "materials_flat.mtlx"  # flat_materials' document, in --out-dir
STAND_INS = "data/heavy/room.mtl"  # the generator's constant stand-ins: each network's look as a Kd
# flat_materials' constant per input type where no stand-in colour applies: mid values, so every
# lobe a network weighs stays on.
FLAT_VALUES = {"float": "0.5", "color3": "0.5, 0.5, 0.5"}
CACHED = {"on": "cache on", "bandwidth": "cache on, `--cache-bandwidth on`",
          "camera": "cache on, `--cache-bandwidth camera`"}
# The cached configurations whose bias is read apart from the noise with a second seed.
TWO_SEEDS = ("on", "camera")
GOAL_SPEEDUP = 2.0
GOAL_WORST_TILE = 40.0
IDENTICAL_DB = 999.0        # pmc compare's PSNR of identical images
GOAL_SIZE = (640, 360, 16)  # the speedup goal's width, height and samples
GOAL_PSNR_SPP = 256         # the worst-tile goal's samples


def parse(argv=None):
    p = common.make_parser("heavy", __doc__)
    common.add_pmc(p)
    common.add_runs(p, 3)
    common.add_image_size(p, 640, 360, 16)
    p.add_argument("--psnr-spp", type=common.positive_int, default=256, metavar="N",
                   help="samples of the cache-on vs cache-off comparison (default 256)")
    p.add_argument("--psnr-width", type=common.positive_int, default=320, metavar="W",
                   help="its image width (default 320)")
    p.add_argument("--psnr-height", type=common.positive_int, default=180, metavar="H",
                   help="its image height (default 180)")
    p.add_argument("--supersample", type=supersample_list, default=[], metavar="K,...",
                   help="also compare --cache-supersample K for each K (0: auto) at the PSNR size")
    common.add_out_dir(p, "out/bench-heavy")
    common.add_doc(p)
    common.add_report_only(p)
    return common.parse_args(p, "heavy", None, argv)


def supersample_list(text):
    """"1,4,16,0" -> [1, 4, 16, 0]: --cache-supersample values (0: auto)."""
    try:
        ks = [int(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise common.argparse.ArgumentTypeError(f"expected a comma-separated list of 0, 1, 2, 4, 8, 16, got {text!r}")
    if not ks or any(k not in (0, 1, 2, 4, 8, 16) for k in ks):
        raise common.argparse.ArgumentTypeError(f"expected a comma-separated list of 0, 1, 2, 4, 8, 16, got {text!r}")
    return ks


def progress(msg):
    print(f"{PROG}: {msg}", flush=True)


def parse_plan(text):
    """`pmc info --dump-cache-plan` -> {material: {nodes, points: [(node, size, key)], mixed: [node]}}
    for the MaterialX materials (MTL ones have no networks to cache)."""
    plans, cur = {}, None
    for line in text.splitlines():
        m = re.match(r"material '([^']+)' \((.*)\)$", line)
        if m:
            cur = plans.setdefault(m.group(1), dict(nodes=None, points=[], mixed=[])) \
                if m.group(2).endswith(".mtlx") else None
            continue
        if cur is None:
            continue
        m = re.search(r"->(\d+);\s*$", line)
        if line.startswith("  passes:") and m:
            cur["nodes"] = int(m.group(1))
        m = re.match(r"    \+ '([^']+)' .*saves a sub-graph of (\d+) nodes, keyed on (\w+)", line)
        if m:
            cur["points"].append([m.group(1), int(m.group(2)), m.group(3)])
        m = re.match(r"    - '([^']+)' .*depends on uv\+position", line)
        if m:
            cur["mixed"].append(m.group(1))
    return plans


def stand_in_colours(mtl_path):
    """{material: "r, g, b"}: the Kd of each material of an MTL file."""
    colours, name = {}, None
    with open(mtl_path) as f:
        for line in f:
            words = line.split()
            if words[:1] == ["newmtl"] and len(words) == 2:
                name = words[1]
            elif words[:1] == ["Kd"] and name and len(words) == 4:
                colours[name] = ", ".join(words[1:])
    return colours


def flat_materials(src, dst, base_colours=None):
    """Writes `src`'s MaterialX document to `dst` with every shader input that a node graph drives
    set to a constant: a material's `base_colours[material]` for its base_color (the stand-in
    albedo, so paths last about as long as with the network), FLAT_VALUES for the rest. The same
    shaders and lobes; the networks are unused, and pmc does not compile them. Returns how many
    inputs it set; an input type without a constant is an error."""
    import xml.etree.ElementTree as ET
    tree = ET.parse(src)
    root = tree.getroot()
    material_of = {}  # shader name -> material name
    for mat in root.iter("surfacematerial"):
        for inp in mat.findall("input"):
            if inp.get("name") == "surfaceshader" and inp.get("nodename"):
                material_of[inp.get("nodename")] = mat.get("name")
    count = 0
    for shader in root:
        if shader.tag in ("nodegraph", "surfacematerial"):
            continue
        for inp in shader.findall("input"):
            if "nodegraph" not in inp.attrib:
                continue
            value = FLAT_VALUES.get(inp.get("type"))
            if inp.get("name") == "base_color" and inp.get("type") == "color3":
                value = (base_colours or {}).get(material_of.get(shader.get("name")), value)
            if value is None:
                raise SystemExit(f"{PROG}: {src}: {shader.get('name')}.{inp.get('name')}: no flat constant "
                                 f"for type {inp.get('type')!r}")
            for attr in ("nodegraph", "output"):
                inp.attrib.pop(attr, None)
            inp.set("value", value)
            count += 1
    tree.write(dst, encoding="unicode", xml_declaration=True)
    return count


class Measure:
    def __init__(self, args):
        self.a = args
        self.out = args.out_dir
        self.log = os.path.join(self.out, "log.txt")
        open(self.log, "w").close()
        self.flat_scene = [SCENE[0], "--mtlx", os.path.join(self.out, FLAT_MTLX)]
        flat_materials(SCENE[2], self.flat_scene[2], stand_in_colours(STAND_INS))

    def render(self, name, scene, extra, spp):
        scene = self.flat_scene if scene is None else scene
        exr, js = f"{self.out}/{name}.exr", f"{self.out}/{name}.json"
        cmd = [self.a.pmc, "render", *scene, "-o", exr, "--stats", js, *extra,
               *common.size_args(self.a.width, self.a.height, spp)]
        return common.run_pmc(cmd, js, self.log, f"render {name}", append=True)[0]

    def compare(self, name, extra):
        progress(f"pmc compare {' '.join(extra)} at {self.a.psnr_width}x{self.a.psnr_height}, {self.a.psnr_spp} spp")
        d = f"{self.out}/compare_{name}"
        common.run([self.a.pmc, "compare", *SCENE, "--out-dir", d, *extra[2:],
                    *common.size_args(self.a.psnr_width, self.a.psnr_height, self.a.psnr_spp)],
                   self.log, f"compare {name}", append=True)
        metrics = common.read_json(f"{d}/metrics.json")
        m = metrics["cached_vs_cacheless"]
        return dict(psnr=m["psnr"], worst_tile_psnr=m["worst_tile_psnr"], worst_tile=m["worst_tile"],
                    worst_trimmed_tile_psnr=m.get("worst_trimmed_tile_psnr"),
                    worst_trimmed_tile=m.get("worst_trimmed_tile"), speed_ratio=metrics.get("speed_ratio"),
                    hit_rate=metrics.get("hit_rate"))

    def second_seed(self, name, extra):
        """A cached configuration's compare with seed 1: bias_estimate's second pair."""
        progress(f"pmc compare {' '.join(extra)} --seed 1 at {self.a.psnr_width}x{self.a.psnr_height}, "
                 f"{self.a.psnr_spp} spp")
        d = f"{self.out}/compare_{name}_seed1"
        common.run([self.a.pmc, "compare", *SCENE, "--out-dir", d, "--seed", "1", *extra[2:],
                    *common.size_args(self.a.psnr_width, self.a.psnr_height, self.a.psnr_spp)],
                   self.log, f"compare {name}, seed 1", append=True)
        return bias_estimate(f"{self.out}/compare_{name}", d)

    def supersample(self):
        """{K: compare result} of --cache-supersample K at the PSNR size (0: auto)."""
        return {str(k): self.compare(f"supersample_{k}", ["--cache", "on", "--cache-supersample", str(k)])
                for k in self.a.supersample}

    def all(self):
        t0 = time.time()
        load = common.LoadSampler()
        progress("warm-up renders (untimed)")
        for name, scene, extra in CONFIGS:
            self.render(f"warm_{name}", scene, extra, 1)
        times, stats = {name: [] for name, _, _ in CONFIGS}, {}
        for r in range(self.a.runs):
            for name, scene, extra in common.round_order(CONFIGS, r):
                st = self.render(f"r{r}_{name}", scene, extra, self.a.spp)
                times[name].append(st["render_seconds"])
                stats[name] = st
                load.sample()
            progress(f"round {r + 1}/{self.a.runs}: " + ", ".join(f"{n} {times[n][-1]:.2f} s" for n in times))
        cached = {}
        for name, _, extra in CONFIGS:
            if name not in CACHED:
                continue
            c = stats[name]["cache"]
            cached[name] = dict(t=common.median(times[name]), ratios=common.round_ratios(times["off"], times[name]),
                                hits={k: c.get(k) for k in ("hit_rate", "uv_hit_rate", "position_hit_rate",
                                                            "lookups", "position_lookups", "bypassed")},
                                memory=c.get("memory_bytes"), size_reason=c.get("size_reason", ""),
                                **self.compare(name, extra))
        extras = {name: extra for name, _, extra in CONFIGS}
        biases = {name: self.second_seed(name, extras[name]) for name in TWO_SEEDS}
        supersampled = self.supersample()
        plan = common.run([self.a.pmc, "info", "--scene", *SCENE, "--dump-cache-plan"], self.log, "cache plan",
                          append=True).output
        return dict(command=self.a.command, now=common.utc_now(), rev=common.git_rev(ignore=["docs/BENCHMARKS.md"]),
                    machine=common.machine(stats["on"].get("device", "")), load=load.note(),
                    elapsed=time.time() - t0, width=self.a.width, height=self.a.height, spp=self.a.spp,
                    runs=self.a.runs, psnr_width=self.a.psnr_width, psnr_height=self.a.psnr_height,
                    psnr_spp=self.a.psnr_spp, times=times, t_off=common.median(times["off"]),
                    t_free=common.median(times["free"]), ratios_free=common.round_ratios(times["off"], times["free"]),
                    t_flat=common.median(times["flat"]), ratios_flat=common.round_ratios(times["off"], times["flat"]),
                    cached=cached, two_seeds=biases["on"], camera_bias=biases["camera"], supersample=supersampled,
                    plan=parse_plan(plan))


TILE = 16  # pmc compare's tile (core/image_metrics.h kMetricTile)


def tile_means(x):
    """Means of a per-pixel array over TILE x TILE tiles (partial tiles at the edges included),
    with each tile's top-left corner."""
    h, w = x.shape
    return [(float(x[y:y + TILE, c:c + TILE].mean()), c, y) for y in range(0, h, TILE) for c in range(0, w, TILE)]


def psnr_db(mse):
    import math
    return 10.0 * math.log10(1.0 / mse) if mse > 0 else IDENTICAL_DB


def bias_estimate(dir1, dir2):
    """bias_figures of two `pmc compare` runs with different seeds (their cache_off.exr and cache_on.exr)."""
    from bench.peers import read_exr
    return bias_figures(*(read_exr(f"{d}/cache_{k}.exr") for d in (dir1, dir2) for k in ("off", "on")))


def bias_figures(off1, on1, off2, on2):
    """The cache's bias with the noise taken out, from cacheless and cached renders with two seeds
    (H x W x 3+ arrays), on pmc compare's scale (linear values clamped to [0, 1], PSNR with peak 1,
    squared errors averaged over the channels):
      noise floor: the two cacheless renders against each other (noise alone, both renders' noise);
      bias: the mean over the image (a tile) of (on1 - off1)(on2 - off2), whose expectation is the
      squared bias, as each seed's noise is independent of the other's. An estimate: where the bias is
      far below the noise it can come out negative (then reported as 999 dB, none measurable). The
      worst tile's range is the estimate +- 2 standard errors of its pixels' products (a tile in
      fireflies is estimated loosely)."""
    import numpy as np
    off1, on1, off2, on2 = (np.clip(np.asarray(x, dtype=np.float64)[:, :, :3], 0.0, 1.0)
                            for x in (off1, on1, off2, on2))
    noise = ((off1 - off2) ** 2).mean(axis=2)
    bias2 = ((on1 - off1) * (on2 - off2)).mean(axis=2)
    worst_noise, worst_bias = max(tile_means(noise)), max(tile_means(bias2))
    x, y = worst_bias[1], worst_bias[2]
    products = ((on1 - off1) * (on2 - off2))[y:y + TILE, x:x + TILE].ravel()
    stderr = float(products.std() / np.sqrt(products.size))  # the estimate's own noise in that tile
    return dict(noise_psnr=psnr_db(float(noise.mean())), noise_worst_tile_psnr=psnr_db(worst_noise[0]),
                noise_worst_tile=[worst_noise[1], worst_noise[2], TILE],
                bias_psnr=psnr_db(float(bias2.mean())), bias_worst_tile_psnr=psnr_db(worst_bias[0]),
                bias_worst_tile=[x, y, TILE], bias_worst_tile_range=[psnr_db(worst_bias[0] + 2 * stderr),
                                                                   psnr_db(worst_bias[0] - 2 * stderr)])


def pct(x):
    return "-" if x is None else f"{100 * x:.1f}%"


def goal(ok):
    return "met" if ok else "**not met**"


def plan_rows(plan):
    rows = []
    for name, p in plan.items():
        points = ", ".join(f"`{n}` {size} ({key})" for n, size, key in p["points"]) or "none"
        rows.append([name, str(p["nodes"]), points, ", ".join(f"`{n}`" for n in p["mixed"]) or "-"])
    return rows


FREE_ROWS = (("flat", "networks free: their shaders with constant inputs (cache off)"),
             ("free", "materials free: room.mtl's constants, simpler shaders (cache off)"))


def free_rows(d):
    """The free-material rows (each absent from results of runs before it was measured)."""
    rows = []
    for key, label in FREE_ROWS:
        if d.get(f"t_{key}") is None:
            continue
        t, ratios = d[f"t_{key}"], d[f"ratios_{key}"]
        rows.append([label, f"{t:.2f}", f"{d['t_off'] / t:.2f}x ({min(ratios):.2f}-{max(ratios):.2f})",
                     "-", "-", "-", "-"])
    return rows


def ceiling_text(d, speed):
    """The cache's speed-up against the ceiling: the networks-free row, else (older results) room.mtl's."""
    key = "flat" if d.get("t_flat") is not None else "free"
    if d.get(f"t_{key}") is None:
        return ""
    ceiling = d["t_off"] / d[f"t_{key}"]
    which = ("The networks-free row (the same shaders, so the same lobes, with constant inputs) is the "
             "ceiling of any cache on this scene" if key == "flat" else
             "The free-material row is the ceiling of any cache on this scene")
    return (f"\n{which}: the cache reaches {speed:.2f}x of {ceiling:.2f}x, "
            f"{100 * (speed - 1) / (ceiling - 1):.0f}% of the time free networks would save.\n")


def cached_results(d):
    """{name: result} of the cached configurations; results.json of runs
    before --cache-bandwidth was measured kept "on" at the top level."""
    if "cached" in d:
        return d["cached"]
    keys = ("hits", "memory", "size_reason", "psnr", "worst_tile_psnr", "worst_tile", "worst_trimmed_tile_psnr")
    return {"on": dict(t=d["t_on"], ratios=d["ratios"], **{k: d.get(k) for k in keys})}


def cached_row(d, name, r):
    h = r["hits"]
    lo, hi = min(r["ratios"]), max(r["ratios"])
    bypassed = f", {h['bypassed']:,} bypassed" if h.get("bypassed") else ""
    tile = f"{r['worst_tile_psnr']:.1f} dB at {tuple(r['worst_tile'])}"
    if r.get("worst_trimmed_tile_psnr"):
        tile += f" ({r['worst_trimmed_tile_psnr']:.1f} dB)"
    psnr = f"{r['psnr']:.1f} dB"
    if r["psnr"] >= IDENTICAL_DB:
        psnr, tile = "identical", "identical"
    return [CACHED[name], f"{r['t']:.2f}", f"**{d['t_off'] / r['t']:.2f}x** ({lo:.2f}-{hi:.2f})",
            f"{pct(h['hit_rate'])} ({pct(h['uv_hit_rate'])} / {pct(h['position_hit_rate'])}){bypassed}",
            f"{r['memory'] / 2**20:.1f} MiB", psnr, tile]


def supersample_text(d, psnr_size):
    """The --supersample rows: the cache's error and speed per sub-sample count (empty without them)."""
    results = d.get("supersample") or {}
    if not results:
        return ""
    rows = []
    for k, r in results.items():
        trimmed = r.get("worst_trimmed_tile_psnr")
        rows.append([f"`--cache-supersample {k}`" + (" (auto)" if k == "0" else ""),
                     f"{r['speed_ratio']:.2f}x" if r.get("speed_ratio") else "-", f"{r['psnr']:.1f} dB",
                     f"{r['worst_tile_psnr']:.1f} dB at {tuple(r['worst_tile'])}",
                     f"{trimmed:.1f} dB at {tuple(r['worst_trimmed_tile'])}" if trimmed else "-"])
    table = common.md_table(["cached render", "off / on (one run each)", "PSNR vs off", "worst 16x16 tile",
                             "worst tile, each tile's 2 worst pixels left out"], rows)
    cmd = " ".join(["build/pmc", "compare", *SCENE, "--out-dir", "DIR", "--cache-supersample", "K",
                    *common.size_args(d["psnr_width"], d["psnr_height"], d["psnr_spp"])])
    return f"""
Supersampled misses (`--cache-supersample K`: a miss stores the mean of K stratified points over its
texel instead of its centre's value; auto is per key kind, at {d['psnr_spp']} spp
{'8 for uv texels and 4 for cells' if d['psnr_spp'] == 256 else 'see pmc info --dump-cache-plan'}), one `pmc compare` each at {psnr_size}:

    {cmd}

{table}
"""


def tile_range(b):
    """ (lo-hi dB): the worst tile's bias estimate +- 2 standard errors, when known."""
    r = b.get("bias_worst_tile_range")
    if not r:
        return ""
    hi = "none measurable" if r[1] >= IDENTICAL_DB else f"{r[1]:.1f}"
    return f" ({r[0]:.1f} to {hi} dB)"


def two_seeds_text(d, psnr_size):
    """The bias against the noise (bias_estimate; empty for results before it was measured)."""
    b = d.get("two_seeds")
    if not b:
        return ""
    on = cached_results(d)["on"]
    cmd = " ".join(["build/pmc", "compare", *SCENE, "--out-dir", "DIR2", "--seed", "1",
                    *common.size_args(d["psnr_width"], d["psnr_height"], d["psnr_spp"])])
    return f"""
Bias against noise at {psnr_size}: the same-seed figures above hold the noise of paths that part
(a cached value that differs in its last bits sends a path elsewhere, and in this room, lit by a low sun,
a diffuse bounce that reaches a glossy surface mirroring the sun is a firefly). A second compare with
another seed separates the two (`bias_estimate` in scripts/bench/heavy.py: the mean of
(on_1 - off_1)(on_2 - off_2) estimates the squared bias):

    {cmd}

| | over the image | worst 16x16 tile |
|---|---|---|
| noise floor: cacheless seed 0 against cacheless seed 1 | {b['noise_psnr']:.1f} dB | {b['noise_worst_tile_psnr']:.1f} dB at {tuple(b['noise_worst_tile'])} |
| cached against cacheless, same seed (the table) | {on['psnr']:.1f} dB | {on['worst_tile_psnr']:.1f} dB at {tuple(on['worst_tile'])} |
| the cache's bias, noise taken out (two seeds) | {b['bias_psnr']:.1f} dB | {b['bias_worst_tile_psnr']:.1f} dB at {tuple(b['bias_worst_tile'])}{tile_range(b)} |
{camera_bias_row(d)}"""


def camera_bias_row(d):
    """The bias row of --cache-bandwidth camera (empty for results before it was measured)."""
    b, r = d.get("camera_bias"), cached_results(d).get("camera")
    if not b or not r:
        return ""
    return (f"| `--cache-bandwidth camera`: its bias, noise taken out ({d['t_off'] / r['t']:.2f}x at "
            f"{d['width']}x{d['height']}, {d['spp']} spp) | {b['bias_psnr']:.1f} dB | "
            f"{b['bias_worst_tile_psnr']:.1f} dB at {tuple(b['bias_worst_tile'])}{tile_range(b)} |\n")


def goals_text(d, cached, size, psnr_size):
    """The issue's goals for the default cache ("on"), and whether this run measured them."""
    on = cached["on"]
    speed = d["t_off"] / on["t"]
    if (d["width"], d["height"], d["spp"]) == GOAL_SIZE:
        speed_goal = goal(speed >= GOAL_SPEEDUP) + f" ({speed:.2f}x)"
    else:
        speed_goal = f"not measured here ({speed:.2f}x at {size})"
    tile = f"{on['worst_tile_psnr']:.1f} dB at {psnr_size}"
    if d["psnr_spp"] == GOAL_PSNR_SPP:
        tile_goal = goal(on["worst_tile_psnr"] >= GOAL_WORST_TILE) + f" ({tile})"
        b = d.get("two_seeds")
        if b:
            tile_goal += (f"; the bias alone (two seeds, noise taken out): {b['bias_worst_tile_psnr']:.1f} dB, "
                          + goal(b["bias_worst_tile_psnr"] >= GOAL_WORST_TILE))
    else:
        tile_goal = f"not measured here ({tile})"
    camera, cb = cached.get("camera"), d.get("camera_bias")
    if camera and cb and d["psnr_spp"] == GOAL_PSNR_SPP:
        tile_goal += (f". With `--cache-bandwidth camera` (level floors at camera hits): "
                      f"{d['t_off'] / camera['t']:.2f}x, its bias's worst tile {cb['bias_worst_tile_psnr']:.1f} dB")
    return (f"Goals (issue 39), for the default cache: cache on at least {GOAL_SPEEDUP:.1f}x at 640x360, 16 spp: "
            f"{speed_goal}; the worst 16x16 tile at least {GOAL_WORST_TILE:.0f} dB at 256 spp: {tile_goal}.")


def notes_text(d, cached):
    """What the table shows about the plan and the bias (facts of the scene; numbers of this run)."""
    on = cached["on"]
    lines = [
        "Notes:",
        "- Every material but the marble looks up 4-5 points per evaluation: its uv layers and its position",
        "  weathering (or the drum's rust) are separate points, and the 2-5 nodes where they meet (the",
        "  right-hand column) run at every hit. A miss of any point evaluates that point's sub-graph; the",
        "  position-only weathering (`weather_k`: a domain-warped 7-octave `fractal3d`, two `worleynoise3d`, a",
        "  5-octave `fractal3d`) has 29 nodes but by bench.node_costs costs about 350 average nodes, more",
        "  than the 100-odd-node uv layers (their 2D noises are cheap): node counts say little of cost here.",
        "- The drum's `rust_rough` (6 nodes, one of them a 3-octave `fractal3d` that the `rust` point also",
        "  reads) is below `--cache-min-nodes 8` and so runs at every hit of the drum, although by",
        "  bench.node_costs it costs about 30 average nodes: a cost model weighing nodes would cache it.",
        f"- Bias: at {d['psnr_width']}x{d['psnr_height']} the ottoman's threads (1.25 cm), the wood's pores, the",
        "  brick's specks and pebbles and the plaster's fine craquelure are finer than a pixel, and a",
        "  footprint texel holds one value of them where the cacheless render averages the pattern over",
        "  the pixel's samples. Camera-ray hits, whose texel is what the pixel shows, use the cache in a",
        "  pixel's first 16 samples only (`--cache-camera-samples 16`) and evaluate exactly after, so at",
        f"  {d['psnr_spp']} spp that error weighs {min(16, d['psnr_spp'])}/{d['psnr_spp']} of the camera's "
        "share (at 16 spp, the speed goal's frame, the",
        "  cache serves every hit). The same-seed worst tile is the paths' noise: "
        f"{on['worst_tile_psnr']:.1f} dB (the bias alone, below).",
    ]
    bw = cached.get("bandwidth")
    if bw and bw["hits"]["hit_rate"] == 0 and bw["hits"].get("bypassed"):
        lines += ["  `--cache-bandwidth on` is no answer here: every point's level floor (texels no coarser than half",
                  "  its finest feature, 0.2-11 mm by `pmc info --dump-cache-plan --cache-bandwidth on`: the last",
                  "  octaves of 4-8-octave fBms, pores, specks, threads) is more than 2 levels finer than the",
                  "  footprint, so every point is evaluated without the cache (`bypassed`):",
                  f"  the cacheless image at the cacheless speed ({d['t_off'] / bw['t']:.2f}x). What would help is",
                  "  a point cached at the footprint with its finest features filtered, or split so that the",
                  "  sub-pixel layers stay uncached and the coarse ones are cached."]
    cam, cb = cached.get("camera"), d.get("camera_bias")
    if cam and cb:
        lines += ["  `--cache-bandwidth camera` applies those floors at camera-ray hits only: there every point is",
                  "  evaluated without the cache, and later hits keep footprint texels, whose detail the bounce's",
                  f"  lobe averages out: {d['t_off'] / cam['t']:.2f}x, and the cache's bias (two seeds, below) "
                  f"{cb['bias_psnr']:.1f} dB over the image,",
                  f"  {cb['bias_worst_tile_psnr']:.1f} dB in its worst tile."]
    elif bw:
        lines += ["  `--cache-bandwidth on` (texels no coarser than half the finest feature, or no cache where that",
                  f"  is more than 2 levels finer than the footprint) reads {bw['worst_tile_psnr']:.1f} dB in the worst "
                  f"tile and {bw['psnr']:.1f} dB",
                  f"  over the image, at {d['t_off'] / bw['t']:.2f}x instead of {d['t_off'] / on['t']:.2f}x."]
    return "\n".join(lines) + "\n"


def report(d):
    cached = cached_results(d)
    speed = d["t_off"] / cached["on"]["t"]
    size = f"{d['width']}x{d['height']}, {d['spp']} spp"
    psnr_size = f"{d['psnr_width']}x{d['psnr_height']}, {d['psnr_spp']} spp"
    table = common.md_table(
        ["render", f"time (s), {size}", "off / this", "hit rate (uv / position)", "cache memory",
         f"PSNR vs off, {psnr_size}", "worst 16x16 tile (trimmed)"],
        [["cache off", f"{d['t_off']:.2f}", "1.00x", "-", "-", "-", "-"],
         *[cached_row(d, name, r) for name, r in cached.items()], *free_rows(d)])
    plan = common.md_table(["material", "nodes after pmc's passes", "cache points: sub-graph nodes (key)",
                            "nodes reading uv and position (not cacheable)"], plan_rows(d["plan"]))
    render_cmd = " ".join(["build/pmc", "render", *SCENE, "-o", "OUT.exr", "--stats", "OUT.json", "--cache",
                           "off|on", "[--cache-bandwidth on|camera]", *common.size_args(d["width"], d["height"], d["spp"])])
    compare_cmd = " ".join(["build/pmc", "compare", *SCENE, "--out-dir", "DIR", "[--cache-bandwidth on|camera]",
                            *common.size_args(d["psnr_width"], d["psnr_height"], d["psnr_spp"])])
    section = f"""{SECTION}

Produced by `{d['command']}` on {d['now']} ({d['elapsed'] / 60:.1f} minutes).
Machine: {d['machine']}; checkout {d['rev']}; {d['load']}.

The scene (`data/heavy`, written by `scripts/make_heavy_scene.py`; `scripts/demo --heavy` renders it): an
open-fronted room of aged plaster walls and ceiling, an oak plank floor, a brick back wall, a marble plinth
and ball, a painted steel drum rusting through and a tartan ottoman, lit by an area quad under the ceiling
and a low sun (`room.lights.json`). Every surface is a procedural MaterialX network of 100-300 nodes after
pmc's passes, built from stdlib nodes the way artists build them: structured patterns (planks, bricks,
threads, bands) from the uv, weathering and solid stone and rust from the position, with domain-warped
fBm, Worley cells and cell borders. No textures. Method: `scripts/bench/heavy.py`; {common.rounds_text(d['runs'])}
of every row at {size}, the order rotated every round; ratios over the medians, the per-round ratios in
brackets. PSNR: `pmc compare` (same seed and samples, cached against cacheless) at {psnr_size}.

    {render_cmd}
    {compare_cmd}

{table}
{ceiling_text(d, speed)}
Size: {cached['on']['size_reason']}.

Cache plan (`pmc info --scene data/heavy/room.obj --mtlx data/heavy/materials.mtlx --dump-cache-plan`):

{plan}

{notes_text(d, cached)}{two_seeds_text(d, psnr_size)}{supersample_text(d, psnr_size)}
{goals_text(d, cached, size, psnr_size)}
"""
    on = cached["on"]
    printed = (f"{PROG}: off {d['t_off']:.2f} s, on {on['t']:.2f} s: {speed:.2f}x; hit rate "
               f"{pct(on['hits']['hit_rate'])}; PSNR {on['psnr']:.1f} dB, worst tile {on['worst_tile_psnr']:.1f} dB")
    return section, printed


def main(argv=None):
    args = parse(argv)
    common.measure_and_report(args, PROG, SECTION, lambda a: Measure(a).all(), report, inputs=[SCENE[0], SCENE[2]])


if __name__ == "__main__":
    main()
