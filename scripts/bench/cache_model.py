"""bench.cache_model — the cache's cost model (materials/node_costs.h) against
measurement: cache off, on with the cost model (the default) and on with the
node count alone (--cache-model nodes), interleaved, on the default scene,
the heavy procedural scene, the shared scenes scripts/bench-cache uses and
bench.peers' Cornell box and spider, at each image size; the model's
predicted speedup beside the measured one. Writes the "Cache cost model"
section of docs/BENCHMARKS.md.

    scripts/python -m bench.cache_model                      160x90 and 640x360, 16 spp, 5 rounds
    scripts/python -m bench.cache_model --runs 1 --doc -     a quick look

Method: per scene and size, one untimed 32x18, 1-spp render of each
configuration first (PoCL's kernel cache, the OS file cache, the device's
calibration; kernel builds are never in render_seconds); then
RUNS rounds, every render once per round, the order rotated (the scene
and size groups, and the configurations within each group; a render
shorter than --short-seconds runs again, back to back, until its renders
add up to that, at most --short-repeats, and the round keeps their median);
medians of `render_seconds` and of the rounds' off / on ratios. The default scene also
renders with every material constant (bench.materials' trivial.mtlx): the
ceiling a free cache could reach; the heavy procedural scene renders its
networks' own shaders with constant inputs (bench.heavy's flat_materials: the
same lobes, no network). The prediction: `pmc render --stats`
reports cache.model.predicted_saving_seconds (each point's gain per lookup,
h C - L - (1 - h) M in unit nodes, times the lookups its material's shaded
hits made, times the calibrated unit node's time); the predicted speedup
is off / (off - saving) with the measured median off time. In brackets,
the same with the measured hit rates. Each row also shows the measured
saving per predicted unit node, which a right model keeps constant.
"""
import os
import time

from bench import common, peer_scenes
from bench import heavy as bench_heavy
from bench import materials as bench_materials

PROG = "bench.cache_model"
SECTION = "## Cache cost model (scripts/bench-cache-model)"
SHARED = common.SHARED_SCENES
SPONZA = [f"{SHARED}/sponza/sponza.obj", "--camera-from", "-110,20,0", "--camera-at", "100,20,0", "--fov", "45",
          "--env", "1,1,1", "--max-depth", "4"]
BRICK = f"{SHARED}/materialx/standard_surface_brick_procedural.mtlx"
PEER = "bench.peers"  # a scene of bench.peer_scenes, written into the output folder at the start
SCENES = [
    ("default", "default room (`data/default`)", ["data/default/room.obj", "--mtlx", "data/default/materials.mtlx"]),
    ("heavy", "heavy procedural room (`data/heavy`)", bench_heavy.SCENE),
    ("teapot", "brick teapot (`M_BrickPattern`)",
     [f"{SHARED}/materialx/geometry/teapot.obj", "--mtlx", BRICK, "--material", "M_BrickPattern", "--env", "1,1,1",
      "--camera-from", "0.75,1.0,2.45", "--camera-at", "-0.09,0.05,-0.01", "--fov", "45"]),
    ("sponza", "Sponza (MTL materials)", SPONZA),
    ("sponza_forced", "Sponza, `--cache-min-nodes 3`", SPONZA + ["--cache-min-nodes", "3"]),
    ("sponza_brick", "Sponza, `M_BrickPattern` everywhere", SPONZA + ["--mtlx", BRICK, "--material", "M_BrickPattern"]),
    ("cornell", "Cornell box (bench.peers' scene: constant materials)", PEER),
    ("spider", "spider (bench.peers' scene: a textured mesh under an HDR map)", PEER),
    ("lines", "line pattern plane, `--cache-min-nodes 4`",
     [f"{SHARED}/materialx/geometry/plane.obj", "--mtlx", f"{SHARED}/materialx/linepattern.mtlx", "--material",
      "test_union", "--env", "1,1,1", "--camera-from", "0,-0.75,0.65", "--camera-at", "0,-0.05,0", "--fov", "45",
      "--cache-min-nodes", "4"]),
]
CONFIGS = {"off": ["--cache", "off"], "cost": ["--cache", "on"], "nodes": ["--cache", "on", "--cache-model", "nodes"]}


