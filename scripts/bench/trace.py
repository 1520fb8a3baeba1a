"""bench.trace — time pmc against Embree's own `pathtracer` tutorial (Debian's
embree-tools) on Sponza, and compare pmc's Embree query styles and chunk
streaming. Prints a table and writes the "Tracing" section of
docs/BENCHMARKS.md.

    scripts/python -m bench.trace                  scripts/setup (build/pmc + embree-tools), then run
    scripts/python -m bench.trace --runs 5         rounds (default 3; medians)
    scripts/python -m bench.trace --pmc build-bench/pmc    this binary, no build (embree-tools is
                                                   still installed when pathtracer is missing)
    scripts/python -m bench.trace --runs 1 --width 160 --height 90 --spp 1 --doc -    a quick look

Every configuration runs once per round and the rounds are interleaved, so
all of them share the machine's noise; each number reported is a median.
"""
import os
import re
import shutil
import subprocess
import sys
import time

from bench import common

PROG = "bench.trace"
SECTION = "## Tracing: pmc vs Embree's pathtracer (scripts/bench-trace)"
LEGACY = {"SCENE": "--scene", "OUTDIR": "--out-dir", "DOC": "--doc", "PMC": "--pmc", "RUNS": "--runs"}
DEPTH = 4
EYE, AT, FOV = (-110, 20, 0), (100, 20, 0), 45
# Configurations besides "pmc" (pmc's defaults: stream, chunk 65536, the one compared with Embree).
MODES = ["single", "stream", "packet16"]
CHUNKS = [65536, 0]


def parse(argv=None):
    p = common.make_parser("trace", __doc__, LEGACY)
    common.add_pmc(p)
    common.add_runs(p, 3)
    p.add_argument("--scene", default=f"{common.SHARED_SCENES}/sponza/sponza.obj",
                   metavar="OBJ", help="the scene (default ../shared/scenes/sponza/sponza.obj; the camera is "
                                       "Sponza's overview)")
    common.add_image_size(p, 640, 360, 16)
    common.add_out_dir(p, "out/bench-trace")
    common.add_doc(p)
    return common.parse_args(p, "trace", LEGACY, argv)


def install_embree_tools():
    print(f"{PROG}: installing embree-tools (Embree's pathtracer)", flush=True)
    sudo = [] if os.geteuid() == 0 else ["sudo"]
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    if (subprocess.run([*sudo, "apt-get", "update", "-qq"], env=env).returncode != 0 or
            subprocess.run([*sudo, "apt-get", "install", "-y", "-qq", "--no-install-recommends", "embree-tools"],
                           env=env).returncode != 0):
        sys.exit(f"{PROG}: installing embree-tools failed")


def csv(v):
    return ",".join(str(x) for x in v)


def spaced(v):
    return [str(x) for x in v]


