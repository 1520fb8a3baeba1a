"""bench.common — the pieces every benchmark module shares.

A benchmark module builds an argparse parser (make_parser, add_* helpers),
parses it with parse_args (which also maps the old scripts' environment
variables onto flags and records the command line that reproduces the run),
moves to the repository root (chdir_root: pmc and the recorded commands use
paths relative to it), finds pmc (find_pmc), then runs pmc in round-robin
rounds (round_order, run, run_pmc, LoadSampler), reduces the rounds to
medians and per-round ratios (median, median_range, round_ratios), formats
markdown (md_table) and rewrites its own section of docs/BENCHMARKS.md
(write_section; replace_section is the pure text operation under it).

Nothing here knows about a particular benchmark; scripts/bench/tests/test_common.py checks
the reductions, the table format and the section replacement.
"""
import argparse
import datetime
import json
import os
import platform
import resource
import shlex
import statistics
import subprocess
import sys
import textwrap
import time
from dataclasses import dataclass

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHARED_SCENES = "../shared/scenes"  # relative to ROOT, as the recorded commands show it
DEFAULT_DOC = "docs/BENCHMARKS.md"
DOC_INTRO = """# Benchmarks

Numbers in this file come from the benchmark modules in `scripts/bench/`
(`scripts/python -m bench.<name>`; `scripts/bench-<name>` runs the same), each
of which rewrites its own section. Every number is a median over several runs;
each section names the command that produced it, the date and the machine
(cores, CPU model, OpenCL device).
"""


# ---- command line ------------------------------------------------------------------
def make_parser(module, doc, legacy=None):
    """An argparse parser for `scripts/python -m bench.<module>`; `doc` (the
    module's docstring) is its description; `legacy` maps the old script's
    environment variables to flags and is listed in the epilog."""
    epilog = ("Relative paths, also those given here, are relative to the repository root, where the\n"
              "benchmarks run pmc (as the commands they record show).")
    if legacy:
        epilog += "\n\n" + textwrap.fill(
            "The old scripts' environment variables still work as defaults for their flags (a flag on the "
            "command line wins; the recorded command shows the flag): " +
            ", ".join(f"{var} ({flag})" for var, flag in legacy.items()) + ".", width=95)
    return argparse.ArgumentParser(prog=f"scripts/python -m bench.{module}", description=doc, epilog=epilog,
                                   formatter_class=argparse.RawDescriptionHelpFormatter, allow_abbrev=False)


def positive_int(text):
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got '{text}'")
    if v < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {v}")
    return v


def add_pmc(p):
    p.add_argument("--pmc", metavar="PATH",
                   help="the pmc binary to run (default build/pmc; scripts/setup builds it first)")


def add_runs(p, default, flag="--runs", what="timed rounds; every configuration once per round (medians)"):
    p.add_argument(flag, type=positive_int, default=default, metavar="N", help=f"{what} (default {default})")


def spp_list(text):
    """An argparse type: comma-separated sample counts, each at least 1, as a
    sorted list without repeats."""
    try:
        v = [int(x) for x in text.split(",") if x]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected whole numbers separated by commas, got '{text}'")
    if not v or min(v) < 1:
        raise argparse.ArgumentTypeError(f"sample counts must be at least 1, got '{text}'")
    return sorted(set(v))


def add_image_size(p, width, height, spp):
    """--width, --height and --spp of the renders a benchmark times."""
    p.add_argument("--width", type=positive_int, default=width, metavar="W", help=f"image width (default {width})")
    p.add_argument("--height", type=positive_int, default=height, metavar="H", help=f"image height (default {height})")
    p.add_argument("--spp", type=positive_int, default=spp, metavar="N", help=f"samples per pixel (default {spp})")


def add_out_dir(p, default, what="images, stats and logs of the last run"):
    p.add_argument("--out-dir", default=default, metavar="DIR", help=f"{what} (default {default})")


def add_doc(p):
    p.add_argument("--doc", default=DEFAULT_DOC, metavar="FILE",
                   help=f"the markdown file whose section this rewrites (default {DEFAULT_DOC}; - prints only)")


def parse_args(parser, module, legacy=None, argv=None):
    """Parses argv (default sys.argv[1:]). Each legacy environment variable
    that is set, and whose flag is not on the command line, becomes that flag
    (a flag that takes no value is added when the variable is 1). Returns the
    namespace with .command: the command line that reproduces the run."""
    argv = list(sys.argv[1:] if argv is None else argv)
    given = {a.split("=", 1)[0] for a in argv if a.startswith("--")}
    for var, flag in (legacy or {}).items():
        value = os.environ.get(var, "")
        if not value or flag in given:
            continue
        action = next(a for a in parser._actions if flag in a.option_strings)
        if action.nargs == 0:
            if value == "1":
                argv.append(flag)
        else:
            argv += [flag, value]
    args = parser.parse_args(argv)
    niceness = os.nice(0)
    args.command = ((f"nice -n {niceness} " if niceness else "") +
                    shlex.join(["scripts/python", "-m", f"bench.{module}", *argv]))
    return args


def chdir_root():
    os.chdir(ROOT)


