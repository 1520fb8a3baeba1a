"""bench.shade — what the shade kernel costs per hit: the shade stage's time
per shaded ray per core, on bench.peers' Cornell box (constant diffuse
materials, a quad and a point light: the light tree), default room (its
MTL stand-ins, a sun disk and an HDR sky: lights at infinity) and spider
(a textured mesh under an HDR map: most camera rays escape to the map),
with a baseline pmc and this tree's, in interleaved rounds.

ns per hit per core = stage_seconds.shade x threads / (rays - shadow_rays):
every traced path ray (camera or continuation) is one hit the shade kernel
handles, escaped rays included (they meet the environment there). pmc runs
with --threads 1 by default, so the figure is one core's. On a shared
machine the stage's wall time also counts the time other processes hold the
core; with --perf (Linux perf) each render runs under `perf record -e
task-clock` and the CPU time spent in the shade kernel's code (PoCL's
pmc_shade.so) per hit is reported too, with the functions it did not
inline that take most of it. Reports the medians of the rounds and the
median per-round ratio current / baseline, and writes the "Shade kernel:
ns per hit" section of docs/BENCHMARKS.md.

    scripts/python -m bench.shade --baseline-pmc PATH     a pmc from before the change
    scripts/python -m bench.shade --runs 1 --doc -         this tree only, a quick look
    scripts/python -m bench.shade --perf --variant no-nee=DIR  what a part costs: DIR holds a copy of
                                                           the kernel sources with that part disabled
    scripts/python -m bench.shade --perf --paired --variant new=DIR   the two side by side

--paired runs a scene's two configurations at the same time, one thread
each, each pinned to its own core (taskset; the cores swap every round),
instead of one after the other: whatever else the machine runs then falls on
both alike, and the per-round ratios are tighter (on the shared 2-core
machine, the same kernel against itself, 5 rounds: paired rounds 0.88-1.13,
medians 0.97-0.99; interleaved 0.79-1.43, medians 0.94-1.16). It needs
exactly two configurations (a baseline or one variant, and current),
--threads 1 and two cores; the two runs share the caches and memory of one
machine, so the absolute figures are those of a loaded machine. Two
processes sharing the caches also evict each other's prefetched lines, so a
change to memory traffic (prefetching, layout) can read better paired than
it renders with two threads: confirm those interleaved, --threads 2.
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

from bench import common, peer_scenes

PROG = "bench.shade"
SECTION = "## Shade kernel: ns per hit (scripts/bench-shade)"
SCENES = ["cornell", "default", "spider"]
PERF_PERIOD_NS = 100000  # one task-clock sample per 0.1 ms of CPU time
SHADE_DSO = "pmc_shade.so"  # PoCL names a kernel's compiled code after the kernel


def parse(argv=None):
    p = common.make_parser("shade", __doc__)
    p.add_argument("--baseline-pmc", metavar="PATH", help="a pmc from before the change (default: none)")
    common.add_pmc(p)
    common.add_runs(p, 5)
    common.add_image_size(p, 160, 120, 32)
    p.add_argument("--threads", type=common.positive_int, default=1, metavar="T",
                   help="pmc's --threads (default 1: one core's time per hit)")
    p.add_argument("--scenes", type=scene_list, default=SCENES, metavar="LIST",
                   help=f"comma-separated, of bench.peers' {', '.join(peer_scenes.SCENES)} "
                        f"(default {','.join(SCENES)})")
    p.add_argument("--variant", action="append", default=[], type=variant, metavar="NAME=DIR",
                   help="also this tree's pmc with the kernel sources under DIR (PMC_KERNEL_DIR: its core/abi, "
                        "core/device and gpu/kernels), e.g. a copy with one part of the shade kernel disabled; "
                        "repeatable")
    p.add_argument("--perf", action="store_true",
                   help="also measure the shade kernel's CPU time per hit with Linux perf (default off)")
    p.add_argument("--paired", action="store_true",
                   help="run a scene's two configurations at the same time, each pinned to a core of its own "
                        "(see above; default: one after the other)")
    p.add_argument("--extra", default="", metavar="ARGS",
                   help="render options added to every render, space-separated (default none)")
    p.add_argument("--note", default="", metavar="TEXT",
                   help="a paragraph added to the section: what the baseline and variants are (default none)")
    common.add_out_dir(p, "out/bench-shade")
    common.add_doc(p)
    a = common.parse_args(p, "shade", None, argv)
    configurations = 1 + bool(a.baseline_pmc) + len(a.variant)
    if a.paired and (configurations != 2 or a.threads != 1):
        p.error(f"--paired needs exactly two configurations (--baseline-pmc or one --variant, and current) and "
                f"--threads 1; got {configurations} with --threads {a.threads}")
    return a


def scene_list(text):
    names = [s for s in text.split(",") if s]
    bad = [s for s in names if s not in peer_scenes.SCENES]
    if not names or bad:
        import argparse
        raise argparse.ArgumentTypeError(f"expected scenes of {', '.join(peer_scenes.SCENES)}, got '{text}'")
    return names


def variant(text):
    name, sep, folder = text.partition("=")
    if not sep or not name or not folder or name in ("current", "baseline"):
        import argparse
        raise argparse.ArgumentTypeError(f"expected NAME=DIR (NAME not current or baseline), got '{text}'")
    return name, folder


def ns_per_hit(stats, threads):
    """The shade stage's nanoseconds per shaded ray per core."""
    hits = stats["rays"] - stats["shadow_rays"]
    return stats["stage_seconds"]["shade"] * threads * 1e9 / max(hits, 1)


