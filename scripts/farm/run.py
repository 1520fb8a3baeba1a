"""The farm job: chunks submitted to Dask, a progress bar, `pmc merge`, a summary.

run_farm(options) is what `scripts/farm-render` runs (farm/__main__.py parses
the command line into a FarmOptions). Without a scheduler address it starts a
LocalCluster of worker processes on this machine, listening on 127.0.0.1
only (scheduler, workers, nannies and their HTTP servers); with one it
connects a Client to the user's cluster.
Each chunk is a task (farm/chunk.py) submitted with Dask's `retries=`: a pmc
failure is retried on another attempt, and when a worker is lost its running
chunks are rescheduled by the scheduler (up to its allowed-failures). Every
wait is bounded: the client connection, each pmc process (--chunk-timeout)
and the whole job (--timeout). The parts go to a folder every worker can
write (on a cluster: a shared path); `pmc merge` adds them at the end.
Chunks plan their cache points with one device calibration: unless
PMC_CACHE_COSTS is set, every chunk's pmc keeps it in the parts folder
(chunk_environment), so the first chunk on a device measures it and the
others read it; with each machine's own calibration, parts from machines
that measured differently would plan different programs, which pmc merge
refuses (their scene hashes differ).
With --denoise every chunk also renders the albedo and normal passes, and
`pmc denoise` runs on the merged frame: OUT.exr/png denoised beside
OUT.noisy.exr/png (parts cannot be denoised one by one: the denoiser needs
the whole frame's samples and neighbours).
"""
import dataclasses
import json
import logging
import math
import os
import shutil
import statistics
import subprocess
import sys
import time
import uuid

from farm import chunk as chunk_module
from farm.split import make_chunks

# Flags the farm sets itself on every chunk.
RESERVED = ("-o", "--samples", "--crop", "--stats", "--hitmap", "--quiet")


class FarmError(Exception):
    """Bad input or a failed job, with a message for the user."""

    def __init__(self, message, exit_code=2):
        super().__init__(message)
        self.exit_code = exit_code


@dataclasses.dataclass
class FarmOptions:
    scene: str
    output: str
    chunks: int
    render_args: list = dataclasses.field(default_factory=list)
    split: str = "samples"
    scheduler: str = None
    workers: int = 2
    pmc: str = None
    parts_dir: str = None
    keep_parts: bool = False
    retries: int = 2
    chunk_timeout: float = 3600.0
    timeout: float = None
    connect_timeout: float = 30.0
    baseline: bool = False
    denoise: bool = False
    summary: str = None
    stats: str = None
    quiet: bool = False
    started_dir: str = None  # tests: where chunks note the worker process that started them
    cluster: object = None   # tests: an existing cluster (LocalCluster) to submit to


def default_pmc():
    env = os.environ.get("PMC")
    if env:
        return env
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.normpath(os.path.join(here, "..", "..", "build", "pmc"))


def pmc_defaults(pmc):
    """pmc render's defaults by flag ({"--spp": 16, ...}), as `pmc info --settings` lists them."""
    try:
        listed = subprocess.run([pmc, "info", "--settings"], capture_output=True, text=True, check=True,
                                timeout=60).stdout
        return {s["flag"]: s["default"] for s in json.loads(listed)}
    except (OSError, subprocess.SubprocessError, ValueError, KeyError, TypeError) as e:
        raise FarmError(f"--pmc: '{pmc}' did not list its settings ('pmc info --settings': {e})")


DENOISE_PASSES = ("albedo", "normal")


def with_denoise_passes(args):
    """pmc render arguments whose --aov lists the passes the denoiser reads
    (added to the user's list, or a new --aov albedo,normal)."""
    out, found = [], False
    i = 0
    while i < len(args):
        a = args[i]
        value = None
        if a == "--aov" and i + 1 < len(args):
            value, i = args[i + 1], i + 1
        elif a.startswith("--aov="):
            value = a.split("=", 1)[1]
        if value is None:
            out.append(a)
        else:
            found = True
            names = [v for v in value.split(",") if v]
            if "all" not in names:
                names += [p for p in DENOISE_PASSES if p not in names]
            out += ["--aov", ",".join(names)]
        i += 1
    return out if found else out + ["--aov", ",".join(DENOISE_PASSES)]


