"""Tests of the benchmark modules without running pmc: every module imports and
its command line parses (defaults, the old environment variables, bad values),
and bench.cache's report turns saved measurements into its section."""
import importlib
import io
import os
import tempfile
import unittest
from contextlib import redirect_stdout
from unittest import mock

from bench import cache, cache_bandwidth, cache_policy, cache_position, common, denoise, mtlx_conformance

MODULES = ["adaptive", "cache", "cache_bandwidth", "cache_model", "cache_policy", "cache_position", "cache_replay", "cacheless", "denoise", "gpu", "heavy", "layered_bsdf", "light_tree", "material_peers", "materials", "mtlx_conformance", "peers", "sampler", "shade", "speed", "sweep", "trace", "waves"]


def parse(module, argv, env=None):
    mod = importlib.import_module(f"bench.{module}")
    legacy = getattr(mod, "LEGACY", {})
    clean = {k: v for k, v in os.environ.items() if k not in legacy}
    with mock.patch.dict(os.environ, {**clean, **(env or {})}, clear=True), mock.patch("os.nice", return_value=0):
        return mod.parse(argv)


class CommandLines(unittest.TestCase):
    def test_every_module_has_help_that_names_its_options(self):
        for m in MODULES:
            out = io.StringIO()
            with self.subTest(module=m), redirect_stdout(out), self.assertRaises(SystemExit) as e:
                parse(m, ["--help"])
            self.assertEqual(e.exception.code, 0)
            self.assertIn(f"scripts/python -m bench.{m}", out.getvalue())
            self.assertIn("--doc FILE", out.getvalue())

    def test_defaults_match_the_old_scripts(self):
        a = parse("cache", [])
        self.assertEqual((a.runs, a.spp, a.eval_spp, a.ref_spp, a.threshold_spp, a.width, a.height),
                         (3, 64, 64, 256, 16, 320, 180))
        self.assertEqual((a.out_dir, a.doc, a.plots, a.only), ("out/bench-cache", "docs/BENCHMARKS.md",
                                                               "docs/plots", []))
        a = parse("cacheless", [])
        self.assertEqual((a.runs, a.spp, a.width, a.height, a.baseline), (5, 16, 320, 180, None))
        a = parse("materials", [])
        self.assertEqual((a.runs, a.spp, a.width, a.height, a.note), (3, 16, 640, 360, ""))
        a = parse("sweep", [])
        self.assertEqual((a.repeat, a.spp, a.ref_spp, a.width, a.height), (3, 8, 1024, 320, 180))
        a = parse("trace", [])
        self.assertEqual((a.runs, a.spp, a.width, a.height, a.scene),
                         (3, 16, 640, 360, "../shared/scenes/sponza/sponza.obj"))

    def test_old_variables_still_work_and_are_recorded_as_flags(self):
        a = parse("cache", [], {"RUNS": "5", "ONLY": "eval,threshold", "DOC": "-"})
        self.assertEqual((a.runs, a.only, a.doc), (5, ["eval", "threshold"], "-"))
        self.assertEqual(a.command, "scripts/python -m bench.cache --runs 5 --only eval,threshold --doc -")
        a = parse("sweep", [], {"REPEAT": "2", "REPORT_ONLY": "1"})
        self.assertEqual((a.repeat, a.report_only), (2, True))
        self.assertEqual(parse("speed", ["--only", "cold,scaling"]).parts, ["cold", "scaling"])
        self.assertEqual(parse("speed", ["--baseline-pmc", "old/pmc"]).parts, ["before", "cold", "scaling"])

    def test_shade_pairs_exactly_two_single_thread_configurations(self):
        self.assertTrue(parse("shade", ["--paired", "--variant", "new=k"]).paired)
        self.assertTrue(parse("shade", ["--paired", "--baseline-pmc", "old/pmc"]).paired)
        for bad in (["--paired"], ["--paired", "--variant", "a=x", "--variant", "b=y"],
                    ["--paired", "--variant", "new=k", "--threads", "2"]):
            with self.subTest(argv=bad), redirect_stdout(io.StringIO()), mock.patch("sys.stderr", io.StringIO()), \
                    self.assertRaises(SystemExit) as e:
                parse("shade", bad)
            self.assertEqual(e.exception.code, 2)

    def test_heavy_flattens_the_networks_shader_inputs_to_constants(self):
        import MaterialX as mx
        from bench import heavy
        data = os.path.join(os.path.dirname(__file__), "..", "..", "..", "data", "heavy")
        src = os.path.join(data, "materials.mtlx")
        colours = heavy.stand_in_colours(os.path.join(data, "room.mtl"))
        self.assertEqual(colours["wood"], "0.45, 0.3, 0.17")  # room.mtl's Kd, as written there
        colours.pop("fabric")  # a material without a stand-in takes the mid grey
        with tempfile.TemporaryDirectory() as tmp:
            dst = os.path.join(tmp, "flat.mtlx")
            count = heavy.flat_materials(src, dst, colours)
            doc, flat = mx.createDocument(), mx.createDocument()
            mx.readFromXmlFile(doc, src)
            mx.readFromXmlFile(flat, dst)
        # MaterialX's own reading: the same materials and shaders, each driven input now a value of its type.
        self.assertEqual([m.getName() for m in flat.getMaterialNodes()], [m.getName() for m in doc.getMaterialNodes()])
        driven = 0
        for material in doc.getMaterialNodes():
            shader = material.getInput("surfaceshader").getConnectedNode()
            twin = flat.getNode(shader.getName())
            for inp in shader.getInputs():
                got = twin.getInput(inp.getName())
                self.assertEqual(got.getType(), inp.getType())
                if not inp.getNodeGraphString():
                    self.assertEqual(got.getValueString(), inp.getValueString())
                    continue
                driven += 1
                self.assertEqual(got.getNodeGraphString(), "")
                want = heavy.FLAT_VALUES[inp.getType()]
                if inp.getName() == "base_color":
                    want = colours.get(material.getName(), want)
                self.assertEqual(got.getValueString(), want, (material.getName(), inp.getName()))
        self.assertEqual(count, driven)
        self.assertGreaterEqual(driven, 12)  # six materials, 2-3 driven inputs each
        valid, why = flat.validate()
        self.assertTrue(valid, why)

    def test_heavy_measures_the_ceiling_against_the_networks_free(self):
        from bench import heavy
        d = dict(t_off=4.8, t_flat=2.0, ratios_flat=[2.3, 2.5], t_free=1.6, ratios_free=[3.0, 3.1])
        rows = heavy.free_rows(d)
        self.assertEqual([r[2] for r in rows], ["2.40x (2.30-2.50)", "3.00x (3.00-3.10)"])
        self.assertIn("reaches 1.20x of 2.40x, 14%", heavy.ceiling_text(d, 1.2))
        old = dict(t_off=4.8, t_free=1.6, ratios_free=[3.0, 3.1])  # results before the flat row
        self.assertEqual(len(heavy.free_rows(old)), 1)
        self.assertIn("reaches 1.20x of 3.00x, 10%", heavy.ceiling_text(old, 1.2))

    def test_heavy_takes_supersample_counts_and_reports_them(self):
        from bench import heavy
        self.assertEqual(parse("heavy", ["--supersample", "1,4,16,0"]).supersample, [1, 4, 16, 0])
        self.assertEqual(parse("heavy", []).supersample, [])
        for bad in ("3", "1,x", "32"):
            with self.subTest(bad=bad), redirect_stdout(io.StringIO()), mock.patch("sys.stderr", io.StringIO()), \
                    self.assertRaises(SystemExit):
                parse("heavy", ["--supersample", bad])
        row = dict(psnr=36.8, worst_tile_psnr=21.6, worst_tile=[112, 128, 16], worst_trimmed_tile_psnr=23.5,
                   worst_trimmed_tile=[112, 128, 16], speed_ratio=2.15)
        text = heavy.supersample_text(dict(psnr_spp=256, psnr_width=320, psnr_height=180,
                                           supersample={"4": row, "0": dict(row, speed_ratio=1.47)}), "320x180, 256 spp")
        self.assertIn("| `--cache-supersample 4` | 2.15x | 36.8 dB | 21.6 dB at (112, 128, 16) |", text)
        self.assertIn("`--cache-supersample 0` (auto) | 1.47x", text)
        self.assertEqual(heavy.supersample_text(dict(psnr_spp=256), "x"), "")

    def test_heavy_parts_the_caches_bias_from_the_noise(self):
        import numpy as np
        from bench import heavy
        rng = np.random.default_rng(7)
        truth = np.full((32, 48, 3), 0.5)
        biased = truth.copy()
        biased[16:32, 16:32] += 0.01  # one tile off by 0.01: 40 dB there
        noisy = lambda x: x + rng.normal(0.0, 0.02, x.shape)  # noise twice the bias, 34 dB per render
        f = heavy.bias_figures(noisy(truth), noisy(biased), noisy(truth), noisy(biased))
        self.assertEqual(f["bias_worst_tile"], [16, 16, 16])
        self.assertAlmostEqual(f["bias_worst_tile_psnr"], 40.0, delta=1.5)
        lo, hi = f["bias_worst_tile_range"]
        self.assertTrue(lo < 40.0 < hi, (lo, hi))
        self.assertAlmostEqual(f["noise_psnr"], 10 * np.log10(1 / (2 * 0.02 ** 2)), delta=0.5)
        self.assertLess(f["noise_worst_tile_psnr"], 32.0)
        self.assertIn("| the cache's bias, noise taken out (two seeds) |", heavy.two_seeds_text(
            dict(two_seeds=f, psnr_width=320, psnr_height=180, psnr_spp=256,
                 cached={"on": dict(psnr=36.0, worst_tile_psnr=21.0, worst_tile=[0, 0, 16])}), "x"))
        camera = dict(two_seeds=f, camera_bias=f, psnr_width=320, psnr_height=180, psnr_spp=256, t_off=10.0,
                      width=640, height=360, spp=16,
                      cached={"on": dict(psnr=36.0, worst_tile_psnr=21.0, worst_tile=[0, 0, 16]),
                              "camera": dict(t=8.0)})
        self.assertIn("| `--cache-bandwidth camera`: its bias, noise taken out (1.25x at 640x360, 16 spp) |",
                      heavy.two_seeds_text(camera, "x"))
        self.assertGreater(f["bias_psnr"], 45.0)  # a sixth of the image at 40 dB, the rest unbiased
        # No bias at all: the estimate stays far below the noise (or none is measurable).
        f = heavy.bias_figures(noisy(truth), noisy(truth), noisy(truth), noisy(truth))
        self.assertGreater(f["bias_worst_tile_psnr"], 40.0)

    def test_bad_values_are_usage_errors(self):
        for module, argv in (("cache", ["--only", "nosuchpart"]), ("cache", ["--spp", "0"]),
                             ("cache_policy", ["--fractions", "1,0"]), ("cache_policy", ["--fractions", "a"]),
                             ("trace", ["--runs", "-1"]), ("sweep", ["--repeat", "x"]),
                             ("materials", ["--no-such-flag"]), ("speed", ["--only", "cold,fast"]),
                             ("speed", ["--only", "before"]), ("speed", ["--only", ""]),
                             ("cache_position", ["--scenes", "nosuch"]), ("cache_position", ["--scenes", ","]),
                             ("cache_bandwidth", ["--configs", "nosuch"]), ("cache_bandwidth", ["--ref-spp", "0"])):
            with self.subTest(argv=argv), self.assertRaises(SystemExit) as e, mock.patch("sys.stderr"):
                parse(module, argv)
            self.assertEqual(e.exception.code, 2)