def find_pmc(pmc, prog, setup="if-missing", extra_packages=()):
    """The pmc binary to benchmark: `pmc` when given, else build/pmc, running
    scripts/setup first when it is missing (setup="if-missing") or always, so
    that the binary matches the tree (setup="always")."""
    if pmc is None:
        pmc = "build/pmc"
        if setup == "always" or not os.access(pmc, os.X_OK):
            env = dict(os.environ)
            if extra_packages:
                env["PMC_EXTRA_PACKAGES"] = " ".join([*extra_packages, env.get("PMC_EXTRA_PACKAGES", "")]).strip()
            if subprocess.run(["scripts/setup"], env=env).returncode != 0:
                sys.exit(f"{prog}: scripts/setup failed")
    if not os.access(pmc, os.X_OK):
        sys.exit(f"{prog}: {pmc} is not an executable (run scripts/setup or pass --pmc)")
    newer = newest_source_after(pmc)
    if newer:
        print(f"{prog}: warning: {pmc} is older than {newer}: it may not be this checkout's code "
              "(rebuild it, e.g. scripts/setup, or pass --pmc)", file=sys.stderr, flush=True)
    return pmc


SOURCE_DIRS = ("app", "core", "gpu", "materials")  # what a pmc binary is built from (its kernels included)


def newest_source_after(binary, root=None):
    """A source file under SOURCE_DIRS of `root` (default the checkout) modified after `binary`
    was written, the newest one; None when there is none (or the binary cannot be read)."""
    try:
        built = os.path.getmtime(binary)
    except OSError:
        return None
    newest, when = None, built
    for top in SOURCE_DIRS:
        for folder, _, files in os.walk(os.path.join(root or ROOT, top)):
            for name in files:
                path = os.path.join(folder, name)
                try:
                    t = os.path.getmtime(path)
                except OSError:
                    continue
                if t > when:
                    newest, when = path, t
    return os.path.relpath(newest, root or ROOT) if newest else None


# ---- the machine -------------------------------------------------------------------
def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def machine(device):
    """"N cores (CPU model), OpenCL device: DEVICE"."""
    return f"{os.cpu_count()} cores ({cpu_model()}), OpenCL device: {device}"


def loadavg():
    """The 1-minute load average, NaN where /proc/loadavg cannot be read."""
    try:
        with open("/proc/loadavg") as f:
            return float(f.read().split()[0])
    except (OSError, ValueError, IndexError):
        return float("nan")


class LoadSampler:
    """The 1-minute load average before the runs and after each of them."""

    def __init__(self):
        self.loads = [loadavg()]

    def sample(self):
        self.loads.append(loadavg())

    def before(self):
        return self.loads[0]

    def median(self):
        return statistics.median(self.loads)

    def max(self):
        return max(self.loads)

    def note(self):
        return (f"1-minute load average {self.before():.1f} before the runs, "
                f"{self.median():.1f} median and {self.max():.1f} max between them")


def utc_now():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")


