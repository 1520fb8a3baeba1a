"""bench.gpu — reports what scripts/gpu-check measured on a machine with a GPU:
the device tests' results, the benchmark renders' times and stages, and how
closely the GPU's images match this machine's OpenCL device at the same seed.
Prints the tables and writes the "On a GPU" section of docs/BENCHMARKS.md.

    scripts/gpu-bundle /tmp/pmc-gpu.tar.xz                  here: pack pmc, the tests, libraries, scenes
    tar -xJf pmc-gpu.tar.xz && scripts/gpu-check pmc-gpu RESULTS    there, in a checkout of the same commit
    scripts/python -m bench.gpu --results RESULTS           here again (--results is repeatable: one
                                                            table per run)

The parity check renders gpu-check's parity-cache-{off,on} images again with
this checkout's pmc (same size, samples and seed) and compares them with
OpenImageIO's idiff; a second render at another seed gives the noise level
the difference should be far below. RESULTS may hold a file `command` with the
command line that ran there, shown with its table.
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

from bench import common

PROG = "bench.gpu"
SECTION = "## On a GPU (scripts/gpu-check, scripts/bench-gpu)"
SCENE = ["data/default/room.obj", "--mtlx", "data/default/materials.mtlx"]
STAGES = ["trace", "shade", "shadow", "sort", "transfer"]


def parse(argv=None):
    p = common.make_parser("gpu", __doc__)
    p.add_argument("--results", action="append", required=True, metavar="DIR",
                   help="a folder scripts/gpu-check wrote (repeatable)")
    common.add_pmc(p)
    common.add_out_dir(p, "out/bench-gpu", "this machine's parity renders")
    common.add_doc(p)
    return common.parse_args(p, "gpu", {}, argv)


def device_line(results):
    """The default device of devices.txt, else the device the renders' stats name."""
    try:
        for line in common.read_text(os.path.join(results, "devices.txt")).splitlines():
            if line.startswith("* "):
                return line[2:].strip()
    except OSError:
        pass
    for path in sorted(glob.glob(os.path.join(results, "bench", "*.json"))):
        return common.read_json(path).get("device", "unknown device")
    return "unknown device"


def test_summary(results):
    """(tests run, failures as "Name: first line of the message") from tests-*.xml."""
    total, failed = 0, []
    for path in sorted(glob.glob(os.path.join(results, "tests-*.xml"))):
        for case in ET.parse(path).getroot().iter("testcase"):
            if case.get("result", "completed") == "suppressed":
                continue
            total += 1
            f = case.find("failure")
            if f is not None:
                text = (f.get("message") or "").strip()
                reason = next((ln for ln in text.splitlines() if "plugin" in ln or "python" in ln), text)
                failed.append(f"{case.get('classname')}.{case.get('name')}: {reason.strip()[:160]}")
    return total, failed


def bench_rows(results):
    """{config: [stats of each round]} from bench/rN-CONFIG.json."""
    runs = {}
    for path in sorted(glob.glob(os.path.join(results, "bench", "r*-*.json"))):
        m = re.match(r"r(\d+)-(.+)\.json$", os.path.basename(path))
        if m:
            runs.setdefault(m.group(2), []).append(common.read_json(path))
    return runs


def frame_of(s):
    """What a cache-on render is compared with: the cache-off one of the same scene and size. The
    scene is named by its folder and file (data/heavy/room.obj -> heavy/room.obj)."""
    scene = "/".join(s.get("scene", "").replace("\\", "/").split("/")[-2:])
    return scene, s["width"], s["height"]


def options_of(s):
    c = s.get("cache", {})
    out = [f"{s['width']}x{s['height']}", f"{s['spp']} spp", f"lanes {s['shade_lanes']}"]
    if not c.get("enabled"):
        return ", ".join(out + ["cache off"])
    out.append(f"cache {c['policy']}, eval {c['eval']}, {c['filter']}, {c['cells']}x{c['entries']}")
    return ", ".join(out)


def table(runs):
    rows = []
    base = {}
    for name, stats in runs.items():
        if not stats[0].get("cache", {}).get("enabled"):
            base.setdefault(frame_of(stats[0]), common.median([s["render_seconds"] for s in stats]))
    for name, stats in sorted(runs.items(), key=lambda kv: (kv[1][0].get("scene", ""), kv[1][0]["width"], kv[0])):
        t = [s["render_seconds"] for s in stats]
        med = common.median(t)
        c = stats[0].get("cache", {})
        ref = base.get(frame_of(stats[0]))
        speed = f"{ref / med:.2f}x" if ref and c.get("enabled") else "-"
        rows.append([f"`{name}`", options_of(stats[0]), f"{med:.2f} ({min(t):.2f}-{max(t):.2f})",
                     f"{common.median([s['rays_per_second'] for s in stats]) / 1e6:.1f}"] +
                    [f"{common.median([s['stage_seconds'][k] for s in stats]):.2f}" for k in STAGES] +
                    [f"{100 * c['hit_rate']:.1f}%" if c.get("enabled") else "-", speed])
    header = ["config", "settings", "render s (range)", "Mrays/s"] + [f"{k} s" for k in STAGES] + \
             ["hit rate", "speedup vs cache off"]
    return common.md_table(header, rows), len(next(iter(runs.values()))) if runs else 0