def scene_result(key, t_off, t_on, ratios, psnr, **kw):
    s = next(s for s in cache.SCENES if s["key"] == key)
    r = dict(scene=s, ok=True, t_off=t_off, t_on=t_on, ratios=ratios, psnr=psnr, relmse=0.0012, max_abs=0.1,
             psnr_q=psnr - 4, relmse_q=0.004, spp_q=1, hit_rate=0.9, memory=8 * 2**20, cells=131072, entries=8,
             enabled=True, compare_times=(1.0, 1.0), plan=[11, 147])
    r.update(kw)
    return r


class CacheReport(unittest.TestCase):
    def data(self):
        return dict(results=[scene_result("default", 4.0, 2.0, [1.5, 2.5, 2.0], 42.0),
                             dict(scene=cache.SCENES[2], ok=False, error="render sponza: exit status 1 (log: x)\n..."),
                             scene_result("teapot", 1.0, 1.25, [0.8], 35.0, plan=[21])],
                    evals=None, threshold=None, elapsed=90.0, device="PoCL", now="2026-01-01 00:00 UTC", load="1.0",
                    rev="abc1234", cpu="CPU", cores=2, command="scripts/python -m bench.cache --runs 3", runs=3,
                    spp=4, spp_q=1, eval_spp=2, ref_spp=4, threshold_spp=1, outdir="out/x")

    def test_section_layout_and_numbers(self):
        with tempfile.TemporaryDirectory() as d:
            section, printed = cache.report(self.data(), os.path.join(d, "plots"), os.path.join(d, "B.md"))
        lines = section.splitlines()
        self.assertEqual(lines[0], cache.SECTION)
        self.assertIn("Produced by `scripts/python -m bench.cache --runs 3` on 2026-01-01 00:00 UTC (1.5 minutes).",
                      section)
        header = ("| scene | cache points (sub-graph sizes) | off (s) | on (s) | off / on (range of rounds) | "
                  "hit rate | cache memory | PSNR on vs off at 1 spp (dB) | PSNR on vs off at 4 spp (dB) | "
                  "relMSE on vs off at 4 spp |")
        self.assertIn(header + "\n|---|---|---|---|---|---|---|---|---|---|\n", section)
        self.assertIn("| default room (`data/default`) | 2 (11-147 nodes) | 4.00 | 2.00 | **2.00x** (1.50-2.50) | "
                      "90.0% | 8.0 MiB (131072 x 8) | 38.0 | 42.0 | 0.0012 |", section)
        self.assertIn("| Sponza (MTL materials) | failed: render sponza: exit status 1 (log: x) |  |  |  |  |  |  |  "
                      "|  |", section)
        self.assertIn("- **>= 1.5x on the default scene** (the paper's best is 1.31x): 2.00x, met at 4 spp, 90% hits.",
                      section)
        self.assertIn("**not met** on teapot 35.0 dB", section)
        self.assertIn("- Slower with the cache:\n  teapot 0.80x (largest cached sub-graph 21 nodes)", section)
        self.assertIn("Measure it with `scripts/python -m bench.cache --only threshold`.", section)
        self.assertNotIn("### Images", section)  # no compare folders under out/x
        self.assertIn(header, printed)

    def test_the_section_replaces_the_old_one_in_place(self):
        with tempfile.TemporaryDirectory() as d:
            doc = os.path.join(d, "B.md")
            with open(doc, "w") as f:
                f.write(f"# B\n\n{cache.SECTION}\n\nold\n\n## Next\n\nkept\n")
            section, _ = cache.report(self.data(), os.path.join(d, "plots"), doc)
            with redirect_stdout(io.StringIO()):
                common.write_section(doc, cache.SECTION, section, "test")
            text = common.read_text(doc)
        self.assertNotIn("\nold\n", text)
        self.assertEqual(text.count(cache.SECTION), 1)
        self.assertTrue(text.endswith("\n\n## Next\n\nkept\n"))

