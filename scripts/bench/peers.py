"""bench.peers — pmc beside Blender Cycles and Mitsuba 3 on the shared scenes:
render time at equal samples, error against each renderer's own high-sample
reference, efficiency 1 / (relMSE x seconds), and error-against-time plots
(issue 36). Not a test: numbers for docs/BENCHMARKS.md.

Needs the peers in .venv: scripts/setup-peers installs Blender's `bpy` 5.0.1
and `mitsuba` from PyPI and Debian's libllvm19 (for Mitsuba's llvm_ad_rgb).

    scripts/bench-peers                                     every scene and renderer (long: about an hour)
    scripts/bench-peers --scenes cornell --renderers pmc,cycles --spp 4,16 --reference-spp 256
    scripts/bench-peers --report-only                       the tables again from OUT_DIR/results.json

Method (also written into the section):
  scenes     bench.peer_scenes: the OBJ with every material as a diffuse
             stand-in (Kd x map_Kd, Ke, map_d), the same camera, lights and
             environment for every renderer, converted with written factors
             (bench.peer_cycles, bench.peer_mitsuba)
  renderers  pmc (defaults: the material cache on; its reference with the
             cache off), Cycles (bpy, CPU), Mitsuba 3 llvm_ad_rgb and
             scalar_rgb; every one on --threads threads, max depth matched
             (pmc: with fewer threads than the machine has cores, one wave
             loop, so that its host and device threads never add up to more);
             pmc+oidn and cycles+oidn: the same with Open Image Denoise,
             against the plain renderer's reference, the denoiser's time added;
             pmc+adaptive: pmc with --adaptive-threshold (a timed render's
             sample count is its pixels' most), against pmc's reference
  time       seconds of N samples = (t(N) - t(1)) x N / (N - 1), where t is a
             render's own time (pmc: its render_seconds; Cycles: the render
             call; Mitsuba: mi.render and the image's evaluation, kernels
             compiled by an untimed render first): scene loading, BVH
             building, kernel compilation and per-render set-up drop out
  error      relMSE = mean over pixels and channels of (x - ref)^2 /
             (ref^2 + 0.01) (pmc's own definition), against the same
             renderer's reference at --reference-spp with another seed
  rounds     --runs rounds; in each, every renderer renders every sample
             count once (the renderers' order rotates between rounds), with
             the round's seed; times and errors are medians over rounds
"""
import json
import math
import os
import subprocess
import sys
import time

from bench import common, peer_scenes

PROG = "bench.peers"
SECTION = "## Against Cycles and Mitsuba 3 (scripts/bench-peers)"
RENDERERS = ["pmc", "pmc+oidn", "pmc+adaptive", "cycles", "cycles+oidn", "mitsuba-llvm", "mitsuba-scalar"]
LABELS = {"pmc": "pmc", "pmc+oidn": "pmc + OIDN", "pmc+adaptive": "pmc, adaptive sampling", "cycles": "Cycles 5.0.1", "cycles+oidn": "Cycles 5.0.1 + OIDN",
          "mitsuba-llvm": "Mitsuba 3 llvm_ad_rgb",
          "mitsuba-scalar": "Mitsuba 3 scalar_rgb"}
PY = ".venv/bin/python"
PLOT = "peers.png"  # in plots/ beside the --doc file (common.plot_path), which links it