def cache_notes(runs):
    """A line per image size: the cache's effect on the render and the shade stage."""
    notes = []
    by_size = {}
    for stats in runs.values():
        s0 = stats[0]
        key = "on" if s0.get("cache", {}).get("enabled") else "off"
        default_cache = key == "off" or (s0["cache"]["policy"] == "keep-first" and s0["cache"]["eval"] == "center"
                                         and s0["cache"]["filter"] == "bilinear")
        if s0["shade_lanes"] == 1 and default_cache:
            by_size.setdefault(frame_of(s0), {}).setdefault(key, stats)
    for (scene, w, h), pair in sorted(by_size.items()):
        if "off" in pair and "on" in pair:
            r = {k: common.median([s["render_seconds"] for s in v]) for k, v in pair.items()}
            sh = {k: common.median([s["stage_seconds"]["shade"] for s in v]) for k, v in pair.items()}
            verdict = "faster" if r["on"] < r["off"] else "slower"
            where = f"{scene}, " if scene else ""
            notes.append(f"- {where}{w}x{h}: the cache makes the render {verdict}, {r['off']:.2f} -> {r['on']:.2f} s "
                         f"({r['off'] / r['on']:.2f}x); the shade stage {sh['off']:.2f} -> {sh['on']:.2f} s.")
    return notes


def idiff_rms(a, b):
    p = subprocess.run(["idiff", "-fail", "0", "-warn", "0", a, b], capture_output=True, text=True)
    m = re.search(r"RMS error = ([0-9.eE+-]+)", p.stdout)
    if not m:
        sys.exit(f"{PROG}: idiff {a} {b} gave no RMS error:\n{p.stdout}{p.stderr}")
    return float(m.group(1))


def parity(args, results):
    """Rows comparing the GPU's parity renders with this machine's device."""
    if not shutil.which("idiff"):
        sys.exit(f"{PROG}: idiff not found (Debian's openimageio-tools)")
    rows = []
    for cache in ("off", "on"):
        gpu_exr = os.path.join(results, "bench", f"parity-cache-{cache}.exr")
        stats = os.path.join(results, "bench", f"parity-cache-{cache}.json")
        if not os.path.exists(gpu_exr):
            continue
        s = common.read_json(stats)
        size = common.size_args(s["width"], s["height"], s["spp"]) + ["--cache", cache]
        here, noise = (os.path.join(args.out_dir, f"parity-cache-{cache}-seed{k}.exr") for k in (s["seed"], s["seed"] + 1))
        log = os.path.join(args.out_dir, "parity.log")
        for path, seed in ((here, s["seed"]), (noise, s["seed"] + 1)):
            common.run([args.pmc, "render", *SCENE, *size, "--seed", str(seed), "-o", path], log, append=True)
        rows.append([f"cache {cache}", f"{s['width']}x{s['height']}, {s['spp']} spp, seed {s['seed']}",
                     f"{idiff_rms(gpu_exr, here):.2e}", f"{idiff_rms(here, noise):.2e}"])
    return rows


def main(argv=None):
    a = parse(argv)
    common.chdir_root()
    a.pmc = common.find_pmc(a.pmc, PROG, extra_packages=["openimageio-tools"])
    os.makedirs(a.out_dir, exist_ok=True)
    here = common.machine(device_line_here(a.pmc))
    parts = [SECTION, "", f"Produced by `{a.command}` on {common.utc_now()}. Parity renders here: {here}."]
    for results in a.results:
        log = os.path.join(results, "log")
        first = common.read_text(log).splitlines()[0] if os.path.exists(log) else ""
        cmd = os.path.join(results, "command")
        parts += ["", f"### {device_line(results)}", ""]
        if first:
            parts.append(f"{first.replace('gpu-check: ', '')}.")
        if os.path.exists(cmd):
            parts.append(f"Ran there: `{common.read_text(cmd).strip()}`")
        total, failed = test_summary(results)
        if total:
            parts += ["", f"Tests (`pmc_device_tests`): {total - len(failed)} of {total} passed."]
            parts += [f"- failed: {f}" for f in failed]
        runs = bench_rows(results)
        if runs:
            text, rounds = table(runs)
            parts += ["", f"The default scene (data/default; the heavy procedural scene, data/heavy, in the `heavy-` rows), medians of {common.rounds_text(rounds)}; stages "
                          "in seconds of wall clock (transfer includes waiting for the device):", "", text]
            notes = cache_notes(runs)
            if notes:
                parts += ["", "With the default cache settings against the cache off:", *notes]
        rows = parity(a, results)
        if rows:
            parts += ["", "The GPU's image against this machine's device at the same seed (RMS over the "
                          "image), and this machine's image against itself at the next seed (the noise):", "",
                      common.md_table(["render", "settings", "RMS GPU vs here", "RMS seed vs seed+1"], rows)]
    section = "\n".join(parts) + "\n"
    print(section)
    common.write_section(a.doc, SECTION, section, PROG)


def device_line_here(pmc):
    out = subprocess.run([pmc, "info", "--devices"], capture_output=True, text=True).stdout
    return next((ln[2:].split("|")[1].strip() for ln in out.splitlines() if ln.startswith("* ")), "unknown")


if __name__ == "__main__":
    main()
