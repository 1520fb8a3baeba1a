"""bench.sweep — the paper-style figures: two `pmc sweep` runs on the default
scene, scripts/plot_sweep.py on each, the plots in docs/plots/ and the "Cache
sweeps and equal-time convergence" section of docs/BENCHMARKS.md (commands,
the numbers the plots show, what they say).

    scripts/python -m bench.sweep                  build/pmc (scripts/setup first if it is missing)
    scripts/python -m bench.sweep --repeat 5       timing rounds per sweep (default 3; medians)
    scripts/python -m bench.sweep --repeat 1 --spp 1 --ref-spp 4 --width 64 --height 36 \\
        --plots /tmp/plots --doc -                 a quick look
    scripts/python -m bench.sweep --report-only    re-plot the CSVs of the last run, rewrite the section

1. Cache size (the paper's Fig. 4): cells 1024 .. 1048576 x entries 1, 4, 8
   at mip bias 0, center mode; render time and hit rate against memory.
2. Mip bias x cache mode at the automatic size, and equal-time convergence:
   mip biases -1, 0, 1, 2 with --cache-eval hit and center; then cache off
   and on (the default settings) at 1 .. 64 spp, relMSE against a cacheless
   REF_SPP reference. `pmc sweep --repeat` renders every row once per round
   (round-robin), so all rows share the machine's drift; times are medians.
With --report-only the date and load lines are those of the rewrite.
"""
import os
import re
import sys
import time

from bench import common

PROG = "bench.sweep"
SECTION = "## Cache sweeps and equal-time convergence (scripts/bench-sweep)"
OLD_SECTIONS = ["## Cache sweeps and equal-time convergence (scripts/plot_sweep.py)"]
LEGACY = {"REPEAT": "--repeat", "SPP": "--spp", "REF_SPP": "--ref-spp", "OUTDIR": "--out-dir", "PLOTS": "--plots",
          "DOC": "--doc", "PMC": "--pmc", "REPORT_ONLY": "--report-only"}
SCENE = ["data/default/room.obj", "--mtlx", "data/default/materials.mtlx"]
CONVERGENCE = "1,2,4,8,16,32,64"
SIZE_ARGS = ["--cells", "1024,4096,16384,65536,262144,1048576", "--entries", "1,4,8", "--mip-bias", "0",
             "--cache-evals", "center", "--reference-spp", "1"]


def parse(argv=None):
    p = common.make_parser("sweep", __doc__, LEGACY)
    common.add_pmc(p)
    common.add_runs(p, 3, flag="--repeat", what="timing rounds per sweep, every row once per round (medians)")
    p.add_argument("--spp", type=common.positive_int, default=8, metavar="N", help="the sweeps' samples (default 8)")
    p.add_argument("--ref-spp", type=common.positive_int, default=1024, metavar="N",
                   help="the reference of the convergence curves (default 1024: far more samples than the "
                        "curves' 64, so that its own noise stays below their error)")
    p.add_argument("--width", type=common.positive_int, default=320, metavar="W", help="image width (default 320)")
    p.add_argument("--height", type=common.positive_int, default=180, metavar="H", help="image height (default 180)")
    common.add_out_dir(p, "out/bench-sweep", "the CSVs, images and logs")
    p.add_argument("--plots", default="docs/plots", metavar="DIR",
                   help="where the plots go (default docs/plots)")
    common.add_doc(p)
    p.add_argument("--report-only", action="store_true",
                   help="render nothing: re-plot the CSVs of the last run in OUT_DIR and rewrite the section")
    return common.parse_args(p, "sweep", LEGACY, argv)


def progress(msg):
    print(f"{PROG}: {msg}", flush=True)


def run(cmd, log):
    progress(" ".join(cmd))
    try:
        return common.run(cmd, log).output
    except common.RunFailed as e:
        output = common.read_text(log).split("\n", 1)[-1]
        sys.exit(f"{PROG}: failed ({e}):\n{output[-3000:]}")


def body(text):
    """plot_sweep's numbers without its 'wrote ...' and row-count lines."""
    return "\n".join("    " + line for line in text.splitlines()
                     if line.strip() and not line.startswith("plot_sweep:"))


def size_rows(text):
    """The cache-size table plot_sweep prints, and the cacheless time."""
    rows = []
    for line in text.splitlines():
        m = re.match(r"\s+(\d+)\s+(\d+)\s+([\d.]+)\s+([\d.]+)%\s+([\d.]+)", line)
        if m:
            rows.append(dict(cells=int(m[1]), entries=int(m[2]), t=float(m[3]), hit=float(m[4]), mib=float(m[5])))
    off = re.search(r"cache off: ([\d.]+) s", text)
    return rows, float(off[1]) if off else None


