"""bench.gpu's reading of a scripts/gpu-check folder, on a made-up one: test
counts and failure reasons from the GoogleTest XML, medians and the cache's
speedup per image size, and the device line."""
import json
import os
import tempfile
import unittest

from bench import gpu

XML = """<?xml version="1.0" encoding="UTF-8"?>
<testsuites tests="3" failures="1">
  <testsuite name="A" tests="3">
    <testcase name="Passes" classname="A" result="completed" />
    <testcase name="Skipped" classname="A" result="suppressed" />
    <testcase name="NeedsThePlugin" classname="A" result="completed">
      <failure message="unknown file&#x0A;x.hdr: reading this file needs the image plugin" type="" />
    </testcase>
  </testsuite>
</testsuites>
"""


def stats(w, render, shade, cache, scene="/repo/data/default/room.obj"):
    c = {"enabled": cache, "policy": "keep-first", "eval": "center", "filter": "bilinear", "cells": 8,
         "entries": 8, "hit_rate": 0.5} if cache else {"enabled": False}
    return {"scene": scene, "width": w, "height": w // 2, "spp": 16, "shade_lanes": 1, "render_seconds": render,
            "rays_per_second": 1e6, "device": "Some GPU (Vendor)", "cache": c,
            "stage_seconds": {k: shade if k == "shade" else 0.1 for k in gpu.STAGES}}


class ReadsAGpuCheckFolder(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp()
        os.makedirs(os.path.join(self.dir, "bench"))
        with open(os.path.join(self.dir, "tests-0.xml"), "w") as f:
            f.write(XML)
        for r, (off, on) in enumerate([(2.0, 1.0), (3.0, 1.5), (2.2, 1.2)], 1):
            for name, s in ((f"r{r}-big-cache-off", stats(200, off, 1.0, False)),
                            (f"r{r}-big-cache-on", stats(200, on, 0.4, True))):
                with open(os.path.join(self.dir, "bench", name + ".json"), "w") as f:
                    json.dump(s, f)

    def test_counts_tests_and_names_the_failures_reason(self):
        total, failed = gpu.test_summary(self.dir)
        self.assertEqual(total, 2)
        self.assertEqual(failed, ["A.NeedsThePlugin: x.hdr: reading this file needs the image plugin"])

    def test_medians_and_the_cache_speedup(self):
        runs = gpu.bench_rows(self.dir)
        self.assertEqual(sorted(runs), ["big-cache-off", "big-cache-on"])
        text, rounds = gpu.table(runs)
        self.assertEqual(rounds, 3)
        self.assertIn("| 2.20 (2.00-3.00) |", text)
        self.assertIn("| 1.20 (1.00-1.50) |", text)
        self.assertIn("| 1.83x |", text)  # 2.2 / 1.2
        notes = gpu.cache_notes(runs)
        self.assertEqual(len(notes), 1)
        self.assertIn("faster, 2.20 -> 1.20 s (1.83x); the shade stage 1.00 -> 0.40 s", notes[0])

    def test_the_device_comes_from_the_stats_without_devices_txt(self):
        self.assertEqual(gpu.device_line(self.dir), "Some GPU (Vendor)")


if __name__ == "__main__":
    unittest.main()


class ComparesEachSceneWithItsOwnCacheOffRun(unittest.TestCase):
    def test_the_heavy_scenes_rows_use_its_own_baseline(self):
        d = tempfile.mkdtemp()
        os.makedirs(os.path.join(d, "bench"))
        heavy = "/repo/data/heavy/room.obj"
        for name, s in (("r1-cache-off", stats(200, 2.0, 1.0, False)), ("r1-cache-on", stats(200, 1.0, 0.5, True)),
                        ("r1-heavy-cache-off", stats(200, 9.0, 8.0, False, heavy)),
                        ("r1-heavy-cache-on", stats(200, 3.0, 2.0, True, heavy))):
            with open(os.path.join(d, "bench", name + ".json"), "w") as f:
                json.dump(s, f)
        runs = gpu.bench_rows(d)
        text, _ = gpu.table(runs)
        self.assertIn("| 2.00x |", text)  # 2.0 / 1.0: the default scene against its own
        self.assertIn("| 3.00x |", text)  # 9.0 / 3.0: the heavy scene against its own
        notes = gpu.cache_notes(runs)
        self.assertEqual(len(notes), 2)
        self.assertTrue(any(n.startswith("- heavy/room.obj, 200x100:") and "(3.00x)" in n for n in notes), notes)
