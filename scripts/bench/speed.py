"""bench.speed — the speed issue's own numbers on the default scene: render
time against an older pmc (same images or equally accurate), the first render
after an empty kernel cache against a warm one, and scaling with threads and
image size (with peak memory). Prints tables and writes the "Speed" section of
docs/BENCHMARKS.md.

    scripts/python -m bench.speed --baseline-pmc ../pmc-baseline/build/pmc --baseline-label 31f7cc9
                                       all three parts (default 3 rounds; medians)
    scripts/python -m bench.speed --only cold,scaling      without the older pmc
    scripts/python -m bench.speed --only before --runs 5 --baseline-pmc OLD

Parts:
  before   default scene, cache off, 640x360, 16 spp: --baseline-pmc against
           this build, round-robin. Accuracy: RMS of each image against a
           256-spp render of this build (OpenImageIO's idiff), and whether the
           two images are identical.
  cold     the same render, with the cache off and on, with POCL_CACHE_DIR
           pointing to a new, empty folder (PoCL compiles the kernels), then
           with that folder warm; compares render_seconds and lists
           kernel_build_seconds and warm-up. The same for the demo's
           `pmc compare` (8 spp): its cache speed ratio, first run and second.
  scaling  render_seconds with --threads 1 and 2 (640x360), and at 360p,
           720p, 1080p and 4K (2 spp: the time per sample is what scales), with
           the process's peak resident memory.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

from bench import common

PROG = "bench.speed"
SECTION = "## Speed: default scene, cold kernel cache, scaling (scripts/bench-speed)"
SCENE = ["data/default/room.obj", "--mtlx", "data/default/materials.mtlx"]
PARTS = ["before", "cold", "scaling"]
PART_TITLES = ["### Against an older pmc", "### Cold kernel cache", "### Scaling"]
DEMO_SPP = 8  # scripts/demo's samples per pixel
SIZES = [("360p", 640, 360), ("720p", 1280, 720), ("1080p", 1920, 1080), ("4K", 3840, 2160)]


def parse(argv=None):
    p = common.make_parser("speed", __doc__)
    common.add_pmc(p)
    common.add_runs(p, 3)
    p.add_argument("--baseline-pmc", metavar="PATH",
                   help="an older pmc binary for the 'before' part (built from the commit to compare with)")
    p.add_argument("--baseline-label", metavar="TEXT",
                   help="what the older pmc is, for the report (for example the commit it was built from)")
    p.add_argument("--only", default=",".join(PARTS), metavar="PARTS",
                   help=f"comma-separated parts to run, of {','.join(PARTS)} (default all)")
    p.add_argument("--spp", type=common.positive_int, default=16, metavar="N",
                   help="samples per pixel of the 'before' and 'cold' renders (default 16)")
    p.add_argument("--reference-spp", type=common.positive_int, default=256, metavar="N",
                   help="samples per pixel of the accuracy reference (default 256)")
    p.add_argument("--scaling-spp", type=common.positive_int, default=2, metavar="N",
                   help="samples per pixel of the image-size runs (default 2)")
    common.add_out_dir(p, "out/bench-speed")
    common.add_doc(p)
    a = common.parse_args(p, "speed", None, argv)
    a.parts = [x for x in a.only.split(",") if x]
    bad = [x for x in a.parts if x not in PARTS]
    if bad or not a.parts:
        p.error(f"--only: unknown part(s) {','.join(bad) or '(none)'}; choose from {','.join(PARTS)}")
    if "before" in a.parts and not a.baseline_pmc:
        p.error("the 'before' part needs --baseline-pmc PATH (or leave it out: --only cold,scaling)")
    return a


def run_measured(cmd, log, env=None):
    """Runs cmd; returns (wall seconds, CPU seconds user+sys, peak RSS in MiB)
    from wait4's rusage of that one process (not the maximum over all children
    so far)."""
    t0 = time.perf_counter()
    with open(log, "w") as f:
        f.write(" ".join(cmd) + "\n")
        f.flush()
        p = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=f, stderr=subprocess.STDOUT, env=env)
        _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        raise common.RunFailed(f"exit status {code} (log: {log})")
    return wall, ru.ru_utime + ru.ru_stime, ru.ru_maxrss / 1024.0


def idiff(a, b):
    """(identical, RMS error) of two EXRs by OpenImageIO's idiff."""
    p = subprocess.run(["idiff", "-fail", "0", "-warn", "0", a, b], capture_output=True, text=True)
    m = re.search(r"RMS error\s*=\s*([0-9.eE+-]+|nan|inf)", p.stdout + p.stderr)
    if p.returncode not in (0, 1, 2, 3, 4) or not m:
        sys.exit(f"{PROG}: idiff {a} {b} failed:\n{p.stdout}{p.stderr}")
    return p.returncode == 0, float(m.group(1))