def perf_shade_ns(data, hits):
    """{function: CPU ns per hit} of the shade kernel's code in a perf
    recording of task-clock samples ("" the total)."""
    rep = subprocess.run(["perf", "report", "-i", data, "--sort", "dso,sym", "-n", "--stdio"],
                         capture_output=True, text=True, check=True).stdout
    out = {"": 0.0}
    for line in rep.splitlines():
        m = re.match(r"\s*[\d.]+%\s+(\d+)\s+(\S+)\s+\[.\]\s+(.*)", line)
        if m and m.group(2) == SHADE_DSO:
            ns = int(m.group(1)) * PERF_PERIOD_NS / max(hits, 1)
            out[m.group(3).strip()] = ns
            out[""] += ns
    return out


def main(argv=None):
    a = parse(argv)
    common.chdir_root()
    out = a.out_dir
    os.makedirs(out, exist_ok=True)
    pmc = common.find_pmc(a.pmc, PROG)
    # The cache's cost model plans with a calibration keyed by the kernel's
    # source, so a baseline or a variant would get a calibration, and
    # perhaps a plan (a marginal cache point), of its own: every
    # configuration plans with the table instead, unless the caller chose.
    os.environ.setdefault("PMC_CACHE_COSTS", "table")
    binaries = {"current": [pmc]}  # the command that runs each configuration's pmc
    if a.baseline_pmc:
        if not os.access(a.baseline_pmc, os.X_OK):
            sys.exit(f"{PROG}: {a.baseline_pmc} is not an executable")
        binaries = {"baseline": [a.baseline_pmc], **binaries}
    for name, folder in a.variant:
        if not os.path.isfile(os.path.join(folder, "gpu", "kernels", "pmc_kernels.cl")):
            sys.exit(f"{PROG}: --variant {name}={folder}: no gpu/kernels/pmc_kernels.cl there")
        binaries[name] = ["env", f"PMC_KERNEL_DIR={os.path.abspath(folder)}", pmc]
    if a.paired and ((os.cpu_count() or 1) < 2 or not shutil.which("taskset")):
        sys.exit(f"{PROG}: --paired needs two cores and taskset (util-linux)")
    if a.perf and not shutil.which("perf"):
        sys.exit(f"{PROG}: --perf needs Linux perf on the PATH")
    jobs = {s: peer_scenes.write_scene_files(s, os.path.join(out, "scenes", s)) for s in a.scenes}
    configs = [(b, s) for s in a.scenes for b in binaries]
    extra = a.extra.split()

    def render(which, scene, name, spp=None, cpu=None):
        js = f"{out}/{name}.json"
        pin = ["taskset", "-c", str(cpu)] if cpu is not None else []
        cmd = [*pin, *binaries[which], "render", *peer_scenes.render_args(jobs[scene]), "--max-depth", "8", "--threads", str(a.threads),
               "-o", f"{out}/{name}.exr", "--stats", js, *common.size_args(a.width, a.height, spp or a.spp), *extra]
        data = f"{out}/{name}.perf"
        if a.perf:
            cmd = ["perf", "record", "-q", "-o", data, "-e", "task-clock", "-c", str(PERF_PERIOD_NS), "--", *cmd]
        try:
            s, _ = common.run_pmc(cmd, js, f"{out}/{name}.log")
        except common.RunFailed as e:
            sys.exit(f"{PROG}: {name} failed with {e}")
        hits = s["rays"] - s["shadow_rays"]
        return {"ns": ns_per_hit(s, a.threads), "shade": s["stage_seconds"]["shade"], "render": s["render_seconds"],
                "hits": hits, "device": s.get("device", "?"), "cpu": perf_shade_ns(data, hits) if a.perf else {}}

    print(f"{PROG}: {', '.join(binaries)}; {', '.join(a.scenes)}; {a.runs} rounds", flush=True)
    for which, scene in configs:  # PoCL's kernel cache, the OS file cache
        render(which, scene, f"{which}_{scene}_warmup", 1)
    loads = common.LoadSampler()
    res = {k: [] for k in configs}
    t0 = time.time()
    for r in range(a.runs):
        if a.paired:  # a scene's two configurations at once, on cores that swap every round
            for scene in a.scenes:
                pair = [(w, s) for w, s in configs if s == scene]
                with ThreadPoolExecutor(2) as pool:
                    runs = [pool.submit(render, w, s, f"{w}_{s}", None, (i + r) % 2) for i, (w, s) in enumerate(pair)]
                    for (w, s), run in zip(pair, runs):
                        res[(w, s)].append(run.result())
                loads.sample()
        else:
            for which, scene in common.round_order(configs, r):
                res[(which, scene)].append(render(which, scene, f"{which}_{scene}"))
                loads.sample()
        print(f"  round {r + 1}/{a.runs}  " +
              "  ".join(f"{w} {s} {res[(w, s)][-1]['ns']:6.0f} ns" for w, s in configs), flush=True)
    elapsed = time.time() - t0

    def values(which, scene, key):
        return [x[key] for x in res[(which, scene)]]

    def cpu_ns(which, scene, fn=""):
        return [x["cpu"].get(fn, 0.0) for x in res[(which, scene)]]

    def reference(which):
        """What a configuration is compared with: the baseline for current, current for a variant."""
        if which == "current":
            return "baseline" if "baseline" in binaries else None
        return None if which == "baseline" else "current"

    def ratio_text(xs, ys):
        r = common.median_range(common.round_ratios(xs, ys))
        return f"**{r[0]:.3f}** ({r[1]:.2f}-{r[2]:.2f})"

    rows = []
    cpu_rows = []
    for scene in a.scenes:
        for which in binaries:
            ref = reference(which)
            ratio = ratio_text(values(which, scene, "ns"), values(ref, scene, "ns")) if ref else ""
            ns = values(which, scene, "ns")
            rows.append([scene, which, f"**{common.median(ns):.0f}** ({min(ns):.0f}-{max(ns):.0f})",
                         f"{common.median(values(which, scene, 'shade')):.2f}",
                         f"{common.median(values(which, scene, 'render')):.2f}",
                         f"{res[(which, scene)][0]['hits']}", ratio])
            if a.perf:
                cpu = cpu_ns(which, scene)
                cpu_ratio = ratio_text(cpu, cpu_ns(ref, scene)) if ref else ""
                names = {fn for x in res[(which, scene)] for fn in x["cpu"] if fn}
                top = sorted(names, key=lambda fn: -common.median(cpu_ns(which, scene, fn)))[:5]
                cpu_rows.append([scene, which, f"**{common.median(cpu):.0f}** ({min(cpu):.0f}-{max(cpu):.0f})",
                                 cpu_ratio, "; ".join(f"`{fn}` {common.median(cpu_ns(which, scene, fn)):.0f}"
                                                      for fn in top)])
    table = common.md_table(["scene", "pmc", "shade ns per hit per core (range)", "shade (s)", "render (s)",
                             "hits", "ns against current's (variants) or baseline's (current), range of rounds"], rows)
    device = res[configs[-1]][0]["device"]
    base_line = f"Baseline: `{a.baseline_pmc}`. " if a.baseline_pmc else ""
    base_line += "".join(f"Variant {n}: this pmc with PMC_KERNEL_DIR={f}. " for n, f in a.variant)
    size = " ".join(common.size_args(a.width, a.height, a.spp))
    # the note is a paragraph of the section: the recorded command points to it
    command = a.command.replace(shlex.quote(a.note), "'(the paragraphs after the tables)'") if a.note else a.command
    section = f"""{SECTION}

Produced by `{command}` on {common.utc_now()} ({elapsed / 60:.1f} minutes of timed runs).
Machine: {common.machine(device)}; {loads.note()}.
{base_line}Current: {common.git_rev(ignore=["docs"])}. Median of {a.runs} {'paired rounds (the two configurations at the same time, a core each)' if a.paired else 'interleaved rounds'}, each scene
bench.peers writes (scripts/bench/peer_scenes.py) rendered as

    PMC_CACHE_COSTS={os.environ["PMC_CACHE_COSTS"]} build/pmc render SCENE.obj --lights SCENE.lights.json --camera-from ... --max-depth 8 --threads {a.threads} {size}{(' ' + a.extra) if a.extra else ''}

ns per hit per core = the shade stage's seconds x threads / (rays - shadow_rays), every camera and
continuation ray being one hit the shade kernel handles:

{table}
"""
    if a.perf:
        cpu_table = common.md_table(["scene", "pmc", "shade CPU ns per hit (range)",
                                     "against current's or baseline's (range of rounds)",
                                     "of which in functions not inlined (ns per hit)"], cpu_rows)
        section += f"""
CPU time in the shade kernel's code per hit (`perf record -e task-clock -c {PERF_PERIOD_NS}`, the samples
in PoCL's {SHADE_DSO}): what the wall-clock figure would be on an idle core. The last column splits it
by function where PoCL did not inline one (the work-group function holds everything it inlined).

{cpu_table}
"""
        table += "\n\n" + cpu_table
    if a.note:
        section += "\n" + a.note.strip() + "\n"
    if a.variant:
        key = cpu_ns if a.perf else (lambda w, sc: values(w, sc, "ns"))
        parts = [f"{name} on {scene}: {common.median(key('current', scene)) - common.median(key(name, scene)):.0f} ns"
                 for scene in a.scenes for name, _ in a.variant]
        section += f"""
What the part each variant leaves out costs per hit ({'CPU' if a.perf else 'wall-clock'} ns, current's median less the
variant's): {'; '.join(parts)}.
"""
    print()
    print(table)
    common.write_section(a.doc, SECTION, section, PROG)


if __name__ == "__main__":
    main()
