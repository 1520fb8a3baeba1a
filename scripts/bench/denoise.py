"""bench.denoise — time to a clean image: error against a high-sample
reference as a function of time, for pmc's renders as they come and denoised
with Intel Open Image Denoise (render time + denoise time). For each scene a
reference is rendered once (cacheless, REF_SPP samples, another seed); then
for each sample count `pmc compare SCENE --reference REF --denoise` renders
the frame cacheless and cached, denoises the cached render (albedo and
normal passes) and measures all three against the reference. Each sample
count runs --runs times in rounds that rotate the order; times are medians.
Plots relMSE against seconds (plots/denoise.png beside the --doc file) and writes the
"Denoising" section of docs/BENCHMARKS.md.

    scripts/python -m bench.denoise                                default room and Sponza
    scripts/python -m bench.denoise --scenes default --runs 1 --spps 4,16 --ref-spp 256 --doc -   a quick look

Cycles with its OIDN denoiser (bpy) is not installed here, so it is not a
column yet.
"""
import os
import sys
import time

from bench import common

PROG = "bench.denoise"
SECTION = "## Denoising: time to a clean image (scripts/bench-denoise)"
PLOT = "denoise.png"  # in plots/ beside the --doc file (common.plot_path)
SHARED = common.SHARED_SCENES
SCENES = {
    "default": dict(name="default room", args=["data/default/room.obj", "--mtlx", "data/default/materials.mtlx",
                                              "--max-depth", "4"]),
    "sponza": dict(name="Sponza (MTL materials)",
                   args=[f"{SHARED}/sponza/sponza.obj", "--camera-from", "-110,20,0", "--camera-at", "100,20,0",
                         "--fov", "45", "--env", "1,1,1", "--max-depth", "4"]),
}


def parse(argv=None):
    p = common.make_parser("denoise", __doc__)
    common.add_pmc(p)
    common.add_runs(p, 3)
    p.add_argument("--width", type=common.positive_int, default=320, metavar="W", help="image width (default 320)")
    p.add_argument("--height", type=common.positive_int, default=180, metavar="H", help="image height (default 180)")
    p.add_argument("--spps", type=common.spp_list, default=[1, 2, 4, 8, 16, 32, 64], metavar="LIST",
                   help="sample counts measured (default 1,2,4,8,16,32,64)")
    p.add_argument("--ref-spp", type=common.positive_int, default=4096, metavar="N",
                   help="samples of the cacheless reference (default 4096)")
    p.add_argument("--scenes", default="default,sponza", metavar="LIST",
                   help=f"scenes among {','.join(SCENES)} (default default,sponza)")
    common.add_out_dir(p, "out/bench-denoise")
    common.add_doc(p)
    common.add_report_only(p)
    a = common.parse_args(p, "denoise", None, argv)
    a.scene_keys = [s for s in a.scenes.split(",") if s]
    for s in a.scene_keys:
        if s not in SCENES:
            p.error(f"--scenes: unknown scene '{s}' (scenes: {', '.join(SCENES)})")
    return a


def measure(a):
    OUT = a.out_dir
    data = {"width": a.width, "height": a.height, "spps": a.spps, "ref_spp": a.ref_spp, "runs": a.runs,
            "command": a.command, "date": common.utc_now(), "rev": common.git_rev(ignore=["docs"]), "scenes": {}}
    loads = common.LoadSampler()
    t0 = time.time()
    for key in a.scene_keys:
        sc = SCENES[key]
        ref = f"{OUT}/{key}_reference.exr"
        print(f"{PROG}: {key}: reference, {a.ref_spp} spp at {a.width}x{a.height}", flush=True)
        try:
            common.run([a.pmc, "render", *sc["args"], "--cache", "off", "--seed", "977", "-o", ref,
                        *common.size_args(a.width, a.height, a.ref_spp)], f"{OUT}/{key}_reference.log", "reference")
        except common.RunFailed as e:
            sys.exit(f"{PROG}: {e}")
        rows = {spp: [] for spp in a.spps}
        for r in range(a.runs):
            for spp in common.round_order(a.spps, r):
                d = f"{OUT}/{key}_{spp}"
                cmd = [a.pmc, "compare", *sc["args"], "--reference", ref, "--denoise", "--out-dir", d,
                       *common.size_args(a.width, a.height, spp)]
                try:
                    common.run(cmd, f"{d}.log", f"{key} {spp} spp")
                except common.RunFailed as e:
                    sys.exit(f"{PROG}: {e}")
                m = common.read_json(f"{d}/metrics.json")
                rows[spp].append({"off": m["time_off_seconds"], "on": m["time_on_seconds"],
                                  "denoise": m["denoise"]["seconds"], "device": m["denoise"]["device"],
                                  "relmse_off": m["cacheless_vs_reference"]["relmse"],
                                  "relmse_on": m["cached_vs_reference"]["relmse"],
                                  "relmse_denoised": m["denoised_vs_reference"]["relmse"]})
                loads.sample()
            print(f"  {key} round {r + 1}/{a.runs} done", flush=True)
        data["scenes"][key] = rows
    data["elapsed"] = time.time() - t0
    data["load"] = [loads.before(), loads.median(), loads.max()]
    return data


def summary(rows):
    """Per sample count: median times and the errors (the same every round: same seed)."""
    out = []
    for spp, runs in sorted(rows.items(), key=lambda kv: int(kv[0])):
        med = {k: common.median([r[k] for r in runs]) for k in ("off", "on", "denoise")}
        out.append(dict(spp=int(spp), **med, **{k: runs[0][k] for k in
                                                 ("relmse_off", "relmse_on", "relmse_denoised", "device")}))
    return out


