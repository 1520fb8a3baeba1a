"""scripts/check-function-length on a small tree: what it reports, and what it lets pass."""
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "check-function-length")


def write(root, path, text):
    full = os.path.join(root, path)
    os.makedirs(os.path.dirname(full), exist_ok=True)
    with open(full, "w", encoding="utf-8") as f:
        f.write(text)


def body(lines):
    """Statements filling a body of `lines` lines from its opening brace to its closing one."""
    return "".join("  x += %d;\n" % i for i in range(lines - 2))


class CheckFunctionLengthTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def run_check(self, *args):
        r = subprocess.run([sys.executable, SCRIPT, "--root", self.root, "--limit", "20"] + list(args),
                           capture_output=True, text=True)
        return r.returncode, r.stdout

    def test_functions_at_the_limit_pass(self):
        write(self.root, "core/ok.cpp", "namespace pmc {\nint f(int x) {\n" + body(19) + "  return x;\n}\n}\n")
        self.assertEqual(self.run_check(), (0, ""))

    def test_a_long_function_fails_naming_it(self):
        write(self.root, "core/long.cpp", "// {{{ braces in comments do not count\n"
              "static int long_one(int x) const noexcept {\n" + body(20) + '  const char* s = "}}}";\n}\n')
        code, out = self.run_check()
        self.assertEqual(code, 1)
        self.assertIn("core/long.cpp:2: long_one is 21 lines", out)

    def test_lambdas_and_blocks_count_towards_their_function(self):
        write(self.root, "gpu/nested.cpp", "void outer() {\n  auto f = [&](int y) {\n" + body(12) +
              "  };\n  if (f(1)) {\n" + body(8) + "  }\n}\n")
        code, out = self.run_check()
        self.assertEqual(code, 1)
        self.assertIn("outer is 22 lines", out)
        self.assertNotIn("?", out)

    def test_methods_and_constructors_are_functions_and_classes_are_not(self):
        write(self.root, "materials/cls.h", "namespace pmc {\nclass C {\n public:\n"
              "  C(int a) : a_(a), b_{a, 2} {\n" + body(21) + "  }\n"
              "  int m() const {\n" + body(21) + "  }\n" + "  int a_;\n" * 30 + "};\n}\n")
        code, out = self.run_check()
        self.assertEqual(code, 1)
        self.assertIn("cls.h:4: C is 21 lines", out)
        self.assertIn(": m is 21 lines", out)
        self.assertEqual(out.count(" lines (at most"), 2)

    def test_data_tables_are_allowed_by_name(self):
        write(self.root, "materials/table.cpp", "std::vector<Def> build() {\n" + body(40) + "}\n"
              "const int kTable[] = {\n" + "  1,\n" * 40 + "};\n")
        write(self.root, "scripts/check-function-length.allow",
              "materials/table.cpp build  # a table of def() lines\n")
        self.assertEqual(self.run_check(), (0, ""))
        code, out = self.run_check("-v")
        self.assertEqual(code, 0)
        write(self.root, "scripts/check-function-length.allow", "materials/table.cpp gone  # stale\n")
        code, out = self.run_check("-v")
        self.assertEqual(code, 1)
        self.assertIn("build is 40 lines", out)
        self.assertIn("allowlist entry matched nothing: materials/table.cpp gone", out)


if __name__ == "__main__":
    unittest.main()
