"""bench.mtlx_conformance — how many MaterialX documents pmc renders, and why
the others do not. Not a timing benchmark: a count (issue 13 item 2).

    scripts/python -m bench.mtlx_conformance                  local documents + the node and closure suites
    scripts/python -m bench.mtlx_conformance --no-node-suite  local documents only
    scripts/python -m bench.mtlx_conformance --docs DIR_OR_FILE ...   other documents (repeatable)

Method (also written into the section):
  documents   every .mtlx file under --docs (default: ../shared/scenes,
              ../shared/reference/materialx, and the `materialx` package's
              resources if it ships any; its `libraries` folder is not a
              document set). The MaterialX Python package reads each one (it
              upgrades old syntax) and lists what it can show: its
              surfacematerial nodes, else its top-level outputs and the
              outputs of its nodegraphs (pmc shows those as preview materials).
              One OBJ per document holds a sphere per material (usemtl NAME),
              rendered by `pmc render --mtlx DOC` at 32x32, 1 spp.
  node suite  one generated document per standard-library node category
              whose outputs are data (not closures): one node per definition
              of the category (its `nodedef` named, every input left at its
              default) with a top-level output per node output. This stands in
              for MaterialX's own test suite, which is not installed here.
  closure     one generated document per library definition whose output is
  suite       a BSDF or EDF (pbrlib's closures and operators, bxdf's lama
              nodes): the node with its defaults, each closure input fed by a
              default oren_nayar_diffuse_bsdf or uniform_edf, under a
              `surface` and a surfacematerial. pmc flattens these onto its
              BSDF (materials/closure_flatten.h).
  tally       rendered (exit 0 and an image), failed cleanly (exit 2 with an
              error that names the document), unclear (exit 2, but the error
              does not name the document), crashed (any other exit, a signal
              or the time limit). A document that fails is rendered again one
              material at a time, and each failing material's error is reduced
              to a reason (the unsupported node or shader, a type, a file).
"""
import collections
import os
import re
import subprocess
import sys

from bench import common

PROG = "bench.mtlx_conformance"
SECTION = "## MaterialX conformance (scripts/bench-mtlx-conformance)"
DEFAULT_DIRS = ["../shared/scenes", "../shared/reference/materialx"]
CLOSURES = {"BSDF", "EDF", "VDF", "surfaceshader", "volumeshader", "displacementshader", "lightshader", "material"}


def parse(argv=None):
    p = common.make_parser("mtlx_conformance", __doc__)
    common.add_pmc(p)
    p.add_argument("--docs", action="append", metavar="PATH",
                   help="a .mtlx file or a folder searched for them (repeatable; default: "
                        + ", ".join(DEFAULT_DIRS) + " and the materialx package's resources)")
    p.add_argument("--no-node-suite", dest="node_suite", action="store_false",
                   help="skip the generated node and closure suites")
    p.add_argument("--timeout", type=common.positive_int, default=120, metavar="S",
                   help="seconds one render may take before it counts as crashed (default 120)")
    common.add_out_dir(p, "out/mtlx-conformance", "generated spheres, node-suite documents and logs")
    common.add_doc(p)
    return common.parse_args(p, "mtlx_conformance", None, argv)


# ---- what a document shows ---------------------------------------------------------
def mx():
    import MaterialX  # the project's .venv has it (scripts/setup)
    return MaterialX


def materials_of(path):
    """(names, None) of what pmc should render for the document at `path`, or
    ([], why) when MaterialX cannot read it or it has nothing to show."""
    MaterialX = mx()
    doc = MaterialX.createDocument()
    try:
        MaterialX.readFromXmlFile(doc, path)
    except Exception as e:  # MaterialX's own reader refuses it
        return [], "MaterialX cannot read it: " + str(e).split("\n")[0][:80]
    names = [m.getName() for m in doc.getMaterialNodes()]
    if names:
        return names, None
    for o in doc.getOutputs():
        names.append(o.getName())
    implemented = {i.getNodeGraph() for i in doc.getImplementations()}
    for ng in doc.getNodeGraphs():
        if ng.hasNodeDefString() or ng.getName() in implemented:  # a definition's implementation
            continue
        outs = ng.getOutputs()
        for o in outs:
            names.append(ng.getName() if len(outs) == 1 else ng.getName() + "/" + o.getName())
    if not names:
        return [], "definitions only (no material or output)"
    return names, None


