"""bench.ci_compare — the quality gate behind scripts/ci-compare (the
user-facing command; see its header for usage and exit codes): renders SCENE
with the material cache off and on at equal samples (`pmc compare`, small
settings), prints a short report and exits 1 when the cached image is too far
from the cacheless one, 2 on a usage error (its own or pmc's), 3 when pmc
fails otherwise. Only the standard library: scripts/ci-compare runs it with
any python3 when the project's .venv is missing.

Its argument handling is its own, not argparse: every option it does not know
goes to `pmc compare` unchanged, and a usage error must exit with 2 and a
message naming the option.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

from bench.common import ROOT

HELP = """usage: scripts/ci-compare SCENE.obj [--mtlx F.mtlx ...] [--material NAME] --min-psnr DB
                          [--max-relmse X] [--min-bias-psnr DB] [--min-bias-tile-psnr DB]
                          [--out-dir DIR] [--pmc PATH] [pmc compare options]

Renders SCENE with the material cache off and on at equal samples (pmc compare)
and fails when the cached render differs too much from the cacheless one.

options:
  --min-psnr DB     fail when PSNR(cache on vs cache off) is below DB
  --max-relmse X    also fail when relMSE(cache on vs cache off) is above X
  --min-bias-psnr DB
                    fail when the cache's bias over the image, with the noise taken out,
                    is below DB: pmc compare --bias renders both again with a second seed
                    (twice the time), and the mean of (on1 - off1)(on2 - off2) cancels the
                    fireflies of paths that part, which a same-seed PSNR counts as error
  --min-bias-tile-psnr DB
                    the same for the bias's worst 16x16 tile
                    (at least one of --min-psnr, --min-bias-psnr, --min-bias-tile-psnr)
  --out-dir DIR     where images, metrics.json and report.md go (default: a new temp dir)
  --pmc PATH        pmc binary (default: $PMC, else build/pmc, else pmc on PATH)
  -h, --help        this text
  anything else     passed to pmc compare; defaults --width 160 --height 120 --spp 8

