"""One chunk of a frame: one `pmc render` process, run inside a Dask task.

render_chunk() only uses the standard library and is shipped to workers by
value (cloudpickle), so a worker needs pmc and the scene on a shared path,
not this package. The pmc process dies with the worker (PR_SET_PDEATHSIG on
Linux): when Dask loses a worker it reschedules the chunk elsewhere, and no
orphan keeps writing the part. The part is written atomically by pmc itself
(temporary + rename), so a retried chunk simply writes it again.
"""
import ctypes
import json
import os
import signal
import socket
import subprocess
import sys
import time


def _die_with_parent():
    try:
        libc = ctypes.CDLL("libc.so.6", use_errno=True)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except OSError:
        pass


def render_chunk(pmc, scene, part, stats, chunk, render_args, timeout, started_dir=None, env=None):
    """Renders `chunk` into `part` (EXR) and `stats` (JSON); returns a summary dict.
    `env`: variables set for pmc on top of the worker's environment.
    Raises RuntimeError (with pmc's message) when pmc fails, so Dask's retries apply."""
    cmd = [pmc, "render", scene, "-o", part, "--stats", stats, "--quiet",
           "--samples", "%d:%d" % tuple(chunk["samples"])]
    if chunk.get("crop"):
        cmd += ["--crop", ",".join(str(v) for v in chunk["crop"])]
    cmd += list(render_args)
    if started_dir:  # for tests and progress: which worker process runs which chunk
        with open(os.path.join(started_dir, "chunk-%d.started" % chunk["index"]), "a") as f:
            f.write("%d\n" % os.getpid())
    t0 = time.monotonic()
    try:
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                              timeout=timeout, preexec_fn=_die_with_parent if sys.platform == "linux" else None,
                              env=dict(os.environ, **env) if env else None)
    except subprocess.TimeoutExpired:
        raise RuntimeError("chunk %d: pmc render did not finish within %s s" % (chunk["index"], timeout))
    seconds = time.monotonic() - t0
    if proc.returncode != 0:
        raise RuntimeError("chunk %d: pmc render exited with %d: %s" %
                           (chunk["index"], proc.returncode, proc.stderr.strip()[-2000:]))
    with open(stats) as f:
        st = json.load(f)
    return {"index": chunk["index"], "seconds": seconds, "render_seconds": st.get("render_seconds", 0.0),
            "kernel_build_seconds": st.get("kernel_build_seconds", 0.0),
            "kernel_warmup_seconds": st.get("kernel_warmup_seconds", 0.0),
            "host": socket.gethostname(), "pid": os.getpid()}
