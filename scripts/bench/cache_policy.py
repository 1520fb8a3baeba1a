"""bench.cache_policy — the cache's replacement policy (--cache-policy keep-first
vs priority) in tables smaller than pmc's automatic size. Prints a table and
writes the "Cache replacement policy" section of docs/BENCHMARKS.md.

    scripts/python -m bench.cache_policy                 default scene, 640x360, 16 spp, 3 rounds
    scripts/python -m bench.cache_policy --runs 1 --width 160 --height 90 --spp 4 --doc -    a quick look
    scripts/python -m bench.cache_policy --rt-priority 50    time under chrt -f 50 (a shared, loaded machine)

Method (default scene, data/default):
  1. an untimed render with the cache on at the measured size: fills PoCL's
     kernel cache and the OS file cache, and its stats give the automatic
     table size (cells; entries stay 8);
  2. per table size (the automatic size divided by each of --fractions) and
     policy, one `pmc compare` (same seed, cached vs cacheless): PSNR of the
     cached image against the cacheless one;
  3. RUNS rounds, each running `pmc render --cache off` and every (size,
     policy) once, the order rotated every round. Per configuration: the
     median render_seconds, the speedup median off / median on with the range
     of per-round ratios, the camera-ray hit rate (camera_hits /
     camera_lookups) and the total hit rate from --stats, and the share of
     the full-size speedup a smaller table keeps.
"""
import argparse
import os
import time

from bench import common

PROG = "bench.cache_policy"
SECTION = "## Cache replacement policy (scripts/bench-cache-policy)"
DEFAULT_ARGS = ["data/default/room.obj", "--mtlx", "data/default/materials.mtlx"]
POLICIES = ["keep-first", "priority"]
FIT = "keep-first + fit"  # --cache-fit on: coarser texels instead of another policy
VARIANTS = {"keep-first": ["--cache-policy", "keep-first"], "priority": ["--cache-policy", "priority"],
            FIT: ["--cache-policy", "keep-first", "--cache-fit", "on"]}
GOAL_FRACTION = 16  # the goal: at 1/16 of the automatic size keep 90% of the full-size speedup
GOAL_SHARE = 0.9


def fractions_arg(text):
    try:
        fs = [int(x) for x in text.split(",") if x]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected whole numbers separated by commas, got '{text}'")
    if not fs or any(f < 1 for f in fs):
        raise argparse.ArgumentTypeError(f"every divisor must be at least 1, got '{text}'")
    return fs


def parse(argv=None):
    p = common.make_parser("cache_policy", __doc__)
    common.add_pmc(p)
    common.add_runs(p, 3)
    common.add_image_size(p, 640, 360, 16)
    p.add_argument("--bias-spp", type=common.positive_int, default=256, metavar="N",
                   help="samples per pixel of the half-size comparisons that measure --cache-fit's bias "
                        "(default 256)")
    p.add_argument("--fractions", type=fractions_arg, default=[1, 4, 16, 64], metavar="LIST",
                   help="table sizes as divisors of the automatic cell count (default 1,4,16,64)")
    p.add_argument("--rt-priority", type=common.positive_int, metavar="P",
                   help="run the timed renders under `chrt -f P` (SCHED_FIFO), so that other processes on "
                        "a shared machine disturb them less")
    common.add_out_dir(p, "out/bench-cache-policy")
    common.add_doc(p)
    common.add_report_only(p)
    return common.parse_args(p, "cache_policy", None, argv)


def progress(msg):
    print(f"{PROG}: {msg}", flush=True)


def config_name(policy, divisor):
    return f"{policy} 1/{divisor}"


def tag(name):
    return name.replace(" + ", "_").replace(" ", "_").replace("/", "_")