class DenoiseTimeTo(unittest.TestCase):
    def test_time_to_an_error_interpolates_log_log_between_measured_points(self):
        # relMSE falling as 1/t: (1 s, 1.0), (4 s, 0.25); 0.5 is reached at 2 s.
        self.assertAlmostEqual(denoise.time_to([(4.0, 0.25), (1.0, 1.0)], 0.5), 2.0)
        self.assertEqual(denoise.time_to([(1.0, 1.0), (4.0, 0.25)], 0.25), 4.0)
        self.assertIsNone(denoise.time_to([(1.0, 1.0), (4.0, 0.25)], 0.1))

    def test_unknown_scene_and_bad_sample_lists_are_usage_errors(self):
        for argv in (["--scenes", "default,kitchen"], ["--spps", "4,x"], ["--spps", "0"]):
            with self.subTest(argv=argv), redirect_stdout(io.StringIO()), mock.patch("sys.stderr", io.StringIO()), \
                    self.assertRaises(SystemExit) as e:
                parse("denoise", argv)
            self.assertEqual(e.exception.code, 2)


if __name__ == "__main__":
    unittest.main()


class MtlxConformance(unittest.TestCase):
    def test_reasons_name_the_node_shader_or_type(self):
        r = mtlx_conformance.reason_of
        self.assertEqual(r("a.mtlx: premult 'p': unsupported node 'premult' (ND_premult_color4): pmc has no"),
                         "node premult")
        self.assertEqual(r("a.mtlx: node 's': 'toon' is not a supported surface shader (pmc supports ...)"),
                         "shader toon")
        self.assertEqual(r("a.mtlx: c 'x': node 'oren_nayar_diffuse_bsdf' (ND_x) outputs a BSDF closure: generic"),
                         "closure graph (BSDF node oren_nayar_diffuse_bsdf)")
        self.assertEqual(r("a.mtlx: input 'm': values of type matrix33 are not supported"), "type matrix33")

    def test_spheres_bind_each_material(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "s.obj")
            mtlx_conformance.sphere_obj(path, ["A", "B"], rings=2, segments=3)
            text = common.read_text(path)
            self.assertEqual([l for l in text.splitlines() if l.startswith("usemtl")], ["usemtl A", "usemtl B"])
            self.assertEqual(sum(l.startswith("f ") for l in text.splitlines()), 2 * 2 * 2 * 3)
            self.assertEqual(sum(l.startswith("v ") for l in text.splitlines()), 2 * 3 * 4)