def main(argv=None):
    a = parse(argv)
    common.chdir_root()
    PMC = common.find_pmc(a.pmc, PROG, extra_packages=["openimageio-tools"])
    if "before" in a.parts and not shutil.which("idiff"):
        sys.exit(f"{PROG}: idiff not found (Debian's openimageio-tools; scripts/setup with "
                 f"PMC_EXTRA_PACKAGES=openimageio-tools installs it)")
    OUT, RUNS = a.out_dir, a.runs
    os.makedirs(OUT, exist_ok=True)
    loads = common.LoadSampler()
    device = None
    sections = []

    def render(binary, name, extra, env=None, size=(640, 360), spp=None, cache="off"):
        """One render; returns its stats plus wall and peak RSS."""
        global_spp = a.spp if spp is None else spp
        cmd = [binary, "render", *SCENE, "-o", f"{OUT}/{name}.exr", *common.size_args(*size, global_spp),
               "--cache", cache, "--stats", f"{OUT}/{name}.json", *extra]
        wall, cpu, rss = run_measured(cmd, f"{OUT}/{name}.log", env)
        s = common.read_json(f"{OUT}/{name}.json")
        loads.sample()
        nonlocal device
        device = device or s.get("device", "?")
        return {"wall": wall, "cpu": cpu, "rss": rss, "render": s["render_seconds"],
                "build": s.get("kernel_build_seconds", float("nan")),
                "warmup": s.get("kernel_warmup_seconds", float("nan"))}

    def fmt(v):
        return f"{v:.2f}" if abs(v) < 100 else f"{v:.0f}"

    def med(rs, key):
        return common.median(r[key] for r in rs)

    # ---- before: an older pmc against this one
    if "before" in a.parts:
        base = a.baseline_pmc
        if not os.access(base, os.X_OK):
            sys.exit(f"{PROG}: --baseline-pmc {base} is not an executable")
        print(f"{PROG}: before: reference {a.reference_spp} spp, warm-up, then {RUNS} round(s)", flush=True)
        render(PMC, "reference", [], spp=a.reference_spp)
        render(base, "warmup-baseline", [], spp=1)
        render(PMC, "warmup-current", [], spp=1)
        res = {"baseline": [], "current": []}
        for r in range(RUNS):
            for name in common.round_order(["baseline", "current"], r, "reverse"):
                res[name].append(render(base if name == "baseline" else PMC, name, []))
                print(f"  round {r + 1}/{RUNS} {name:9s} render {res[name][-1]['render']:6.2f}s", flush=True)
        ratios = common.round_ratios([x["render"] for x in res["current"]], [x["render"] for x in res["baseline"]])
        same, _ = idiff(f"{OUT}/baseline.exr", f"{OUT}/current.exr")
        _, rms_base = idiff(f"{OUT}/baseline.exr", f"{OUT}/reference.exr")
        _, rms_cur = idiff(f"{OUT}/current.exr", f"{OUT}/reference.exr")
        rows = [[name, fmt(med(res[name], "render")), fmt(med(res[name], "wall")), f"{rms:.5f}"]
                for name, rms in (("baseline", rms_base), ("current", rms_cur))]
        table = common.md_table(["pmc", "render_seconds", "whole run (s)", f"RMS vs {a.reference_spp} spp"], rows)
        ratio = common.median(ratios)
        label = f" ({a.baseline_label})" if a.baseline_label else ""
        text = (f"Render time, this build against `{base}`{label} (default scene, cache off, 640x360, {a.spp} spp):\n\n"
                f"{table}\n\nrender_seconds ratio current / baseline (median of per-round ratios): "
                f"**{ratio:.2f}** ({100 * (1 - ratio):.0f}% lower). Images "
                f"{'identical (idiff)' if same else 'differ; compare their RMS against the reference'}.")
        print("\n" + text + "\n")
        sections.append(("### Against an older pmc", text))

    # ---- cold: an empty PoCL kernel cache against a warm one
    def demo(name, env):
        """scripts/demo's comparison (pmc compare, 640x360, DEMO_SPP spp); returns its metrics."""
        out = f"{OUT}/{name}"
        cmd = [PMC, "compare", *SCENE, "--spp", str(DEMO_SPP), "--out-dir", out, "--quiet"]
        wall, _, _ = run_measured(cmd, f"{OUT}/{name}.log", env)
        m = common.read_json(f"{out}/metrics.json")
        loads.sample()
        return {"wall": wall, "ratio": m["speed_ratio"], "off": m["time_off_seconds"], "on": m["time_on_seconds"]}

    if "cold" in a.parts:
        print(f"{PROG}: cold: {RUNS} round(s) of (new kernel cache, the same cache warm) for cache off, "
              f"cache on and the demo's comparison", flush=True)
        kinds = ["off", "on", "demo"]
        res = {(k, t): [] for k in kinds for t in ("cold", "warm")}
        for r in range(RUNS):
            for kind in common.round_order(kinds, r, "rotate"):
                cache_dir = tempfile.mkdtemp(prefix="pmc-pocl-cache-")
                env = dict(os.environ, POCL_CACHE_DIR=cache_dir)
                try:
                    for t in ("cold", "warm"):
                        name = f"{t}-{kind}"
                        res[(kind, t)].append(demo(name, env) if kind == "demo" else
                                              render(PMC, name, [], env, cache=kind))
                finally:
                    shutil.rmtree(cache_dir, ignore_errors=True)
                c, w = res[(kind, "cold")][-1], res[(kind, "warm")][-1]
                key = "ratio" if kind == "demo" else "render"
                print(f"  round {r + 1}/{RUNS} {kind:4s} cold {key} {c[key]:5.2f} (wall {c['wall']:.1f}s), "
                      f"warm {key} {w[key]:5.2f} (wall {w['wall']:.1f}s)", flush=True)

        def cold_over_warm(kind, key):
            return common.median(common.round_ratios([x[key] for x in res[(kind, "cold")]],
                                                     [x[key] for x in res[(kind, "warm")]]))

        rows = [[f"cache {k}", t, fmt(med(res[(k, t)], "render")), fmt(med(res[(k, t)], "build")),
                 fmt(med(res[(k, t)], "warmup")), fmt(med(res[(k, t)], "wall"))]
                for k in ("off", "on") for t in ("cold", "warm")]
        table = common.md_table(["render", "kernel cache", "render_seconds", "kernel_build_seconds",
                                 "kernel_warmup_seconds", "whole run (s)"], rows)
        demo_rows = [[t, fmt(med(res[("demo", t)], "off")), fmt(med(res[("demo", t)], "on")),
                      f"{med(res[('demo', t)], 'ratio'):.2f}x", fmt(med(res[("demo", t)], "wall"))]
                     for t in ("cold", "warm")]
        demo_table = common.md_table(["kernel cache", "cache off render (s)", "cache on render (s)",
                                      "speed ratio off / on", "whole run (s)"], demo_rows)
        r_off, r_on = cold_over_warm("off", "render"), cold_over_warm("on", "render")
        r_demo = cold_over_warm("demo", "ratio")
        text = (f"First render after an empty kernel cache (`POCL_CACHE_DIR` a new folder) against the next "
                f"render with that cache (default scene, 640x360, {a.spp} spp; each kind in its own new "
                f"folder):\n\n{table}\n\n"
                f"render_seconds cold / warm (median of per-round ratios): cache off **{r_off:.2f}**, cache on "
                f"**{r_on:.2f}** (goal at most 1.15). PoCL's compile lands in kernel_build_seconds and the "
                f"warm-up, which launches every kernel with the render's own work-group sizes and grid "
                f"classes before the clock starts.\n\n"
                f"The demo's comparison (`pmc compare`, as `scripts/demo` runs it: {DEMO_SPP} spp), first run "
                f"with an empty kernel cache against the second:\n\n{demo_table}\n\n"
                f"Speed ratio of the first run over the second's (median of per-round ratios): "
                f"**{r_demo:.2f}** (1: the first run shows the same speedup).")
        print("\n" + text + "\n")
        sections.append(("### Cold kernel cache", text))

    # ---- scaling: threads and image size
    if "scaling" in a.parts:
        print(f"{PROG}: scaling: warm-up, then {RUNS} round(s) of threads 1, 2 and 4 image sizes", flush=True)
        render(PMC, "warmup-scaling", [], spp=1)
        configs = [("threads 1", ["--threads", "1"], (640, 360), a.spp),
                   ("threads 2", ["--threads", "2"], (640, 360), a.spp)]
        configs += [(label, [], (w, h), a.scaling_spp) for label, w, h in SIZES]
        res = {c[0]: [] for c in configs}
        for r in range(RUNS):
            for label, extra, size, spp in common.round_order(configs, r, "rotate"):
                res[label].append(render(PMC, "scaling-" + label.replace(" ", ""), extra, size=size, spp=spp))
                print(f"  round {r + 1}/{RUNS} {label:9s} render {res[label][-1]['render']:6.2f}s "
                      f"peak {res[label][-1]['rss']:.0f} MiB", flush=True)
        t1, t2 = med(res["threads 1"], "render"), med(res["threads 2"], "render")
        thread_rows = [[label, fmt(med(res[label], "render")), fmt(med(res[label], "wall")),
                        fmt(med(res[label], "cpu"))] for label in ("threads 1", "threads 2")]
        thread_table = common.md_table(["640x360, " + f"{a.spp} spp", "render_seconds", "whole run (s)",
                                        "CPU user+sys (s)"], thread_rows)
        base_px = SIZES[0][1] * SIZES[0][2]
        base_t = med(res[SIZES[0][0]], "render")
        size_rows = []
        for label, w, h in SIZES:
            t = med(res[label], "render")
            size_rows.append([f"{label} ({w}x{h})", f"{w * h / base_px:.0f}x", fmt(t), f"{t / base_t:.1f}x",
                              f"{1e9 * t / (w * h * a.scaling_spp):.0f}", fmt(med(res[label], "cpu")),
                              f"{med(res[label], 'rss'):.0f}"])
        size_table = common.md_table(["image", "pixels", "render_seconds", "time", "ns per sample",
                                      "whole run CPU (s)", "peak RSS (MiB)"], size_rows)
        text = (f"Threads (`--threads`: host and PoCL worker threads) on {os.cpu_count()} cores: 2 threads take "
                f"{t2 / t1:.2f}x the time of 1 (the CPU time says how much of the machine a run got: on a "
                f"machine shared with other work, wall times are inflated).\n\n{thread_table}\n\nImage size ({a.scaling_spp} spp, all threads; "
                f"peak RSS is the whole process's maximum resident memory):\n\n{size_table}")
        print("\n" + text + "\n")
        sections.append(("### Scaling", text))

    machine = common.machine(device)
    produced = (f"Produced by `{a.command}` on {common.utc_now()}, pmc at {common.git_rev('unknown revision')} "
                f"(`{PMC}`), {RUNS} round(s) interleaved, medians ({loads.note()}). Machine: {machine}.")
    # Parts not run this time keep their text from the file (each names its own run).
    kept = previous_parts(a.doc)
    titles = dict(zip(PARTS, PART_TITLES))
    parts = []
    for part in PARTS:
        new = next((text for title, text in sections if title == titles[part]), None)
        if new is not None:
            parts.append(f"{titles[part]}\n\n{produced}\n\n{new}")
        elif part in kept:
            parts.append(kept[part])
    body = "\n\n".join(parts)
    section = f"""{SECTION}

Scene: `{' '.join(SCENE)}`, cache off where a part does not say otherwise. Each part below says
which command produced it, when and on which machine; timings are wall-clock seconds.

{body}
"""
    print(loads.note())
    common.write_section(a.doc, SECTION, section, PROG)


def previous_parts(doc):
    """The "### " parts of this module's section in `doc`, by part name."""
    if doc == "-" or not os.path.exists(doc):
        return {}
    text = common.read_text(doc)
    start = text.find(SECTION + "\n")
    if start < 0:
        return {}
    end = text.find("\n## ", start + len(SECTION))
    section = text[start:end if end >= 0 else len(text)]
    found = {}
    for part, title in zip(PARTS, PART_TITLES):
        i = section.find(title + "\n")
        if i < 0:
            continue
        j = section.find("\n### ", i + len(title))
        found[part] = section[i:j if j >= 0 else len(section)].rstrip("\n")
    return found


if __name__ == "__main__":
    main()