class Measure:
    def __init__(self, args):
        self.a = args
        self.out = args.out_dir
        self.log = os.path.join(self.out, "log.txt")
        open(self.log, "w").close()
        self.size = common.size_args(args.width, args.height, args.spp)

    def render(self, tag, extra, timed=True):
        exr, js = f"{self.out}/{tag}.exr", f"{self.out}/{tag}.json"
        rt = ["chrt", "-f", str(self.a.rt_priority)] if timed and self.a.rt_priority else []
        cmd = [*rt, self.a.pmc, "render", *DEFAULT_ARGS, "-o", exr, "--stats", js, *self.size, *extra]
        return common.run_pmc(cmd, js, self.log, f"render {tag}", append=True)[0]

    def compare(self, tag, extra, size=None):
        d = f"{self.out}/{tag}"
        common.run([self.a.pmc, "compare", *DEFAULT_ARGS, "--out-dir", d, *(size or self.size), *extra], self.log,
                   f"compare {tag}", append=True)
        return common.read_json(f"{d}/metrics.json")

    def fit_bias(self):
        """Cached vs cacheless at half size and --bias-spp: the automatic table, then --cache-fit in
        tables of 1/d of it (the policies alone do not change the image)."""
        size = common.size_args(max(1, self.a.width // 2), max(1, self.a.height // 2), self.a.bias_spp)
        progress(f"pmc compare at half size, {self.a.bias_spp} spp: the automatic table")
        full = self.compare("bias_automatic", [], size)
        out = {"automatic": dict(psnr=full["psnr"], worst=full["cached_vs_cacheless"]["worst_tile_psnr"],
                                 cells=full["cache"]["cells"], fit_levels=0.0)}
        for d in self.a.fractions:
            if d == 1:
                continue
            progress(f"pmc compare at half size, {self.a.bias_spp} spp: --cache-fit on, 1/{d}")
            cells = max(1, full["cache"]["cells"] // d)
            m = self.compare(f"bias_fit_{d}", ["--cache-cells", str(cells), "--cache-fit", "on"], size)
            out[str(d)] = dict(psnr=m["psnr"], worst=m["cached_vs_cacheless"]["worst_tile_psnr"], cells=cells,
                               fit_levels=m["cache"]["fit_levels"])
        return out

    def all(self):
        t0 = time.time()
        load = common.LoadSampler()
        progress("warm-up and the automatic table size (untimed)")
        warm = self.render("warm_on", ["--cache", "on"], timed=False)
        self.render("warm_off", ["--cache", "off"], timed=False)
        full_cells, entries = warm["cache"]["cells"], warm["cache"]["entries"]
        device = warm.get("device", "")
        configs = [("off", ["--cache", "off"])]
        cells = {}
        for d in self.a.fractions:
            cells[d] = max(1, full_cells // d)
            for variant, flags in VARIANTS.items():
                if variant == FIT and d == 1:
                    continue  # the automatic table fits: fit changes nothing there
                configs.append((config_name(variant, d), ["--cache", "on", "--cache-cells", str(cells[d]), *flags]))
        psnr, worst_tile, fit_levels = {}, {}, {}
        for name, extra in configs[1:]:
            progress(f"pmc compare, {name}")
            m = self.compare("compare_" + tag(name), extra[2:])
            psnr[name] = m["psnr"]
            worst_tile[name] = m.get("cached_vs_cacheless", {}).get("worst_tile_psnr")
            fit_levels[name] = m.get("cache", {}).get("fit_levels", 0.0)
        bias = self.fit_bias()
        times = {name: [] for name, _ in configs}
        stats = {}
        for r in range(self.a.runs):
            for name, extra in common.round_order(configs, r):
                st = self.render(f"r{r}_" + tag(name), extra)
                times[name].append(st["render_seconds"])
                stats[name] = st["cache"]
                load.sample()
            progress(f"round {r + 1}/{self.a.runs}: " + ", ".join(f"{n} {times[n][-1]:.2f} s" for n, _ in configs))
        return dict(command=self.a.command, now=common.utc_now(), rev=common.git_rev(ignore=["docs/BENCHMARKS.md"]),
                    machine=common.machine(device), load=load.note(), elapsed=time.time() - t0,
                    width=self.a.width, height=self.a.height, spp=self.a.spp, runs=self.a.runs,
                    rt_priority=self.a.rt_priority, full_cells=full_cells, entries=entries,
                    fractions=self.a.fractions, cells=cells, times=times, psnr=psnr, worst_tile=worst_tile,
                    fit_levels=fit_levels, bias=bias, bias_spp=self.a.bias_spp,
                    cache={n: {k: s.get(k) for k in ("lookups", "misses", "hit_rate", "camera_hit_rate",
                                                     "camera_lookups", "camera_hits", "replaced", "dropped_full",
                                                     "memory_bytes")}
                           for n, s in stats.items()})


def report(data):
    """The section (markdown) and what to print."""
    t_off = common.median(data["times"]["off"])
    rows = []
    speedup = {}
    for d in data["fractions"]:
        for policy in VARIANTS:
            n = config_name(policy, d)
            if n not in data["cache"]:
                continue
            c = data["cache"][n]
            t = common.median(data["times"][n])
            speedup[n] = t_off / t
            ratios = common.round_ratios(data["times"]["off"], data["times"][n])
            rows.append((d, policy, n, c, t, ratios))
    full = speedup.get(config_name("keep-first", 1))
    table_rows = []
    worst = data.get("worst_tile", {})
    levels = data.get("fit_levels", {})
    for d, policy, n, c, t, ratios in rows:
        share = f"{100 * speedup[n] / full:.0f}%" if full else "-"
        label = f"`keep-first` + `--cache-fit on` ({levels.get(n, 0):.1f} levels coarser)" if policy == FIT else f"`{policy}`"
        table_rows.append([f"1/{d}" + (" (automatic)" if d == 1 else ""), str(data["cells"][str(d)]),
                           f"{c['memory_bytes'] / 2**20:.2f}", label,
                           f"{100 * c['camera_hit_rate']:.1f}%", f"{100 * c['hit_rate']:.1f}%",
                           str(c["replaced"]), f"{t:.2f}",
                           f"**{speedup[n]:.2f}x** ({min(ratios):.2f}-{max(ratios):.2f})", share,
                           f"{data['psnr'][n]:.1f}", f"{worst[n]:.1f}" if worst.get(n) is not None else "-"])
    table = common.md_table(["table", "cells", "MiB", "policy", "camera hit rate", "total hit rate", "replaced",
                             "time (s)", "speedup off / on (range)", "of full-size speedup", "PSNR vs off (dB)",
                             "worst 16x16 tile (dB)"],
                            table_rows)

    # Goals and verdicts.
    lines = []
    kf = {d: data["cache"][config_name("keep-first", d)] for d in data["fractions"]}
    pr = {d: data["cache"][config_name("priority", d)] for d in data["fractions"]}
    never_less = all(pr[d]["camera_hits"] >= kf[d]["camera_hits"] for d in data["fractions"])
    idle = [d for d in data["fractions"] if pr[d]["replaced"] == 0]
    lines.append("- Camera-ray hit rate, keep-first -> priority: " + ", ".join(
        f"1/{d}: {100 * kf[d]['camera_hit_rate']:.1f}% -> {100 * pr[d]['camera_hit_rate']:.1f}% "
        f"({pr[d]['replaced']} replaced)" for d in data["fractions"]) +
        f". Priority hits at least as often on camera rays at every size: **{'yes' if never_less else 'no'}**." +
        (" Where priority replaced nothing (" + ", ".join(f"1/{d}" for d in idle) + "), the camera hits of the "
         "first sample alone had filled the table: no entry was deeper, both policies ran the same algorithm, "
         "and their counts differ only by which thread inserted first." if idle else ""))
    if GOAL_FRACTION in data["fractions"] and full:
        for policy in POLICIES + [FIT]:
            n = config_name(policy, GOAL_FRACTION)
            if n not in speedup:
                continue  # a run from before --cache-fit
            share = speedup[n] / full
            lines.append(f"- At 1/{GOAL_FRACTION} of the automatic size, `{policy}` keeps {100 * share:.0f}% of the "
                         f"full-size speedup ({speedup[n]:.2f}x of {full:.2f}x): goal {100 * GOAL_SHARE:.0f}% "
                         f"**{'met' if share >= GOAL_SHARE else 'not met'}**.")
    if GOAL_FRACTION in data["fractions"]:
        d = GOAL_FRACTION
        wins = (speedup[config_name("priority", d)] >= speedup[config_name("keep-first", d)] and
                pr[d]["camera_hits"] >= kf[d]["camera_hits"])
        lines.append(f"- Default: priority {'wins' if wins else 'does not win'} at 1/{d} (speedup "
                     f"{speedup[config_name('priority', d)]:.2f}x against keep-first's "
                     f"{speedup[config_name('keep-first', d)]:.2f}x; total hit rate {100 * pr[d]['hit_rate']:.1f}% "
                     f"against {100 * kf[d]['hit_rate']:.1f}%), so `keep-first` "
                     f"{'could give way to priority' if wins else 'stays the default'}.")
    fits = [(d, config_name(FIT, d)) for d in data["fractions"] if config_name(FIT, d) in data["psnr"]]
    if fits and full:
        lines.append("- `--cache-fit on` (keep-first): " + ", ".join(
            f"1/{d}: {speedup[n]:.2f}x ({100 * speedup[n] / full:.0f}% of the full-size speedup), "
            f"{100 * data['cache'][n]['hit_rate']:.1f}% hits, {data['psnr'][n]:.1f} dB"
            + (f" (worst tile {worst[n]:.1f} dB)" if worst.get(n) is not None else "")
            for d, n in fits) + f"; the automatic table: {data['psnr'][config_name('keep-first', 1)]:.1f} dB. "
            "It keeps the speed by coarsening the texels, so the error grows as the table shrinks: a trade the user "
            "chooses, not a policy, and it stays off by default.")
    bias = data.get("bias")
    bias_text = ""
    if bias:
        rows_b = [["automatic", str(bias["automatic"]["cells"]), "0.0", f"{bias['automatic']['psnr']:.1f}",
                   f"{bias['automatic']['worst']:.1f}"]]
        rows_b += [[f"1/{d}, `--cache-fit on`", str(bias[str(d)]["cells"]), f"{bias[str(d)]['fit_levels']:.1f}",
                    f"{bias[str(d)]['psnr']:.1f}", f"{bias[str(d)]['worst']:.1f}"]
                   for d in data["fractions"] if str(d) in bias]
        bias_text = (f"\n\nThe bias of `--cache-fit` (its texels are coarser, so its image is not the full table's): "
                     f"one `pmc compare` each at {data['width'] // 2}x{data['height'] // 2}, {data['bias_spp']} spp "
                     f"(enough samples that the cache's bias shows above the noise), tables as fractions of the "
                     f"automatic size at that resolution:\n\n" +
                     common.md_table(["table", "cells", "fit levels", "PSNR vs off (dB)", "worst 16x16 tile (dB)"],
                                     rows_b))
    psnrs = sorted({round(v, 3) for k, v in data["psnr"].items() if not k.startswith(FIT)})
    lines.append("- PSNR against the cacheless render is " +
                 (f"the same {psnrs[0]:.1f} dB for every size and policy" if len(psnrs) == 1 else
                  f"{psnrs[0]:.1f}-{psnrs[-1]:.1f} dB") + (" (without fit)" if fits else "") +
                 ": in `--cache-eval center` (the default) a texel's value does not depend on who inserted it, "
                 "so neither the table size nor the policy changes the image (tests/gpu/cache_policy_render_test.cpp "
                 "requires bit-identical images); they change only how often the work is saved.")
    # False hits the 2 lost fingerprint bits can add: every miss compares with at most `entries` entries.
    worst_misses = max(data["cache"][config_name("priority", d)]["misses"] for d in data["fractions"])
    false_hits = worst_misses * data["entries"] * 2.0**-30
    smallest = max(data["fractions"])
    any_kf = kf[min(data["fractions"])]
    deeper = 1 - any_kf["camera_lookups"] / any_kf["lookups"] if any_kf["lookups"] else 0.0
    goal_rates = sorted(100 * x[GOAL_FRACTION]["hit_rate"] for x in (kf, pr)) if GOAL_FRACTION in kf else []
    goal_hits = f"{goal_rates[0]:.0f}-{goal_rates[1]:.0f}%" if goal_rates else "-"
    if 1 not in kf:
        kf[1] = any_kf
    cmd = " ".join(["build/pmc", "render", *DEFAULT_ARGS, "-o", "OUT.exr", "--stats", "OUT.json",
                    "--cache", "off|on", "--cache-cells", "N", "--cache-policy", "keep-first|priority",
                    "[--cache-fit on]",
                    *common.size_args(data["width"], data["height"], data["spp"])])
    rt = (f" Timed renders ran under `chrt -f {data['rt_priority']}`." if data.get("rt_priority") else "")
    section = f"""{SECTION}

Produced by `{data['command']}` on {data['now']} ({data['elapsed'] / 60:.1f} minutes).
Machine: {data['machine']}; checkout {data['rev']}; {data['load']}.{rt}

Default scene, {data['width']}x{data['height']}, {data['spp']} spp, seed 0, `--cache-eval center`. The automatic
table here is {data['full_cells']} cells x {data['entries']} entries; the smaller tables divide its cells by
{', '.join(str(d) for d in data['fractions'])}. {common.rounds_text(data['runs'])} of `--cache off` and every
(size, policy), the order rotated each round; time is the median `render_seconds`, speedup the median off
over the median on, in brackets the lowest and highest ratio of one round; "of full-size speedup" is that
speedup over keep-first's at the automatic size. Hit rates come from `--stats` (`camera_hit_rate`: lookups
at camera-ray hits, depth 0; `hit_rate`: all lookups). PSNR: one `pmc compare` per configuration (cached vs
cacheless, same seed). Other processes may share the 2 cores: single times vary by 10-30%; read ratios.

    {cmd}

{table}

""" + "\n".join(lines) + bias_text + f"""

![speedup and hit rate against the table size, per policy](plots/cache_policy.png)

How priority works (core/device/pmc_cache.h): a full cell keeps its first entries under keep-first (the
paper's rule). Under priority an entry's high word holds 30 bits of the key's fingerprint and a 2-bit depth
tag (min(depth, 3)); an insert from a camera-ray hit that finds its cell full replaces the deepest non-camera
entry with one 64-bit CAS from the word it read; camera entries are never replaced. The tag costs two
fingerprint bits: over 2^22 descriptors, pairs of 30-bit fingerprints agree at 2^-30 as expected
(tests/core/cache_policy_test.cpp), so a lookup of an absent key in a full 8-entry cell hits falsely with
probability about 8 x 2^-30 = 7.5e-9 (keep-first: 1.9e-9). Here at most {worst_misses} lookups missed in
one render, so a frame has at most {false_hits:.2g} false hits expected under priority ({false_hits / 4:.2g} with
keep-first's 32 bits).

Why priority does not pay for time: the renderer is a wavefront, so every camera-ray hit of a sample is shaded
before any of its deeper bounces. A table too small for one sample's camera texels is full of camera entries
after the first sample's first bounce, and there is nothing deeper to replace (priority replaced
{pr[smallest]['replaced']} entries at 1/{smallest}). In between, priority does what it is built for (more
camera-ray hits), but the entries it evicts are looked up again by the deeper bounces of later samples, which
make up {100 * deeper:.0f}% of the lookups, so the total hit rate falls and with it the saved work. At 1/16
the table holds too few entries for the frame's texels whatever the policy ({goal_hits} of the lookups hit,
against {100 * kf[1]['hit_rate']:.0f}% at the automatic size). No policy could win there: replayed from a trace of
every lookup, even Belady's MIN, which knows the future, stays short of the goal (section "Cache
replacement bounds").

How `--cache-fit on` works (core/cache_sizing.h): no policy can keep more keys than the table holds, so fit
shrinks the keys instead. When the table has fewer entries than the frame's expected keys need at load factor
1/2 (the rule that sizes the automatic table), every texel and position cell is made coarser by half a level
per halving of the table (a level has a quarter of the texels), so the frame's keys fit again. The image is
exactly the render with `--mip-bias` lowered by that many levels (tests/gpu/cache_fit_test.cpp), so its error
is that of coarser texels, at any table size.
"""
    return section, "\n" + table + "\n\n" + "\n".join(lines) + bias_text + "\n"


PLOT = "cache_policy.png"  # in plots/ beside the --doc file (common.plot_path)


def plot(data, path):
    """The size-versus-policy curves: speedup and hit rates against the table size, one line per policy."""
    try:
        import matplotlib
    except ImportError:
        print(f"{PROG}: matplotlib is not installed (Debian: python3-matplotlib): {path} not drawn")
        return
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t_off = common.median(data["times"]["off"])
    fig, (ax_s, ax_h) = plt.subplots(1, 2, figsize=(10, 3.8))
    for variant, style in zip(VARIANTS, ("o-", "s-", "^-")):
        pts = [(d, config_name(variant, d)) for d in data["fractions"] if config_name(variant, d) in data["cache"]]
        if variant == FIT:  # at the automatic size fit changes nothing: its curve starts at keep-first's point
            pts = [(1, config_name("keep-first", 1))] + pts
        mib = [data["cache"][n]["memory_bytes"] / 2**20 for _, n in pts]
        ax_s.plot(mib, [t_off / common.median(data["times"][n]) for _, n in pts], style, label=variant)
        ax_h.plot(mib, [100 * data["cache"][n]["hit_rate"] for _, n in pts], style, label=f"{variant}: all lookups")
        ax_h.plot(mib, [100 * data["cache"][n]["camera_hit_rate"] for _, n in pts], style[0] + ":",
                  color=ax_h.lines[-1].get_color(), label=f"{variant}: camera rays")
    full = t_off / common.median(data["times"][config_name("keep-first", 1)])
    ax_s.axhline(1.0, color="grey", lw=0.8)
    ax_s.axhline(GOAL_SHARE * full, color="grey", lw=0.8, ls="--")
    ax_s.text(0.02, GOAL_SHARE * full, f"{100 * GOAL_SHARE:.0f}% of the full-size speedup", va="bottom",
              fontsize=8, color="grey", transform=ax_s.get_yaxis_transform())
    ax_s.text(0.02, 1.0, "cacheless", va="bottom", fontsize=8, color="grey", transform=ax_s.get_yaxis_transform())
    for ax in (ax_s, ax_h):
        ax.set_xscale("log", base=2)
        ax.set_xlabel("cache table (MiB)")
        ax.grid(alpha=0.3)
    ax_s.set_ylabel("speedup, cache off / on")
    ax_h.set_ylabel("hit rate (%)")
    ax_s.legend(fontsize=8)
    ax_h.legend(fontsize=7)
    fig.suptitle(f"Default scene, {data['width']}x{data['height']}, {data['spp']} spp: table size against policy",
                 fontsize=10)
    fig.tight_layout()
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    print(f"{PROG}: wrote {path}")


def main(argv=None):
    args = parse(argv)
    common.measure_and_report(args, PROG, SECTION, lambda a: Measure(a).all(), report, inputs=(DEFAULT_ARGS[0],))
    if args.doc != "-":  # the curves go with the section
        plot(common.read_json(os.path.join(args.out_dir, "results.json")), common.plot_path(args, PLOT))


if __name__ == "__main__":
    main()