def parse(argv=None):
    p = common.make_parser("peers", __doc__)
    common.add_pmc(p)
    common.add_runs(p, 3)
    p.add_argument("--scenes", default=",".join(peer_scenes.SCENES), metavar="LIST",
                   help=f"comma-separated scenes, of {','.join(peer_scenes.SCENES)} (default all)")
    p.add_argument("--renderers", default=",".join(RENDERERS), metavar="LIST",
                   help=f"comma-separated renderers, of {','.join(RENDERERS)} (default all)")
    p.add_argument("--width", type=common.positive_int, default=160, metavar="W", help="image width (default 160)")
    p.add_argument("--height", type=common.positive_int, default=120, metavar="H",
                   help="image height (default 120)")
    p.add_argument("--spp", type=common.spp_list, default="4,16,64", metavar="LIST",
                   help="sample counts of the timed renders (default 4,16,64)")
    p.add_argument("--reference-spp", type=common.positive_int, default=1024, metavar="N",
                   help="samples of each renderer's reference (default 1024)")
    p.add_argument("--max-depth", type=common.positive_int, default=8, metavar="D",
                   help="surface hits per path, pmc's --max-depth (default 8)")
    p.add_argument("--threads", type=common.positive_int, default=2, metavar="T",
                   help="threads of every renderer (default 2)")
    p.add_argument("--adaptive-threshold", type=float, default=0.02, metavar="T",
                   help="pmc+adaptive's --adaptive-threshold (default 0.02)")
    p.add_argument("--adaptive-min-spp", type=common.positive_int, default=8, metavar="N",
                   help="pmc+adaptive's --adaptive-min-spp (default 8)")
    common.add_out_dir(p, "out/bench-peers")
    common.add_doc(p)
    common.add_report_only(p)
    args = common.parse_args(p, "peers", argv=argv)
    args.scene_list = [s for s in args.scenes.split(",") if s]
    args.renderer_list = [r for r in args.renderers.split(",") if r]
    for s in args.scene_list:
        if s not in peer_scenes.SCENES:
            p.error(f"unknown scene {s!r} (known: {', '.join(peer_scenes.SCENES)})")
    for r in args.renderer_list:
        if r not in RENDERERS:
            p.error(f"unknown renderer {r!r} (known: {', '.join(RENDERERS)})")
    args.spp_list = args.spp
    if min(args.spp_list) < 2:
        p.error("--spp needs sample counts of at least 2 (the time is (t(N) - t(1)) N / (N - 1))")
    return args


# ---- images and errors ---------------------------------------------------------------
def read_exr(path):
    """The RGB pixels of an EXR as a float array (through Mitsuba's Bitmap,
    which every run of this benchmark has)."""
    import numpy as np
    import mitsuba as mi
    if mi.variant() is None:
        mi.set_variant("scalar_rgb")
    bmp = mi.Bitmap(path)
    names = [bmp.struct_()[i].name for i in range(bmp.channel_count())]
    if len(names) != 3 and all(c in names for c in "RGB"):  # the image's channels among other layers
        arr = np.array(bmp, dtype=np.float64)
        return arr[:, :, [names.index(c) for c in "RGB"]]
    bmp = bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
    return np.array(bmp, dtype=np.float64)


def relmse(img, ref):
    import numpy as np
    if img.shape != ref.shape:
        raise SystemExit(f"{PROG}: image sizes differ: {img.shape} against {ref.shape}")
    bad = ~np.isfinite(img)
    img = np.where(bad, 0.0, img)
    return float(np.mean((img - ref) ** 2 / (ref * ref + 0.01))), int(bad.sum())


# ---- running one renderer ------------------------------------------------------------
def run_pmc(args, job, spps, seed, folder, cache, denoise=False, adaptive=False):
    """pmc renders; returns {spp: (render_seconds, exr, denoise seconds)}
    (spp 1 included). With denoise, exr is the denoised image; with adaptive,
    pixels stop early (--adaptive-threshold)."""
    cam = job["camera"]
    out = {}
    extra = ["--adaptive-threshold", str(args.adaptive_threshold), "--adaptive-min-spp",
             str(args.adaptive_min_spp)] if adaptive else []
    if args.threads < (os.cpu_count() or 1):  # two loops would keep up to 2 x threads busy
        extra += ["--waves-in-flight", "1"]
    for spp in [1] + spps:
        exr = os.path.join(folder, f"pmc_{cache}{'_oidn' if denoise else ''}{'_ad' if adaptive else ''}_{spp}_s{seed}.exr")
        stats = exr[:-4] + ".json"
        cmd = [args.pmc, "render", job["obj"], "--lights", job["lights_file"],
               "--camera-from", ",".join(map(str, cam["from"])), "--camera-at", ",".join(map(str, cam["at"])),
               "--fov", str(cam["vfov"]), "--max-depth", str(args.max_depth), "--seed", str(seed),
               "--threads", str(args.threads), "--cache", cache, "-o", exr, "--stats", stats,
               *(["--denoise"] if denoise else []), *extra, *common.size_args(args.width, args.height, spp)]
        st, _ = common.run_pmc(cmd, stats, os.path.join(folder, "pmc.log"), f"pmc {job['scene']}", append=True)
        out[spp] = (st["render_seconds"], exr, st["denoise"]["seconds"] if denoise else 0.0)
    return out


