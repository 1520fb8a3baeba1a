#!/usr/bin/env python3
"""scripts/plot_sweep.py — turn `pmc sweep`'s sweep.csv into PNG plots.

    scripts/plot_sweep.py [--allow-empty] SWEEP.csv [MORE.csv ...] OUTDIR

With several CSVs (the same sweep run several times, e.g. interleaved with
other work on a busy machine), rows with the same kind, cells, entries, mip
bias, cache eval and spp are merged: each number is the median over the files
that have it. Writes into OUTDIR (each plot is skipped, with a message, when the CSV has no
rows of the kind it needs):

  cache_size_time.png   render time and hit rate against cache size
                        (cells x entries), one line per entries value, at one
                        mip bias and one --cache-eval (the paper's Fig. 4);
                        the cacheless time as a dashed line.
  mip_bias_error.png    error against render time for every mip bias, one
                        line per --cache-eval at one cache size: relMSE vs the
                        reference (left) and PSNR vs the cacheless render at
                        equal samples (right); the cacheless render as a star.
  convergence.png       equal-time convergence: relMSE vs the reference
                        against seconds for cache off and on (log-log), each
                        point labelled with its samples per pixel.

It exits 1 when there is nothing to plot, unless --allow-empty (what `pmc
sweep --plots png` passes: it warns instead). It also prints, per plot, the numbers it drew and, for the convergence
curves, the time each curve needs to reach the other's errors (log-log
interpolation), i.e. the speed-up at equal error.

Needs matplotlib (Debian: python3-matplotlib; scripts/setup installs it).
When the `python3` on PATH lacks it (a pyenv or venv python), the script runs
itself again with /usr/bin/python3. Uses the Agg backend: no display needed.
"""
import csv
import math
import os
import sys

USAGE = "usage: scripts/plot_sweep.py [--allow-empty] SWEEP.csv [MORE.csv ...] OUTDIR"
KEY = ("kind", "cells", "entries", "mip_bias", "cache_eval", "spp")
NUMBERS = ("time_seconds", "hit_rate", "memory_bytes", "psnr_vs_cacheless", "relmse_vs_cacheless",
           "relmse_vs_reference")


def import_matplotlib():
    try:
        import matplotlib
    except ImportError:
        system = "/usr/bin/python3"
        if os.path.realpath(sys.executable) != os.path.realpath(system) and os.access(system, os.X_OK) \
                and not os.environ.get("PLOT_SWEEP_REEXEC"):
            os.environ["PLOT_SWEEP_REEXEC"] = "1"
            os.execv(system, [system, os.path.abspath(__file__)] + sys.argv[1:])
        sys.exit("plot_sweep: matplotlib is not installed (Debian: apt-get install python3-matplotlib)")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def num(v):
    """Float from a CSV cell; None when empty or not a number."""
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def read_rows(path):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        need = {"kind", "cells", "entries", "mip_bias", "cache_eval", "spp", "time_seconds"}
        missing = need - set(reader.fieldnames or [])
        if missing:
            sys.exit(f"plot_sweep: {path}: not a pmc sweep CSV (missing columns: {', '.join(sorted(missing))})")
        rows = []
        for r in reader:
            row = dict(r)
            for k in ("cells", "entries", "spp"):
                row[k] = int(float(r[k])) if num(r.get(k)) is not None else 0
            for k in ("mip_bias",) + NUMBERS:
                row[k] = num(r.get(k))
            rows.append(row)
    return rows


