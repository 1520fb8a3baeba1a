"""Tests of the farm package: the split, the command line's checks, and the
LocalCluster it starts (worker processes, every listening socket on
127.0.0.1, closed at the end). The end-to-end renders (4 chunks, tiles, a
killed worker) are GoogleTests: tests/app/farm_render_test.cpp.
Run by ctest: scripts/python -m unittest discover -s scripts/farm/tests."""
import contextlib
import os
import sys
import tempfile
import unittest

import psutil

from farm import __main__ as cli
from farm import run, split

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))


class Split(unittest.TestCase):
    def test_sample_ranges_are_contiguous_and_cover_the_frame(self):
        for spp in (1, 7, 16, 1024):
            for n in range(1, min(spp, 9) + 1):
                r = split.sample_ranges(spp, n)
                self.assertEqual(len(r), n)
                self.assertEqual(r[0][0], 0)
                self.assertEqual(r[-1][1], spp)
                for (a, b), (c, _) in zip(r, r[1:]):
                    self.assertEqual(b, c)
                sizes = [b - a for a, b in r]
                self.assertLessEqual(max(sizes) - min(sizes), 1)

    def test_more_chunks_than_samples_is_refused(self):
        with self.assertRaisesRegex(ValueError, "more than the frame's 4 samples"):
            split.sample_ranges(4, 5)

    def test_tiles_cover_every_pixel_once(self):
        for w, h, n in ((40, 24, 4), (7, 5, 6), (1920, 1080, 12), (5, 9, 3)):
            tiles = split.tile_grid(w, h, n)
            self.assertEqual(len(tiles), n)
            covered = [[0] * w for _ in range(h)]
            for x0, y0, x1, y1 in tiles:
                self.assertTrue(0 <= x0 < x1 <= w and 0 <= y0 < y1 <= h)
                for y in range(y0, y1):
                    for x in range(x0, x1):
                        covered[y][x] += 1
            self.assertTrue(all(c == 1 for row in covered for c in row), (w, h, n))

    def test_a_grid_that_does_not_fit_is_refused(self):
        with self.assertRaisesRegex(ValueError, "does not fit"):
            split.tile_grid(2, 2, 9)


class CommandLine(unittest.TestCase):
    def test_render_options_pass_through_and_decide_the_split(self):
        o = cli.parse(["s.obj", "-o", "x.exr", "--chunks", "3", "--spp", "12", "--width=64", "--cache", "off"])
        self.assertEqual(o.render_args, ["--spp", "12", "--width=64", "--cache", "off"])
        defaults = run.pmc_defaults(run.default_pmc())  # `pmc info --settings`
        self.assertEqual(run.render_setting(o.render_args, "--spp", defaults), 12)
        self.assertEqual(run.render_setting(o.render_args, "--width", defaults), 64)
        self.assertEqual(run.render_setting(o.render_args, "--height", defaults), 360)  # pmc's default

    def test_the_defaults_come_from_pmc(self):
        defaults = run.pmc_defaults(run.default_pmc())
        self.assertEqual((defaults["--spp"], defaults["--width"], defaults["--height"]), (16, 640, 360))
        with tempfile.TemporaryDirectory() as d:
            with self.assertRaisesRegex(run.FarmError, "did not list its settings"):
                run.pmc_defaults(os.path.join(d, "nopmc"))

    def test_bad_input_is_refused_with_exit_code_2_before_any_cluster_starts(self):
        scene = os.path.join(ROOT, "data", "default", "room.obj")
        with tempfile.TemporaryDirectory() as d:
            cases = [
                (["missing.obj", "-o", f"{d}/x.exr", "--chunks", "2"], "no such scene file"),
                ([scene, "-o", f"{d}/x.png", "--chunks", "2"], "must end in .exr"),
                ([scene, "-o", f"{d}/no/x.exr", "--chunks", "2"], "does not exist"),
                ([scene, "-o", f"{d}/x.exr", "--chunks", "2", "--samples", "0:4"], "set by the farm"),
                ([scene, "-o", f"{d}/x.exr", "--chunks", "0"], "--chunks"),
                ([scene, "-o", f"{d}/x.exr", "--chunks", "20", "--spp", "8"], "more than the frame's 8"),
                ([scene, "-o", f"{d}/x.exr", "--chunks", "2", "--spp", "many"], "--spp"),
                ([scene, "-o", f"{d}/x.exr", "--chunks", "2", "--pmc", f"{d}/nopmc"], "not an executable pmc"),
                ([scene, "-o", f"{d}/x.exr", "--chunks", "2", "--scheduler", "localhost"], "tcp://"),
                ([scene, "-o", f"{d}/x.exr", "--chunks", "2", "--adaptive-threshold", "0.05"], "--split tiles"),
                ([scene, "-o", f"{d}/x.exr", "--chunks", "2", "--adaptive-threshold=0.1"], "--split tiles"),
            ]
            for argv, message in cases:
                err = _stderr_of(lambda: cli.main(argv + ["--quiet"]), expect=2)
                self.assertIn(message, err, argv)
            self.assertEqual(os.listdir(d), [])