def parse(argv=None):
    p = common.make_parser("cache_model", __doc__)
    common.add_pmc(p)
    common.add_runs(p, 5)
    p.add_argument("--sizes", default="160x90,640x360", help="image sizes WxH, comma-separated (default: %(default)s)")
    p.add_argument("--spp", type=common.positive_int, default=16, help="samples per pixel (default: %(default)s)")
    p.add_argument("--only", default="", help="scene keys, comma-separated (default: all)")
    p.add_argument("--nodes", default="default",
                   help="scene keys that also render with --cache-model nodes, comma-separated (default: %(default)s)")
    p.add_argument("--short-seconds", type=float, default=0.5,
                   help="a render shorter than this runs again in its round until its renders there add up to "
                        "this, at most --short-repeats times, and the round keeps their median "
                        "(default: %(default)s)")
    p.add_argument("--short-repeats", type=common.positive_int, default=15,
                   help="the most renders per round of a short render (default: %(default)s)")
    common.add_out_dir(p, "out/bench-cache-model", "images, stats and logs of the last run")
    common.add_doc(p)
    common.add_report_only(p)
    return common.parse_args(p, "cache_model", None, argv)


class Measure:
    def __init__(self, args):
        self.a = args
        self.out = args.out_dir
        self.log = os.path.join(self.out, "log.txt")
        open(self.log, "w").close()

    def render(self, name, args, size, spp=None):
        w, h = size
        exr, js = f"{self.out}/{name}.exr", f"{self.out}/{name}.json"
        cmd = [self.a.pmc, "render", *args, "-o", exr, "--stats", js, *common.size_args(w, h, spp or self.a.spp)]
        return common.run_pmc(cmd, js, self.log, f"render {name}", append=True)[0]

    @staticmethod
    def round_jobs(jobs, r):
        """Round r's order: the scene-and-size groups rotated, and within each
        group its configurations rotated, so that off and on swap places every
        round (rotating the whole list kept each pair in one order)."""
        groups = {}
        for name in jobs:
            groups.setdefault(name.rsplit("_", 1)[0], []).append(name)
        return [name for g in common.round_order(list(groups), r) for name in common.round_order(groups[g], r)]

    def all(self):
        t0 = time.time()
        trivial = os.path.join(self.out, "trivial.mtlx")
        bench_materials.write_trivial(trivial)
        flat = os.path.join(self.out, bench_heavy.FLAT_MTLX)
        bench_heavy.flat_materials(bench_heavy.SCENE[2], flat, bench_heavy.stand_in_colours(bench_heavy.STAND_INS))
        # Per scene, the renders of its ceiling (cacheless, no network runs).
        ceilings = {"default": ["data/default/room.obj", "--mtlx", trivial, "--cache", "off"],
                    "heavy": [bench_heavy.SCENE[0], "--mtlx", flat, "--cache", "off"]}
        only = [s for s in self.a.only.split(",") if s]
        sizes = [tuple(int(v) for v in s.split("x")) for s in self.a.sizes.split(",")]
        jobs = {}  # name -> (args, size)
        for key, _, args in SCENES:
            if only and key not in only:
                continue
            if args == PEER:
                args = peer_scenes.render_args(peer_scenes.write_scene_files(key, os.path.join(self.out, "scenes", key)))
            for size in sizes:
                for cfg, extra in CONFIGS.items():
                    if cfg == "nodes" and key not in self.a.nodes.split(","):
                        continue
                    jobs[f"{key}_{size[0]}x{size[1]}_{cfg}"] = (args + extra, size)
                if key in ceilings:
                    jobs[f"{key}_{size[0]}x{size[1]}_ceiling"] = (ceilings[key], size)
        for name, (args, size) in jobs.items():  # untimed, small: kernel builds, file cache, calibration
            self.render(name, args, (32, 18), spp=1)
        load = common.LoadSampler()
        seconds = {n: [] for n in jobs}
        stats = {}
        for r in range(self.a.runs):
            print(f"{PROG}: round {r + 1} of {self.a.runs}", flush=True)
            for name in self.round_jobs(jobs, r):
                s = self.render(name, *jobs[name])
                times = [s["render_seconds"]]
                # A render this short is noise-bound, and its place after another job's long render
                # moved it by about 5%: repeat it until the repeats add up, and keep the median.
                while sum(times) < self.a.short_seconds and len(times) < self.a.short_repeats:
                    times.append(self.render(name, *jobs[name])["render_seconds"])
                seconds[name].append(common.median(times))
                stats[name] = s
                load.sample()
        device = next(iter(stats.values()))["device"] if stats else ""
        keep = {n: dict(cache=s["cache"]) for n, s in stats.items()}
        return dict(command=self.a.command, now=common.utc_now(), rev=common.git_rev(ignore=["docs/BENCHMARKS.md"]),
                    machine=common.machine(device), load=load.note(), elapsed=time.time() - t0, runs=self.a.runs,
                    spp=self.a.spp, short=[self.a.short_seconds, self.a.short_repeats], sizes=[list(s) for s in sizes], scenes=[k for k, _, _ in SCENES
                                                                               if not only or k in only],
                    seconds=seconds, stats=keep)