exit status: 0 pass, 1 gate failed, 2 usage error, 3 pmc failed to render"""

FLAGS = {"--quiet", "--bias", "--denoise"}  # pmc compare options that take no value


def usage(msg):
    print(f"ci-compare: {msg}", file=sys.stderr)
    print("usage: scripts/ci-compare SCENE.obj [--mtlx F] [--material NAME] --min-psnr DB "
          "[--max-relmse X] [options] (see --help)", file=sys.stderr)
    sys.exit(2)


def number(opt, text):
    try:
        v = float(text)
    except ValueError:
        usage(f"{opt}: expected a number, got '{text}'")
    if v != v or v in (float("inf"), float("-inf")):
        usage(f"{opt}: expected a finite number, got '{text}'")
    return v


def verdict(ok):
    return "ok" if ok else "FAIL"


def main(argv=None):
    args = list(sys.argv[1:] if argv is None else argv)
    if any(a in ("-h", "--help") for a in args):
        print(HELP)
        sys.exit(0)

    scene = None
    min_psnr = max_relmse = out_dir = pmc = min_bias = min_bias_tile = None
    passthrough = []
    i = 0
    while i < len(args):
        a = args[i]
        name, eq, inline = a.partition("=")
        if a.startswith("--") and name in ("--min-psnr", "--max-relmse", "--min-bias-psnr", "--min-bias-tile-psnr",
                                           "--out-dir", "--pmc"):
            if eq:
                value = inline
            elif i + 1 < len(args):
                value = args[i + 1]
                i += 1
            else:
                usage(f"{name}: missing value")
            if name == "--min-psnr":
                min_psnr = number(name, value)
            elif name == "--min-bias-psnr":
                min_bias = number(name, value)
            elif name == "--min-bias-tile-psnr":
                min_bias_tile = number(name, value)
            elif name == "--max-relmse":
                max_relmse = number(name, value)
                if max_relmse < 0:
                    usage(f"--max-relmse: must not be negative, got {value}")
            elif name == "--out-dir":
                out_dir = value
            else:
                pmc = value
        elif a == "--cache" or name == "--cache":
            usage("--cache: ci-compare renders both (cache off and on); leave --cache out")
        elif a.startswith("--"):
            passthrough.append(a)
            if not eq and a not in FLAGS:
                if i + 1 >= len(args):
                    usage(f"{a}: missing value")
                passthrough.append(args[i + 1])
                i += 1
        else:
            if scene is not None:
                usage(f"more than one scene given ('{scene}' and '{a}')")
            scene = a
        i += 1

    if scene is None:
        usage("missing SCENE.obj")
    bias_gate = min_bias is not None or min_bias_tile is not None
    if min_psnr is None and not bias_gate:
        usage("missing a gate: --min-psnr DB (and/or --min-bias-psnr DB, --min-bias-tile-psnr DB)")

    given = {p.partition("=")[0] for p in passthrough if p.startswith("--")}
    defaults = [("--width", "160"), ("--height", "120"), ("--spp", "8")]
    for opt, val in defaults:
        if opt not in given:
            passthrough += [opt, val]
    if "--quiet" not in given:
        passthrough.append("--quiet")
    if bias_gate and "--bias" not in given:
        passthrough.append("--bias")

    if pmc is None:
        pmc = os.environ.get("PMC") or os.path.join(ROOT, "build", "pmc")
        if not os.access(pmc, os.X_OK):
            pmc = shutil.which("pmc") or pmc
    if not os.access(pmc, os.X_OK):
        print(f"ci-compare: pmc binary not found or not executable: {pmc} (run scripts/setup, or pass --pmc)",
              file=sys.stderr)
        sys.exit(3)

    made_tmp = out_dir is None
    if made_tmp:
        out_dir = tempfile.mkdtemp(prefix="ci-compare.")

    cmd = [pmc, "compare", scene, "--out-dir", out_dir] + passthrough
    print("ci-compare: " + " ".join(cmd), flush=True)
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if proc.stdout:
        sys.stdout.write("".join("  | " + line + "\n" for line in proc.stdout.rstrip("\n").split("\n")))
    if proc.returncode != 0:
        if made_tmp:  # nothing worth keeping: do not leave an empty folder behind
            shutil.rmtree(out_dir, ignore_errors=True)
        if proc.returncode == 2:
            print("ci-compare: pmc compare refused the command line (exit 2): see its message above", file=sys.stderr)
            sys.exit(2)
        how = f"exit {proc.returncode}" if proc.returncode > 0 else f"signal {-proc.returncode}"
        print(f"ci-compare: ERROR: pmc compare failed ({how}); no verdict", file=sys.stderr)
        sys.exit(3)

    metrics_path = os.path.join(out_dir, "metrics.json")
    try:
        with open(metrics_path) as f:
            m = json.load(f)
        psnr = float(m["psnr"])
        relmse = float(m["relmse"])
        bias = m["cache_bias"] if bias_gate else m.get("cache_bias")  # a --bias of its own: shown
        bias_psnr, bias_tile = (float(bias["psnr"]), float(bias["worst_tile_psnr"])) if bias else (None, None)
    except (OSError, ValueError, KeyError, TypeError) as e:
        print(f"ci-compare: ERROR: cannot read {metrics_path}: {e}", file=sys.stderr)
        sys.exit(3)

    t_off, t_on = m.get("time_off_seconds", 0.0), m.get("time_on_seconds", 0.0)
    ratio = m.get("speed_ratio", t_off / t_on if t_on else 0.0)
    cache = m.get("cache", {})
    failures = []
    psnr_ok = min_psnr is None or psnr >= min_psnr
    if not psnr_ok:
        failures.append(f"PSNR {psnr:.2f} dB is below --min-psnr {min_psnr:g} dB")
    bias_ok = min_bias is None or bias_psnr >= min_bias
    if not bias_ok:
        failures.append(f"the cache's bias {bias_psnr:.2f} dB is below --min-bias-psnr {min_bias:g} dB")
    bias_tile_ok = min_bias_tile is None or bias_tile >= min_bias_tile
    if not bias_tile_ok:
        failures.append(f"the cache's bias in its worst tile {bias_tile:.2f} dB is below --min-bias-tile-psnr "
                        f"{min_bias_tile:g} dB")
    relmse_ok = max_relmse is None or relmse <= max_relmse
    if not relmse_ok:
        failures.append(f"relMSE {relmse:.4g} is above --max-relmse {max_relmse:g}")

    print(f"ci-compare report: {scene} ({m.get('width')}x{m.get('height')}, {m.get('spp')} spp, seed {m.get('seed')})")
    print(f"  render time        cache off {t_off:.3f} s, cache on {t_on:.3f} s, speed-up {ratio:.2f}x "
          "(one run each: not a benchmark)")
    print(f"  PSNR on vs off     {psnr:.2f} dB" + ("  (identical images)" if psnr >= 999 else "") +
          (f"   min {min_psnr:g} dB: {verdict(psnr_ok)}" if min_psnr is not None else "   (no --min-psnr)"))
    if bias:
        tile = bias.get("worst_tile", [0, 0, 16])
        print(f"  bias (two seeds)   {bias_psnr:.2f} dB" + ("  (none measurable)" if bias_psnr >= 999 else "") +
              (f"   min {min_bias:g} dB: {verdict(bias_ok)}" if min_bias is not None else ""))
        print(f"  bias, worst tile   {bias_tile:.2f} dB at ({tile[0]}, {tile[1]})" +
              (f"   min {min_bias_tile:g} dB: {verdict(bias_tile_ok)}" if min_bias_tile is not None else "") +
              f"; noise floor {float(bias.get('noise_psnr', 0)):.2f} dB")
    print(f"  relMSE on vs off   {relmse:.4g}" +
          (f"   max {max_relmse:g}: {verdict(relmse_ok)}" if max_relmse is not None else "   (no --max-relmse)"))
    print(f"  max abs error      {m.get('max_abs_error', float('nan')):.4g}")
    if cache.get("enabled", True) is False or not cache.get("cells"):
        print("  cache              not used: no cacheable nodes in this scene's materials")
    else:
        print(f"  cache              hit rate {100 * m.get('hit_rate', 0):.1f}%, "
              f"{(m.get('cache_memory_bytes') or 0) / 2**20:.2f} MiB ({cache.get('cells')} cells x "
              f"{cache.get('entries')} entries), mip bias {cache.get('mip_bias')}, eval {cache.get('eval')}")
    for key, label in (("cached_vs_reference", "relMSE on vs ref"), ("cacheless_vs_reference", "relMSE off vs ref")):
        if key in m:
            print(f"  {label:<18s} {m[key]['relmse']:.4g}")
    print(f"  images             {out_dir}/cache_off.png cache_on.png difference.png hitmap.png report.md")
    if failures:
        for f_ in failures:
            print(f"ci-compare: FAIL: {f_}", file=sys.stderr)
        print(f"ci-compare: FAIL (see {out_dir}/difference.png)", file=sys.stderr)
        sys.exit(1)
    print("ci-compare: PASS")
    sys.exit(0)


if __name__ == "__main__":
    main()
