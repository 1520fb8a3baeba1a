"""bench.waves — small frames against large ones at the same number of paths:
whether a wave's fixed costs (kernel launches, the host's passes over the
queues, the last bounces' short queues) still dominate small frames. Renders
the default scene at 160x120, 512 spp and at 640x360, 43 spp (19200 x 512 =
9.8M paths, 230400 x 43 = 9.9M) with a baseline pmc (waves of one sample
each) and this tree's (several samples of each pixel per wave when the frame
is smaller than a wave), in interleaved rounds, and reports the median
render_seconds and the median per-round ratio small / large for each.
Prints a table and writes the "Waves" section of docs/BENCHMARKS.md.

    scripts/python -m bench.waves --baseline-pmc PATH     a pmc from before the change
    scripts/python -m bench.waves --runs 1 --doc -         this tree only, a quick look
"""
import os
import sys
import time

from bench import common

PROG = "bench.waves"
SECTION = "## Waves: small frames against large ones at equal paths (scripts/bench-waves)"
SCENE = ["data/default/room.obj", "--mtlx", "data/default/materials.mtlx"]
SIZES = {"small": (160, 120, 512), "large": (640, 360, 43)}


def parse(argv=None):
    p = common.make_parser("waves", __doc__)
    p.add_argument("--baseline-pmc", metavar="PATH", help="a pmc from before the change (default: none)")
    common.add_pmc(p)
    common.add_runs(p, 5)
    p.add_argument("--extra", default="", metavar="ARGS",
                   help="render options added to every render, space-separated (default none)")
    common.add_out_dir(p, "out/bench-waves")
    common.add_doc(p)
    return common.parse_args(p, "waves", None, argv)


def main(argv=None):
    a = parse(argv)
    common.chdir_root()
    out = a.out_dir
    os.makedirs(out, exist_ok=True)
    binaries = {"current": common.find_pmc(a.pmc, PROG)}
    if a.baseline_pmc:
        if not os.access(a.baseline_pmc, os.X_OK):
            sys.exit(f"{PROG}: {a.baseline_pmc} is not an executable")
        binaries = {"baseline": a.baseline_pmc, **binaries}
    configs = [(b, s) for b in binaries for s in SIZES]
    extra = a.extra.split()

    def render(which, size, name, spp=None):
        w, h, n = SIZES[size]
        js = f"{out}/{name}.json"
        cmd = [binaries[which], "render", *SCENE, "-o", f"{out}/{name}.exr", "--stats", js,
               *common.size_args(w, h, spp or n), *extra]
        try:
            s, _ = common.run_pmc(cmd, js, f"{out}/{name}.log")
        except common.RunFailed as e:
            sys.exit(f"{PROG}: {name} failed with {e}")
        return {"render": s["render_seconds"], "paths": s.get("paths", 0), "device": s.get("device", "?")}

    print(f"{PROG}: {', '.join(binaries)}; {a.runs} rounds", flush=True)
    for which, size in configs:  # PoCL's kernel cache, the OS file cache
        render(which, size, f"{which}_{size}_warmup", 2)
    loads = common.LoadSampler()
    res = {k: [] for k in configs}
    t0 = time.time()
    for r in range(a.runs):
        for which, size in common.round_order(configs, r):
            res[(which, size)].append(render(which, size, f"{which}_{size}"))
            loads.sample()
        print(f"  round {r + 1}/{a.runs}  " +
              "  ".join(f"{w} {s} {res[(w, s)][-1]['render']:6.2f}s" for w, s in configs), flush=True)
    elapsed = time.time() - t0

    def times(which, size):
        return [x["render"] for x in res[(which, size)]]

    rows = []
    ratios = {}
    for which in binaries:
        ratio = common.median_range(common.round_ratios(times(which, "small"), times(which, "large")))
        ratios[which] = ratio
        rows.append([which, f"{common.median(times(which, 'small')):.2f}", f"{common.median(times(which, 'large')):.2f}",
                     f"**{ratio[0]:.3f}** ({ratio[1]:.2f}-{ratio[2]:.2f})"])
    table = common.md_table(["pmc", "160x120, 512 spp (s)", "640x360, 43 spp (s)",
                             "small / large (range of rounds)"], rows)
    device = res[configs[-1]][0]["device"]
    paths = {s: res[("current", s)][0]["paths"] for s in SIZES}
    base_line = (f"Baseline: `{a.baseline_pmc}` (waves of one sample of every pixel). " if a.baseline_pmc else "")
    commands = "\n".join(
        f"    {'BASELINE/pmc' if which == 'baseline' else 'build/pmc'} render {' '.join(SCENE)} "
        f"{' '.join(common.size_args(*SIZES[s]))}{(' ' + a.extra) if a.extra else ''}"
        for which in binaries for s in SIZES)
    section = f"""{SECTION}

Produced by `{a.command}` on {common.utc_now()} ({elapsed / 60:.1f} minutes of timed runs).
Machine: {common.machine(device)}; {loads.note()}.
{base_line}Current: {common.git_rev(ignore=["docs"])}. Median of {a.runs} interleaved rounds
(paths: {paths['small']} small, {paths['large']} large):

{commands}

{table}

A wave now holds several samples of every pixel when the frame has fewer pixels than
kWaveTargetPaths, 2^16 (gpu/wavefront_renderer.cpp), so a 160x120 frame renders its 512 samples in
waves of {(1 << 16) // (160 * 120)} samples (57600 paths) instead of 512 waves of 19200 paths; a 640x360
frame keeps one sample per wave. Both binaries run with their defaults, so the current one's
large frames, whose waves are the baseline's, show what its Sobol sampler costs.
"""
    print()
    print(table)
    common.write_section(a.doc, SECTION, section, PROG)


if __name__ == "__main__":
    main()