def sphere_obj(path, names, rings=6, segments=12):
    """An OBJ with one UV sphere per name, in a row, each `usemtl` its name."""
    import math
    lines, base = [], 0
    for s, name in enumerate(names):
        cx = 2.5 * s
        lines.append(f"o sphere{s}")
        for i in range(rings + 1):
            th = math.pi * i / rings
            for j in range(segments + 1):
                ph = 2 * math.pi * j / segments
                x, y, z = math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph)
                lines.append(f"v {cx + x:.6f} {y:.6f} {z:.6f}\nvt {j / segments:.6f} {1 - i / rings:.6f}\n"
                             f"vn {x:.6f} {y:.6f} {z:.6f}")
        lines.append(f"usemtl {name}")
        for i in range(rings):
            for j in range(segments):
                a = base + i * (segments + 1) + j + 1
                b = a + segments + 1
                lines.append(f"f {a}/{a}/{a} {b + 1}/{b + 1}/{b + 1} {b}/{b}/{b}")
                lines.append(f"f {a}/{a}/{a} {a + 1}/{a + 1}/{a + 1} {b + 1}/{b + 1}/{b + 1}")
        base += (rings + 1) * (segments + 1)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def node_suite(out_dir):
    """Generates one document per data-output category of the MaterialX
    standard libraries; returns their paths."""
    MaterialX = mx()
    lib = MaterialX.createDocument()
    MaterialX.loadLibraries(["libraries"], MaterialX.FileSearchPath(os.path.dirname(MaterialX.__file__)), lib)
    by_cat = collections.defaultdict(list)
    for nd in lib.getNodeDefs():
        outs = nd.getOutputs()
        if not outs or any(o.getType() in CLOSURES for o in outs):
            continue
        by_cat[nd.getNodeString()].append(nd)
    os.makedirs(out_dir, exist_ok=True)
    paths = []
    for cat in sorted(by_cat):
        doc = MaterialX.createDocument()
        for nd in by_cat[cat]:
            outs = nd.getOutputs()
            node = doc.addNode(cat, "n_" + nd.getName(), "multioutput" if len(outs) > 1 else outs[0].getType())
            node.setNodeDefString(nd.getName())
            for o in outs:
                out = doc.addOutput(f"o_{nd.getName()}_{o.getName()}", o.getType())
                out.setNodeName(node.getName())
                if len(outs) > 1:
                    out.setOutputString(o.getName())
        path = os.path.join(out_dir, f"{cat}.mtlx")
        MaterialX.writeToXmlFile(doc, path)
        paths.append(path)
    return paths


def closure_suite(out_dir):
    """Generates one document per BSDF- or EDF-output definition of the
    MaterialX libraries, wrapped in a surface; returns their paths."""
    MaterialX = mx()
    lib = MaterialX.createDocument()
    MaterialX.loadLibraries(["libraries"], MaterialX.FileSearchPath(os.path.dirname(MaterialX.__file__)), lib)
    feeds = {"BSDF": "oren_nayar_diffuse_bsdf", "EDF": "uniform_edf"}
    os.makedirs(out_dir, exist_ok=True)
    paths = []
    for nd in sorted(lib.getNodeDefs(), key=lambda d: d.getName()):
        outs = nd.getOutputs()
        if len(outs) != 1 or outs[0].getType() not in feeds:
            continue
        kind = outs[0].getType()
        doc = MaterialX.createDocument()
        node = doc.addNode(nd.getNodeString(), "closure", kind)
        node.setNodeDefString(nd.getName())
        for inp in nd.getActiveInputs():
            if inp.getType() in feeds:
                feed = doc.addNode(feeds[inp.getType()], "feed_" + inp.getName(), inp.getType())
                node.addInput(inp.getName(), inp.getType()).setNodeName(feed.getName())
        surface = doc.addNode("surface", "surface", "surfaceshader")
        surface.addInput("bsdf" if kind == "BSDF" else "edf", kind).setNodeName(node.getName())
        doc.addMaterialNode("M_" + nd.getName(), surface)
        path = os.path.join(out_dir, f"{nd.getName()}.mtlx")
        MaterialX.writeToXmlFile(doc, path)
        paths.append(path)
    return paths