def plan_text(cache):
    if not cache.get("enabled"):
        return "none (cache off)"
    return f"{cache['hit_rate'] * 100:.1f}% hits"


def predicted_units(data, base):
    """The model's predicted saving of a cached render, in unit nodes (and with
    the measured hit rates), or None without a model or points."""
    model = data["stats"][f"{base}_cost"]["cache"].get("model")
    if not model or model["predicted_saving_seconds"] == 0:
        return None
    return 1e9 * model["predicted_saving_seconds"] / model["unit_ns"], \
        1e9 * model["saving_at_measured_hit_rates_seconds"] / model["unit_ns"]


def fitted_unit_ns(data):
    """The median over the rows of measured saving / predicted unit nodes:
    the time a unit node would need for the model to be right on the median
    row (it predicts savings relative to each other)."""
    implied = []
    for key in data["scenes"]:
        for w, h in data["sizes"]:
            base = f"{key}_{w}x{h}"
            units = predicted_units(data, base)
            if units and units[0] > 0:
                saving = common.median(data["seconds"][f"{base}_off"]) - common.median(data["seconds"][f"{base}_cost"])
                implied.append(1e9 * saving / units[0])
    return common.median(implied) if implied else float("nan")


def short_text(data):
    """How the run treated short renders (runs before the option have no entry)."""
    if "short" not in data:
        return ""
    s, n = data["short"]
    return (f" (a render under {s:g} s runs again, back to back, until its renders add up to {s:g} s, at most "
            f"{n} in a round, which keeps their median: such a render is noise-bound, and where the line "
            f"pattern's pair followed a long render, the first of the two read about 5% faster than the second)")


