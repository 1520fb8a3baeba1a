"""Tests of bench.common: section replacement in BENCHMARKS.md, the round
reductions (medians, per-round ratios, round order), markdown tables and the
command-line plumbing (old environment variables, the recorded command).
Run by ctest: scripts/python -m unittest discover -s scripts/bench/tests."""
import argparse
import math
import os
import tempfile
import unittest
from unittest import mock

from bench import common

DOC = """# Benchmarks

Intro.

## Tracing (scripts/bench-trace)

old tracing
| a | b |

## Cache: off vs on (scripts/bench-cache)

old cache

### a subsection that belongs to the cache section

more cache

## Materials (scripts/bench-materials)

materials text
"""


class ReplaceSection(unittest.TestCase):
    def test_replaces_a_middle_section_up_to_the_next_level_two_title(self):
        new = "## Cache: off vs on (scripts/bench-cache)\n\nnew cache\n"
        out = common.replace_section(DOC, "## Cache: off vs on (scripts/bench-cache)", new)
        self.assertEqual(out, DOC.replace(
            "old cache\n\n### a subsection that belongs to the cache section\n\nmore cache\n", "new cache\n"))

    def test_replaces_the_last_section_to_the_end(self):
        new = "## Materials (scripts/bench-materials)\n\nnew materials\n\n\n"
        out = common.replace_section(DOC, "## Materials (scripts/bench-materials)", new)
        self.assertTrue(out.endswith("more cache\n\n## Materials (scripts/bench-materials)\n\nnew materials\n"))
        self.assertEqual(out[:out.index("## Materials")], DOC[:DOC.index("## Materials")])

    def test_appends_a_missing_section_after_one_blank_line(self):
        new = "## Sweeps (scripts/bench-sweep)\n\nsweeps\n"
        out = common.replace_section(DOC + "\n\n", "## Sweeps (scripts/bench-sweep)", new)
        self.assertEqual(out, DOC + "\n" + new)

    def test_falls_back_to_an_old_title(self):
        new = "## New title\n\nbody\n"
        out = common.replace_section(DOC, "## New title", new, old_titles=["## Tracing (scripts/bench-trace)"])
        self.assertNotIn("old tracing", out)
        self.assertIn("Intro.\n\n## New title\n\nbody\n\n## Cache: off vs on", out)

    def test_a_title_must_be_a_whole_line(self):
        doc = "# B\n\nSee ## Cache for why.\n\n## Cache extra\n\nx\n"
        out = common.replace_section(doc, "## Cache", "## Cache\n\ny\n")
        self.assertEqual(out, doc + "\n## Cache\n\ny\n")

    def test_replacing_twice_gives_the_same_text(self):
        new = "## Tracing (scripts/bench-trace)\n\nnew\n"
        once = common.replace_section(DOC, "## Tracing (scripts/bench-trace)", new)
        self.assertEqual(common.replace_section(once, "## Tracing (scripts/bench-trace)", new), once)

    def test_write_section_creates_the_file_and_keeps_other_sections(self):
        with tempfile.TemporaryDirectory() as d:
            doc = os.path.join(d, "sub", "BENCH.md")
            with mock.patch("builtins.print"):
                common.write_section(doc, "## A", "## A\n\na1\n", "test")
                common.write_section(doc, "## B", "## B\n\nb1\n", "test")
                common.write_section(doc, "## A", "## A\n\na2\n", "test")
            text = common.read_text(doc)
            self.assertTrue(text.startswith(common.DOC_INTRO))
            self.assertTrue(text.endswith("## A\n\na2\n\n## B\n\nb1\n"))
            self.assertFalse(os.path.exists(doc + ".tmp"))

    def test_write_section_to_dash_writes_nothing(self):
        with tempfile.TemporaryDirectory() as d:
            cwd = os.getcwd()
            os.chdir(d)
            try:
                common.write_section("-", "## A", "## A\n", "test")
                self.assertEqual(os.listdir(d), [])
            finally:
                os.chdir(cwd)