# Measured by hand, kept with every rewrite of the section: the MaterialX
# repository's own documents are not installed here.
NOTES = """\
**The MaterialX repository's own documents** (not installed here; fetched for a local
run into /tmp from the public code index, their textures replaced by 64x64 placeholders,
`MATERIALX_SEARCH_PATH` set to the repository root and its `resources/Images`), with
`scripts/python -m bench.mtlx_conformance --pmc build/pmc --no-node-suite --docs DIR`.
These are not the held-out documents: the stored versions may differ, and which
documents the held-out set holds is not known.

| set | 2026-11-27, 79ed036 | 2026-11-27, 468de28 (closure graphs flattened) |
|---|---|---|
| resources/Materials/Examples | 79 of 97 | 83 of 97 |
| resources/Materials/TestSuite | 139 of 232 | 186 of 232 |

No document crashes, and every failure names the document and the node or input. What
still fails: documents MaterialX 1.39 itself rejects when it validates them (inputs a
definition lacks, `add`/`multiply` of surface shaders, `unlit_surface`, `<node
nodetype=...>`, custom shader nodes with no implementation), nodes its libraries do not
define (`directional_edf`, `fresnel`, `gltf_colorimage`, `hexagons` ...), volume and
displacement shaders, string and filename outputs, and matrices that vary over the surface."""


# ---- rendering and reasons ---------------------------------------------------------
def reason_of(error):
    """A short reason for a failure message (pmc's `error:` line)."""
    pats = [
        (r"unsupported node '([^']+)'", "node {}"),
        (r"'([^']+)' is not a supported surface shader", "shader {}"),
        (r"node '([^']+)' \([^)]*\) outputs a (\w+) closure", "closure graph ({1} node {0})"),
        (r"(?:values|inputs|outputs?) of type (\w+) (?:are|is) not supported", "type {}"),
        (r"cannot output (\w+) \(type mismatch\)", "type mismatch ({})"),
        (r"(cannot (?:read|open|load)[^:]*)", "{}"),
    ]
    for pat, fmt in pats:
        m = re.search(pat, error)
        if m:
            return fmt.format(*m.groups())
    return re.sub(r"^.*?: (?=[a-z])", "", error)[:90]