def report(data):
    names = {k: n for k, n, _ in SCENES}
    unit = fitted_unit_ns(data)
    model_unit = "none reported"
    for st in data["stats"].values():
        if st["cache"].get("model"):
            model_unit = f"{st['cache']['model']['unit_ns']:.2f} ns"
            break
    rows, printed, ratios_all = [], [], []
    costs = ""
    for key in data["scenes"]:
        for w, h in data["sizes"]:
            base = f"{key}_{w}x{h}"
            off = data["seconds"][f"{base}_off"]
            off_med = common.median(off)
            cells = [names[key], f"{w}x{h}", f"{off_med:.2f}"]
            for cfg in ("cost", "nodes"):
                if f"{base}_{cfg}" not in data["seconds"]:
                    cells += ["-", "-"]
                    continue
                on = data["seconds"][f"{base}_{cfg}"]
                r, lo, hi = common.median_range(common.round_ratios(off, on))
                cells += [f"{common.median(on):.2f}", f"**{r:.2f}x** ({lo:.2f}-{hi:.2f})"]
                if cfg == "cost":
                    same = not data["stats"][f"{base}_cost"]["cache"].get("enabled", True)
                    ratios_all.append((names[key], f"{w}x{h}", r, same))
            cache = data["stats"][f"{base}_cost"]["cache"]
            model = cache.get("model")
            units = predicted_units(data, base)
            if model:
                costs = costs or f"{model['costs']}: lookup L {model['lookup']:.1f}, miss M {model['miss']:.1f} + " \
                                 f"{model['miss_per_cost']:.2f} x C unit nodes"
            if units:
                saving = off_med - common.median(data["seconds"][f"{base}_cost"])
                def ratio(seconds):
                    return f"{off_med / (off_med - seconds):.2f}x" if seconds < off_med else "more than off"

                pred = ratio(model["predicted_saving_seconds"])
                pred_h = ratio(model["saving_at_measured_hit_rates_seconds"])
                cells += [f"{pred} ({pred_h})", f"{1e9 * saving / units[0]:.1f}",
                          f"{model['expected_uv_hit_rate'] * 100:.0f}% / {cache['uv_hit_rate'] * 100:.0f}%"]
            else:
                cells += ["1.00x (no point pays: the cacheless program)", "-", "-"]
            ceiling = data["seconds"].get(f"{base}_ceiling")
            if ceiling:
                c = common.median(common.round_ratios(off, ceiling))
                cost_r = common.median(common.round_ratios(off, data["seconds"][f"{base}_cost"]))
                cells.append(f"{c:.2f}x (on: {100 * cost_r / c:.0f}% of it)")
            else:
                cells.append("-")
            rows.append(cells)
            printed.append(f"{key:14s} {w}x{h}: " + " | ".join(cells[2:]))
    table = common.md_table(["scene", "size", "off (s)", "on, cost model (s)", "off / on (range of rounds)",
                             "on, node count (s)", "off / on (range)",
                             "predicted off / on (at the measured hit rates)", "measured ns per predicted unit node",
                             "uv hit rate expected / measured", "ceiling: constant materials"], rows)
    slow = [f"{n} {s} {r:.2f}x" for n, s, r, same in ratios_all if r < 0.98 and not same]
    same = [r for _, _, r, same in ratios_all if same]
    same_text = (f" Rows whose cached render turned the cache off (no point pays: `cache.enabled` false, the "
                 f"cacheless program both ways, the same pixels) are left out of that count: {len(same)} of them, "
                 f"their ratios {min(same):.2f}-{max(same):.2f}, the noise of timing one program twice."
                 if same else "")
    head = (f"Produced by `{data['command']}` on {data['now']} ({data['elapsed'] / 60:.1f} minutes).\n"
            f"Machine: {data['machine']}; checkout {data['rev']}; {data['load']}.\n")
    section = f"""{SECTION}

{head}
Method (`scripts/bench/cache_model.py`): per scene and size, `--cache off`, `--cache on` (the cost
model, `--cache-model cost`, the default) and, where the table has the column, `--cache on
--cache-model nodes` (the node count alone, the plan before the model); {common.rounds_text(data['runs'])},
every render once per round, the order rotated (the groups, and the renders within each), {data['spp']} spp{short_text(data)}; medians of
`render_seconds` and of the rounds' off / on ratios. The prediction is the model's: `pmc render --stats` reports
`cache.model.predicted_saving_seconds`, each point's gain per lookup (h C - L - (1 - h) M, unit
nodes) times the lookups its material's shaded hits made, times the calibrated time of a unit node
({model_unit}); the predicted ratio is off / (off - saving) with the measured off time, in brackets the
same with the measured hit rates. "Measured ns per predicted unit node" divides the measured saving
(off - on) by the predicted unit nodes: were the model right up to its time scale, it would be the
same on every row (the median here: {unit:.1f} ns). Costs: {costs or 'none reported'}. The ceiling renders the default scene with
every material constant, and the heavy scene with its networks' shaders given constant inputs (the same
lobes), so that no network runs: what a cache that always hit for free could reach.

    build/pmc render SCENE --cache off|on [--cache-model nodes] -o OUT.exr --stats OUT.json --width W --height H --spp {data['spp']} --quiet

{table}

Cache on with the cost model below 0.98x of off (median of the rounds): {', '.join(slow) if slow else 'none'}.{same_text}
"""
    return section, "\n".join(printed)


def main(argv=None):
    args = parse(argv)
    common.measure_and_report(args, PROG, SECTION, lambda a: Measure(a).all(), report,
                              inputs=("data/default/room.obj", bench_heavy.SCENE[0], bench_heavy.SCENE[2]))


if __name__ == "__main__":
    main()