class CachePolicyReport(unittest.TestCase):
    def data(self, camera_hits_priority_16):
        def cache_stats(camera_hits, hit_rate, replaced):
            return dict(lookups=1000, misses=400, hit_rate=hit_rate, camera_hit_rate=camera_hits / 200,
                        camera_lookups=200, camera_hits=camera_hits, replaced=replaced, dropped_full=10,
                        memory_bytes=2**20)
        return dict(command="scripts/python -m bench.cache_policy", now="now", rev="abc", machine="m", load="l",
                    elapsed=60, width=64, height=36, spp=4, runs=2, rt_priority=None, full_cells=1024, entries=8,
                    fractions=[1, 16], cells={"1": 1024, "16": 64},
                    times={"off": [4.0, 4.4], "keep-first 1/1": [2.0, 2.2], "priority 1/1": [2.0, 2.2],
                           "keep-first 1/16": [3.0, 3.3], "priority 1/16": [2.1, 2.3]},
                    psnr={"keep-first 1/1": 45.0, "priority 1/1": 45.0, "keep-first 1/16": 45.0,
                          "priority 1/16": 45.0},
                    cache={"keep-first 1/1": cache_stats(180, 0.8, 0), "priority 1/1": cache_stats(180, 0.8, 0),
                           "keep-first 1/16": cache_stats(40, 0.1, 0),
                           "priority 1/16": cache_stats(camera_hits_priority_16, 0.08, 77)})

    def test_verdicts_follow_the_numbers(self):
        section, _ = cache_policy.report(self.data(90))
        self.assertTrue(section.startswith(cache_policy.SECTION))
        self.assertIn("keep-first -> priority: 1/1: 90.0% -> 90.0% (0 replaced), 1/16: 20.0% -> 45.0% (77 replaced). "
                      "Priority hits at least as often on camera rays at every size: **yes**. Where priority "
                      "replaced nothing (1/1)", section)
        # full 2.0 / 2.1 -> speedup 2.0x; priority 1/16: 4.2 / 2.2 = 1.91x, 95%; keep-first 4.2 / 3.15 = 1.33x, 67%
        self.assertIn("`priority` keeps 95% of the full-size speedup (1.91x of 2.00x): goal 90% **met**", section)
        self.assertIn("`keep-first` keeps 67% of the full-size speedup (1.33x of 2.00x): goal 90% **not met**",
                      section)
        self.assertIn("the same 45.0 dB for every size and policy", section)
        self.assertIn("- Default: priority wins at 1/16 (speedup 1.91x against keep-first's 1.33x", section)
        self.assertIn("| 1/16 | 64 | 1.00 | `priority` | 45.0% | 8.0% | 77 | 2.20 |", section)
        section, _ = cache_policy.report(self.data(30))
        self.assertIn("on camera rays at every size: **no**", section)
        self.assertIn("- Default: priority does not win at 1/16", section)

    def test_fit_rows_and_verdict(self):
        data = self.data(30)
        fit = "keep-first + fit 1/16"
        data["times"][fit] = [2.1, 2.2]  # 4.2 / 2.15 = 1.95x, 98% of 2.00x
        data["psnr"][fit] = 41.5
        data["worst_tile"] = {fit: 30.25}
        data["fit_levels"] = {fit: 2.0}
        data["cache"][fit] = dict(data["cache"]["keep-first 1/1"], hit_rate=0.85)
        section, _ = cache_policy.report(data)
        self.assertIn("| 1/16 | 64 | 1.00 | `keep-first` + `--cache-fit on` (2.0 levels coarser) |", section)
        self.assertIn("`keep-first + fit` keeps 98% of the full-size speedup (1.95x of 2.00x): goal 90% **met**",
                      section)
        self.assertIn("1/16: 1.95x (98% of the full-size speedup), 85.0% hits, 41.5 dB (worst tile 30.2 dB); "
                      "the automatic table: 45.0 dB", section)
        # The policies' PSNR line leaves fit out: they still render the same image.
        self.assertIn("the same 45.0 dB for every size and policy (without fit)", section)