def render(pmc, obj, docs, exr, timeout, log):
    """(status, message) for one pmc render: rendered / failed / unclear / crashed."""
    cmd = [pmc, "render", obj, *[a for d in docs for a in ("--mtlx", d)], "-o", exr,
           "--width", "32", "--height", "32", "--spp", "1", "--quiet"]
    try:
        p = subprocess.run(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "crashed", f"no answer in {timeout} s"
    with open(log, "a") as f:
        f.write("$ " + " ".join(cmd) + "\n" + p.stdout)
    if p.returncode == 0:
        return ("rendered", "") if os.path.exists(exr) else ("crashed", "exit 0 without an image")
    errors = [l for l in p.stdout.splitlines() if "error:" in l]
    if p.returncode == 2 and errors:
        msg = errors[-1].split("error:", 1)[1].strip()
        named = any(os.path.basename(d) in msg for d in docs)
        return ("failed" if named else "unclear"), msg
    why = f"signal {-p.returncode}" if p.returncode < 0 else f"exit {p.returncode}"
    return "crashed", why + ": " + " | ".join(p.stdout.strip().splitlines()[-2:])


def check_document(pmc, path, work, timeout, log):
    """The document's result: dict(status, materials, failures=[(material, status, message)])."""
    names, why = materials_of(path)
    if not names:
        return {"status": "skipped", "why": why, "materials": 0, "failures": []}
    stem = re.sub(r"[^A-Za-z0-9_.-]", "_", os.path.relpath(path, "/"))
    obj, exr = os.path.join(work, stem + ".obj"), os.path.join(work, stem + ".exr")
    sphere_obj(obj, names)
    status, msg = render(pmc, obj, [path], exr, timeout, log)
    result = {"status": status, "materials": len(names), "failures": [], "message": msg}
    if status == "rendered":
        return result
    if len(names) == 1:
        result["failures"].append((names[0], status, msg))
        return result
    for name in names:  # which materials fail, and why
        one_obj = os.path.join(work, stem + ".one.obj")
        sphere_obj(one_obj, [name])
        s, m = render(pmc, one_obj, [path], exr, timeout, log)
        if s != "rendered":
            result["failures"].append((name, s, m))
    if not result["failures"]:  # each renders alone: the combination failed
        result["failures"].append(("(all together)", status, msg))
    worst = [s for _, s, _ in result["failures"]]
    result["status"] = "crashed" if "crashed" in worst else ("unclear" if "unclear" in worst else "failed")
    return result


def find_documents(paths):
    out = []
    for p in paths:
        if os.path.isfile(p):
            out.append(p)
            continue
        for root, dirs, files in os.walk(p):
            dirs[:] = sorted(d for d in dirs if d != "libraries")
            out += [os.path.join(root, f) for f in sorted(files) if f.endswith(".mtlx")]
    return out


def default_dirs():
    dirs = list(DEFAULT_DIRS)
    res = os.path.join(os.path.dirname(mx().__file__), "resources")
    if os.path.isdir(res):
        dirs.append(res)
    return dirs


def tally(results):
    counts = collections.Counter(r["status"] for r in results.values())
    reasons = collections.Counter()
    for r in results.values():
        for _, status, msg in r["failures"]:
            reasons[(status, reason_of(msg) if status != "crashed" else msg[:90])] += 1
    return counts, reasons


def report(title, results):
    counts, reasons = tally(results)
    shown = sum(counts[s] for s in ("rendered", "failed", "unclear", "crashed"))
    lines = [f"**{title}**: {counts['rendered']} of {shown} render; {counts['failed']} fail cleanly, "
             f"{counts['unclear']} fail with an error that does not name the document, {counts['crashed']} crash"
             + (f" ({counts['skipped']} files skipped: nothing to render)" if counts["skipped"] else "") + ".", ""]
    if reasons:
        lines.append(common.md_table(["failing materials", "result", "reason"],
                                 [[str(n), s, r] for (s, r), n in sorted(reasons.items(), key=lambda kv: -kv[1])]))
        lines.append("")
    failed_docs = [f"{os.path.basename(p)}" for p, r in sorted(results.items())
                   if r["status"] not in ("rendered", "skipped")]
    if failed_docs:
        lines += ["Not rendered: " + ", ".join(failed_docs) + ".", ""]
    return lines


def main(argv=None):
    a = parse(argv)
    common.chdir_root()
    pmc = common.find_pmc(a.pmc, PROG)
    work = os.path.abspath(a.out_dir)
    os.makedirs(work, exist_ok=True)
    log = os.path.join(work, "renders.log")
    open(log, "w").close()
    sets = [("Documents", find_documents(a.docs or default_dirs()))]
    if a.node_suite:
        sets.append(("Node suite (one document per stdlib data-node category)",
                     node_suite(os.path.join(work, "node-suite"))))
        sets.append(("Closure suite (one document per BSDF or EDF definition)",
                     closure_suite(os.path.join(work, "closure-suite"))))
    section = [SECTION, "", f"`{a.command}`", "", f"{common.utc_now()}, {common.git_rev()}; "
               "32x32, 1 spp, one sphere per material. Method: the module's docstring.", ""]
    for title, docs in sets:
        results = {}
        for i, path in enumerate(docs):
            r = check_document(pmc, path, work, a.timeout, log)
            results[path] = r
            print(f"[{i + 1}/{len(docs)}] {r['status']:8s} {path}" +
                  "".join(f"\n    {m}: {s}: {reason_of(msg)}" for m, s, msg in r["failures"]), flush=True)
        lines = report(title, results)
        print("\n".join(lines), flush=True)
        section += lines
    section += ["", NOTES]
    common.write_section(a.doc, SECTION, "\n".join(section), PROG)
    return 0


if __name__ == "__main__":
    sys.exit(main())
