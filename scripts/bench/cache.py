"""bench.cache — the progressive material cache, off vs on, at equal samples
on several scenes; --cache-eval hit vs center (with nearest and with bilinear
texel selection) on the default scene; and the cache point threshold
(--cache-min-nodes) on the default scene. Prints tables and writes the
"Cache: off vs on" section of docs/BENCHMARKS.md, and copies the per-scene
images (the paper's Fig. 1) to PLOTS/scenes.

    scripts/python -m bench.cache                  build/pmc (scripts/setup first if it is missing)
    scripts/python -m bench.cache --runs 5         timed rounds (default 3; medians)
    scripts/python -m bench.cache --only default,eval --runs 1 --spp 4 --doc -    a quick look
    scripts/python -m bench.cache --report-only    the tables and section from --out-dir's results.json

Method, per scene:
  1. one 1-spp render with the cache off and one with it on, not timed.
     PoCL's kernel compile is not in render_seconds (pmc launches every
     kernel once with no work before timing and reports that separately as
     kernel_warmup_seconds); these renders only fill PoCL's on-disk kernel
     cache (~/.cache/pocl) and the OS file cache (scene, textures) so the
     timed renders all start alike;
  2. two `pmc compare` (same seed, same samples, cache on vs off): at SPP for
     PSNR, relMSE and max error of cache on vs cache off, hit rate, cache
     memory; and at SPP/4 (at least 1) for PSNR only. The cache's bias does
     not shrink with samples, the decorrelated path noise does, so PSNR
     rising from SPP/4 to SPP shows how much of the difference is noise;
  3. RUNS rounds of `pmc render --cache off` and `--cache on` with --stats,
     alternating which goes first, so both share the machine's noise. The
     table shows the median render_seconds of each and their ratio, plus the
     range of the per-round ratios (off/on of the same round).
eval (default scene, half the table's size, EVAL_SPP): a cacheless reference
with REF_SPP samples and another seed; `pmc compare --reference` once per
cached configuration (--cache-eval hit; --cache-eval center --cache-filter
nearest; --cache-eval center --cache-filter bilinear) for the errors; RUNS
interleaved rounds of off and the three cached configurations (times); each
cached configuration once more, compared with its first round's image (the
same command again).
threshold (default scene, the table's size, THRESHOLD_SPP): RUNS rounds of
`--cache off` and `--cache-min-nodes T` for T in 3,4,8,16,32,64, the order
reversed every other round; per T the median render_seconds, off / on
(median over median), the range of the per-round ratios, the hit rate and
the cache points (`pmc info --dump-cache-plan --cache-min-nodes T`).
"""
import json
import math
import os
import re
import shutil
import sys
import time

from bench import common

PROG = "bench.cache"
SECTION = "## Cache: off vs on (scripts/bench-cache)"
LEGACY = {"RUNS": "--runs", "SPP": "--spp", "EVAL_SPP": "--eval-spp", "REF_SPP": "--ref-spp",
          "THRESHOLD_SPP": "--threshold-spp", "ONLY": "--only", "OUTDIR": "--out-dir", "DOC": "--doc",
          "PMC": "--pmc", "PLOTS": "--plots", "REPORT_ONLY": "--report-only"}
FIGURE_SCENES = ["default", "teapot", "sponza", "sponza_brick", "lines"]  # Fig. 1 style images
PAPER_MB = 763           # the paper's 10^7 cells x 10 entries
THRESHOLDS = [3, 4, 8, 16, 32, 64]
DEFAULT_MIN_NODES = 8    # pmc's --cache-min-nodes default

SHARED = common.SHARED_SCENES
DEFAULT_ARGS = ["data/default/room.obj", "--mtlx", "data/default/materials.mtlx"]
SCENES = [
    dict(key="default", name="default room (`data/default`)", args=DEFAULT_ARGS),
    dict(key="teapot", name="brick teapot (`M_BrickPattern`)",
         args=[f"{SHARED}/materialx/geometry/teapot.obj", "--mtlx",
               f"{SHARED}/materialx/standard_surface_brick_procedural.mtlx", "--material", "M_BrickPattern",
               "--env", "1,1,1", "--camera-from", "0.75,1.0,2.45", "--camera-at", "-0.09,0.05,-0.01",
               "--fov", "45"]),
    dict(key="sponza", name="Sponza (MTL materials)",
         args=[f"{SHARED}/sponza/sponza.obj", "--camera-from", "-110,20,0", "--camera-at", "100,20,0",
               "--fov", "45", "--env", "1,1,1", "--max-depth", "4"]),
    dict(key="sponza_forced", name="Sponza, `--cache-min-nodes 3` (Kd x texture forced into the cache)",
         args=[f"{SHARED}/sponza/sponza.obj", "--camera-from", "-110,20,0", "--camera-at", "100,20,0",
               "--fov", "45", "--env", "1,1,1", "--max-depth", "4", "--cache-min-nodes", "3"]),
    dict(key="sponza_brick", name="Sponza with the procedural brick on every surface (`M_BrickPattern`)",
         args=[f"{SHARED}/sponza/sponza.obj", "--mtlx", f"{SHARED}/materialx/standard_surface_brick_procedural.mtlx",
               "--material", "M_BrickPattern", "--camera-from", "-110,20,0", "--camera-at", "100,20,0",
               "--fov", "45", "--env", "1,1,1", "--max-depth", "4"]),
    dict(key="lines", name="line pattern plane (`linepattern.mtlx` `test_union`, `--cache-min-nodes 4`)",
         args=[f"{SHARED}/materialx/geometry/plane.obj", "--mtlx", f"{SHARED}/materialx/linepattern.mtlx",
               "--material", "test_union", "--env", "1,1,1", "--camera-from", "0,-0.75,0.65",
               "--camera-at", "0,-0.05,0", "--fov", "45", "--cache-min-nodes", "4"]),
]
PARTS = [s["key"] for s in SCENES] + ["eval", "threshold"]
# The hit vs center study: name, options. Names are the keys in results.json.
EVAL_CONFIGS = [
    ("hit", ["--cache-eval", "hit"]),
    ("center_nearest", ["--cache-eval", "center", "--cache-filter", "nearest"]),
    ("center_bilinear", ["--cache-eval", "center", "--cache-filter", "bilinear"]),
]
EVAL_SHORT = {"hit": "hit", "center_nearest": "center nearest", "center_bilinear": "center bilinear",
              "center": "center"}  # "center": results.json of runs before --cache-filter
