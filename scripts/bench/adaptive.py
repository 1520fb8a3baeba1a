"""bench.adaptive — does adaptive sampling (pmc render --adaptive-threshold)
pay? pmc with and without it on bench.peers' scenes: render time, relMSE
against pmc's own cacheless reference, efficiency 1 / (relMSE x seconds),
and the samples per pixel it drew (issue 36, item 5). Not a test: numbers
for docs/BENCHMARKS.md.

    scripts/bench-adaptive                                   4 scenes, thresholds 0.01,0.02,0.05
    scripts/bench-adaptive --scenes cornell --spp 16,64 --reference-spp 256 --runs 1 --doc -

Method: bench.peers' scenes, camera, lights and time measure ((t(N) - t(1))
x N / (N - 1) of pmc's render_seconds); every configuration renders every
sample count once per round, the order rotating, with the round's seed;
medians over rounds. A timed render's sample count is its pixels' most.
"""
import os
import time

from bench import common, peer_scenes, peers

PROG = "bench.adaptive"
SECTION = "## Adaptive sampling: does it pay? (scripts/bench-adaptive)"


def thresholds(text):
    try:
        values = [float(v) for v in text.split(",") if v]
    except ValueError:
        raise common.argparse.ArgumentTypeError(f"expected numbers like 0.01,0.05, got {text!r}")
    if not values or any(not 0 < v <= 1 for v in values):
        raise common.argparse.ArgumentTypeError(f"thresholds must be in (0, 1], got {text!r}")
    return values


def parse(argv=None):
    p = common.make_parser("adaptive", __doc__)
    common.add_pmc(p)
    common.add_runs(p, 2)
    p.add_argument("--scenes", default=",".join(peer_scenes.SCENES), metavar="LIST",
                   help=f"comma-separated scenes, of {','.join(peer_scenes.SCENES)} (default all)")
    p.add_argument("--thresholds", type=thresholds, default="0.01,0.02,0.05", metavar="LIST",
                   help="--adaptive-threshold values to try (default 0.01,0.02,0.05)")
    p.add_argument("--min-spp", type=common.positive_int, default=8, metavar="N",
                   help="--adaptive-min-spp (default 8)")
    p.add_argument("--width", type=common.positive_int, default=160, metavar="W", help="image width (default 160)")
    p.add_argument("--height", type=common.positive_int, default=120, metavar="H",
                   help="image height (default 120)")
    p.add_argument("--spp", type=common.spp_list, default="64,256", metavar="LIST",
                   help="sample counts of the timed renders (default 64,256)")
    p.add_argument("--reference-spp", type=common.positive_int, default=2048, metavar="N",
                   help="samples of the reference (default 2048)")
    p.add_argument("--max-depth", type=common.positive_int, default=8, metavar="D",
                   help="surface hits per path (default 8)")
    p.add_argument("--threads", type=common.positive_int, default=2, metavar="T", help="pmc's threads (default 2)")
    common.add_out_dir(p, "out/bench-adaptive")
    common.add_doc(p)
    common.add_report_only(p)
    args = common.parse_args(p, "adaptive", argv=argv)
    args.scene_list = [s for s in args.scenes.split(",") if s]
    for s in args.scene_list:
        if s not in peer_scenes.SCENES:
            p.error(f"unknown scene {s!r} (known: {', '.join(peer_scenes.SCENES)})")
    args.spp_list = args.spp
    if min(args.spp_list) < 2:
        p.error("--spp needs sample counts of at least 2 (the time is (t(N) - t(1)) N / (N - 1))")
    return args


def config_name(t):
    return "plain" if t is None else f"threshold {t:g}"


def render(args, job, spps, seed, folder, threshold, reference=False):
    """peers.run_pmc with this threshold (None: off); adds each render's mean spp."""
    a = common.argparse.Namespace(**vars(args))
    a.adaptive_threshold, a.adaptive_min_spp = (threshold or 0.0), args.min_spp
    sub = os.path.join(folder, config_name(threshold).replace(" ", "_"))
    os.makedirs(sub, exist_ok=True)
    runs = peers.run_pmc(a, job, spps, seed, sub, "off" if reference else "on", adaptive=threshold is not None)
    mean_spp = {}
    for spp, (_, exr, _) in runs.items():
        st = common.read_json(exr[:-4] + ".json")
        mean_spp[spp] = st.get("adaptive", {}).get("mean_spp", float(spp))
    return runs, mean_spp