class PlotPath(unittest.TestCase):
    def test_a_plot_goes_beside_its_doc_file_or_into_the_out_dir(self):
        from types import SimpleNamespace
        self.assertEqual(common.plot_path(SimpleNamespace(doc="docs/BENCHMARKS.md", out_dir="out/x"), "p.png"),
                         "docs/plots/p.png")  # where the section's link plots/p.png points
        self.assertEqual(common.plot_path(SimpleNamespace(doc="/tmp/s/doc.md", out_dir="out/x"), "p.png"),
                         "/tmp/s/plots/p.png")
        self.assertEqual(common.plot_path(SimpleNamespace(doc="-", out_dir="out/x"), "p.png"), "out/x/p.png")


class Reductions(unittest.TestCase):
    def test_median_of_odd_and_even_counts(self):
        self.assertEqual(common.median([3.0, 1.0, 2.0]), 2.0)
        self.assertEqual(common.median([4.0, 1.0, 3.0, 2.0]), 2.5)
        self.assertEqual(common.median(x for x in [5.0]), 5.0)

    def test_median_of_nothing_is_nan(self):
        self.assertTrue(math.isnan(common.median([])))

    def test_median_range(self):
        self.assertEqual(common.median_range(iter([2.0, 9.0, 1.0])), (2.0, 1.0, 9.0))

    def test_round_ratios_pair_runs_of_the_same_round(self):
        # The median of per-round ratios differs from the ratio of medians: it is the one reported.
        off, on = [2.0, 4.0, 9.0], [1.0, 4.0, 3.0]
        ratios = common.round_ratios(off, on)
        self.assertEqual(ratios, [2.0, 1.0, 3.0])
        self.assertEqual(common.median(ratios), 2.0)
        self.assertAlmostEqual(common.median(off) / common.median(on), 4.0 / 3.0)

    def test_round_ratios_need_as_many_rounds_on_both_sides(self):
        with self.assertRaises(ValueError):
            common.round_ratios([1.0, 2.0], [1.0])

    def test_rotate_puts_each_configuration_first_once(self):
        c = ["a", "b", "c"]
        orders = [common.round_order(c, r, "rotate") for r in range(3)]
        self.assertEqual(orders, [["a", "b", "c"], ["b", "c", "a"], ["c", "a", "b"]])
        self.assertEqual(common.round_order(c, 3, "rotate"), c)

    def test_reverse_alternates_which_goes_first(self):
        self.assertEqual(common.round_order(("off", "on"), 0, "reverse"), ["off", "on"])
        self.assertEqual(common.round_order(("off", "on"), 1, "reverse"), ["on", "off"])
        self.assertEqual(common.round_order(("off", "on"), 2, "reverse"), ["off", "on"])
        with self.assertRaises(ValueError):
            common.round_order(["a"], 0, "shuffle")

    def test_rounds_text(self):
        self.assertEqual(common.rounds_text(1), "1 round")
        self.assertEqual(common.rounds_text(3), "3 rounds")

    def test_load_note(self):
        s = common.LoadSampler()
        s.loads = [1.0, 3.0, 2.0, 2.5]
        self.assertEqual(s.note(), "1-minute load average 1.0 before the runs, 2.2 median and 3.0 max between them")


class Tables(unittest.TestCase):
    def test_md_table(self):
        self.assertEqual(common.md_table(["scene", "off (s)"], [["room", "1.00"], ["teapot", ""]]),
                         "| scene | off (s) |\n|---|---|\n| room | 1.00 |\n| teapot |  |")

    def test_md_table_without_rows_is_the_header(self):
        self.assertEqual(common.md_table(["a"], []), "| a |\n|---|")

    def test_size_args_order(self):
        self.assertEqual(common.size_args(320, 180, 8),
                         ["--width", "320", "--height", "180", "--spp", "8", "--quiet"])