def findings(plot_size, plot_bias, spp, ref_spp):
    """What the numbers say, one numbered paragraph per plot."""
    out = []
    rows, t_off = size_rows(plot_size)
    if rows and t_off:
        best_hit = max(r["hit"] for r in rows)
        sat = min((r for r in rows if r["hit"] >= best_hit - 2.0), key=lambda r: r["mib"])
        fastest = min(rows, key=lambda r: r["t"])
        slower = [r for r in rows if r["t"] > t_off]
        out.append(
            f"1. **Cache size** (Fig. 4 of the paper): the hit rate reaches {sat['hit']:.0f}% (within 2 points of "
            f"the best, {best_hit:.0f}%) at {sat['mib']:.2f} MiB ({sat['cells']} cells x {sat['entries']} entries); "
            f"the fastest setting, {fastest['cells']} x {fastest['entries']} ({fastest['mib']:.2f} MiB, "
            f"{fastest['hit']:.0f}% hits), takes {fastest['t']:.2f} s against {t_off:.2f} s without the cache "
            f"({t_off / fastest['t']:.2f}x). " +
            (f"Tables too small for the scene do not pay: all {len(slower)} settings slower than no cache are "
             f"of {max(r['mib'] for r in slower):.2g} MiB or less, at {max(r['hit'] for r in slower):.0f}% hits or "
             "fewer (" + ", ".join(f"{r['cells']} x {r['entries']}: {r['hit']:.0f}% hits, {r['t']:.2f} s"
                                   for r in sorted(slower, key=lambda r: (r["mib"], r["entries"]))) +
             "): every miss pays a lookup and an insert on top of the full evaluation."
             if slower else "No setting was slower than the cacheless render."))
        same_mem = {}
        for r in rows:
            same_mem.setdefault(round(r["mib"], 3), []).append(r)
        pairs = [v for v in same_mem.values() if len(v) > 1]
        if pairs:
            v = sorted(max(pairs, key=lambda v: v[0]["mib"]), key=lambda r: r["entries"])
            out.append(
                f"   At equal memory ({v[0]['mib']:.2f} MiB) more entries per cell keep more keys: " +
                ", ".join(f"{r['entries']} {'entry' if r['entries'] == 1 else 'entries'} {r['hit']:.0f}% hits"
                          for r in v) +
                " (a one-entry cell loses every colliding key).")

    bias = []
    for line in plot_bias.splitlines():
        m = re.match(r"\s+(hit|center\S*)\s+([+-]?[\d.]+)\s+([\d.]+)\s+([\d.]+)%\s+([\d.eE+-]+)\s+([\d.]+|nan|inf)",
                     line)
        if m:
            bias.append(dict(ev=m[1], bias=float(m[2]), t=float(m[3]), hit=float(m[4]), rel=float(m[5]),
                             psnr=float(m[6])))
    off_line = re.search(r"cache off\s+([\d.]+)\s+([\d.eE+-]+)", plot_bias)
    if bias and off_line:
        t_off_b, rel_off = float(off_line[1]), float(off_line[2])
        out.append(
            f"2. **Mip bias and cache mode** at the automatic size: against the {ref_spp}-spp reference every "
            f"setting's relMSE is within {100 * max(abs(b['rel'] / rel_off - 1) for b in bias):.1f}% of the "
            f"cacheless render's ({rel_off:.4g}): at {spp} spp the cache's bias is far below the Monte Carlo "
            "noise. Against the cacheless image at equal samples (PSNR), per mode from bias -1 to +2: " +
            "; ".join(f"{ev}: " + ", ".join(f"{b['psnr']:.1f} dB at {b['hit']:.0f}% hits, {t_off_b / b['t']:.2f}x"
                                            for b in sorted((b for b in bias if b["ev"] == ev),
                                                            key=lambda b: b["bias"]))
                      for ev in sorted({b["ev"] for b in bias})) +
            ". Finer virtual texels (positive bias) trade hits, and so speed, for accuracy.")
    conv_on = re.findall(r"relMSE ([\d.eE+-]+): cache on ([\d.]+) s, cache off ([\d.]+) s \(interpolated\): ([\d.]+)x",
                         plot_bias)
    if conv_on:
        out.append(
            "3. **Equal-time convergence**: for the errors the cached render reaches at its sample counts, the "
            "cacheless render needs (log-log interpolation) " +
            ", ".join(f"{float(c[3]):.2f}x" for c in conv_on) +
            " the time; " + ("the cache reaches the same error sooner from the first interpolated point on."
                             if all(float(c[3]) > 1.0 for c in conv_on) else
                             "where the factor is below 1 (the first samples, while the table fills) the cache "
                             "costs more than it saves.") +
            " So at equal time the cached image is the better one: that is the question a user asks.")
    return out


