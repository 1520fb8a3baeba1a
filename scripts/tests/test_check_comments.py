"""scripts/check-comments on a small tree: what it reports, and what it lets pass."""
import os
import subprocess
import sys
import tempfile
import textwrap
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "check-comments")


def write(root, path, text):
    full = os.path.join(root, path)
    os.makedirs(os.path.dirname(full), exist_ok=True)
    with open(full, "w", encoding="utf-8") as f:
        f.write(textwrap.dedent(text))


class CheckCommentsTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = self.tmp.name
        write(self.root, "core/real.h", """\
            // real.h: see core/real.cpp and docs/ (both exist), real_fn() and PMC_REAL.
            #define PMC_REAL 1
            #define PMC_FAMILY_A 2
            int real_fn();
            """)
        write(self.root, "core/real.cpp", "// PMC_FAMILY_* and core/*.h are globs that match\n")
        write(self.root, "docs/DESIGN.md", "")

    def tearDown(self):
        self.tmp.cleanup()

    def run_check(self):
        r = subprocess.run([sys.executable, SCRIPT, "--root", self.root], capture_output=True, text=True)
        return r.returncode, r.stdout

    def test_a_clean_tree_passes(self):
        self.assertEqual(self.run_check(), (0, ""))

    def test_missing_paths_and_symbols_and_flags_below_app(self):
        write(self.root, "gpu/stale.cpp", """\
            // Lives in core/gone.h, run by gone_fn() with PMC_GONE; the code's
            // strings are not comments: "real_fn()" is fine.
            /* PMC_NOFAMILY_* and the
             * --cache-policy flag */
            const char* msg = "pass --allow-partial";  // x-- and a -- b; https://a/core/none.h
            """)
        write(self.root, "app/flags.cpp", '// app/ may say --cache-policy\nconst char* s = "--spp";\n')
        write(self.root, "scripts/tool.py", '"""Writes tests/none_test.cpp."""\n# calls helper()\nx = 1\n')
        rc, out = self.run_check()
        self.assertEqual(rc, 1)
        self.assertIn("gpu/stale.cpp:1: path: core/gone.h does not exist", out)
        self.assertIn("gpu/stale.cpp:1: symbol: gone_fn() is not in the code", out)
        self.assertIn("gpu/stale.cpp:1: symbol: PMC_GONE is not in the code", out)
        self.assertIn("gpu/stale.cpp:3: symbol: PMC_NOFAMILY_* is not in the code", out)
        self.assertIn("gpu/stale.cpp:4: flag: comment names the command-line flag --cache-policy", out)
        self.assertIn("gpu/stale.cpp:5: flag: string names the command-line flag --allow-partial", out)
        self.assertIn("scripts/tool.py:1: path: tests/none_test.cpp does not exist", out)
        self.assertIn("scripts/tool.py:2: symbol: helper() is not in the code", out)
        self.assertNotIn("app/flags.cpp", out)
        self.assertNotIn("real_fn", out)
        self.assertNotIn("-- b", out)
        self.assertNotIn("none.h", out)
        self.assertEqual(len(out.splitlines()), 8, out)

    def test_the_allowlist_lets_named_findings_pass(self):
        write(self.root, "gpu/stale.cpp", "// core/gone.h, --cache-policy\n")
        write(self.root, "scripts/check-comments.allow",
              "# why\npath gpu/*.cpp core/gone.h\nflag gpu/stale.cpp --cache-policy  # the flag\n")
        self.assertEqual(self.run_check(), (0, ""))


if __name__ == "__main__":
    unittest.main()
