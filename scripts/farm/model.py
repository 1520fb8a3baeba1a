"""The farm's speedup model (docs/SCALING.md), from measured inputs (farm/scaling.py).

One chunk costs   T = F + warm + n * ts
  F     fixed cost of a chunk: process start, scene load, BVH, kernel build/warm-up;
  ts    steady seconds per sample of the whole frame (warm cache);
  warm  extra seconds of the first sample over ts (cold cache: every texel a
        miss; cacheless scenes: first-launch effects only);
  n     samples the chunk renders.
One process: T1 = F + warm + S * ts. With W workers and one chunk each:
  split by samples   T = F + warm + ceil(S / W) * ts         (every worker warms
                     a cache over the whole frame: warm is paid W times in total);
  split by tiles     T = F + warm * (p / W + 1 - p) + S * ts / W
                     (a tile's misses: its share p / W of the camera-visible
                     texels plus all 1 - p reached by indirect rays; p from the
                     misses of a quarter tile, m_q / m_frame = p / 4 + 1 - p;
                     tiles assumed equally expensive);
  pre-warmed/shared  T = F + ceil(S / W) * ts  (samples split; no warm-up; a
                     shared table's network cost is not modelled: an upper bound).
Speedup = T1 / T. This is a model, not a measurement of a farm.
"""
import math


def primary_share(m):
    """p: the share of a frame's misses that come from camera-visible texels."""
    if not m.get("cache") or not m.get("misses_frame_3"):
        return 1.0
    r = m["misses_quarter_tile_3"] / m["misses_frame_3"]
    return min(1.0, max(0.0, (1.0 - r) * 4.0 / 3.0))


def project(m, workers):
    S, F, ts = m["spp"], m["fixed_seconds"], m["ts"]
    warm = max(0.0, m["t1"] - ts)
    p = primary_share(m)
    t1 = F + warm + S * ts
    rows = []
    for w in workers:
        n = math.ceil(S / w)
        samples = F + warm + n * ts
        tiles = F + warm * (p / w + 1.0 - p) + S * ts / w
        warmed = F + n * ts
        rows.append({"workers": w, "samples_seconds": samples, "samples_speedup": t1 / samples,
                     "tiles_seconds": tiles, "tiles_speedup": t1 / tiles,
                     "prewarmed_seconds": warmed, "prewarmed_speedup": t1 / warmed})
    return {"one_process_seconds": t1, "warm_seconds": warm, "primary_share": p, "rows": rows}


def table(m, proj):
    head = (f"{m['scene']} {m['width']}x{m['height']} {m['spp']} spp: F {m['fixed_seconds']:.2f} s, "
            f"first sample {m['t1']:.2f} s, ts {m['ts']:.2f} s/sample, warm {proj['warm_seconds']:.2f} s, "
            f"p {proj['primary_share']:.2f}, one process {proj['one_process_seconds'] / 60:.1f} min")
    lines = [head, "| workers | by samples: min (speedup) | by tiles: min (speedup) | pre-warmed cache: min (speedup) |",
             "|---:|---:|---:|---:|"]
    for r in proj["rows"]:
        lines.append(f"| {r['workers']} | {r['samples_seconds'] / 60:.1f} ({r['samples_speedup']:.1f}x) | "
                     f"{r['tiles_seconds'] / 60:.1f} ({r['tiles_speedup']:.1f}x) | "
                     f"{r['prewarmed_seconds'] / 60:.1f} ({r['prewarmed_speedup']:.1f}x) |")
    return "\n".join(lines)