def git_rev(unknown="unknown", ignore=()):
    """The checkout's short commit, "with uncommitted changes" when tracked
    files differ from it (pathspecs in `ignore` do not count)."""
    try:
        rev = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                             check=True).stdout.strip()
        spec = ["--", ".", *(f":!{p}" for p in ignore)] if ignore else []
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", *spec],
                               capture_output=True, text=True, check=True).stdout.strip()
        return rev + (" with uncommitted changes" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return unknown


# ---- rounds and their reduction ----------------------------------------------------
def round_order(configs, r, style="rotate"):
    """The order of `configs` in round r (from 0). "rotate": start one later
    each round, so none always runs first; "reverse": every other round
    backwards, so a pair alternates which goes first."""
    configs = list(configs)
    if style == "rotate":
        k = r % len(configs) if configs else 0
        return configs[k:] + configs[:k]
    if style == "reverse":
        return configs if r % 2 == 0 else configs[::-1]
    raise ValueError(f"round_order: unknown style '{style}'")


def median(xs):
    """The median, NaN for no values."""
    xs = list(xs)
    return statistics.median(xs) if xs else float("nan")


def median_range(xs):
    """(median, lowest, highest)."""
    xs = list(xs)
    return median(xs), min(xs), max(xs)


def round_ratios(num, den):
    """num[i] / den[i] per round: two configurations of the same round ran
    close together and share the machine's load, so their ratio is steadier
    than a ratio of medians."""
    num, den = list(num), list(den)
    if len(num) != len(den):
        raise ValueError(f"round_ratios: {len(num)} rounds against {len(den)}")
    return [a / b for a, b in zip(num, den)]


def rounds_text(n):
    """"1 round", "3 rounds"."""
    return f"{n} round" + ("" if n == 1 else "s")


# ---- markdown ----------------------------------------------------------------------
def md_table(header, rows):
    """A GitHub markdown table: a header row, a |---| row, one row per list."""
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(out)


def _title_line(text, title):
    """Where the line that is exactly `title` starts in text, or -1."""
    pos = 0
    while True:
        i = text.find(title, pos)
        if i < 0:
            return -1
        end = i + len(title)
        if (i == 0 or text[i - 1] == "\n") and (end == len(text) or text[end] == "\n"):
            return i
        pos = i + 1


def replace_section(text, title, section, old_titles=()):
    """`text` with the "## " section headed `title` (or, failing that, one of
    `old_titles`) replaced by `section`, which starts with its own title line;
    the section runs up to the next "## " line or the end. Without such a
    section, `section` is appended after one blank line. Other sections are
    kept byte for byte, with one blank line before the next one."""
    for t in (title, *old_titles):
        start = _title_line(text, t)
        if start >= 0:
            break
    else:
        return text.rstrip("\n") + "\n\n" + section.rstrip("\n") + "\n"
    nxt = text.find("\n## ", start + len(t))
    rest = text[nxt + 1:] if nxt >= 0 else ""
    return text[:start] + section.rstrip("\n") + "\n" + ("\n" + rest if rest else "")


def write_section(doc, title, section, prog, old_titles=()):
    """Rewrites `title`'s section of the markdown file `doc` (created with
    DOC_INTRO when missing); doc "-" writes nothing. The file is read right
    before writing (other modules own other sections) and replaced
    atomically."""
    if doc == "-":
        return
    text = read_text(doc) if os.path.exists(doc) else DOC_INTRO
    text = replace_section(text, title, section, old_titles)
    os.makedirs(os.path.dirname(doc) or ".", exist_ok=True)
    with open(doc + ".tmp", "w") as f:
        f.write(text)
    os.replace(doc + ".tmp", doc)
    print(f"{prog}: updated {doc}", flush=True)


# ---- running pmc -------------------------------------------------------------------
class RunFailed(Exception):
    """A command exited non-zero; str() says how and where its log is, .tail
    holds the last lines of its output."""

    def __init__(self, message, tail=""):
        super().__init__(message)
        self.tail = tail


@dataclass
class Finished:
    output: str  # stdout and stderr together
    wall: float  # seconds
    cpu: float   # user + system seconds of the command and its children


def run(cmd, log, what=None, append=False):
    """Runs cmd (stdin closed, stdout and stderr together), timing its wall
    clock and CPU time. The log gets the command line and the output: a file
    of its own, or with append=True "$ command" and the output added to a log
    of many commands. Raises RunFailed on a non-zero exit."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    line = " ".join(str(c) for c in cmd)
    with open(log, "a" if append else "w") as f:
        f.write(("$ " if append else "") + line + "\n" + p.stdout)
    if p.returncode != 0:
        why = f"signal {-p.returncode}" if p.returncode < 0 else f"exit status {p.returncode}"
        tail = "\n".join(p.stdout.strip().split("\n")[-5:])
        raise RunFailed((f"{what}: " if what else "") + f"{why} (log: {log})", tail)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return Finished(p.stdout, wall, cpu)


def read_text(path):
    with open(path) as f:
        return f.read()


def read_json(path):
    with open(path) as f:
        return json.load(f)


def run_pmc(cmd, stats, log, what=None, append=False):
    """Runs a pmc command that writes --stats `stats`; returns (the stats
    JSON, Finished)."""
    done = run(cmd, log, what, append)
    return read_json(stats), done


def size_args(w, h, spp):
    """pmc's image size, samples and --quiet, in the order the recorded commands show them."""
    return ["--width", str(w), "--height", str(h), "--spp", str(spp), "--quiet"]


def plot_path(args, name):
    """Where a section's plot goes: plots/NAME beside the --doc file (the section links it as
    plots/NAME), or OUT_DIR/NAME when --doc - only prints, so a run for another file or none never
    touches docs/plots."""
    if args.doc == "-":
        return os.path.join(args.out_dir, name)
    return os.path.join(os.path.dirname(args.doc), "plots", name)


def add_report_only(p):
    p.add_argument("--report-only", action="store_true",
                   help="render nothing: rewrite the table and the section from OUT_DIR/results.json of the last run")


def measure_and_report(args, prog, section_title, measure, report, inputs=()):
    """The main of a benchmark that measures once and reports: with
    --report-only the saved OUT_DIR/results.json of the last run, else
    measure(args) after finding pmc and checking the input files exist (the
    results saved, and read back so both paths report the same JSON shapes);
    then prints report(data)'s text and writes its section to --doc."""
    chdir_root()
    saved = os.path.join(args.out_dir, "results.json")
    if args.report_only:
        try:
            data = read_json(saved)
        except (OSError, ValueError) as e:
            sys.exit(f"{prog}: --report-only needs {saved} from an earlier run: {e}")
    else:
        args.pmc = find_pmc(args.pmc, prog)
        for path in inputs:
            if not os.path.isfile(path):
                sys.exit(f"{prog}: {path} not found (../shared beside the repository?)")
        os.makedirs(args.out_dir, exist_ok=True)
        data = measure(args)
        with open(saved, "w") as f:
            json.dump(data, f, indent=1)
        data = json.loads(json.dumps(data))  # string keys, as a saved run has
    section, printed = report(data)
    print(printed)
    write_section(args.doc, section_title, section, prog)