def chunk_environment(parts_dir, environ=None):
    """The variables every chunk's pmc gets: PMC_CACHE_COSTS in the parts
    folder (shared by the chunks), unless the user set it."""
    environ = os.environ if environ is None else environ
    if environ.get("PMC_CACHE_COSTS"):
        return {}
    return {"PMC_CACHE_COSTS": os.path.join(parts_dir, "device-costs")}


def check_denoiser(pmc):
    """FarmError (bad input) unless pmc can load Open Image Denoise, before any chunk renders."""
    try:
        proc = subprocess.run([pmc, "info", "--denoiser"], capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.SubprocessError) as e:
        raise FarmError(f"--denoise: could not ask pmc whether Open Image Denoise loads: {e}")
    if proc.returncode != 0:
        said = (proc.stdout.strip() or proc.stderr.strip()).replace("Open Image Denoise: ", "")
        raise FarmError(f"--denoise: Open Image Denoise {said}")


def render_setting(args, flag, defaults):
    """The value of `flag` among pmc render arguments (last one wins), else pmc's default."""
    value = defaults[flag]
    for i, a in enumerate(args):
        if a == flag and i + 1 < len(args):
            value = args[i + 1]
        elif a.startswith(flag + "="):
            value = a.split("=", 1)[1]
    try:
        value = int(value)
    except ValueError:
        raise FarmError(f"{flag}: expected a whole number, got {value!r}")
    if value < 1:
        raise FarmError(f"{flag}: must be at least 1, got {value}")
    return value


def adaptive_requested(args):
    """Whether pmc render arguments turn adaptive sampling on (a nonzero --adaptive-threshold, last one wins)."""
    value = "0"
    for i, a in enumerate(args):
        if a == "--adaptive-threshold" and i + 1 < len(args):
            value = args[i + 1]
        elif a.startswith("--adaptive-threshold="):
            value = a.split("=", 1)[1]
    try:
        return float(value) != 0.0
    except ValueError:
        return True  # pmc refuses the value itself, naming it


def check_options(o):
    if not os.path.isfile(o.scene):
        raise FarmError(f"{o.scene}: no such scene file")
    if not o.output.lower().endswith(".exr"):
        raise FarmError(f"-o: '{o.output}' must end in .exr")
    out_dir = os.path.dirname(os.path.abspath(o.output))
    if not os.path.isdir(out_dir):
        raise FarmError(f"-o: folder '{out_dir}' does not exist")
    if not (os.path.isfile(o.pmc) and os.access(o.pmc, os.X_OK)):
        raise FarmError(f"--pmc: '{o.pmc}' is not an executable pmc (build it, or pass --pmc / $PMC)")
    for a in o.render_args:
        if a.split("=", 1)[0] in RESERVED:
            raise FarmError(f"{a}: set by the farm for each chunk; leave it out of the render options")
    if o.chunks < 1:
        raise FarmError(f"--chunks: must be at least 1, got {o.chunks}")
    if o.workers < 1:
        raise FarmError(f"--workers: must be at least 1, got {o.workers}")
    if o.retries < 0:
        raise FarmError(f"--retries: must not be negative, got {o.retries}")
    if o.split == "samples" and o.chunks > 1 and adaptive_requested(o.render_args):
        raise FarmError("--adaptive-threshold: a pixel's error decides its next samples, so its samples "
                        "cannot be split over chunks; use --split tiles")
    if o.scheduler and o.cluster is None and not o.scheduler.startswith(("tcp://", "tls://", "ucx://")):
        raise FarmError(f"--scheduler: expected tcp://HOST:PORT, got {o.scheduler!r}")


class ProgressBar:
    def __init__(self, total, quiet):
        self.total, self.quiet, self.t0 = total, quiet, time.monotonic()
        self.tty = sys.stderr.isatty()

    def update(self, done, note=""):
        if self.quiet:
            return
        width = 30
        filled = width * done // self.total
        line = "farm: [%s%s] %d/%d chunks, %.1f s%s" % (
            "#" * filled, "." * (width - filled), done, self.total, time.monotonic() - self.t0, note)
        sys.stderr.write(("\r" + line) if self.tty else line + "\n")
        if self.tty and done == self.total:
            sys.stderr.write("\n")
        sys.stderr.flush()


