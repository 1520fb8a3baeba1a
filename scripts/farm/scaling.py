"""Inputs of docs/SCALING.md's farm model, measured with pmc itself.

    scripts/python -m farm.scaling [--width 1920 --height 1080 --spp 1024] [--out DIR] [--scenes default,sponza]

For each scene it renders the first samples of the frame as parts (they are
what a farm chunk renders first) and reads the stats JSON:
  * fixed cost F of one chunk = process wall time - render_seconds (process
    start, OBJ/texture load, material compile, BVH, kernel build and warm-up;
    kernel_build_seconds and kernel_warmup_seconds are reported apart);
  * the first sample's render time t1 and the steady per-sample time ts from
    runs of 1 and 3 samples (ts = (render(3) - render(1)) / 2);
  * cache: hit rate of sample 1 and of samples 2-3, misses of the whole frame
    and of one quarter tile (--crop) over 3 samples, and the cache-off
    per-sample time (what a miss costs at most).
Then it prints the model (farm/model.py) for 1..64 workers. Results go to
DIR/scaling.json; the numbers depend on the machine and its load.
"""
import argparse
import json
import os
import subprocess
import sys
import time

from farm.model import project, table
from farm.run import default_pmc

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
SHARED = os.environ.get("PMC_SCENES", os.path.normpath(os.path.join(ROOT, "..", "shared", "scenes")))
SCENES = {
    "default": ["data/default/room.obj", "--mtlx", "data/default/materials.mtlx"],
    "sponza": [f"{SHARED}/sponza/sponza.obj", "--camera-from", "-110,20,0", "--camera-at", "100,20,0",
               "--fov", "45", "--env", "1,1,1", "--max-depth", "4"],
}


def render(pmc, args, out, tag):
    exr, js = os.path.join(out, tag + ".exr"), os.path.join(out, tag + ".json")
    cmd = [pmc, "render", *args, "-o", exr, "--stats", js, "--quiet"]
    t0 = time.monotonic()
    subprocess.run(cmd, check=True, cwd=ROOT, stdout=subprocess.DEVNULL)
    wall = time.monotonic() - t0
    with open(js) as f:
        st = json.load(f)
    st["wall_seconds"] = wall
    st["command"] = " ".join(["build/pmc", "render", *args, "-o", "OUT.exr", "--stats", "OUT.json", "--quiet"])
    return st


def measure(pmc, key, w, h, spp, out):
    base = SCENES[key] + ["--width", str(w), "--height", str(h), "--spp", str(spp)]
    r1 = render(pmc, base + ["--samples", "0:1"], out, key + "_1")
    r3 = render(pmc, base + ["--samples", "0:3"], out, key + "_3")
    m = {"scene": key, "width": w, "height": h, "spp": spp, "runs": {"1": r1, "3": r3}}
    m["fixed_seconds"] = r1["wall_seconds"] - r1["render_seconds"]
    m["kernel_seconds"] = r1["kernel_build_seconds"] + r1["kernel_warmup_seconds"]
    m["t1"] = r1["render_seconds"]
    m["ts"] = (r3["render_seconds"] - r1["render_seconds"]) / 2
    c1, c3 = r1["cache"], r3["cache"]
    m["cache"] = c3["enabled"]
    if c3["enabled"]:
        m["hit_rate_sample1"] = c1["hit_rate"]
        dl = c3["lookups"] - c1["lookups"]
        m["hit_rate_samples2_3"] = (c3["hits"] - c1["hits"]) / dl if dl else 0.0
        m["misses_frame_3"] = c3["misses"]
        tile = render(pmc, base + ["--samples", "0:3", "--crop", f"0,0,{w // 2},{h // 2}"], out, key + "_tile")
        m["misses_quarter_tile_3"] = tile["cache"]["misses"]
        m["tile_render_seconds_3"] = tile["render_seconds"]
        off = render(pmc, base + ["--samples", "0:3", "--cache", "off"], out, key + "_off")
        m["ts_cache_off"] = off["render_seconds"] / 3
        m["runs"]["tile"], m["runs"]["off"] = tile, off
    return m


def main(argv=None):
    p = argparse.ArgumentParser(prog="farm.scaling", description=__doc__.split("\n\n")[0])
    p.add_argument("--width", type=int, default=1920)
    p.add_argument("--height", type=int, default=1080)
    p.add_argument("--spp", type=int, default=1024)
    p.add_argument("--scenes", default="default,sponza")
    p.add_argument("--out", default=os.path.join(ROOT, "out", "scaling"))
    p.add_argument("--pmc", default=default_pmc())
    a = p.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    results = [measure(os.path.abspath(a.pmc), k, a.width, a.height, a.spp, a.out) for k in a.scenes.split(",")]
    with open(os.path.join(a.out, "scaling.json"), "w") as f:
        json.dump(results, f, indent=2)
    for m in results:
        print(table(m, project(m, [1, 2, 4, 8, 16, 32, 64])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