class CommandLine(unittest.TestCase):
    def parser(self):
        p = common.make_parser("demo", "demo", {"RUNS": "--runs", "REPORT_ONLY": "--report-only"})
        common.add_runs(p, 3)
        p.add_argument("--report-only", action="store_true")
        return p

    def parse(self, argv, env):
        with mock.patch.dict(os.environ, env, clear=False), mock.patch("os.nice", return_value=0):
            for k in ("RUNS", "REPORT_ONLY"):
                if k not in env:
                    os.environ.pop(k, None)
            return common.parse_args(self.parser(), "demo", {"RUNS": "--runs", "REPORT_ONLY": "--report-only"},
                                     argv)

    def test_defaults_and_the_recorded_command(self):
        a = self.parse([], {})
        self.assertEqual((a.runs, a.report_only), (3, False))
        self.assertEqual(a.command, "scripts/python -m bench.demo")

    def test_old_environment_variables_become_flags(self):
        a = self.parse([], {"RUNS": "5", "REPORT_ONLY": "1"})
        self.assertEqual((a.runs, a.report_only), (5, True))
        self.assertEqual(a.command, "scripts/python -m bench.demo --runs 5 --report-only")

    def test_a_flag_on_the_command_line_wins_over_the_environment(self):
        a = self.parse(["--runs=2"], {"RUNS": "5"})
        self.assertEqual(a.runs, 2)
        self.assertEqual(a.command, "scripts/python -m bench.demo --runs=2")

    def test_empty_variables_count_as_unset(self):
        self.assertEqual(self.parse([], {"RUNS": ""}).runs, 3)

    def test_bad_counts_are_usage_errors(self):
        for bad in (["--runs", "0"], ["--runs", "x"]):
            with self.assertRaises(SystemExit) as e, mock.patch("sys.stderr"):
                self.parse(bad, {})
            self.assertEqual(e.exception.code, 2)
        with self.assertRaises(argparse.ArgumentTypeError):
            common.positive_int("-1")

    def test_no_abbreviated_flags(self):
        with self.assertRaises(SystemExit), mock.patch("sys.stderr"):
            self.parse(["--run", "2"], {})


class Running(unittest.TestCase):
    def test_run_logs_and_times_a_command(self):
        with tempfile.TemporaryDirectory() as d:
            log = os.path.join(d, "x.log")
            done = common.run(["sh", "-c", "echo hello; echo err >&2"], log)
            self.assertEqual(done.output, "hello\nerr\n")
            self.assertGreaterEqual(done.wall, 0.0)
            self.assertEqual(common.read_text(log), "sh -c echo hello; echo err >&2\nhello\nerr\n")

    def test_run_appends_to_a_shared_log(self):
        with tempfile.TemporaryDirectory() as d:
            log = os.path.join(d, "all.log")
            common.run(["echo", "a"], log, append=True)
            common.run(["echo", "b"], log, append=True)
            self.assertEqual(common.read_text(log), "$ echo a\na\n$ echo b\nb\n")

    def test_a_failing_command_raises_with_its_exit_status_and_log(self):
        with tempfile.TemporaryDirectory() as d:
            log = os.path.join(d, "f.log")
            with self.assertRaises(common.RunFailed) as e:
                common.run(["sh", "-c", "echo one; echo two; exit 3"], log, "render x")
            self.assertEqual(str(e.exception), f"render x: exit status 3 (log: {log})")
            self.assertEqual(e.exception.tail, "one\ntwo")

    def test_run_pmc_reads_the_stats(self):
        with tempfile.TemporaryDirectory() as d:
            stats = os.path.join(d, "s.json")
            s, _ = common.run_pmc(["sh", "-c", f"echo '{{\"render_seconds\": 1.5}}' > {stats}"], stats,
                                  os.path.join(d, "l.log"))
            self.assertEqual(s, {"render_seconds": 1.5})


if __name__ == "__main__":
    unittest.main()


class StaleBinary(unittest.TestCase):
    def test_names_the_newest_source_written_after_the_binary(self):
        with tempfile.TemporaryDirectory() as d:
            for rel, t in (("core/a.h", 100), ("gpu/kernels/k.cl", 300), ("docs/x.md", 400), ("pmc", 200)):
                path = os.path.join(d, rel)
                os.makedirs(os.path.dirname(path), exist_ok=True)
                open(path, "w").close()
                os.utime(path, (t, t))
            binary = os.path.join(d, "pmc")
            self.assertEqual(common.newest_source_after(binary, d), os.path.join("gpu", "kernels", "k.cl"))
            os.utime(binary, (350, 350))  # docs/ is not a source of the binary
            self.assertIsNone(common.newest_source_after(binary, d))
            self.assertIsNone(common.newest_source_after(os.path.join(d, "missing"), d))