def run_peer(args, renderer, job, spps, seed, folder):
    """A peer renders in its own process; returns {spp: (seconds, exr,
    denoise seconds)} with {1: (fixed seconds, None, 0)}."""
    tag = renderer.replace("-", "_").replace("+", "_")
    full = dict(job, width=args.width, height=args.height, max_depth=args.max_depth, threads=args.threads,
                seed=seed, denoise=renderer.endswith("+oidn"), renders=[{"spp": s, "out": os.path.abspath(os.path.join(folder, f"{tag}_{s}_s{seed}.exr"))}
                                    for s in spps])
    job_path = os.path.join(folder, f"{tag}_s{seed}.job.json")
    result_path = os.path.join(folder, f"{tag}_s{seed}.result.json")
    with open(job_path, "w") as f:
        json.dump(full, f, indent=1)
    if renderer.startswith("cycles"):
        cmd = [PY, "scripts/bench/peer_cycles.py", job_path, result_path]
    else:
        variant = "llvm_ad_rgb" if renderer == "mitsuba-llvm" else "scalar_rgb"
        cmd = [PY, "scripts/bench/peer_mitsuba.py", variant, job_path, result_path]
    common.run(cmd, os.path.join(folder, f"{tag}.log"), f"{renderer} {job['scene']}", append=True)
    res = common.read_json(result_path)
    out = {1: (res["fixed_seconds"], None, 0.0)}
    for r, spec in zip(res["renders"], full["renders"]):
        out[r["spp"]] = (r["seconds"], spec["out"], res.get("denoise_seconds", 0.0))
    return out


def base(renderer):
    """The renderer without its denoiser: whose reference a variant is measured against."""
    return renderer.split("+")[0]


def render(args, renderer, job, spps, seed, folder, reference=False):
    if renderer.startswith("pmc"):
        return run_pmc(args, job, spps, seed, folder, "off" if reference else "on", renderer.endswith("+oidn"),
                       renderer.endswith("+adaptive"))
    return run_peer(args, renderer, job, spps, seed, folder)


def seconds_of(runs, spp):
    """(t(N) - t(1)) x N / (N - 1): the time of N samples without fixed
    costs, plus the denoiser's time where there is one."""
    return max(runs[spp][0] - runs[1][0], 0.0) * spp / (spp - 1) + runs[spp][2]