# What a failing part may raise; caught per part so the others still report.
PART_ERRORS = (common.RunFailed, OSError, KeyError, ValueError, TypeError, ZeroDivisionError)


def parse(argv=None):
    p = common.make_parser("cache", __doc__, LEGACY)
    common.add_pmc(p)
    common.add_runs(p, 3)
    p.add_argument("--spp", type=common.positive_int, default=64, metavar="N",
                   help="samples per pixel of the off/on table (default 64; its PSNR is also measured at N/4)")
    p.add_argument("--width", type=common.positive_int, default=320, metavar="W",
                   help="image width of the off/on table and the threshold study (default 320; the eval "
                        "study renders at half the size)")
    p.add_argument("--height", type=common.positive_int, default=180, metavar="H", help="image height (default 180)")
    p.add_argument("--eval-spp", type=common.positive_int, default=64, metavar="N",
                   help="samples of the hit/center study (default 64)")
    p.add_argument("--ref-spp", type=common.positive_int, default=256, metavar="N",
                   help="samples of its cacheless reference (default 256)")
    p.add_argument("--threshold-spp", type=common.positive_int, default=16, metavar="N",
                   help="samples of the --cache-min-nodes study (default 16)")
    p.add_argument("--only", default="", metavar="PARTS",
                   help=f"comma-separated parts to run (default all): {','.join(PARTS)} "
                        "(eval: the hit vs center study; threshold: the --cache-min-nodes study)")
    common.add_out_dir(p, "out/bench-cache")
    common.add_doc(p)
    p.add_argument("--plots", default="docs/plots", metavar="DIR",
                   help="the per-scene images go to DIR/scenes (default docs/plots)")
    p.add_argument("--report-only", action="store_true",
                   help="render nothing: rewrite the tables and the section from OUT_DIR/results.json of the "
                        "last run")
    args = common.parse_args(p, "cache", LEGACY, argv)
    args.only = [k for k in args.only.split(",") if k]
    for k in args.only:
        if k not in PARTS:
            p.error(f"--only: unknown part '{k}' (known: {','.join(PARTS)})")
    return args


def progress(msg):
    print(f"{PROG}: {msg}", flush=True)


def mib(b):
    return b / 2**20


