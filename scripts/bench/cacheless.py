"""bench.cacheless — did the material cache slow down the cacheless path?
Renders the same scenes with a pmc built from a baseline commit from before
the cache existed and with this tree's pmc `--cache off`, in interleaved
rounds, and compares render_seconds and the shade stage. Prints a table and
writes the "Cacheless speed" section of docs/BENCHMARKS.md.

    scripts/python -m bench.cacheless                   baseline = the parent of the commit that
                                                        added core/abi/pmc_cache.h
    scripts/python -m bench.cacheless --baseline COMMIT
    scripts/python -m bench.cacheless --runs 1 --spp 1 --width 64 --height 36 --doc -    a quick look

The baseline is exported with `git archive` and built (Release, target pmc
only) into OUT_DIR/baseline-build; a second run reuses that build
(--baseline-pmc PATH uses a binary built elsewhere instead). Each round runs
baseline and current once per scene, alternating which goes first, so both
share the machine's noise; each binary renders every scene once, untimed,
before the rounds (PoCL's kernel cache, the OS file cache). Changes between
the baseline and this tree other than the cache (interpreter work, bug
fixes) are in the comparison too: the section says which commits lie
between them.
"""
import os
import shutil
import subprocess
import sys
import time

from bench import common

PROG = "bench.cacheless"
SECTION = "## Cacheless speed: before and after the cache (scripts/bench-cacheless)"
LEGACY = {"BASELINE": "--baseline", "RUNS": "--runs", "PMC": "--pmc", "OUTDIR": "--out-dir", "DOC": "--doc",
          "SPP": "--spp", "WIDTH": "--width", "HEIGHT": "--height"}
SHARED = common.SHARED_SCENES
SCENES = [
    ("default room (MaterialX networks)", "default",
     ["data/default/room.obj", "--mtlx", "data/default/materials.mtlx"]),
    ("brick teapot (`M_BrickPattern`)", "teapot",
     [f"{SHARED}/materialx/geometry/teapot.obj", "--mtlx",
      f"{SHARED}/materialx/standard_surface_brick_procedural.mtlx", "--material", "M_BrickPattern",
      "--env", "1,1,1", "--camera-from", "0.75,1.0,2.45", "--camera-at", "-0.09,0.05,-0.01", "--fov", "45"]),
    ("Sponza (MTL materials)", "sponza",
     [f"{SHARED}/sponza/sponza.obj", "--camera-from", "-110,20,0", "--camera-at", "100,20,0", "--fov", "45",
      "--env", "1,1,1", "--max-depth", "4"]),
]
FIRST_CACHE_FILE = "core/abi/pmc_cache.h"  # where the commit that added the cache put it


def parse(argv=None):
    p = common.make_parser("cacheless", __doc__, LEGACY)
    p.add_argument("--baseline", metavar="COMMIT",
                   help=f"the commit to compare with (default: the parent of the commit that added "
                        f"{FIRST_CACHE_FILE})")
    p.add_argument("--baseline-pmc", metavar="PATH",
                   help="a pmc built from --baseline elsewhere (default: build it into OUT_DIR/baseline-build)")
    common.add_pmc(p)
    common.add_runs(p, 5)
    common.add_image_size(p, 320, 180, 16)
    common.add_out_dir(p, "out/bench-cacheless", "the baseline's source and build, images, stats and logs")
    common.add_doc(p)
    return common.parse_args(p, "cacheless", LEGACY, argv)


def git(*args):
    p = subprocess.run(["git", *args], capture_output=True, text=True)
    return p.stdout.strip() if p.returncode == 0 else None