# ---- measuring -----------------------------------------------------------------------
def check_peers(renderers):
    """Exits with what to install when a peer is missing from .venv."""
    probes = {"cycles": "import bpy", "cycles+oidn": "import bpy", "mitsuba-llvm": "import mitsuba; mitsuba.set_variant('llvm_ad_rgb')",
              "mitsuba-scalar": "import mitsuba; mitsuba.set_variant('scalar_rgb')",
              "images": "import mitsuba"}  # read_exr reads every image through Mitsuba's Bitmap
    for r in list(renderers) + ["images"]:
        if r not in probes:
            continue
        p = subprocess.run([PY, "-c", probes[r]], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            why = (p.stderr.strip().splitlines() or ["failed"])[-1]
            sys.exit(f"{PROG}: {r}: {why}; scripts/setup-peers installs the peers (bpy, mitsuba, libllvm19)")


def measure(args):
    check_peers(args.renderer_list)
    load = common.LoadSampler()
    data = {"command": args.command, "width": args.width, "height": args.height, "spp": args.spp_list, "reference_spp": args.reference_spp,
            "max_depth": args.max_depth, "threads": args.threads, "runs": args.runs,
            "machine": common.machine("cpu"), "rev": common.git_rev(), "date": common.utc_now(), "scenes": {}}
    for name in args.scene_list:
        folder = os.path.join(args.out_dir, name)
        job = peer_scenes.write_scene_files(name, os.path.join(folder, "files"))
        print(f"{PROG}: {name}: {job['triangles']} triangles; references at {args.reference_spp} spp", flush=True)
        scene = {"what": peer_scenes.SCENES[name]["what"], "triangles": job["triangles"], "renderers": {}}
        refs, ref_seconds = {}, {}
        for r in dict.fromkeys(base(r) for r in args.renderer_list):  # each base renderer's reference, once
            runs = render(args, r, job, [args.reference_spp], 1000, folder, reference=True)
            refs[r] = read_exr(runs[args.reference_spp][1])
            ref_seconds[r] = seconds_of(runs, args.reference_spp)
        for r in args.renderer_list:
            scene["renderers"][r] = {"reference_seconds": ref_seconds[base(r)], "rounds": []}
        for rnd in range(args.runs):
            for r in common.round_order(args.renderer_list, rnd):
                runs = render(args, r, job, args.spp_list, 1 + rnd, folder)
                row = {}
                for spp in args.spp_list:
                    err, bad = relmse(read_exr(runs[spp][1]), refs[base(r)])
                    row[str(spp)] = {"seconds": seconds_of(runs, spp), "relmse": err, "bad_values": bad}
                scene["renderers"][r]["rounds"].append(row)
                load.sample()
                print(f"{PROG}: {name} round {rnd + 1}/{args.runs} {r}: " +
                      ", ".join(f"{s} spp {row[str(s)]['seconds']:.2f} s relMSE {row[str(s)]['relmse']:.3g}"
                                for s in args.spp_list), flush=True)
        data["scenes"][name] = scene
    data["load"] = load.note()
    return data


# ---- reporting -----------------------------------------------------------------------
def summary(entry, spp):
    secs = [r[str(spp)]["seconds"] for r in entry["rounds"]]
    errs = [r[str(spp)]["relmse"] for r in entry["rounds"]]
    t, e = common.median(secs), common.median(errs)
    eff = 1.0 / (e * t) if e > 0 and t > 0 else float("inf")
    return t, e, eff


def plot(data, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    names = list(data["scenes"])
    fig, axes = plt.subplots(1, len(names), figsize=(4.2 * len(names), 3.6), squeeze=False)
    for ax, name in zip(axes[0], names):
        for r, entry in data["scenes"][name]["renderers"].items():
            pts = [p for p in (summary(entry, s)[:2] for s in data["spp"]) if p[0] > 0]  # 0 s: below timing
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=LABELS[r])
        ax.set_title(name)
        ax.set_xlabel("render seconds")
        ax.set_ylabel("relMSE vs own reference")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def summary_lines(data, top):
    """One line per comparison the issue's goals name, over every scene."""
    out = []
    pairs = [("pmc", "cycles", "efficiency, pmc / Cycles"),
             ("pmc+adaptive", "pmc", "efficiency, pmc with adaptive sampling / without"),
             ("pmc+oidn", "cycles+oidn", "efficiency with OIDN, pmc / Cycles"),
             ("pmc", "mitsuba-llvm", f"render time at {data['reference_spp']} spp, pmc / Mitsuba llvm_ad_rgb")]
    for a, b, what in pairs:
        cells = []
        for name, scene in data["scenes"].items():
            rs = scene["renderers"]
            if a not in rs or b not in rs:
                continue
            if what.startswith("render time"):
                cells.append(f"{name} {rs[a]['reference_seconds'] / rs[b]['reference_seconds']:.2f}")
            else:
                cells.append(f"{name} {summary(rs[a], top)[2] / summary(rs[b], top)[2]:.2f}")
        if cells:
            out.append(f"- {what}: " + ", ".join(cells))
    return out + [""] if out else []


def report(data):
    top = max(data["spp"])
    lines = [SECTION, "", f"Produced by `{data['command']}`.", "",
             f"Measured {data['date']} at {data['rev']} on {data['machine']}; {data['width']}x{data['height']}, "
             f"max depth {data['max_depth']}, {data['threads']} threads each, "
             f"{common.rounds_text(data['runs'])}; references at {data['reference_spp']} spp; {data['load']}.", ""]
    printed = []
    for name, scene in data["scenes"].items():
        lines += [f"**{name}** ({scene['what']}; {scene['triangles']:,} triangles)", ""]
        rows = []
        rs = scene["renderers"]
        for r, entry in rs.items():
            t, e, eff = summary(entry, top)
            # pmc beside the same kind: denoised rows against pmc + OIDN, the others against pmc
            mine = "pmc+oidn" if r.endswith("+oidn") else "pmc"
            pmc_eff = summary(rs[mine], top)[2] if mine in rs else None
            times = " / ".join(f"{summary(entry, s)[0]:.2f}" for s in data["spp"])
            own_ref = r == base(r)
            rows.append([LABELS[r], times, f"{e:.3g}", f"{eff:.3g}",
                         f"{pmc_eff / eff:.2f}" if pmc_eff else "–",
                         f"{entry['reference_seconds']:.1f}" if own_ref else "–",
                         f"{rs['pmc']['reference_seconds'] / entry['reference_seconds']:.2f}"
                         if own_ref and "pmc" in rs else "–"])
        header = ["renderer", f"seconds at {' / '.join(map(str, data['spp']))} spp", f"relMSE at {top} spp",
                  "efficiency", "pmc's efficiency / this", f"seconds at {data['reference_spp']} spp",
                  "pmc's time / this"]
        table = common.md_table(header, rows)
        lines += [table, ""]
        printed += [name, table, ""]
    lines += summary_lines(data, top)
    lines += [f"![relMSE against render time](plots/{PLOT})", ""]
    lines += [METHOD]
    return "\n".join(lines), "\n".join(printed)


METHOD = """Efficiency is 1 / (relMSE x seconds) at the largest timed sample count; a ratio above 1 in
"pmc's efficiency / this" means pmc reaches a given error sooner (denoised rows are set
against pmc + OIDN, the others against pmc). "+ OIDN" rows are the same renderer with
Open Image Denoise on (pmc `--denoise`; Cycles' OpenImageDenoise denoiser with albedo and
normal, prefiltered), measured against the renderer's own noisy reference; their time adds
the denoiser's (pmc: its stats; Cycles: a denoised 1-sample render's time less a plain
one's). Materials are diffuse
stand-ins (Kd x map_Kd, Ke, map_d) in every renderer, so this measures light transport
and sampling. Times leave out scene loading, BVH building and kernel compilation:
(t(N) - t(1)) x N / (N - 1) of each renderer's own render time. Conversions and settings:
the module comments of scripts/bench/peer_cycles.py and peer_mitsuba.py (Cycles: box
filter, no adaptive sampling, clamping or glossy filter; Mitsuba: path
integrator, box filter, independent sampler)."""


def main(argv=None):
    args = parse(argv)
    common.measure_and_report(args, PROG, SECTION, measure, report)
    plot(common.read_json(os.path.join(args.out_dir, "results.json")), common.plot_path(args, PLOT))


if __name__ == "__main__":
    main()