def _start_client(o, stack):
    import distributed

    if o.cluster is not None:
        return stack.enter_context(distributed.Client(o.cluster, timeout=o.connect_timeout))
    if o.scheduler:
        try:
            return stack.enter_context(distributed.Client(o.scheduler, timeout=o.connect_timeout))
        except (OSError, TimeoutError) as e:
            raise FarmError(f"--scheduler {o.scheduler}: cannot connect within {o.connect_timeout:g} s ({e})", 1)
    cluster = stack.enter_context(distributed.LocalCluster(
        n_workers=o.workers, threads_per_worker=1, processes=True, host="127.0.0.1",
        # Every listening socket on loopback: the scheduler's and workers' HTTP
        # servers (health, metrics; started even without a dashboard) default to
        # all interfaces, so they are pinned to 127.0.0.1 as well.
        dashboard_address="127.0.0.1:0", worker_dashboard_address="127.0.0.1:0",
        silence_logs=logging.ERROR))
    return stack.enter_context(distributed.Client(cluster, timeout=o.connect_timeout))


def run_farm(o):
    """Renders, merges and returns the summary dict (see print_summary)."""
    import contextlib

    import cloudpickle
    import distributed

    o.pmc = os.path.abspath(o.pmc or default_pmc())
    check_options(o)
    if o.denoise:
        check_denoiser(o.pmc)
    o.scene = os.path.abspath(o.scene)
    output = os.path.abspath(o.output)
    defaults = pmc_defaults(o.pmc)
    spp = render_setting(o.render_args, "--spp", defaults)
    width = render_setting(o.render_args, "--width", defaults)
    height = render_setting(o.render_args, "--height", defaults)
    try:
        chunks = make_chunks(o.split, o.chunks, spp, width, height)
    except ValueError as e:
        raise FarmError(str(e))
    render_args = with_denoise_passes(o.render_args) if o.denoise else list(o.render_args)
    local = o.scheduler is None and o.cluster is None
    if local and "--threads" not in render_args:  # the local workers share this machine's cores
        render_args += ["--threads", str(max(1, (os.cpu_count() or 1) // o.workers))]
    token = uuid.uuid4().hex[:8]
    parts_dir = os.path.abspath(o.parts_dir or (os.path.splitext(output)[0] + ".parts"))
    os.makedirs(parts_dir, exist_ok=True)
    for i, c in enumerate(chunks):
        c["index"] = i
        c["part"] = os.path.join(parts_dir, "part-%03d.exr" % i)
        c["stats"] = os.path.join(parts_dir, "part-%03d.json" % i)

    # Workers need pmc and the scene, not this package: the task function travels by value.
    cloudpickle.register_pickle_by_value(chunk_module)
    results = []
    with contextlib.ExitStack() as stack:
        t_cluster = time.monotonic()
        client = _start_client(o, stack)
        cluster_seconds = time.monotonic() - t_cluster
        workers = len(client.scheduler_info().get("workers", {}))
        bar = ProgressBar(len(chunks), o.quiet)
        t0 = time.monotonic()
        futures = [client.submit(chunk_module.render_chunk, o.pmc, o.scene, c["part"], c["stats"],
                                 {k: c[k] for k in ("index", "samples", "crop")}, render_args,
                                 o.chunk_timeout, o.started_dir, chunk_environment(parts_dir),
                                 key="pmc-chunk-%s-%03d" % (token, c["index"]),
                                 retries=o.retries, pure=False)
                   for c in chunks]
        bar.update(0)
        deadline = None if o.timeout is None else time.monotonic() + o.timeout
        pending = set(futures)
        try:
            while pending:
                left = None if deadline is None else max(0.0, deadline - time.monotonic())
                try:
                    done, pending = distributed.wait(pending, timeout=left, return_when="FIRST_COMPLETED")
                except (distributed.TimeoutError, TimeoutError):
                    raise FarmError(f"farm: the job did not finish within --timeout {o.timeout:g} s "
                                    f"({len(results)} of {len(chunks)} chunks done)", 1)
                for future in done:
                    try:
                        results.append(future.result())
                    except Exception as e:  # failed after its retries, or its worker died too often
                        raise FarmError(f"farm: {e}", 1)
                bar.update(len(results))
        finally:
            client.cancel(futures)
        wall = time.monotonic() - t0

    t_merge = time.monotonic()
    merged = os.path.join(parts_dir, "merged.exr") if o.denoise else output
    merge = [o.pmc, "merge", *[c["part"] for c in chunks], "-o", merged]
    if o.stats:
        merge += ["--stats", o.stats]
    proc = subprocess.run(merge, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                          timeout=o.chunk_timeout)
    if proc.returncode != 0:
        raise FarmError(f"farm: pmc merge failed: {proc.stderr.strip()}", 1)
    merge_seconds = time.monotonic() - t_merge
    denoise_seconds = None
    if o.denoise:  # OUT.exr/png denoised, OUT.noisy.exr/png the merged frame
        t_denoise = time.monotonic()
        proc = subprocess.run([o.pmc, "denoise", merged, "-o", output], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True, timeout=o.chunk_timeout)
        if proc.returncode != 0:
            raise FarmError(f"farm: pmc denoise failed: {proc.stderr.strip()}", 1)
        denoise_seconds = time.monotonic() - t_denoise

    baseline = None
    if o.baseline:  # one process for the whole frame, for a measured speedup
        base_out = os.path.join(parts_dir, "baseline.exr")
        t_base = time.monotonic()
        b = subprocess.run([o.pmc, "render", o.scene, "-o", base_out, "--quiet", *o.render_args],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=o.chunk_timeout)
        if b.returncode != 0:
            raise FarmError(f"farm: the baseline render failed: {b.stderr.strip()}", 1)
        baseline = time.monotonic() - t_base

    results.sort(key=lambda r: r["index"])
    summary = summarise(chunks, results, wall, workers, cluster_seconds, merge_seconds, baseline, o)
    summary["denoise_seconds"] = denoise_seconds
    if not o.keep_parts:
        shutil.rmtree(parts_dir, ignore_errors=True)
    if o.summary:
        tmp = o.summary + ".tmp"
        with open(tmp, "w") as f:
            json.dump(summary, f, indent=2)
        os.replace(tmp, o.summary)
    return summary


def summarise(chunks, results, wall, workers, cluster_seconds, merge_seconds, baseline, o):
    seconds = [r["seconds"] for r in results]
    setup = [max(0.0, r["seconds"] - r["render_seconds"]) for r in results]
    # One process would pay the setup once and render every sample: the chunks'
    # render time summed plus one chunk's setup (the median).
    one_process = statistics.median(setup) + sum(r["render_seconds"] for r in results)
    return {
        "chunks": len(chunks), "split": o.split, "workers": workers,
        "scheduler": o.scheduler or ("given cluster" if o.cluster is not None else "LocalCluster on 127.0.0.1"),
        "wall_seconds": wall, "cluster_start_seconds": cluster_seconds, "merge_seconds": merge_seconds,
        "chunk_seconds": {"min": min(seconds), "median": statistics.median(seconds), "max": max(seconds)},
        "chunk_setup_seconds_median": statistics.median(setup),
        "one_process_seconds_estimate": one_process,
        "speedup_estimate": one_process / wall if wall > 0 else math.nan,
        "one_process_seconds_measured": baseline,
        "speedup_measured": baseline / wall if baseline and wall > 0 else None,
        "per_chunk": [{"index": r["index"], "samples": list(chunks[r["index"]]["samples"]),
                       "crop": chunks[r["index"]]["crop"], "seconds": r["seconds"],
                       "render_seconds": r["render_seconds"], "host": r["host"]} for r in results],
        "output": os.path.abspath(o.output),
    }


def print_summary(s, out=sys.stderr):
    c = s["chunk_seconds"]
    print(f"farm: {s['chunks']} chunks ({s['split']}) on {s['workers']} workers ({s['scheduler']}): "
          f"{s['wall_seconds']:.1f} s wall", file=out)
    print(f"farm: seconds per chunk: min {c['min']:.2f}, median {c['median']:.2f}, max {c['max']:.2f} "
          f"(setup per chunk, median: {s['chunk_setup_seconds_median']:.2f} s: process start, scene, BVH, kernels)",
          file=out)
    print(f"farm: speedup over one process: {s['speedup_estimate']:.2f}x estimated "
          f"(one process ~ {s['one_process_seconds_estimate']:.1f} s = one chunk's setup + all chunks' render time)"
          + (f", {s['speedup_measured']:.2f}x measured ({s['one_process_seconds_measured']:.1f} s)"
             if s["speedup_measured"] else ""), file=out)
    if s.get("denoise_seconds") is None:
        print(f"farm: merged in {s['merge_seconds']:.2f} s -> {s['output']}", file=out)
    else:
        noisy = os.path.splitext(s["output"])[0] + ".noisy.exr"
        print(f"farm: merged in {s['merge_seconds']:.2f} s -> {noisy}; denoised in {s['denoise_seconds']:.2f} s "
              f"-> {s['output']}", file=out)