def time_to(points, target):
    """The least time among `points` (time, relMSE) whose error is at most target, interpolated
    log-log between the measured points; None when none reaches it."""
    import math
    pts = sorted(points)
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if e0 > target >= e1 and e0 > 0 and e1 > 0:
            f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    hits = [t for t, e in pts if e <= target]
    return min(hits) if hits else None


def plot(data, path):
    try:
        import matplotlib
    except ImportError:
        print(f"{PROG}: matplotlib is not installed (Debian: python3-matplotlib): {path} not drawn")
        return
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    keys = list(data["scenes"])
    fig, axes = plt.subplots(1, len(keys), figsize=(5 * len(keys), 3.8), squeeze=False)
    for ax, key in zip(axes[0], keys):
        s = summary(data["scenes"][key])
        ax.plot([r["off"] for r in s], [r["relmse_off"] for r in s], "o-", label="pmc, cache off")
        ax.plot([r["on"] for r in s], [r["relmse_on"] for r in s], "s-", label="pmc, cache on")
        ax.plot([r["on"] + r["denoise"] for r in s], [r["relmse_denoised"] for r in s], "^-",
                label="pmc, cache on + OIDN (render + denoise time)")
        for r in s:
            ax.annotate(f"{r['spp']}", (r["on"] + r["denoise"], r["relmse_denoised"]), fontsize=7,
                        xytext=(3, 3), textcoords="offset points")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("seconds")
        ax.set_ylabel(f"relMSE vs {data['ref_spp']}-spp reference")
        ax.set_title(SCENES[key]["name"], fontsize=10)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.suptitle(f"{data['width']}x{data['height']}: error against time (labels: samples per pixel)", fontsize=10)
    fig.tight_layout()
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    print(f"{PROG}: wrote {path}")


def report(data):
    tables, verdicts = [], []
    device = "?"
    for key, rows in data["scenes"].items():
        s = summary(rows)
        device = s[0]["device"]
        tab = common.md_table(
            ["spp", "render, cache on (s)", "denoise (s)", "relMSE cacheless", "relMSE cached", "relMSE denoised",
             "noisy / denoised"],
            [[str(r["spp"]), f"{r['on']:.2f}", f"{r['denoise']:.2f}", f"{r['relmse_off']:.3g}", f"{r['relmse_on']:.3g}",
              f"{r['relmse_denoised']:.3g}",
              f"**{r['relmse_on'] / r['relmse_denoised']:.1f}x**" if r["relmse_denoised"] > 0 else "?"] for r in s])
        tables.append(f"**{SCENES[key]['name']}**\n\n{tab}")
        noisy = [(r["on"], r["relmse_on"]) for r in s]
        clean = [(r["on"] + r["denoise"], r["relmse_denoised"]) for r in s]
        best = min(r["relmse_on"] for r in s)  # the best error the noisy renders reach
        t_noisy, t_clean = time_to(noisy, best), time_to(clean, best)
        # The reference's own noise: relMSE falls as 1/spp, so about a render's error x spp / ref_spp.
        floor = s[-1]["relmse_on"] * s[-1]["spp"] / data["ref_spp"]
        if t_clean is not None and t_noisy:
            first = min((r["on"] + r["denoise"], r["relmse_denoised"], r["spp"]) for r in s)
            when = (f"already at {first[0]:.2f} s with {first[2]} spp (relMSE {first[1]:.3g})"
                    if first[1] <= best else f"in **{t_clean:.2f} s**")
            verdicts.append(f"{SCENES[key]['name']}: the noisy renders reach relMSE {best:.3g} in {t_noisy:.2f} s, "
                            f"denoised renders {when}, **{t_noisy / t_clean:.1f}x** sooner at least; the "
                            f"reference's own noise is about {floor:.2g} of every figure")
    lb, lm, lx = data["load"]
    section = f"""{SECTION}

Produced by `{data['command']}` on {data['date']} ({data['elapsed'] / 60:.1f} minutes); pmc at {data['rev']}.
Machine: {common.machine(device)}; load average {lb:.1f} before the runs, {lm:.1f} median and {lx:.1f} max
between them. {data['width']}x{data['height']}; per sample count, `pmc compare SCENE --reference REF.exr
--denoise` (cacheless and cached renders with the same seed; the cached one denoised by OIDN on the
CPU with its albedo and normal passes, prefiltered); the reference is a cacheless
{data['ref_spp']}-spp render with another seed. Times are medians of {data['runs']} rotating rounds; render time
excludes the kernel build, denoise time is OIDN's device, filters and execution.

![relMSE against time](plots/denoise.png)

{(chr(10) + chr(10)).join(tables)}

{'. '.join(verdicts) + '.' if verdicts else ''} Times are wall-clock on a machine shared with other
work (see the load average): compare the curves' shapes and the ratios within one run.

Cycles with OIDN (bpy from PyPI) is not installed on this machine, so it is not compared yet.
"""
    return section, "\n\n".join(tables)


def main(argv=None):
    a = parse(argv)
    inputs = [SCENES[k]["args"][0] for k in a.scene_keys]
    common.measure_and_report(a, PROG, SECTION, measure, lambda d: (plot(d, common.plot_path(a, PLOT)), report(d))[1],
                              inputs)


if __name__ == "__main__":
    main()