# ---- measurements ----------------------------------------------------------------
class Measure:
    """Runs pmc for the parts; every command goes to OUT/log.txt."""

    def __init__(self, args):
        self.a = args
        self.pmc = args.pmc
        self.out = args.out_dir
        self.w, self.h = args.width, args.height
        self.ew, self.eh = max(1, args.width // 2), max(1, args.height // 2)
        self.spp_q = max(1, args.spp // 4)  # second PSNR column: PSNR rising with samples is decorrelated noise
        self.log = os.path.join(self.out, "log.txt")
        open(self.log, "w").close()

    def run(self, cmd, what):
        return common.run(cmd, self.log, what, append=True).output

    def render(self, scene_args, tag, cache, w, h, spp, extra=()):
        exr, js = f"{self.out}/{tag}.exr", f"{self.out}/{tag}.json"
        cmd = [self.pmc, "render", *scene_args, "-o", exr, "--stats", js, "--cache", cache,
               *common.size_args(w, h, spp), *extra]
        return common.run_pmc(cmd, js, self.log, f"render {tag}", append=True)[0]

    def compare(self, scene_args, tag, w, h, spp, extra=()):
        d = f"{self.out}/{tag}"
        self.run([self.pmc, "compare", *scene_args, "--out-dir", d, *common.size_args(w, h, spp), *extra],
                 f"compare {tag}")
        return common.read_json(f"{d}/metrics.json")

    def cache_plan(self, scene_args, w, h, spp):
        """Sizes (nodes) of the sub-graphs `pmc info --dump-cache-plan` caches
        for a w x h frame of spp samples (the cost model's plan depends on them)."""
        info = [self.pmc, "info", "--scene", scene_args[0], "--dump-cache-plan", "--width", str(w), "--height", str(h),
                "--spp", str(spp)]
        for i, x in enumerate(scene_args):
            if x in ("--mtlx", "--material", "--cache-min-nodes", "--max-depth", "--cache-model"):
                info += [x, scene_args[i + 1]]
        out = self.run(info, "info --dump-cache-plan")
        return [int(n) for n in re.findall(r"^\s*\+ .*saves a sub-graph of (\d+) nodes", out, re.M)]

    def scene(self, s):
        key, a, W, H, SPP = s["key"], s["args"], self.w, self.h, self.a.spp
        progress(f"{key}: warm-up (untimed)")
        self.render(a, f"{key}_warm_off", "off", W, H, 1)
        self.render(a, f"{key}_warm_on", "on", W, H, 1)
        plan = self.cache_plan(a, W, H, SPP)
        progress(f"{key}: pmc compare, {SPP} spp")
        m = self.compare(a, f"{key}_compare", W, H, SPP)
        progress(f"{key}: pmc compare, {self.spp_q} spp")
        mq = self.compare(a, f"{key}_compare_{self.spp_q}spp", W, H, self.spp_q)
        t = {"off": [], "on": []}
        stats_on = None
        device = ""
        for r in range(self.a.runs):
            got = {}
            for c in common.round_order(("off", "on"), r, "reverse"):
                st = self.render(a, f"{key}_{c}_{r}", c, W, H, SPP)
                device = st.get("device", device)
                got[c] = st["render_seconds"]
                t[c].append(got[c])
                if c == "on":
                    stats_on = st
            progress(f"{key}: round {r + 1}/{self.a.runs}: off {got['off']:.2f} s, on {got['on']:.2f} s")
        cache = stats_on.get("cache", {}) if stats_on else {}
        return device, dict(scene=s, ok=True, t_off=common.median(t["off"]), t_on=common.median(t["on"]),
                            ratios=common.round_ratios(t["off"], t["on"]),
                            times=t, psnr=m["psnr"], relmse=m["relmse"], max_abs=m["max_abs_error"],
                            psnr_q=mq["psnr"], relmse_q=mq["relmse"], spp_q=self.spp_q,
                            hit_rate=cache.get("hit_rate", m.get("hit_rate", 0.0)),
                            memory=cache.get("memory_bytes", m.get("cache_memory_bytes", 0)),
                            cells=cache.get("cells", 0), entries=cache.get("entries", 0),
                            enabled=cache.get("enabled", bool(m.get("cache_memory_bytes"))),
                            compare_times=(m["time_off_seconds"], m["time_on_seconds"]), plan=plan)

    def evals(self):
        a, EW, EH, EVAL_SPP, REF_SPP = DEFAULT_ARGS, self.ew, self.eh, self.a.eval_spp, self.a.ref_spp
        progress(f"eval: cacheless reference, {REF_SPP} spp at {EW}x{EH}")
        ref = f"{self.out}/eval_reference.exr"
        self.run([self.pmc, "render", *a, "-o", ref, "--cache", "off", "--seed", "7919",
                  *common.size_args(EW, EH, REF_SPP)], "reference")
        errs = {}
        for name, extra in EVAL_CONFIGS:
            progress(f"eval: pmc compare {' '.join(extra)}")
            errs[name] = self.compare(a, f"eval_compare_{name}", EW, EH, EVAL_SPP, [*extra, "--reference", ref])
        configs = [("off", "off", [])] + [(name, "on", extra) for name, extra in EVAL_CONFIGS]
        times = {name: [] for name, _, _ in configs}
        hits = {}
        for r in range(self.a.runs):
            for name, cache, extra in common.round_order(configs, r, "reverse"):
                st = self.render(a, f"eval_{name}_{r}", cache, EW, EH, EVAL_SPP, extra)
                times[name].append(st["render_seconds"])
                if name != "off":
                    hits[name] = st["cache"]["hit_rate"]
            progress(f"eval: round {r + 1}/{self.a.runs}: " +
                     ", ".join(f"{n} {times[n][-1]:.2f} s" for n, _, _ in configs))
        # Run to run: the same command again, compared with the first round's image.
        again = {}
        for name, extra in EVAL_CONFIGS:
            progress(f"eval: same seed again, {' '.join(extra)}")
            again[name] = self.compare(a, f"eval_again_{name}", EW, EH, EVAL_SPP,
                                       [*extra, "--reference", f"{self.out}/eval_{name}_0.exr"]
                                       )["cached_vs_reference"]["psnr"]
        return dict(configs=[[name, extra] for name, extra in EVAL_CONFIGS], errs=errs,
                    times={k: common.median(v) for k, v in times.items()}, all_times=times, hits=hits, again=again)

    def threshold(self):
        a, W, H, SPP = DEFAULT_ARGS, self.w, self.h, self.a.threshold_spp
        progress("threshold: warm-up (untimed)")
        self.render(a, "threshold_warm_off", "off", W, H, 1)
        self.render(a, "threshold_warm_on", "on", W, H, 1)
        # The node count alone (--cache-model nodes): under the cost model the
        # threshold is only a floor, and this study measures the threshold.
        by_nodes = ["--cache-model", "nodes"]
        plans = {T: self.cache_plan([*a, "--cache-min-nodes", str(T), *by_nodes], W, H, SPP) for T in THRESHOLDS}
        configs = [("off", "off", [])] + [(str(T), "on", ["--cache-min-nodes", str(T), *by_nodes])
                                          for T in THRESHOLDS]
        times = {name: [] for name, _, _ in configs}
        stats = {}
        for r in range(self.a.runs):
            got = {}
            for name, cache, extra in common.round_order(configs, r, "reverse"):
                st = self.render(a, f"threshold_{name}_{r}", cache, W, H, SPP, extra)
                got[name] = st["render_seconds"]
                times[name].append(got[name])
                stats[name] = st
            progress(f"threshold: round {r + 1}/{self.a.runs}: " + ", ".join(
                f"{'off' if n == 'off' else 'T=' + n} {got[n]:.2f} s" for n, _, _ in configs))
        rows = []
        for T in THRESHOLDS:
            c = stats[str(T)].get("cache", {})
            rows.append(dict(T=T, times=times[str(T)], t_on=common.median(times[str(T)]),
                             ratios=common.round_ratios(times["off"], times[str(T)]),
                             hit_rate=c.get("hit_rate", 0.0), enabled=c.get("enabled", False) and bool(plans[T]),
                             memory=c.get("memory_bytes", 0), plan=plans[T]))
        return dict(spp=SPP, times_off=times["off"], t_off=common.median(times["off"]), rows=rows)

    def all(self, scenes, run_eval, run_threshold):
        now = common.utc_now()
        try:
            load = "%.1f" % os.getloadavg()[0]
        except OSError:
            load = "?"
        results = []
        device = ""
        started = time.time()
        for s in scenes:
            try:
                dev, res = self.scene(s)
                device = dev or device
                results.append(res)
            except PART_ERRORS as e:
                progress(f"{s['key']}: FAILED: {e}" + (f"\n{e.tail}" if getattr(e, "tail", "") else ""))
                results.append(dict(scene=s, ok=False, error=str(e) or repr(e)))
        evals = threshold = None
        if run_eval:
            try:
                evals = self.evals()
            except PART_ERRORS as e:
                progress(f"eval: FAILED: {e}")
                evals = dict(error=str(e) or repr(e))
        if run_threshold:
            try:
                threshold = self.threshold()
            except PART_ERRORS as e:
                progress(f"threshold: FAILED: {e}")
                threshold = dict(error=str(e) or repr(e))
        a = self.a
        return dict(results=results, evals=evals, threshold=threshold, elapsed=time.time() - started,
                    device=device, now=now, load=load, rev=common.git_rev(), cpu=common.cpu_model(),
                    cores=os.cpu_count(), command=a.command, runs=a.runs, spp=a.spp, spp_q=self.spp_q,
                    eval_spp=a.eval_spp, ref_spp=a.ref_spp, threshold_spp=a.threshold_spp, outdir=self.out,
                    width=self.w, height=self.h, eval_width=self.ew, eval_height=self.eh)


# ---- report ------------------------------------------------------------------------
def plan_text(plan):
    if not plan:
        return "none"
    if len(plan) == 1:
        return f"1 ({plan[0]} nodes)"
    if min(plan) == max(plan):
        return f"{len(plan)} ({plan[0]} nodes each)"
    return f"{len(plan)} ({min(plan)}-{max(plan)} nodes)"


def psnr_text(p):
    if p is None:
        return "-"
    return "identical (999)" if p >= 999 else f"{p:.1f}"


def again_text(p):
    return "-" if p is None else ("identical" if p >= 999 else f"{p:.1f} dB")


def goal(ok):
    return "met" if ok else "**not met**"


def report(data, plots, doc):
    """(section, text to print) from the measurements `data` (results.json)."""
    results, evals, elapsed = data["results"], data["evals"], data["elapsed"]
    threshold = data.get("threshold")
    RUNS, SPP, EVAL_SPP, REF_SPP, OUT = data["runs"], data["spp"], data["eval_spp"], data["ref_spp"], data["outdir"]
    SPP_Q = data.get("spp_q", max(1, SPP // 4))
    W, H = data.get("width", 320), data.get("height", 180)
    EW, EH = data.get("eval_width", 160), data.get("eval_height", 90)
    rounds = common.rounds_text
    machine = f"{data['cores']} cores ({data['cpu']}), OpenCL device: {data['device'] or 'unknown'}"
    load = f"load average when it started: {data['load']}"

    rows = []
    for r in results:
        s = r["scene"]
        if not r["ok"]:
            rows.append([s["name"], f"failed: {r['error'].splitlines()[0]}", "", "", "", "", "", "", "", ""])
            continue
        lo, hi = min(r["ratios"]), max(r["ratios"])
        mem = f"{mib(r['memory']):.1f} MiB ({r['cells']} x {r['entries']})" if r["enabled"] else "not used"
        rows.append([s["name"], plan_text(r.get("plan")), f"{r['t_off']:.2f}", f"{r['t_on']:.2f}",
                     f"**{r['t_off'] / r['t_on']:.2f}x** ({lo:.2f}-{hi:.2f})", f"{100 * r['hit_rate']:.1f}%", mem,
                     psnr_text(r.get("psnr_q")), psnr_text(r["psnr"]), f"{r['relmse']:.2g}"])
    table = common.md_table(
        ["scene", "cache points (sub-graph sizes)", "off (s)", "on (s)", "off / on (range of rounds)", "hit rate",
         "cache memory", f"PSNR on vs off at {SPP_Q} spp (dB)", f"PSNR on vs off at {SPP} spp (dB)",
         f"relMSE on vs off at {SPP} spp"], rows)

    by_key = {r["scene"]["key"]: r for r in results if r["ok"]}
    goals = []
    if "default" in by_key:
        r = by_key["default"]
        x = r["t_off"] / r["t_on"]
        goals.append(f"- **>= 1.5x on the default scene** (the paper's best is 1.31x): {x:.2f}x, "
                     f"{goal(x >= 1.5)} at {SPP} spp, {100 * r['hit_rate']:.0f}% hits.")
    if "sponza" in by_key:
        r = by_key["sponza"]
        x = r["t_off"] / r["t_on"]
        goals.append(f"- **never slower than 0.99x on Sponza**: {x:.2f}x (rounds {min(r['ratios']):.2f}-"
                     f"{max(r['ratios']):.2f}), {goal(x >= 0.99)}. " +
                     ("Nothing in Sponza's MTL networks (Kd x texture, 3 nodes) is worth a cache point, so pmc "
                      "turns the cache off and both runs are the same program; the spread is the machine's noise."
                      if not r["enabled"] else ""))
    cached = [r for r in results if r["ok"] and r["enabled"]]
    psnr_met = [f"{r['scene']['key']} {r['psnr']:.1f} dB" for r in cached if r["psnr"] >= 40]
    psnr_missed = [f"{r['scene']['key']} {r['psnr']:.1f} dB" for r in cached if r["psnr"] < 40]
    if cached:
        low_q = [r for r in cached if r.get("psnr_q") is not None and r["psnr_q"] < 40 and r["psnr"] >= 40]
        goals.append(f"- **PSNR >= 40 dB vs the cacheless render at equal samples ({SPP} spp)**: " +
                     (f"met on {', '.join(psnr_met)}" if psnr_met else "met nowhere") +
                     (f"; **not met** on {', '.join(psnr_missed)}" if psnr_missed else "; met on every scene that "
                      "uses the cache") + " (scenes without cache points render identical images)." +
                     ((f" At {SPP_Q} spp the same comparison gives " + ", ".join(
                         f"{r['scene']['key']} {r['psnr_q']:.1f} dB" for r in low_q) +
                       ": **below 40 dB at the lower sample count**, because the on/off difference there is mostly "
                       "decorrelated path noise, which shrinks with samples (see the first note).") if low_q else ""))
        goals.append(f"- **memory far below the paper's {PAPER_MB} MB**: " + ", ".join(
            f"{r['scene']['key']} {mib(r['memory']):.0f} MiB at {100 * r['hit_rate']:.0f}% hits" for r in cached) +
            f"; {goal(all(mib(r['memory']) * 10 < PAPER_MB for r in cached))} (at least 10x smaller).")

    eval_title = "### `--cache-eval hit` vs `center`, `--cache-filter nearest` vs `bilinear` (default scene)"
    eval_text = ""
    if evals and "errs" in evals:
        e, t, hits = evals["errs"], evals["times"], evals["hits"]
        again = evals.get("again", {})
        names = [n for n, _ in evals["configs"]] if "configs" in evals else [n for n in ("hit", "center") if n in e]
        opts = ({n: " ".join(x) for n, x in evals["configs"]} if "configs" in evals
                else {n: f"--cache-eval {n}" for n in names})
        off_ref = e[names[0]]["cacheless_vs_reference"]["relmse"]
        rel = {n: e[n]["cached_vs_reference"]["relmse"] for n in names}
        lines = [["cache off", f"{t['off']:.2f}", "1.00x", "-", f"{off_ref:.4g}", "-", "-", "-"]]
        for n in names:
            default = " (default)" if n == "center_bilinear" else ""
            lines.append([f"`{opts[n]}`{default}", f"{t[n]:.2f}", f"{t['off'] / t[n]:.2f}x", f"{100 * hits[n]:.1f}%",
                          f"{rel[n]:.4g}", f"{100 * (rel[n] / off_ref - 1):+.1f}%", psnr_text(e[n]["psnr"]),
                          again_text(again.get(n))])
        by_err = sorted(names, key=rel.get)
        by_time = sorted(names, key=t.get)
        err_gap = (rel[by_err[1]] - rel[by_err[0]]) / off_ref if len(names) > 1 else 0.0
        time_gap = (t[by_time[1]] - t[by_time[0]]) / t[by_time[1]] if len(names) > 1 else 0.0
        err_line = "Lowest error: " + ", then ".join(
            f"{EVAL_SHORT.get(n, n)} ({100 * (rel[n] / off_ref - 1):+.1f}%{' relMSE added' if i == 0 else ''})"
            for i, n in enumerate(by_err))
        if len(names) > 1:
            err_line += (f"; the first two differ by {100 * err_gap:.1f}% of the cacheless relMSE"
                         f"{': within noise' if err_gap < 0.01 else ''}")
        time_line = "Fastest: " + ", then ".join(
            f"{EVAL_SHORT.get(n, n)} ({t[n]:.2f} s, {t['off'] / t[n]:.2f}x{' off / on' if i == 0 else ''})"
            for i, n in enumerate(by_time))
        if len(names) > 1:
            time_line += (f"; the first two differ by {100 * time_gap:.0f}%"
                          f"{': within noise' if time_gap < 0.05 else ''}")
        eval_table = common.md_table(["render", "time (s)", "off / on", "hit rate", "relMSE vs reference",
                                      "relMSE added", "PSNR on vs off (dB)", "same command again"], lines)
        eval_text = f"""
{eval_title}

{EW}x{EH}, {EVAL_SPP} spp (enough samples that the cache's bias shows above the
noise), median of {rounds(RUNS)}, interleaved, of off and the {len(names)} cached
configurations (order reversed every other round); errors from one
`pmc compare OPTIONS --reference REF.exr` each, against a cacheless
{REF_SPP}-spp reference rendered with another seed. "relMSE added" is how much
the cache adds to the cacheless render's relMSE vs the reference.

{eval_table}

"same command again": PSNR between two renders with identical options and
seed.

{err_line}.
{time_line}. See the notes for why.
"""
    elif evals:
        eval_text = f"\n{eval_title}\n\nfailed: {evals['error']}\n"

    threshold_title = "### Cache point threshold (`--cache-min-nodes`)"
    threshold_text = ""
    if threshold and "rows" in threshold:
        th = threshold
        t_off = th["t_off"]
        trows = [["cache off", "-", f"{t_off:.2f}", "1.00x", "-"]]
        for row in th["rows"]:
            ratio = t_off / row["t_on"]
            default = " (default)" if row["T"] == DEFAULT_MIN_NODES else ""
            hit = f"{100 * row['hit_rate']:.1f}%" if row["enabled"] else "- (cache off: no cache point)"
            trows.append([f"`--cache-min-nodes {row['T']}`{default}", plan_text(row["plan"]), f"{row['t_on']:.2f}",
                          f"**{ratio:.2f}x** ({min(row['ratios']):.2f}-{max(row['ratios']):.2f})", hit])
        best = min(th["rows"], key=lambda row: row["t_on"])
        dflt = next((row for row in th["rows"] if row["T"] == DEFAULT_MIN_NODES), None)
        if dflt is None:
            verdict = f"Fastest in this run: `--cache-min-nodes {best['T']}` ({t_off / best['t_on']:.2f}x)."
        elif best is dflt:
            verdict = f"Fastest in this run: the default, {best['T']} ({t_off / best['t_on']:.2f}x)."
        else:
            gap = (dflt["t_on"] - best["t_on"]) / dflt["t_on"]
            verdict = (f"Fastest in this run: `--cache-min-nodes {best['T']}` ({t_off / best['t_on']:.2f}x); the "
                       f"default gave {t_off / dflt['t_on']:.2f}x, {100 * gap:.0f}% slower"
                       f"{': within noise' if gap < 0.05 else ''}.")
        threshold_cmd = " ".join(["build/pmc", "render", *DEFAULT_ARGS, "-o", "OUT.exr", "--stats", "OUT.json",
                                  "--cache", "off|on", "--cache-min-nodes", "T", *common.size_args(W, H, th["spp"])])
        threshold_table = common.md_table(["configuration", "cache points (sub-graph sizes)", "time (s)",
                                           "off / on (range of rounds)", "hit rate"], trows)
        threshold_text = f"""
{threshold_title}

Default scene, {W}x{H}, {th['spp']} spp: {rounds(RUNS)} of `--cache off` and
`--cache-min-nodes T` for T = {', '.join(str(row['T']) for row in th['rows'])}, the order reversed every
other round. Time is the median `render_seconds`; "off / on" is median off over
median on, in brackets the lowest and highest ratio of a single round. Cache
points as `pmc info --dump-cache-plan --cache-min-nodes T` lists them.

    {threshold_cmd}

{threshold_table}

The default is `--cache-min-nodes {DEFAULT_MIN_NODES}`. {verdict}
"""
    elif threshold:
        threshold_text = f"\n{threshold_title}\n\nfailed: {threshold['error']}\n"

    # Fig. 1 of the paper, per scene: the cached render, |on - off| x 5 and the hit map
    # (from the SPP-spp `pmc compare`), copied next to the sweep plots.
    figure_rows = []
    for key in FIGURE_SCENES:
        r = by_key.get(key)
        src = f"{OUT}/{key}_compare"
        if not r or not os.path.isdir(src):
            continue
        os.makedirs(f"{plots}/scenes", exist_ok=True)
        names = []
        for image, suffix in (("cache_on.png", "render"), ("difference.png", "difference"),
                              ("hitmap.png", "hitmap")):
            if os.path.exists(f"{src}/{image}"):
                shutil.copyfile(f"{src}/{image}", f"{plots}/scenes/{key}_{suffix}.png")
                rel = os.path.relpath(plots, os.path.dirname(doc) or ".") if doc != "-" else plots
                names.append(f"![{key} {suffix}]({rel}/scenes/{key}_{suffix}.png)")
        if len(names) == 3:
            figure_rows.append([r["scene"]["name"], *names])
    figures_text = ("\n### Images (the paper's Fig. 1 on our scenes)\n\n"
                    f"{W}x{H}, {SPP} spp, from the `pmc compare` of the table above: the cached render, "
                    "the absolute difference from the cacheless render x 5, and the cache points found per sample "
                    "(viridis, 0 to 20, colour bar on the right). Where the difference shows structure rather than "
                    "noise, the cache's texels are coarser than the pattern (see the notes).\n\n" +
                    common.md_table(["scene", "cached render", "difference x 5", "hit map"], figure_rows) + "\n"
                    ) if figure_rows else ""

    cmd_lines = "\n".join(
        "    " + " ".join(["build/pmc", "render", *r["scene"]["args"], "-o", "OUT.exr", "--stats", "OUT.json",
                           "--cache", "off|on", *common.size_args(W, H, SPP)]) for r in results)
    notes = []
    rising = [r for r in cached if r.get("psnr_q") is not None and r["psnr"] < 999]
    notes.append(
        "- PSNR (on vs off) is computed on clamped linear values, peak 1 (999: identical images). The two\n"
        "  renders share the seed, but once a cached value differs slightly from the exact one, the paths that\n"
        "  follow it take other random decisions, so the difference mixes the cache's bias with decorrelated\n"
        "  Monte Carlo noise. The bias does not shrink with samples; the noise does" +
        (f" ({SPP / SPP_Q:.3g}x the samples: {10 * math.log10(SPP / SPP_Q):.1f} dB\n  more PSNR if the difference "
         "were all noise, none if it were all bias)." if SPP > SPP_Q else ".") +
        ("\n  From " + f"{SPP_Q} to {SPP} spp: " + ", ".join(
            f"{r['scene']['key']} {r['psnr_q']:.1f} -> {r['psnr']:.1f} dB ({r['psnr'] - r['psnr_q']:+.1f})"
            for r in rising) + "." if rising else ""))
    notes.append(
        "- Cache memory is cells x entries x 8 bytes. pmc sizes the table from the image and the samples\n"
        "  (pixels x cache points per material x 1 + 3 (1 - 1/sqrt(spp)), at load factor 1/2; core/cache_sizing.h\n"
        "  gives the measurements behind the rule): a few MiB at these image sizes, where the paper uses a fixed\n"
        "  763 MB table (10^7 cells x 10 entries, also 8 bytes an entry). `docs/plots/cache_size_time.png` shows\n"
        "  the hit rate saturating at a few MiB for 320x180.")
    if threshold and "rows" in threshold:
        rows_t = threshold["rows"]
        best_t = min(rows_t, key=lambda row: row["t_on"])
        within = [row["T"] for row in rows_t if row["t_on"] <= best_t["t_on"] * 1.05]
        th_measured = ("In this run (off / on): " + ", ".join(
            f"{row['T']}: {threshold['t_off'] / row['t_on']:.2f}x" for row in rows_t) +
            f"; within 5% of the fastest ({best_t['T']}): {', '.join(str(t) for t in within)}; the default "
            f"{DEFAULT_MIN_NODES} is " + ("among them." if DEFAULT_MIN_NODES in within else
                                          "**not** among them: see the threshold table."))
    else:
        th_measured = "Measure it with `scripts/python -m bench.cache --only threshold`."
    notes.append(
        f"- `--cache-min-nodes` (default {DEFAULT_MIN_NODES}) is the smallest sub-graph that gets a cache point. "
        "A lookup\n"
        "  hashes material, node, mip level and texel, probes a cell in global memory and decodes the entry; a\n"
        "  miss adds an insert. On PoCL's CPU device a sub-graph of a few nodes is cheaper to evaluate than\n"
        "  that, and each cache point also takes table space from the others; too high a threshold drops\n"
        f"  sub-graphs worth caching. {th_measured}")
    slow = [r for r in cached if r["t_off"] / r["t_on"] < 1.0]
    fast = [r for r in cached if r["t_off"] / r["t_on"] >= 1.0]
    if slow:
        notes.append(
            "- Slower with the cache:\n  " + ", ".join(
                f"{r['scene']['key']} {r['t_off'] / r['t_on']:.2f}x (largest cached sub-graph "
                f"{max(r['plan']) if r.get('plan') else '?'} nodes)" for r in slow) +
            (", while " + ", ".join(f"{r['scene']['key']} ({max(r['plan']) if r.get('plan') else '?'} nodes) gains "
                                    f"{r['t_off'] / r['t_on']:.2f}x" for r in fast) if fast else "") +
            ".\n  Small sub-graphs do not pay for their lookup even at high hit rates (see the note above)." +
            ("\n  Sponza's MTL networks (Kd x texture, 3 nodes) stay out at the default threshold, and forcing them\n"
             "  in (`--cache-min-nodes 3`) shows that this is the right call." if by_key.get("sponza_forced") in slow
             else ""))
    forced = by_key.get("sponza_forced")
    if forced and forced not in slow:
        notes.append(
            f"- Sponza with its 3-node MTL networks forced into the cache (`--cache-min-nodes 3`) ran at "
            f"{forced['t_off'] / forced['t_on']:.2f}x:\n  a lookup now costs about as much as the 3 nodes it "
            "replaces, so below the default threshold the cache neither\n  pays nor hurts much; the default "
            "keeps such networks out (identical programs, exactly 1x).")
    lines_r = by_key.get("lines")
    if lines_r and lines_r["psnr"] < 30:
        notes.append(
            f"- The line pattern's {lines_r['psnr']:.1f} dB: a cached value is one texel of a virtual texture whose\n"
            "  resolution follows the ray-cone footprint (`floor(-log2(min |g|)) + mip bias`, so a texel is 1-2\n"
            "  footprints wide), and every sample in that texel gets the same value. That removes the\n"
            "  within-pixel anti-aliasing the samples would otherwise give: harmless on smooth or texel-scale\n"
            "  patterns, but grid lines a fraction of a pixel wide alias into moiré and thick lines (look at\n"
            f"  `{plots}/scenes/lines_difference.png`). A positive `--mip-bias` trades hits for accuracy.")
    if evals and "errs" in evals:
        notes.append(
            "- `--cache-eval center` evaluates a miss at the texel centre, with image textures filtered at the\n"
            "  footprint without the mip bias (2 x 2^-(lambda - bias) in uv) rather than at the texel's size, so\n"
            "  its error falls with `--mip-bias`.\n"
            "  A texel's value then does not depend on which sample inserted it, hit or miss, whatever the order:\n"
            "  two runs with the same seed give identical images. With `--cache-filter nearest` every sample in a\n"
            "  texel reads that texel: its error is that of point-sampling the pattern at texel centres, a blocky\n"
            "  image, there even when the cache misses. `--cache-filter bilinear` (the default) adds a uniform\n"
            "  random offset in [-0.5, 0.5) to uv x 2^lambda before flooring: each lookup reads one of the four\n"
            "  texels around the hit with its bilinear weight, so over the samples the cache returns the bilinear\n"
            "  interpolation of texel-centre values instead of blocks; the noise the choice adds averages out like\n"
            "  the rest of the Monte Carlo noise. `--cache-eval hit` stores the inserting sample's exact value:\n"
            "  misses are exact, hits get the value of another point of the same texel, so at low hit rates\n"
            "  (finer mip bias) it stays close to the cacheless image; but the stored value depends on which\n"
            "  sample got there first, so two runs with the same seed differ (the 'same command again' column" +
            "".join(f"; {EVAL_SHORT.get(n, n)}: {again_text(v)}" for n, v in evals.get("again", {}).items()) + ").")
        notes.append(
            "- Why `--cache-eval center --cache-filter bilinear` is the default although `hit` may add a little\n"
            "  less error (the eval table): a center-mode image does not depend on which sample inserted a texel,\n"
            "  so the same command gives the same image (any `--threads`), which is what CI gates on cached\n"
            "  renders (`scripts/ci-compare`) need; a hit-mode image changes from run to run. Its error is of the\n"
            "  same order (both far below the Monte Carlo noise at these sample counts, see the relMSE columns),\n"
            "  and the bilinear selection removes the blockiness nearest texels would show.")
    notes.append(
        "- `render_seconds` does not include PoCL's kernel compile: pmc launches every kernel once with no work\n"
        "  before rendering and reports that as `kernel_warmup_seconds` (apart from `kernel_build_seconds`),\n"
        "  in `pmc render`, `pmc compare` and `pmc sweep` alike. The untimed warm-up renders are kept only to\n"
        "  fill PoCL's on-disk kernel cache (`~/.cache/pocl`) and the OS file cache (scene, textures) before\n"
        "  anything is timed.")

    section = f"""{SECTION}

Produced by `{data['command']}` on {data['now']} ({elapsed / 60:.1f} minutes).
Machine: {machine}; checkout {data["rev"]}; {load}.
Images, stats and the full log of the last run: `{OUT}/`.

Method: per scene, one untimed 1-spp render with the cache off and one with it
on first (they fill PoCL's kernel cache and the OS file cache; the kernel
compile itself is never in `render_seconds`, pmc reports it as
`kernel_warmup_seconds`); then two `pmc compare` at the table's image size, one
at {SPP} spp for PSNR, relMSE, hit rate and memory and one at {SPP_Q} spp for
PSNR; then {rounds(RUNS)} of `pmc render --cache off` and `--cache on`
(`--stats`), alternating which goes first. Times are medians of
`render_seconds` (rendering only: no loading, BVH, kernel build or warm-up);
"off / on" is median off over median on, in brackets the lowest and highest
ratio of a single round. {W}x{H}, {SPP} spp, seed 0, default cache size (pmc
sizes it from the image, the samples and the cache points). The other processes on this 2-core machine make
single runs vary by 10-30%: read ratios, not absolute seconds.

{cmd_lines}

{table}

Goals:

""" + "\n".join(goals) + "\n" + figures_text + eval_text + threshold_text + "\nNotes:\n\n" + "\n".join(notes) + "\n"

    printed = "\n" + table + "\n\n" + "\n".join(goals) + "\n"
    if eval_text:
        printed += eval_text + "\n"
    if threshold_text:
        printed += threshold_text + "\n"
    return section, printed


def main(argv=None):
    args = parse(argv)
    common.chdir_root()
    scenes = [s for s in SCENES if not args.only or s["key"] in args.only]
    saved = os.path.join(args.out_dir, "results.json")
    if args.report_only:
        try:
            data = common.read_json(saved)
        except (OSError, ValueError) as e:
            sys.exit(f"{PROG}: --report-only needs {saved} from an earlier run: {e}")
    else:
        args.pmc = common.find_pmc(args.pmc, PROG)
        for s in scenes:
            if not os.path.isfile(s["args"][0]):
                sys.exit(f"{PROG}: scene {s['args'][0]} not found")
        os.makedirs(args.out_dir, exist_ok=True)
        data = Measure(args).all(scenes, not args.only or "eval" in args.only,
                                 not args.only or "threshold" in args.only)
        with open(saved, "w") as f:
            json.dump(data, f, indent=1)
    section, printed = report(data, args.plots, args.doc)
    print(printed)
    common.write_section(args.doc, SECTION, section, PROG)


if __name__ == "__main__":
    main()