def merge_runs(files):
    """Rows of several sweep CSVs, one row per KEY, each number the median
    over the files that have it (in the first file's row order)."""
    groups, order = {}, []
    for rows in files:
        for r in rows:
            k = tuple(r[c] for c in KEY)
            if k not in groups:
                groups[k] = []
                order.append(k)
            groups[k].append(r)
    merged = []
    for k in order:
        g = groups[k]
        row = dict(g[0])
        for c in NUMBERS:
            vals = sorted(r[c] for r in g if r[c] is not None)
            if vals:
                n = len(vals)
                row[c] = vals[n // 2] if n % 2 else 0.5 * (vals[n // 2 - 1] + vals[n // 2])
        row["runs"] = len(g)
        merged.append(row)
    return merged


def fmt_bias(b):
    return f"{b:+g}" if b else "0"


def pick_common(values, preferred):
    """`preferred` when present, else the most common value (ties: the first)."""
    values = list(values)
    if preferred in values:
        return preferred
    return max(set(values), key=lambda v: (values.count(v), -values.index(v)))


def plot_cache_size(plt, rows, out):
    settings = [r for r in rows if r["kind"] == "setting" and r["time_seconds"] is not None]
    if not settings:
        print("plot_sweep: no 'setting' rows: skipping cache_size_time.png")
        return None
    bias = pick_common([r["mip_bias"] for r in settings], 0.0)
    ev = pick_common([r["cache_eval"] for r in settings], "center")
    sel = [r for r in settings if r["mip_bias"] == bias and r["cache_eval"] == ev]
    if len({(r["cells"], r["entries"]) for r in sel}) < 2:
        print("plot_sweep: only one cache size in this sweep: skipping cache_size_time.png")
        return None
    cacheless = [r for r in rows if r["kind"] == "cacheless" and r["time_seconds"] is not None]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    print(f"cache_size_time.png (mip bias {fmt_bias(bias)}, --cache-eval {ev}):")
    print("  cells      entries  time (s)  hit rate  memory (MiB)")
    for entries in sorted({r["entries"] for r in sel}):
        pts = sorted((r for r in sel if r["entries"] == entries), key=lambda r: r["cells"])
        xs = [r["cells"] * r["entries"] for r in pts]
        label = f"{entries} {'entry' if entries == 1 else 'entries'} per cell"
        ax.plot(xs, [r["time_seconds"] for r in pts], "o-", label=label)
        ax2.plot(xs, [100 * (r["hit_rate"] or 0) for r in pts], "o-", label=label)
        for r in pts:
            mib = (r["memory_bytes"] or 0) / 2**20
            print(f"  {r['cells']:<10d} {entries:<8d} {r['time_seconds']:8.3f}  {100 * (r['hit_rate'] or 0):7.1f}%"
                  f"  {mib:10.2f}")
    if cacheless:
        t = sorted(r["time_seconds"] for r in cacheless)[len(cacheless) // 2]
        ax.axhline(t, color="black", linestyle="--", linewidth=1, label=f"cache off ({t:.2f} s)")
        print(f"  cache off: {t:.3f} s")
    spp = sel[0]["spp"] if sel else 0
    for a in (ax, ax2):
        a.set_xscale("log", base=2)
        a.set_xlabel("cache size: cells x entries (8 bytes each: 2^17 entries = 1 MiB)")
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=8)
    ax.set_ylabel("render time (s)")
    ax.set_ylim(bottom=0)
    ax.set_title(f"Render time vs cache size ({spp} spp, mip bias {fmt_bias(bias)}, {ev})", fontsize=10)
    ax2.set_ylabel("cache hit rate (%)")
    ax2.set_ylim(0, 100)
    ax2.set_title("Hit rate vs cache size", fontsize=10)
    fig.tight_layout()
    path = os.path.join(out, "cache_size_time.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_mip_bias(plt, rows, out):
    settings = [r for r in rows if r["kind"] == "setting" and r["time_seconds"] is not None]
    if not settings:
        print("plot_sweep: no 'setting' rows: skipping mip_bias_error.png")
        return None
    # One cache size: the largest one swept, so that capacity does not limit the hit rate.
    size = max({(r["cells"], r["entries"]) for r in settings}, key=lambda s: (s[0] * s[1], s[1]))
    sel = [r for r in settings if (r["cells"], r["entries"]) == size]
    if len({r["mip_bias"] for r in sel}) < 2 and len({r["cache_eval"] for r in sel}) < 2:
        print("plot_sweep: only one mip bias and one --cache-eval in this sweep: skipping mip_bias_error.png")
        return None
    have_ref = any(r["relmse_vs_reference"] for r in rows)
    have_psnr = any(r["psnr_vs_cacheless"] is not None for r in sel)
    if not have_ref and not have_psnr:
        print("plot_sweep: no error columns in 'setting' rows: skipping mip_bias_error.png")
        return None
    cacheless = [r for r in rows if r["kind"] == "cacheless" and r["time_seconds"] is not None]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    print(f"mip_bias_error.png ({size[0]} cells x {size[1]} entries):")
    print("  eval    bias  time (s)  hit rate  relMSE vs ref  PSNR vs off (dB)")
    for k, ev in enumerate(sorted({r["cache_eval"] for r in sel})):
        dy = 6 if k % 2 == 0 else -12  # labels of the second line below its points
        pts = sorted((r for r in sel if r["cache_eval"] == ev), key=lambda r: r["mip_bias"])
        for r in pts:
            rel = r["relmse_vs_reference"]
            psnr = r["psnr_vs_cacheless"]
            print(f"  {ev:<7s} {fmt_bias(r['mip_bias']):>4s}  {r['time_seconds']:8.3f}  "
                  f"{100 * (r['hit_rate'] or 0):7.1f}%  {rel if rel is not None else float('nan'):13.5f}  "
                  f"{psnr if psnr is not None else float('nan'):8.2f}")
        if have_ref:
            p = [r for r in pts if r["relmse_vs_reference"]]
            line = ax.plot([r["time_seconds"] for r in p], [r["relmse_vs_reference"] for r in p], "o-",
                           label=f"cache on, --cache-eval {ev}")
            for r in p:
                ax.annotate(fmt_bias(r["mip_bias"]), (r["time_seconds"], r["relmse_vs_reference"]),
                            textcoords="offset points", xytext=(3, dy), fontsize=7, color=line[0].get_color())
        if have_psnr:
            p = [r for r in pts if r["psnr_vs_cacheless"] is not None]
            ax2.plot([r["time_seconds"] for r in p], [min(r["psnr_vs_cacheless"], 99) for r in p], "o-",
                     label=f"cache on, --cache-eval {ev}")
            for r in p:
                ax2.annotate(f"bias {fmt_bias(r['mip_bias'])}, {100 * (r['hit_rate'] or 0):.0f}% hits",
                             (r["time_seconds"], min(r["psnr_vs_cacheless"], 99)), textcoords="offset points",
                             xytext=(5, dy), fontsize=7)
    if cacheless:
        c = cacheless[0]
        print(f"  cache off     {c['time_seconds']:8.3f}            {c['relmse_vs_reference'] or float('nan'):13.5f}")
        if have_ref and c["relmse_vs_reference"]:
            ax.plot([c["time_seconds"]], [c["relmse_vs_reference"]], "k*", markersize=12, label="cache off")
            ax.axhline(c["relmse_vs_reference"], color="black", linestyle="--", linewidth=1)
        if have_psnr:
            ax2.axvline(c["time_seconds"], color="black", linestyle="--", linewidth=1,
                        label=f"cache off time ({c['time_seconds']:.2f} s)")
    spp = sel[0]["spp"]
    if have_ref:
        ys = [r["relmse_vs_reference"] for r in sel + cacheless if r["relmse_vs_reference"]]
        if ys and max(ys) > 10 * min(ys):
            ax.set_yscale("log")
        elif ys:
            # Start at 0: differences of a few per cent must not look like an order of magnitude.
            ax.set_ylim(0, 1.15 * max(ys))
            spread = (max(ys) - min(ys)) / min(ys)
            ax.text(0.03, 0.55, f"all points within {100 * spread:.1f}% of each other:\n"
                    "the cache's error is below this sample count's noise", transform=ax.transAxes,
                    fontsize=8, color="dimgrey")
        ax.set_xlabel("render time (s)")
        ax.set_ylabel("relMSE vs reference (lower is better)")
        ax.set_title(f"Error vs time per mip bias (labels; {spp} spp, {size[0]}x{size[1]} cache)", fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
    else:
        ax.set_axis_off()
        ax.text(0.5, 0.5, "no reference in this sweep", ha="center", va="center")
    if have_psnr:
        ax2.axhline(40, color="grey", linestyle=":", linewidth=1, label="40 dB")
        ax2.set_xlabel("render time (s)")
        ax2.set_ylabel("PSNR vs cacheless, equal spp (dB)")
        ax2.set_title("Difference from the cacheless render", fontsize=10)
        ax2.grid(True, alpha=0.3)
        ax2.legend(fontsize=8)
    else:
        ax2.set_axis_off()
    fig.tight_layout()
    path = os.path.join(out, "mip_bias_error.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def loglog_time_at(curve, err):
    """Seconds at which a (time, relMSE) curve reaches `err`, interpolated in
    log-log between neighbouring points; None outside the curve's range."""
    pts = sorted(curve, key=lambda p: p[0])
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        lo, hi = min(e0, e1), max(e0, e1)
        if lo <= err <= hi and e0 != e1:
            f = (math.log(err) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    return None


def plot_convergence(plt, rows, out):
    curves = {}
    for kind, label in (("convergence_off", "cache off"), ("convergence_on", "cache on")):
        pts = sorted((r for r in rows if r["kind"] == kind and r["time_seconds"] and r["relmse_vs_reference"]),
                     key=lambda r: r["spp"])
        if pts:
            curves[label] = pts
    if not curves:
        print("plot_sweep: no 'convergence_off'/'convergence_on' rows with a reference error: "
              "skipping convergence.png")
        return None
    fig, ax = plt.subplots(figsize=(6.5, 4.6))
    print("convergence.png:")
    for label, pts in curves.items():
        ax.plot([r["time_seconds"] for r in pts], [r["relmse_vs_reference"] for r in pts], "o-", label=label)
        for r in pts:
            ax.annotate(f"{r['spp']}", (r["time_seconds"], r["relmse_vs_reference"]), textcoords="offset points",
                        xytext=(4, 4), fontsize=7)
        print(f"  {label}: " + ", ".join(f"{r['spp']} spp {r['time_seconds']:.2f} s relMSE {r['relmse_vs_reference']:.4g}"
                                         for r in pts))
    if len(curves) == 2:
        off = [(r["time_seconds"], r["relmse_vs_reference"]) for r in curves["cache off"]]
        on = [(r["time_seconds"], r["relmse_vs_reference"]) for r in curves["cache on"]]
        for t_on, err in on:
            t_off = loglog_time_at(off, err)
            if t_off:
                print(f"  relMSE {err:.4g}: cache on {t_on:.2f} s, cache off {t_off:.2f} s (interpolated): "
                      f"{t_off / t_on:.2f}x")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("render time (s)")
    ax.set_ylabel("relMSE vs reference")
    ax.set_title("Equal-time convergence (labels: samples per pixel)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    path = os.path.join(out, "convergence.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv):
    if len(argv) == 2 and argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    if len(argv) < 3:
        print(USAGE, file=sys.stderr)
        return 2
    allow_empty = "--allow-empty" in argv  # pmc sweep: a sweep with nothing to plot is not an error
    argv = [a for a in argv if a != "--allow-empty"]
    if len(argv) < 3:
        print(USAGE, file=sys.stderr)
        return 2
    srcs, out = argv[1:-1], argv[-1]
    for src in srcs:
        if not os.path.isfile(src):
            print(f"plot_sweep: {src}: no such file", file=sys.stderr)
            return 2
    if out.endswith(".csv") and os.path.isfile(out):
        print(f"plot_sweep: the last argument must be the output directory, not {out}", file=sys.stderr)
        return 2
    plt = import_matplotlib()
    rows = merge_runs([read_rows(src) for src in srcs])
    if not rows:
        print(f"plot_sweep: {' '.join(srcs)}: no rows", file=sys.stderr)
        return 1
    if len(srcs) > 1:
        print(f"plot_sweep: {len(rows)} rows, medians over {len(srcs)} files")
    os.makedirs(out, exist_ok=True)
    written = [p for p in (plot_cache_size(plt, rows, out), plot_mip_bias(plt, rows, out),
                           plot_convergence(plt, rows, out)) if p]
    for p in written:
        print(f"plot_sweep: wrote {p}")
    if not written:
        print("plot_sweep: nothing to plot", file=sys.stderr)
        return 0 if allow_empty else 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