class CachePositionReport(unittest.TestCase):
    def data(self, marble_hit):
        def scene(pos_lookups, pos_hit, t_pos):
            hits = {"uv": dict(hit_rate=0.9, uv_hit_rate=0.9, position_hit_rate=0.0, lookups=100, position_lookups=0),
                    "uv+position": dict(hit_rate=0.85, uv_hit_rate=0.9, position_hit_rate=pos_hit, lookups=150,
                                        position_lookups=pos_lookups)}
            bias = {k: dict(psnr=45.0, worst_tile_psnr=36.0, worst_tile=[0, 0, 16]) for k in hits}
            return dict(hits=hits, bias=bias, memory={"uv": 2**20, "uv+position": 2**21},
                        times={"off": [2.0, 2.2, 2.1], "uv": [1.9, 2.0, 2.0], "uv+position": [t_pos] * 3})
        return dict(command="scripts/python -m bench.cache_position", now="now", rev="abc", machine="m", load="l",
                    elapsed=60, width=640, height=360, spp=16, ref_spp=256, runs=3,
                    scenes={"marble": scene(50, marble_hit, 1.0), "default": scene(50, 0.7, 1.2),
                            "solid": scene(150, 0.75, 1.5)})

    def test_goals_follow_the_numbers(self):
        section, _ = cache_position.report(self.data(0.81))
        self.assertTrue(section.startswith(cache_position.SECTION))
        self.assertIn("81.0% of its lookups hit at 16 spp; goal 80% **met**", section)
        self.assertIn("goal 1.3x at 40 dB **met**", section)  # 2.1 / 1.5 = 1.4x, 45 dB
        section, _ = cache_position.report(self.data(0.75))
        self.assertIn("goal 80% **not met**", section)

    def test_lobe_configurations_get_rows_and_a_line(self):
        data = self.data(0.81)
        solid = data["scenes"]["solid"]
        solid["hits"]["lobe"] = dict(solid["hits"]["uv+position"], hit_rate=0.9)
        solid["bias"]["lobe"] = dict(psnr=39.0, worst_tile_psnr=30.0, worst_tile=[0, 0, 16],
                                     worst_trimmed_tile_psnr=41.5)
        solid["memory"]["lobe"] = 2**21
        solid["times"]["lobe"] = [1.4] * 3
        solid["same_seed"] = {"lobe": 33.25}
        section, _ = cache_position.report(data)
        self.assertIn("| solid | `uv+position --cache-lobe-spread 1/32` | 1.40 | **1.50x** (1.43-1.57) |", section)
        self.assertIn("| 90.0% | 33.2 | 39.0 | 30.0 | 41.5 | 2.0 |", section)
        self.assertIn("With position cells widened after rough bounces (`--cache-lobe-spread 1/32`): 1.50x, bias "
                      "39.0 dB over the image, 30.0 dB in its worst tile (41.5 dB trimmed; 1.3x at 40 dB: not "
                      "reached", section)
        self.assertIn("| 45.0 | 36.0 | - | 2.0 |", section)  # no trimmed figure in older results
        self.assertNotIn("--cache-min-nodes 4`): ", section)