def main(argv=None):
    a = parse(argv)
    common.chdir_root()
    if a.pmc is None:
        PMC = common.find_pmc(None, PROG, setup="always", extra_packages=["embree-tools"])
    else:
        PMC = common.find_pmc(a.pmc, PROG)
        if not shutil.which("pathtracer"):
            install_embree_tools()
    if not shutil.which("pathtracer"):
        sys.exit(f"{PROG}: pathtracer not found (embree-tools)")
    SCENE, RUNS, OUT, W, H, SPP = a.scene, a.runs, a.out_dir, a.width, a.height, a.spp
    if not os.path.isfile(SCENE):
        sys.exit(f"{PROG}: scene {SCENE} not found")
    os.makedirs(OUT, exist_ok=True)

    # pmc keeps decoded textures between runs (core/texture_cache.h): the runs
    # share a folder of their own, which the warm-up fills; "pmc-decode" runs
    # with the cache off, as a first run does.
    TEXTURES = f"{OUT}/texture-cache"

    def pmc_cmd(name, spp=SPP, trace="stream", chunk=65536, textures=TEXTURES):
        return [PMC, "render", SCENE, "-o", f"{OUT}/{name}.exr",
                "--camera-from", csv(EYE), "--camera-at", csv(AT), "--fov", str(FOV),
                "--env", "1,1,1", "--width", str(W), "--height", str(H), "--spp", str(spp),
                "--max-depth", str(DEPTH), "--trace-mode", trace, "--chunk-rays", str(chunk),
                "--texture-cache", textures, "--stats", f"{OUT}/{name}.json", "--quiet"]

    def embree_cmd(spp=SPP):
        # Benchmark mode renders exactly one frame (0 warm-up frames, 1 timed) and
        # reports its time; verbose=2 makes Embree log its BVH build time, which the
        # tutorial runs lazily inside that first frame.
        return ["pathtracer", "-i", SCENE, "--vp", *spaced(EYE), "--vi", *spaced(AT),
                "--fov", str(FOV), "--ambientlight", "1", "1", "1", "--size", str(W), str(H),
                "--spp", str(spp), "--max-path-length", str(DEPTH),
                "--benchmark", "0", "1", "--legacy", "--rtcore", "verbose=2"]

    def run_pmc(name, **kw):
        s, done = common.run_pmc(pmc_cmd(name, **kw), f"{OUT}/{name}.json", f"{OUT}/{name}.log")
        st = s["stage_seconds"]
        setup = {f"setup_{k}": v for k, v in s.get("setup_seconds", {}).items() if isinstance(v, (int, float))}
        for k, v in s.get("setup_seconds", {}).get("background", {}).items():
            setup[f"setup_background_{k}"] = v
        return {"wall": done.wall, "cpu": done.cpu, "render": s["render_seconds"], "rays": s["rays"], **setup,
                "shadow_rays": s["shadow_rays"], "paths": s["paths"], "device": s["device"],
                **{k: st[k] for k in ("camera", "trace", "shadow", "shade", "transfer", "film")}}

    def run_embree(name, **kw):
        done = common.run(embree_cmd(**kw), f"{OUT}/{name}.log")
        log = done.output

        def num(key):
            m = re.search(rf"^{key} ([0-9.eE+-]+)\s*$", log, re.M)
            if not m:
                sys.exit(f"{PROG}: no {key} in {OUT}/{name}.log (pathtracer output changed?)")
            return float(m.group(1))

        frame = 1.0 / num("BENCHMARK_RENDER_AVG")
        build = sum(float(x) for x in re.findall(r"^finished .*? : ([0-9.]+)ms", log, re.M)) / 1000.0
        version = re.search(r"Embree Ray Tracing Kernels ([0-9.]+)", log)
        isa = re.search(r"^\s*ISA\s*:(.*)$", log, re.M)
        isa = next((x for x in ("AVX512", "AVX2", "AVX", "SSE4.2") if isa and x in isa.group(1).split()), "?")
        return {"wall": done.wall, "cpu": done.cpu, "frame": frame, "build": build, "render": frame - build,
                "rays": num("BENCHMARK_RENDER_MRAYPS_AVG") * 1e6 * frame,
                "no_textures": len(re.findall(r"image format \S+ not supported", log)),
                "version": version.group(1) if version else "?", "isa": isa}

    def pmc_name(mode, chunk):
        return "pmc" if (mode, chunk) == ("stream", 65536) else f"pmc-{mode}-chunk{chunk}"

    CONFIGS = [("pmc", lambda n: run_pmc(n)), ("embree", lambda n: run_embree(n)),
               ("pmc-decode", lambda n: run_pmc(n, textures="off"))]
    for mode in MODES:
        for chunk in CHUNKS:
            if pmc_name(mode, chunk) != "pmc":
                CONFIGS.append((pmc_name(mode, chunk), lambda n, m=mode, c=chunk: run_pmc(n, trace=m, chunk=c)))

    # Warm-up (not timed): file cache, PoCL's kernel cache, pmc's texture cache.
    print(f"{PROG}: warm-up ({PMC}, pathtracer), then {RUNS} round(s) of {len(CONFIGS)} runs", flush=True)
    try:
        run_pmc("warmup-pmc", spp=1)
        run_embree("warmup-embree", spp=1)
    except common.RunFailed as e:
        sys.exit(f"{PROG}: warm-up failed: {e}")

    loads = common.LoadSampler()
    results = {name: [] for name, _ in CONFIGS}
    failed = {}  # name -> why; a failed pmc variant is reported, not retried
    t_start = time.time()
    for r in range(RUNS):
        for name, fn in common.round_order(CONFIGS, r, "rotate"):
            if name in failed:
                continue
            try:
                res = fn(name)
            except common.RunFailed as e:
                if name in ("pmc", "embree"):
                    sys.exit(f"{PROG}: {name} failed: {e}")
                failed[name] = str(e)
                print(f"  round {r + 1}/{RUNS} {name:22s} FAILED: {e}", flush=True)
                continue
            results[name].append(res)
            loads.sample()
            print(f"  round {r + 1}/{RUNS} {name:22s} wall {res['wall']:6.2f}s  render {res['render']:6.2f}s",
                  flush=True)
    elapsed = time.time() - t_start

    def med(name, key):
        return common.median(x[key] for x in results[name])

    def med_of(name, f):
        return common.median(f(x) for x in results[name])

    # ---- report
    def fmt(v):
        return f"{v:.2f}" if abs(v) < 100 else f"{v:.1f}"

    pm, em = "pmc", "embree"
    paths = W * H * SPP
    pmc_rays, emb_rays = med(pm, "rays"), med(em, "rays")
    rows_cmp = [
        ("full run, wall clock (s)", med(pm, "wall"), med(em, "wall")),
        ("full run, textures decoded (`--texture-cache off`) (s)", med("pmc-decode", "wall"), med(em, "wall")),
        ("full run, CPU time user+sys (s)", med(pm, "cpu"), med(em, "cpu")),
        ("render only (s)", med(pm, "render"), med(em, "render")),
        ("setup: full run minus render (s)", med_of(pm, lambda x: x["wall"] - x["render"]),
         med_of(em, lambda x: x["wall"] - x["render"])),
        ("rays traced (M)", pmc_rays / 1e6, emb_rays / 1e6),
        ("rays per path", pmc_rays / paths, emb_rays / paths),
        ("Mrays/s (render only)", med_of(pm, lambda x: x["rays"] / x["render"]) / 1e6,
         med_of(em, lambda x: x["rays"] / x["render"]) / 1e6),
    ]

    def spread(name, key):
        v = [x[key] for x in results[name]]
        return f"{fmt(min(v))}–{fmt(max(v))}"

    def field(name, f):
        return [f(x) for x in results[name]]

    ranges = {"full run, wall clock (s)": "wall", "full run, CPU time user+sys (s)": "cpu",
              "render only (s)": "render"}
    # The ratio pairs each pmc run with the Embree run of the same round (they ran
    # a few seconds apart), then takes the median: steadier than a ratio of medians.
    ratio = {label: common.median(common.round_ratios(field(pm, lambda x: x[key]), field(em, lambda x: x[key])))
             for label, key in ranges.items()}
    decode_label = "full run, textures decoded (`--texture-cache off`) (s)"
    ratio[decode_label] = common.median(common.round_ratios(field("pmc-decode", lambda x: x["wall"]),
                                                            field(em, lambda x: x["wall"])))
    throughput = lambda x: x["rays"] / x["render"]  # noqa: E731
    ratio["Mrays/s (render only)"] = common.median(common.round_ratios(field(pm, throughput),
                                                                       field(em, throughput)))
    cmp_rows = [[label, fmt(p), fmt(e), f"{ratio.get(label, p / e):.2f}x",
                 spread(pm, ranges[label]) if label in ranges else
                 spread("pmc-decode", "wall") if label == decode_label else "",
                 spread(em, ranges[label]) if label in ranges else ""] for label, p, e in rows_cmp]
    cmp_table = common.md_table(["", "pmc", "Embree pathtracer", "pmc / Embree", "pmc min–max", "Embree min–max"],
                                cmp_rows)

    grid_rows = []
    for mode in MODES:
        for chunk in CHUNKS:
            name = pmc_name(mode, chunk)
            label = [f"`{mode}`", f"{chunk}" + (" (overlap)" if chunk else " (whole queue)")]
            if name in failed:
                grid_rows.append(label + [f"failed: {failed[name].split(' (')[0]}"] + [""] * 5)
                continue
            grid_rows.append(label + [fmt(med(name, k)) for k in ("trace", "shadow", "shade", "transfer", "render")]
                             + [f"{med_of(name, lambda x: x['rays'] / x['trace']) / 1e6:.2f}"])
    grid_table = common.md_table(["`--trace-mode`", "`--chunk-rays`", "trace (s)", "shadow (s)", "shade (s)",
                                  "transfer (s)", "render_seconds", "Mrays/s in trace"], grid_rows)

    stage_keys = ["camera", "trace", "shadow", "shade", "transfer", "film"]
    stage_cols = [("pmc", "chunk 65536")] + ([("pmc-stream-chunk0", "chunk 0")]
                                             if "pmc-stream-chunk0" not in failed else [])
    stage_rows = []
    for k in stage_keys + ["sum of stages", "render_seconds"]:
        row = [k]
        for name, _ in stage_cols:
            render = med(name, "render")
            v = (sum(med(name, s) for s in stage_keys) if k == "sum of stages"
                 else render if k == "render_seconds" else med(name, k))
            row += [fmt(v), f"{100 * v / render:.0f}%"]
        stage_rows.append(row)
    stage_header = ["pmc stage (`stream`)"]
    for _, label in stage_cols:
        stage_header += [f"{label} (s)", "of render"]
    stage_table = common.md_table(stage_header, stage_rows)

    # pmc's setup by step (`setup_seconds`, main-thread steps that add up to
    # `total`), the device opening that overlapped them, and the rest of the
    # run outside setup and render (process start, kernel warm-up, outputs, exit).
    setup_steps = ["scene", "materials", "lights", "bvh", "opencl_device", "renderer", "total"]
    setup_rows = [[f"`{k}`", fmt(med(pm, f"setup_{k}"))] for k in setup_steps if f"setup_{k}" in results[pm][0]]
    if "setup_background_opencl_device" in results[pm][0]:
        setup_rows.append(["`background.opencl_device` (overlapped, not in total)",
                           fmt(med(pm, "setup_background_opencl_device"))])
    if "setup_background_kernel_build" in results[pm][0]:
        setup_rows.append(["`background.kernel_build` (overlapped, not in total)",
                           fmt(med(pm, "setup_background_kernel_build"))])
    if "setup_materials" in results["pmc-decode"][0]:
        setup_rows.append(["`materials` with `--texture-cache off` (every texture decoded)",
                           fmt(med("pmc-decode", "setup_materials"))])
        setup_rows.append(["`total` with `--texture-cache off`", fmt(med("pmc-decode", "setup_total"))])
    if "setup_total" in results[pm][0]:
        setup_rows.append(["outside setup and render: process start, kernel warm-up, outputs, exit",
                           fmt(med_of(pm, lambda x: x["wall"] - x["render"] - x["setup_total"]))])
    setup_table = common.md_table(["pmc `setup_seconds`", "median (s)"], setup_rows)

    # ---- machine
    nproc = os.cpu_count()
    version = results[em][0]["version"]
    no_tex = results[em][0]["no_textures"]
    machine = f"{common.machine(results[pm][0]['device'])}, Embree {version} ({results[em][0]['isa']})"
    # The runs themselves keep every core busy (load ~ nproc); more than one extra
    # core's worth of load between them is other work.
    overloaded = loads.median() > nproc + 1
    load_warning = (f"**The machine was overloaded by other work during these runs (median load "
                    f"{loads.median():.1f} on {nproc} cores): absolute times are inflated; "
                    f"the ratios and CPU times are the usable part.**\n\n" if overloaded else "")

    # ---- stdout
    print()
    print(f"Sponza {W}x{H}, {SPP} spp, path length {DEPTH}, env 1,1,1; medians of {RUNS} runs; {machine}")
    for title, t in [("pmc vs Embree's pathtracer", cmp_table),
                     ("pmc: Embree query styles x streaming", grid_table),
                     ("where pmc's render time goes (stage_seconds)", stage_table),
                     ("where pmc's setup goes (setup_seconds)", setup_table)]:
        print(f"\n{title}\n{t}")
    print(f"\n{loads.note()}")
    if overloaded:
        print(f"{PROG}: warning: the machine was overloaded; absolute times are inflated")
    print(f"{PROG}: {elapsed:.0f}s of timed runs; logs, stats and images in {OUT}/")

    # ---- docs
    pmc_line = " ".join(pmc_cmd("OUT")).replace(f"{OUT}/OUT", "OUT").replace(PMC, "build/pmc", 1)
    emb_line = " ".join(embree_cmd())
    failures = "".join(f"- Failed, not retried: `{name}`: {why}\n" for name, why in failed.items())
    section = f"""{SECTION}

Produced by `{a.command}` on {common.utc_now()}, pmc at {common.git_rev("unknown revision")} (`{PMC}`).
Machine: {machine}.
Median of {RUNS} runs per configuration; the configurations run round-robin, one
of each per round, so they share the machine's noise ({loads.note()}).

{load_warning}Scene: `{SCENE}` (262k triangles), overview camera from ({csv(EYE)}) at
({csv(AT)}), {FOV}° vertical fov, white environment, {W}x{H}, {SPP} spp, path
length {DEPTH} (surface hits per path).

    {pmc_line}
    {emb_line}

- **full run**: wall clock of the whole process: OBJ loading, BVH build,
  rendering, and for pmc also texture loading, OpenCL setup and writing the
  EXR and PNG. pmc keeps decoded textures between runs (`--texture-cache`,
  on by default): "full run" reads them back, as every run after a scene's
  first does; "textures decoded" decodes Sponza's 38 MB of PNG into 110 MB
  of mip chains, as a first run does (which then also writes them to the
  cache; that write is not in these runs). Embree's pathtracer runs in its benchmark mode (one frame, no
  warm-up), which writes no image; with `-o out.ppm` it does the same work
  plus a 0.7 MB PPM write (its `-o` cannot be combined with `--benchmark`: it
  then renders twice).
- **render only**: pmc's `render_seconds` from `--stats`; for Embree, the frame
  time its benchmark mode reports minus the BVH build time Embree logs
  (`--rtcore verbose=2`), because the tutorial builds the BVH lazily inside its
  first frame.
- **rays**: pmc's `rays` (path + shadow rays); Embree's ray count is its
  reported Mrays/s times the frame time.

{cmp_table}

"pmc / Embree" is pmc's number over Embree's (below 1: pmc takes less time or
traces fewer rays); for timed rows it is the median over rounds of the ratio
of the two runs in the same round. pmc traces {emb_rays / pmc_rays:.1f}x fewer rays than Embree's
pathtracer for the same number of paths (see the notes), at
{1 / ratio["Mrays/s (render only)"]:.1f}x lower throughput.

pmc's Embree query styles (`--trace-mode`) and streaming (`--chunk-rays`): with
65536 the host traces chunk k+1 while OpenCL shades chunk k; with 0 each queue
is traced whole, then shaded. `trace` and `shadow` are `stage_seconds`: host
wall time inside Embree calls.

{grid_table}

Where pmc's time goes (`stage_seconds`, trace mode `stream`, the default). `trace` and
`shadow` are host wall time in Embree; `camera`, `shade` and `film` are OpenCL
event times (PoCL runs them on the same cores as Embree); `transfer` is host
time in blocking reads, which also wait for kernels still running, plus the
device time of the hit and occlusion uploads. With chunk 65536 the stages
overlap, so they add up to more than `render_seconds`.

{stage_table}

Where pmc's setup goes (`setup_seconds` from `--stats`, medians): the steps run
one after another on the main thread and add up to `total`. Two jobs run beside
them on TBB's workers: the OpenCL device opens while the scene loads
(`opencl_device` is only the wait for it, once the materials are compiled), and
the OpenCL program builds from there while the textures decode and the BVH
builds (`renderer` is the wait for it). `scene` is pmc's own OBJ parser
(core/obj_parser.h), parallel over 1 MiB chunks of the file; `materials` is
mostly PNG decoding (zlib), in parallel over the textures, each streamed row by
row into the texel pool, and their mip chains. The last row is the rest of
"full run minus render".

{setup_table}

Notes:

- The two renderers do not do the same work per path, so compare Mrays/s as
  well as seconds. Both sample the constant environment at every hit: pmc
  traces one shadow ray per hit whose light sample lies above the surface and
  weights it against the BSDF sample by MIS; Embree's pathtracer traces one
  `rtcOccluded1` shadow ray per hit, through an occlusion filter callback for
  transparency. Embree's pathtracer ends a
  path only when its throughput drops below 0.01 (with untextured `Kd`
  colours, almost never within 4 hits); pmc plays Russian roulette after the
  third hit with survival probability = path throughput (at most 0.95), and
  behind three hits on Sponza's textures that is small: when this section was
  written, about 1% of pmc's paths went on to a fourth ray.
- Sponza's leaves, chains and plants use `map_d` cut-outs. pmc evaluates them
  on the host inside Embree's intersection and occlusion filters (cut-out
  triangles sit in a second Embree geometry), so that cost is part of pmc's
  `trace` time. (Earlier pmc builds ignored `map_d` and rendered them solid.)
  The filters run a program of the opacity's nodes alone; running the whole
  material there (its colour texture too) made the trace stage 2.10 s instead
  of 1.99 s (4 interleaved rounds, 2026-11-26). Before that change, treating
  every cut-out as opaque took the trace stage from 2.28 s to 1.98 s.
- Debian's pathtracer cannot read PNG textures ({no_tex} "image format png not
  supported" errors in its log): it renders Sponza with the materials' `Kd`
  colours, untextured, and with every surface opaque. pmc decodes and samples
  all textures (decoding is in pmc's full-run time).
- pmc builds its BVH with `RTC_BUILD_QUALITY_HIGH` and `RTC_SCENE_FLAG_ROBUST`
  (two geometries: opaque and cut-out triangles); the tutorial uses
  `RTC_BUILD_QUALITY_MEDIUM`, not robust
  (381 geometries, one BVH8). The tutorial renders small pixel tiles and traces
  each pixel's samples one after another with `rtcIntersect1`; pmc traces
  one sample of the whole image per wave.
- Robust traversal has a price, and pmc pays it. Without
  `RTC_SCENE_FLAG_ROBUST`, Sponza's trace stage took 1.87 s against 2.37 s
  (render 0.90x, 4 interleaved rounds, 2026-11-26), which would put pmc's
  whole run at about Embree's. But without it, rays cross shared edges: from
  inside a closed sphere of 81920 triangles, 2 of 2,000,000 random rays
  escaped (none with the flag), and so did 5.8% of rays aimed at points on
  shared edges (none with the flag). In a closed room under a bright sky each
  escape is a firefly, so the flag stays.
- Tracing the secondary rays of a wave in path (pixel) order, instead of the
  order in which the shade kernel queued them (by material), made the trace
  stage slower, 2.28 s against 2.11 s: Embree's incoherent traversal gains
  nothing from neighbouring pixels' bounces being traced together. Not kept.
  (Measured again on 2026-11-26 with the rays gathered in path order inside
  the tracer: render 1.02x. Still not kept.)
- The shade kernel reads each hit's triangle as one 128-byte record with its
  corners' positions, normals and uvs inline (`PmcTriangleRecord`), not
  through the OBJ's indices: a hit's geometry is two cache lines instead of up
  to ten scattered ones. On 2026-11-26 this made the shade stage 1.58 s
  instead of 1.77 s and the render 0.956x (5 interleaved rounds, identical
  pixels), for 128 bytes per triangle (peak memory 352 to 391 MB here).
- Measured on 2026-11-26 and not kept (interleaved rounds, identical pixels
  unless said): a pass that touches each lane's texels before any lane
  filters them (render 1.048x: the texel loads are mostly cache hits at the
  mip levels the ray cones pick); path states padded to 64 bytes so none
  straddles two cache lines (1.029x); waves of 65536 or 131072 paths instead
  of the whole image (1.049x, 1.007x); `-cl-mad-enable -cl-denorms-are-zero`
  (1.009x; same pixels: PoCL already fuses multiply-adds); transparent huge
  pages for every buffer (no difference). Treating every cut-out as opaque
  would save about 3% of the render (0.971x).
- Outputs: the EXR is written with zlib level 1 on OpenEXR's thread pool
  (sized to pmc's thread budget) and the PNG at zlib level 3; Sponza's time
  outside setup and render fell from 0.105 s to 0.076 s, same pixels.
- Process start: pmc does not link OpenImageIO (core/image_backend.h). It
  reads and writes OpenEXR and 8-bit PNG itself (libOpenEXR, libpng) and
  loads OpenImageIO as a plugin only for other formats; Debian's OpenImageIO
  brings about 250 shared libraries whose symbol binding took 0.4-0.5 s of
  every process before `main()`. Sponza's textures are PNGs, so this run
  never loads it (the last setup row fell from 0.58 s to about 0.3 s).
- Both use all cores (TBB for Embree, plus PoCL's threads for pmc). On a small,
  shared machine the times vary by tens of percent from run to run; the CPU
  times vary less than the wall clock.
{failures}"""
    common.write_section(a.doc, SECTION, section, PROG)


if __name__ == "__main__":
    main()