def measure(args):
    peers.check_peers([])  # images are read through Mitsuba's Bitmap
    load = common.LoadSampler()
    t0 = time.time()
    configs = [None] + list(args.thresholds)
    data = {"command": args.command, "width": args.width, "height": args.height, "spp": args.spp_list,
            "reference_spp": args.reference_spp, "max_depth": args.max_depth, "threads": args.threads,
            "runs": args.runs, "min_spp": args.min_spp, "machine": common.machine("cpu"), "rev": common.git_rev(),
            "date": common.utc_now(), "scenes": {}}
    for name in args.scene_list:
        folder = os.path.join(args.out_dir, name)
        job = peer_scenes.write_scene_files(name, os.path.join(folder, "files"))
        print(f"{PROG}: {name}: reference at {args.reference_spp} spp", flush=True)
        runs, _ = render(args, job, [args.reference_spp], 1000, folder, None, reference=True)
        ref = peers.read_exr(runs[args.reference_spp][1])
        scene = {"what": peer_scenes.SCENES[name]["what"], "configs": {config_name(c): [] for c in configs}}
        for rnd in range(args.runs):
            for c in common.round_order(configs, rnd):
                runs, mean_spp = render(args, job, args.spp_list, 1 + rnd, folder, c)
                row = {}
                for spp in args.spp_list:
                    err, _ = peers.relmse(peers.read_exr(runs[spp][1]), ref)
                    row[str(spp)] = {"seconds": peers.seconds_of(runs, spp), "relmse": err,
                                     "mean_spp": mean_spp[spp]}
                scene["configs"][config_name(c)].append(row)
                load.sample()
                print(f"{PROG}: {name} round {rnd + 1}/{args.runs} {config_name(c)}: " +
                      ", ".join(f"{s} spp {row[str(s)]['seconds']:.2f} s relMSE {row[str(s)]['relmse']:.3g} "
                                f"({row[str(s)]['mean_spp']:.1f} spp drawn)" for s in args.spp_list), flush=True)
        data["scenes"][name] = scene
    data["load"] = load.note()
    data["elapsed"] = time.time() - t0
    return data


def summary(rounds, spp):
    t = common.median([r[str(spp)]["seconds"] for r in rounds])
    e = common.median([r[str(spp)]["relmse"] for r in rounds])
    n = common.median([r[str(spp)]["mean_spp"] for r in rounds])
    return t, e, (1.0 / (e * t) if e > 0 and t > 0 else float("inf")), n


def report(data):
    lines = [SECTION, "", f"Produced by `{data['command']}` ({data['elapsed'] / 60:.1f} minutes).", "",
             f"Measured {data['date']} at {data['rev']} on {data['machine']}; {data['width']}x{data['height']}, "
             f"max depth {data['max_depth']}, {data['threads']} threads, `--adaptive-min-spp {data['min_spp']}`, "
             f"{common.rounds_text(data['runs'])}; reference: pmc, cache off, {data['reference_spp']} spp, "
             f"another seed; {data['load']}.", ""]
    header = ["configuration"]
    for s in data["spp"]:
        header += [f"{s} spp: seconds", "relMSE", "samples drawn", "efficiency / plain"]
    printed, verdicts = [], []
    for name, scene in data["scenes"].items():
        rows = []
        plain = scene["configs"]["plain"]
        for cname, rounds in scene["configs"].items():
            row = [cname]
            for s in data["spp"]:
                t, e, eff, n = summary(rounds, s)
                row += [f"{t:.2f}", f"{e:.3g}", f"{n:.1f}", f"{eff / summary(plain, s)[2]:.2f}"]
            rows.append(row)
        table = common.md_table(header, rows)
        lines += [f"**{name}** ({scene['what']})", "", table, ""]
        printed += [name, table, ""]
        top = max(data["spp"])
        best = max(scene["configs"], key=lambda c: summary(scene["configs"][c], top)[2])
        verdicts.append(f"{name}: {best} "
                        f"({summary(scene['configs'][best], top)[2] / summary(plain, top)[2]:.2f}x plain's)")
    lines += [f"Best efficiency at {max(data['spp'])} spp per scene: " + "; ".join(verdicts) + ".", "",
              METHOD]
    return "\n".join(lines), "\n".join(printed)


METHOD = """"efficiency / plain" is 1 / (relMSE x seconds) of the configuration over that of pmc without
adaptive sampling at the same maximum sample count, in the same rounds: above 1, adaptive
sampling reaches a given error sooner. "samples drawn" is the average over pixels. Times are
(t(N) - t(1)) x N / (N - 1) of pmc's render_seconds, as in "Against Cycles and Mitsuba 3"
(same scenes, diffuse stand-in materials, the cache on)."""


def main(argv=None):
    args = parse(argv)
    common.measure_and_report(args, PROG, SECTION, measure, report)


if __name__ == "__main__":
    main()