class CacheBandwidthReport(unittest.TestCase):
    def data(self, worst_doc_tile):
        def b(tile, cached=True):
            return dict(psnr=50.0, worst_tile_psnr=tile, hit_rate=0.8, bypassed=0.1, cached=cached)
        bias = {"default scene": {"default": b(34.9), "floors": b(45.0)},
                "linepattern.mtlx test_grid": {"default": b(15.0), "floors": b(worst_doc_tile)},
                "tiledshape.mtlx nothing": {"default": b(0, False), "floors": b(0, False)}}
        return dict(command="scripts/python -m bench.cache_bandwidth", now="now", rev="abc", machine="m", load="l",
                    elapsed=60, runs=3, ref_spp=256, configs=["default", "floors"], bias=bias,
                    times={"off": [2.0, 2.2, 2.1], "default": [1.4, 1.5, 1.4], "floors": [2.0, 2.0, 2.1]},
                    hits={"default": dict(hit_rate=0.9, bypassed=0.0), "floors": dict(hit_rate=0.8, bypassed=0.5)})

    def test_goals_follow_the_numbers(self):
        section, _ = cache_bandwidth.report(self.data(41.0))
        self.assertTrue(section.startswith(cache_bandwidth.SECTION))
        self.assertIn("`default`: default scene worst tile 34.9 dB, speedup 1.50x", section)
        self.assertIn("worst tile over all materials 15.0 dB (linepattern.mtlx test_grid): goal 40 dB **not met**",
                      section)
        self.assertIn("`floors`: default scene worst tile 45.0 dB, speedup 1.05x; worst tile over all materials "
                      "41.0 dB (linepattern.mtlx test_grid): goal 40 dB **met**", section)
        self.assertIn("no cache points", section)
        section, _ = cache_bandwidth.report(self.data(39.0))
        self.assertIn("39.0 dB (linepattern.mtlx test_grid): goal 40 dB **not met**", section)

    def test_trimmed_worst_tiles_are_shown_beside_the_goal(self):
        data = self.data(41.0)
        data["bias"]["default scene"]["default"]["worst_trimmed_tile_psnr"] = 36.0
        data["bias"]["linepattern.mtlx test_grid"]["default"]["worst_trimmed_tile_psnr"] = 15.5
        section, _ = cache_bandwidth.report(data)
        self.assertIn("| default scene | 34.9 (36.0) / 50.0 (80.0% hit, 10.0% bypassed) |", section)
        self.assertIn("goal 40 dB **not met** (without each tile's 2 largest pixel errors: 15.5 dB, "
                      "linepattern.mtlx test_grid).", section)
        self.assertIn("41.0 dB (linepattern.mtlx test_grid): goal 40 dB **met**.", section)