def resolve_baseline(baseline):
    """(full hash, short hash) of the baseline commit."""
    if not baseline:
        added = (git("log", "--format=%H", "--diff-filter=A", "--", FIRST_CACHE_FILE) or "").split("\n")[-1]
        if not added:
            sys.exit(f"{PROG}: cannot find the commit that added {FIRST_CACHE_FILE}; pass --baseline")
        baseline = git("rev-parse", "--short", f"{added}^")
    full = git("rev-parse", "--verify", "-q", f"{baseline}^{{commit}}")
    if not full:
        sys.exit(f"{PROG}: --baseline {baseline} is not a commit")
    return full, git("rev-parse", "--short", full)


def build_baseline(full, short, outdir):
    """OUT_DIR/baseline-build/pmc, exported and built when missing or from another commit."""
    src, bld = f"{outdir}/baseline-src", f"{outdir}/baseline-build"
    try:
        exported = common.read_text(f"{src}/.commit").strip()
    except OSError:
        exported = ""
    if exported != full:
        shutil.rmtree(src, ignore_errors=True)
        shutil.rmtree(bld, ignore_errors=True)
        os.makedirs(src)
        archive = subprocess.Popen(["git", "archive", full], stdout=subprocess.PIPE)
        untar = subprocess.run(["tar", "-x", "-C", src], stdin=archive.stdout)
        archive.stdout.close()
        if archive.wait() != 0 or untar.returncode != 0:
            sys.exit(f"{PROG}: exporting {short} with git archive failed")
        with open(f"{src}/.commit", "w") as f:
            f.write(full + "\n")
    if not os.access(f"{bld}/pmc", os.X_OK):
        print(f"{PROG}: building the baseline {short} in {bld}", flush=True)
        for cmd, log, tail in (
                (["cmake", "-S", src, "-B", bld, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release"],
                 f"{outdir}/baseline-configure.log", None),
                (["cmake", "--build", bld, "--target", "pmc", "--parallel", str(os.cpu_count())],
                 f"{outdir}/baseline-build.log", 30)):
            try:
                common.run(cmd, log)
            except common.RunFailed as e:
                text = common.read_text(log).splitlines()
                print("\n".join(text[-tail:] if tail else text), file=sys.stderr)
                sys.exit(f"{PROG}: {e}")
    return f"{bld}/pmc"


def render_cmd(binary, which, args, exr, stats, w, h, spp):
    c = [binary, "render", *args, "-o", exr, "--stats", stats, *common.size_args(w, h, spp)]
    if which == "current":
        c += ["--cache", "off"]
    return c


def main(argv=None):
    a = parse(argv)
    common.chdir_root()
    OUT, RUNS, SPP, W, H = a.out_dir, a.runs, a.spp, a.width, a.height
    full, short = resolve_baseline(a.baseline)
    os.makedirs(OUT, exist_ok=True)
    cur = common.find_pmc(a.pmc, PROG)
    base = a.baseline_pmc or build_baseline(full, short, OUT)
    if not os.access(base, os.X_OK):
        sys.exit(f"{PROG}: {base} is not an executable")
    between = git("rev-list", "--count", f"{full}..HEAD")
    head = common.git_rev(ignore=["docs"])
    built = f"given as `{a.baseline_pmc}`" if a.baseline_pmc else "built from a clean\nexport"
    baseline_line = (f"Baseline: pmc at {short}, the last commit without the material cache, {built}; "
                     f"current: {head}, with `--cache off`. {between} commits lie between them.")

    def run(which, args, name, spp):
        c = render_cmd(BIN[which], which, args, f"{OUT}/{name}.exr", f"{OUT}/{name}.json", W, H, spp)
        try:
            s, _ = common.run_pmc(c, f"{OUT}/{name}.json", f"{OUT}/{name}.log")
        except common.RunFailed as e:
            sys.exit(f"{PROG}: {name} failed with {e}")
        return {"render": s["render_seconds"], "shade": s["stage_seconds"]["shade"], "rays": s["rays"],
                "device": s.get("device", "?")}

    BIN = {"baseline": base, "current": cur}
    print(f"{PROG}: baseline {short} ({base}) vs {cur} --cache off; {RUNS} rounds, {W}x{H}, {SPP} spp", flush=True)
    for _, key, args in SCENES:
        for which in BIN:
            run(which, args, f"{key}_{which}_warmup", 1)
    loads = common.LoadSampler()
    res = {(key, w): [] for _, key, _ in SCENES for w in BIN}
    t0 = time.time()
    for r in range(RUNS):
        for _, key, args in SCENES:
            for which in common.round_order(["baseline", "current"], r, "reverse"):
                res[(key, which)].append(run(which, args, f"{key}_{which}", SPP))
                loads.sample()
            b, c = res[(key, "baseline")][-1], res[(key, "current")][-1]
            print(f"  round {r + 1}/{RUNS} {key:8s} baseline {b['render']:6.2f}s  current {c['render']:6.2f}s  "
                  f"current/baseline {c['render'] / b['render']:.3f}", flush=True)
    elapsed = time.time() - t0

    def med(key, which, field):
        return common.median(x[field] for x in res[(key, which)])

    def field(key, which, name):
        return [x[name] for x in res[(key, which)]]

    rows = []
    for label, key, _ in SCENES:
        ratio = common.median_range(common.round_ratios(field(key, "current", "render"),
                                                        field(key, "baseline", "render")))
        shade = common.median(common.round_ratios(field(key, "current", "shade"), field(key, "baseline", "shade")))
        same_rays = field(key, "baseline", "rays") == field(key, "current", "rays")
        rows.append([label, f"{med(key, 'baseline', 'render'):.2f}", f"{med(key, 'current', 'render'):.2f}",
                     f"**{ratio[0]:.3f}** ({ratio[1]:.2f}-{ratio[2]:.2f})",
                     f"{med(key, 'baseline', 'shade'):.2f}", f"{med(key, 'current', 'shade'):.2f}", f"{shade:.3f}",
                     "yes" if same_rays else "no"])
    table = common.md_table(["scene", "baseline render (s)", "current `--cache off` render (s)",
                             "current / baseline (range of rounds)", "baseline shade (s)", "current shade (s)",
                             "shade ratio", "same ray count"], rows)

    device = res[(SCENES[0][1], "current")][0]["device"]

    def shown(which, args):
        c = render_cmd("BASELINE/pmc" if which == "baseline" else "build/pmc", which, args, "OUT.exr", "OUT.json",
                       W, H, SPP)
        return "    " + " ".join(c)

    commands = "\n".join(shown(w, args) for _, _, args in SCENES for w in BIN)
    section = f"""{SECTION}

Produced by `{a.command}` on {common.utc_now()} ({elapsed / 60:.1f} minutes of timed runs).
Machine: {common.machine(device)}; load average
{loads.before():.1f} before the runs, {loads.median():.1f} median and {loads.max():.1f} max between them.
{baseline_line}
Median of {RUNS} interleaved rounds (the order alternates every round), {W}x{H}, {SPP} spp, seed 0:

{commands}

{table}

"current / baseline" below 1 means the current cacheless render is faster. The ratio is the median of
the per-round ratios; the range shows how much single rounds vary on this machine. Besides the cache,
the commits in between changed the interpreter (branch-light operand loads), fixed bugs (noise operand
order, stream tracing), rounded the kernel's stack size up to a power of two and split the shade
kernel into passes with per-work-group queue compaction (one global atomic per work-group instead of
two per ray: most of the gain here), so this measures the cacheless path as users get it, not the
cache code alone. With `--cache off` the compiled programs contain no cache instructions and the
kernel allocates a one-word table; what stays is the shade kernel's two extra arguments, its cache
prefetch pass (a loop that finds no material with cache points and reads nothing) and the
interpreter's two switch cases that never run.
"""
    print()
    print(table)
    print(f"{PROG}: {elapsed:.0f}s of timed runs; logs, stats and images in {OUT}/")
    common.write_section(a.doc, SECTION, section, PROG)


if __name__ == "__main__":
    main()