class ChunkEnvironment(unittest.TestCase):
    def test_chunks_share_one_device_calibration_in_the_parts_folder_unless_the_user_set_one(self):
        self.assertEqual(run.chunk_environment("/p", {}), {"PMC_CACHE_COSTS": "/p/device-costs"})
        self.assertEqual(run.chunk_environment("/p", {"PMC_CACHE_COSTS": "table"}), {})
        self.assertEqual(run.chunk_environment("/p", {"PMC_CACHE_COSTS": "/shared/costs"}), {})


class Denoise(unittest.TestCase):
    def test_the_denoisers_passes_join_the_users_list(self):
        self.assertEqual(run.with_denoise_passes(["--spp", "4"]), ["--spp", "4", "--aov", "albedo,normal"])
        self.assertEqual(run.with_denoise_passes(["--aov", "depth", "--spp", "4"]),
                         ["--aov", "depth,albedo,normal", "--spp", "4"])
        self.assertEqual(run.with_denoise_passes(["--aov=normal,hits"]), ["--aov", "normal,hits,albedo"])
        self.assertEqual(run.with_denoise_passes(["--aov", "all"]), ["--aov", "all"])

    def test_a_missing_denoiser_is_refused_before_any_chunk_renders(self):
        scene = os.path.join(ROOT, "data", "default", "room.obj")
        with tempfile.TemporaryDirectory() as d:
            saved = os.environ.get("PMC_OIDN_LIBRARY")
            os.environ["PMC_OIDN_LIBRARY"] = os.path.join(d, "no", "libOpenImageDenoise.so.2")
            try:
                err = _stderr_of(lambda: cli.main([scene, "-o", f"{d}/x.exr", "--chunks", "2", "--denoise",
                                                   "--quiet"]), expect=2)
            finally:
                if saved is None:
                    del os.environ["PMC_OIDN_LIBRARY"]
                else:
                    os.environ["PMC_OIDN_LIBRARY"] = saved
            self.assertIn("--denoise: Open Image Denoise not available", err)
            self.assertIn("pyoidn", err)
            self.assertEqual(os.listdir(d), [])


def _stderr_of(fn, expect):
    import io
    buf = io.StringIO()
    with contextlib.redirect_stderr(buf):
        code = fn()
    assert code == expect, (code, buf.getvalue())
    return buf.getvalue()


def _tree(pid):
    p = psutil.Process(pid)
    return [p] + p.children(recursive=True)


class LocalClusterBinding(unittest.TestCase):
    def test_two_worker_processes_listen_on_loopback_only_and_stop_with_the_job(self):
        o = run.FarmOptions(scene="s.obj", output="x.exr", chunks=2, workers=2, connect_timeout=60)
        with contextlib.ExitStack() as stack:
            client = run._start_client(o, stack)
            client.wait_for_workers(2, timeout=60)
            info = client.scheduler_info()
            self.assertTrue(info["address"].startswith("tcp://127.0.0.1:"), info["address"])
            workers = info["workers"]
            self.assertEqual(len(workers), 2)
            pids = client.run(os.getpid)
            for address, pid in pids.items():
                self.assertTrue(address.startswith("tcp://127.0.0.1:"), address)
                self.assertNotEqual(pid, os.getpid())  # processes, not threads
            self.assertEqual(len(set(pids.values())), 2)
            # Every listening TCP socket of this process tree is on 127.0.0.1.
            listening = []
            for p in _tree(os.getpid()):
                try:
                    conns = p.connections(kind="inet")
                except psutil.NoSuchProcess:
                    continue
                listening += [c.laddr for c in conns if c.status == psutil.CONN_LISTEN]
            self.assertGreaterEqual(len(listening), 3)  # scheduler, 2 workers (+ nannies)
            for addr in listening:
                self.assertEqual(addr.ip, "127.0.0.1", listening)
            worker_pids = list(pids.values())
        for pid in worker_pids:  # the cluster is closed with the job
            with self.assertRaises(psutil.NoSuchProcess):
                psutil.Process(pid).wait(timeout=30)


if __name__ == "__main__":
    unittest.main()