class ShadeFigures(unittest.TestCase):
    """bench.shade's two per-hit figures from a render's stats and a perf report."""

    def test_ns_per_hit_counts_every_path_ray_once_per_core(self):
        from bench import shade
        stats = {"rays": 3000, "shadow_rays": 1000, "stage_seconds": {"shade": 0.001}}
        self.assertAlmostEqual(shade.ns_per_hit(stats, 2), 0.001 * 2 * 1e9 / 2000)

    def test_perf_report_sums_the_shade_kernel_only(self):
        from bench import shade
        report = ("# Samples: 30\n"
                  "    50.00%  15  pmc_shade.so  [.] _pocl_kernel_pmc_shade_workgroup\n"
                  "    20.00%   6  pmc_shade.so  [.] pmc_tree_importance\n"
                  "    30.00%   9  pmc_camera_rays.so  [.] _pocl_kernel_pmc_camera_rays_workgroup\n")
        done = mock.Mock(stdout=report)
        with mock.patch("subprocess.run", return_value=done):
            ns = shade.perf_shade_ns("unused.perf", hits=1000)
        per_sample = shade.PERF_PERIOD_NS / 1000
        self.assertAlmostEqual(ns[""], 21 * per_sample)
        self.assertAlmostEqual(ns["pmc_tree_importance"], 6 * per_sample)
        self.assertNotIn("_pocl_kernel_pmc_camera_rays_workgroup", ns)