def main(argv=None):
    a = parse(argv)
    common.chdir_root()
    OUT, PLOTS = a.out_dir, a.plots
    PMC = a.pmc if a.report_only else common.find_pmc(a.pmc, PROG)
    os.makedirs(OUT, exist_ok=True)
    os.makedirs(PLOTS, exist_ok=True)

    def sweep_cmd(out_dir, extra):
        return [PMC or "build/pmc", "sweep", *SCENE, "--out-dir", out_dir, "--width", str(a.width),
                "--height", str(a.height), "--spp", str(a.spp), "--repeat", str(a.repeat), "--quiet",
                "--plots", "none", *extra]  # plotted below, into --plots

    def plot_cmd(csv):
        return ["scripts/plot_sweep.py", csv, PLOTS]

    t0 = time.time()
    load_before = common.loadavg()
    size_dir, bias_dir = f"{OUT}/size", f"{OUT}/bias"
    bias_args = ["--entries", "8", "--mip-bias", "-1,0,1,2", "--cache-evals", "center,hit",
                 "--convergence-spp", CONVERGENCE, "--reference-spp", str(a.ref_spp)]
    if a.report_only:
        for d in (size_dir, bias_dir):
            if not os.path.exists(f"{d}/sweep.csv"):
                sys.exit(f"{PROG}: --report-only but {d}/sweep.csv is missing: run the sweeps first")
    else:
        run(sweep_cmd(size_dir, SIZE_ARGS), f"{OUT}/size.log")
    load_mid = common.loadavg()
    if not a.report_only:
        run(sweep_cmd(bias_dir, bias_args), f"{OUT}/bias.log")
    load_after = common.loadavg()
    # plot_sweep.py runs under this interpreter (the project's .venv with matplotlib).
    plot_size = run([sys.executable, *plot_cmd(f"{size_dir}/sweep.csv")], f"{OUT}/plot_size.log")
    plot_bias = run([sys.executable, *plot_cmd(f"{bias_dir}/sweep.csv")], f"{OUT}/plot_bias.log")
    elapsed = time.time() - t0
    for text in (plot_size, plot_bias):
        print(text)

    def shown(cmd):
        return "    " + " ".join("build/pmc" if x == PMC else x for x in cmd)

    cmds = "\n".join([shown(sweep_cmd(size_dir, SIZE_ARGS)), shown(sweep_cmd(bias_dir, bias_args)),
                      shown(plot_cmd(f"{size_dir}/sweep.csv")), shown(plot_cmd(f"{bias_dir}/sweep.csv"))])
    plots_rel = os.path.relpath(PLOTS, os.path.dirname(a.doc) or ".") if a.doc != "-" else PLOTS
    section = f"""{SECTION}

Produced by `{a.command}` on {common.utc_now()} ({elapsed / 60:.1f} minutes), checkout {common.git_rev()}.
Machine: {os.cpu_count()} cores ({common.cpu_model()}); 1-minute load average {load_before:.1f} before, {load_mid:.1f} between and
{load_after:.1f} after the sweeps. Default scene, {a.width}x{a.height}, {a.spp} spp; each sweep renders every
row once per round, {a.repeat} rounds round-robin, times are medians (`render_seconds`).

{cmds}

`plot_sweep.py` writes each plot only when the CSV has what it needs (several
cache sizes; several mip biases or modes; convergence rows), so the first call
writes `cache_size_time.png` and the second the other two. What they plot:

{body(plot_size)}

{body(plot_bias)}

![render time and hit rate vs cache size]({plots_rel}/cache_size_time.png)

![error vs time per mip bias]({plots_rel}/mip_bias_error.png)

![equal-time convergence]({plots_rel}/convergence.png)

What they show:

""" + "\n".join(findings(plot_size, plot_bias, a.spp, a.ref_spp)) + "\n"

    print(section)
    common.write_section(a.doc, SECTION, section, PROG, OLD_SECTIONS)


if __name__ == "__main__":
    main()
