"""scripts/farm-render SCENE.obj -o OUT.exr --chunks N [options] [pmc render options]

The command line of the farm (farm/run.py does the work). Options this parser
does not know are pmc render options, passed to every chunk (--spp, --width,
--height ... decide the split). Exit codes: 0 done, 1 the job failed (a chunk
after its retries, the merge, a timeout), 2 bad input.
"""
import argparse
import sys

from farm.run import FarmError, FarmOptions, print_summary, run_farm


def parse(argv):
    p = argparse.ArgumentParser(
        prog="farm-render",
        usage="farm-render SCENE.obj -o OUT.exr --chunks N [options] [pmc render options]",
        description="Renders one pmc frame in N chunks on Dask distributed (pmc render --samples A:B or "
                    "--crop per chunk), merges them with pmc merge and prints a summary. Without --scheduler "
                    "a LocalCluster of worker processes runs on this machine (127.0.0.1 only). Options not "
                    "listed here are pmc render options (--spp, --width, --height, --cache ...), given to "
                    "every chunk.")
    p.add_argument("scene", metavar="SCENE.obj")
    p.add_argument("-o", dest="output", metavar="OUT.exr", required=True,
                   help="merged image (EXR; the PNG goes beside it)")
    p.add_argument("--chunks", type=int, required=True, metavar="N", help="number of chunks (Dask tasks)")
    p.add_argument("--split", choices=["samples", "tiles"], default="samples",
                   help="samples: N sample ranges of the whole frame (default); tiles: an N-tile grid, all samples")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help="submit to this Dask scheduler (workers need pmc, the scene and --parts-dir on shared "
                        "paths); default: a LocalCluster on this machine")
    p.add_argument("--workers", type=int, default=2, metavar="W",
                   help="LocalCluster worker processes (default 2); each pmc gets cores/W threads unless "
                        "--threads is given")
    p.add_argument("--pmc", metavar="PATH", help="the pmc binary (default $PMC, else build/pmc of this checkout)")
    p.add_argument("--parts-dir", metavar="DIR", help="where chunks write their parts (default OUT.parts/ beside "
                                                     "OUT; removed after the merge unless --keep-parts)")
    p.add_argument("--keep-parts", action="store_true", help="keep the part EXRs and their stats")
    p.add_argument("--retries", type=int, default=2, metavar="R",
                   help="Dask retries of a failed chunk (default 2; chunks of lost workers are rescheduled "
                        "by the scheduler)")
    p.add_argument("--chunk-timeout", type=float, default=3600.0, metavar="S",
                   help="seconds one pmc process may run (default 3600)")
    p.add_argument("--timeout", type=float, metavar="S", help="seconds the whole job may take (default: none "
                                                             "beyond the chunk timeouts and retries)")
    p.add_argument("--baseline", action="store_true",
                   help="also render the frame in one process and report the measured speedup")
    p.add_argument("--denoise", action="store_true",
                   help="render the albedo and normal passes too (added to any --aov) and denoise the merged "
                        "frame with Open Image Denoise (pmc denoise): OUT.exr/png denoised, OUT.noisy.exr/png "
                        "as merged")
    p.add_argument("--stats", metavar="OUT.json", help="pmc merge's merged statistics")
    p.add_argument("--summary", metavar="FILE.json", help="the farm summary as JSON")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--chunk-log", metavar="DIR",
                   help="each chunk appends its worker process id to DIR/chunk-K.started when it starts "
                        "(monitoring; a chunk started twice was rescheduled or retried)")
    args, render_args = p.parse_known_args(argv)
    if any(a == "--" for a in render_args):
        render_args = [a for a in render_args if a != "--"]
    return FarmOptions(scene=args.scene, output=args.output, chunks=args.chunks, render_args=render_args,
                       split=args.split, scheduler=args.scheduler, workers=args.workers, pmc=args.pmc,
                       parts_dir=args.parts_dir, keep_parts=args.keep_parts, retries=args.retries,
                       chunk_timeout=args.chunk_timeout, timeout=args.timeout, baseline=args.baseline,
                       denoise=args.denoise,
                       summary=args.summary, stats=args.stats, quiet=args.quiet,
                       started_dir=args.chunk_log)


def main(argv=None):
    options = parse(sys.argv[1:] if argv is None else argv)
    try:
        summary = run_farm(options)
    except FarmError as e:
        print(f"farm-render: error: {e}", file=sys.stderr)
        return e.exit_code
    print_summary(summary)
    return 0


if __name__ == "__main__":
    sys.exit(main())