class CacheModelRounds(unittest.TestCase):
    """bench.cache_model's round order and its never-slower check."""

    def test_every_pair_swaps_its_order_from_round_to_round(self):
        from bench import cache_model
        jobs = {n: None for n in ["a_160x90_off", "a_160x90_cost", "a_160x90_ceiling", "b_160x90_off",
                                  "b_160x90_cost", "c_640x360_off", "c_640x360_cost"]}
        orders = [cache_model.Measure.round_jobs(jobs, r) for r in range(4)]
        for order in orders:
            self.assertEqual(sorted(order), sorted(jobs))
            for g in ("a_160x90", "b_160x90", "c_640x360"):  # a group's renders run one after another
                at = [i for i, n in enumerate(order) if n.startswith(g)]
                self.assertEqual(at, list(range(at[0], at[0] + len(at))))
        for g in ("b_160x90", "c_640x360"):
            first = [order.index(f"{g}_off") < order.index(f"{g}_cost") for order in orders]
            self.assertEqual(first, [True, False, True, False])

    def test_rows_where_the_cache_turned_itself_off_are_named_apart(self):
        from bench import cache_model
        cache_on = {"enabled": True, "uv_hit_rate": 0.9}
        data = {"command": "x", "now": "now", "rev": "r", "machine": "m", "load": "l", "elapsed": 60.0, "runs": 2,
                "spp": 16, "sizes": [[160, 90]], "scenes": ["default", "lines"], "short": [0.5, 15],
                "seconds": {"default_160x90_off": [1.0, 1.0], "default_160x90_cost": [1.1, 1.1],
                            "lines_160x90_off": [1.0, 1.0], "lines_160x90_cost": [1.05, 1.05]},
                "stats": {"default_160x90_cost": {"cache": cache_on}, "default_160x90_off": {"cache": cache_on},
                          "lines_160x90_cost": {"cache": {"enabled": False}},
                          "lines_160x90_off": {"cache": {"enabled": False}}}}
        section, _ = cache_model.report(data)
        self.assertIn("below 0.98x of off (median of the rounds): default room (`data/default`) 160x90 0.91x.",
                      section)
        self.assertIn("left out of that count: 1 of them, their ratios 0.95-0.95", section)
        self.assertIn("runs again, back to back, until its renders add up to 0.5 s", section)


class LightTreeHall(unittest.TestCase):
    """bench.light_tree's written hall: hundreds of lights, tens of thousands of emissive triangles."""

    def test_the_hall_has_its_lights_and_glowing_triangles(self):
        import json
        import tempfile
        from bench import light_tree
        with tempfile.TemporaryDirectory() as d:
            args = light_tree.write_hall(d)
            self.assertEqual(args[0], os.path.join(d, "hall.obj"))
            with open(args[2]) as f:
                self.assertEqual(len(json.load(f)["lights"]), 300)
            glowing, material = 0, None
            with open(args[0]) as f:
                for line in f:
                    if line.startswith("usemtl "):
                        material = line.split()[1]
                    elif line.startswith("f ") and material.startswith("glow"):
                        glowing += 1
            self.assertEqual(glowing, 4 * 90 * 35 * 2)
            with open(os.path.join(d, "hall.mtl")) as f:
                self.assertEqual(f.read().count("Ke "), 4)
