"""bench.peer_mitsuba — renders one bench.peers job with Mitsuba 3 (PyPI
`mitsuba`), in its own process:

    .venv/bin/python scripts/bench/peer_mitsuba.py VARIANT JOB.json RESULT.json

VARIANT is llvm_ad_rgb (needs Debian's libllvm19) or scalar_rgb. JOB.json is
bench.peer_scenes' job description plus "renders", "width", "height",
"max_depth", "threads" and "seed" (see bench.peer_cycles). RESULT.json gets
each render's seconds (mi.render and the evaluation of the image; the LLVM
backend's kernels are compiled by an untimed 1-sample render first, and
reused at every sample count: a second render at a count takes as long as
the first) and the seconds of a 1-sample render.

Conversions from pmc's lights file:
  point        point, intensity I
  spot         spot, intensity I, cutoff_angle = half the cone, beam_width =
               (1 - blend) of it (Mitsuba fades linearly in the angle, pmc by a
               smoothstep: the penumbrae differ slightly)
  quad         rectangle shape with an area emitter of radiance L, black; a
               two-sided quad is two rectangles back to back, 1e-5 of the
               quad's size apart (coincident ones would hide each other)
  directional  directional, irradiance E (a delta: Mitsuba has no sun disk)
  environment  constant radiance, or envmap turned 180 degrees about +Y so
               that pmc's lat-long convention and Mitsuba's agree (Mitsuba
               interpolates the map bilinearly; pmc and Cycles here look
               texels up nearest)
Materials: twosided(diffuse(Kd x map_Kd)), a Kd other than 1 multiplied into
a linear EXR copy of the texture; mask(map_d) for cut-outs; area emitter Ke.
Integrator: path, max_depth = pmc's max_depth + 1 (Mitsuba counts the camera
segment), the pixel filter a 1-pixel box.
"""
import json
import os
import sys
import time

import drjit as dr
import mitsuba as mi


def texture(m, folder, name):
    """The reflectance of a material: a constant, the texture, or a linear
    EXR copy of the texture scaled by Kd."""
    kd = m["kd"]
    if not m["map_kd"]:
        return {"type": "rgb", "value": kd}
    if all(abs(k - 1.0) < 1e-6 for k in kd):
        return {"type": "bitmap", "filename": m["map_kd"]}
    import numpy as np
    bmp = mi.Bitmap(m["map_kd"]).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
    arr = np.array(bmp) * np.array(kd, dtype=np.float32)
    path = os.path.join(folder, f"kd_{name}.exr")
    mi.Bitmap(arr.astype(np.float32)).write(path)
    return {"type": "bitmap", "filename": path, "raw": True}


def scene_dict(job, folder):
    d = {"type": "scene"}
    cam = job["camera"]
    d["camera"] = {
        "type": "perspective", "fov_axis": "y", "fov": cam["vfov"], "near_clip": 1e-3, "far_clip": 1e6,
        "to_world": mi.ScalarTransform4f().look_at(origin=cam["from"], target=cam["at"], up=cam["up"]),
        "film": {"type": "hdrfilm", "width": job["width"], "height": job["height"], "rfilter": {"type": "box"},
                 "pixel_format": "rgb"},
        "sampler": {"type": "independent", "seed": job["seed"]},
    }
    d["integrator"] = {"type": "path", "max_depth": job["max_depth"] + 1}
    for i, part in enumerate(job["parts"]):
        m = job["materials"][part["material"]]
        bsdf = {"type": "twosided", "material": {"type": "diffuse", "reflectance": texture(m, folder, i)}}
        if m["map_d"]:
            bsdf = {"type": "mask", "opacity": {"type": "bitmap", "filename": m["map_d"], "raw": True},
                    "material": bsdf}
        shape = {"type": "obj", "filename": part["obj"], "bsdf": bsdf}
        if any(m["ke"]):
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": m["ke"]}}
        d[f"part_{i}"] = shape
    for i, l in enumerate(job["lights"]):
        if l["type"] == "point":
            d[f"light_{i}"] = {"type": "point", "position": l["position"],
                               "intensity": {"type": "rgb", "value": l["intensity"]}}
        elif l["type"] == "spot":
            half = 0.5 * l.get("cone_angle_deg", 45.0)
            p, w = l["position"], l["direction"]
            up = [0.0, 1.0, 0.0] if abs(w[1]) < 0.9 * sum(x * x for x in w) ** 0.5 else [1.0, 0.0, 0.0]
            d[f"light_{i}"] = {"type": "spot", "intensity": {"type": "rgb", "value": l["intensity"]},
                               "cutoff_angle": half, "beam_width": (1.0 - l.get("blend", 0.15)) * half,
                               "to_world": mi.ScalarTransform4f().look_at(
                                   origin=p, target=[p[k] + w[k] for k in range(3)], up=up)}
        elif l["type"] == "quad":
            u, v, c = l["edge_u"], l["edge_v"], l["corner"]
            n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            ln = sum(x * x for x in n) ** 0.5
            centre = [c[k] + 0.5 * (u[k] + v[k]) for k in range(3)]
            sides = [1.0, -1.0] if l.get("two_sided") else [1.0]
            for side in sides:
                # the back: edge_v and the normal reversed, moved 1e-5 of the quad's size behind the front
                gap = 0.0 if side > 0 else -1e-5 * ln ** 0.5
                m = [[0.5 * u[k], 0.5 * side * v[k], side * n[k] / ln, centre[k] + gap * n[k] / ln]
                     for k in range(3)] + [[0, 0, 0, 1]]
                d[f"light_{i}" + ("" if side > 0 else "_back")] = {
                    "type": "rectangle", "to_world": mi.ScalarTransform4f(m),
                    "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.0}},
                    "emitter": {"type": "area", "radiance": {"type": "rgb", "value": l["radiance"]}}}
        elif l["type"] == "directional":
            d[f"light_{i}"] = {"type": "directional", "direction": l["direction"],
                               "irradiance": {"type": "rgb", "value": l["irradiance"]}}
        else:
            raise SystemExit(f"peer_mitsuba: light type {l['type']} is not converted")
    env = job["environment"]
    if env and "radiance" in env:
        d["environment"] = {"type": "constant", "radiance": {"type": "rgb", "value": env["radiance"]}}
    elif env:
        d["environment"] = {"type": "envmap", "filename": env["map"], "scale": env.get("scale", 1.0),
                            "to_world": mi.ScalarTransform4f().rotate(axis=[0, 1, 0], angle=180.0)}
    return d


def timed_render(scene, spp, seed):
    t0 = time.perf_counter()
    img = mi.render(scene, spp=spp, seed=seed)
    dr.eval(img)
    dr.sync_thread()
    return img, time.perf_counter() - t0


def main():
    variant, job_path, result_path = sys.argv[1:4]
    mi.set_variant(variant)
    job = json.load(open(job_path))
    dr.set_thread_count(job["threads"])
    folder = os.path.dirname(os.path.abspath(result_path))
    scene = mi.load_dict(scene_dict(job, folder))
    result = {"renders": []}
    if variant.startswith("llvm"):
        timed_render(scene, 1, job["seed"])  # compiles the kernels of a 1-sample render
    _, result["fixed_seconds"] = timed_render(scene, 1, job["seed"])
    for r in job["renders"]:
        img, seconds = timed_render(scene, r["spp"], job["seed"])
        mi.Bitmap(img).write(r["out"])
        result["renders"].append({"spp": r["spp"], "seconds": seconds})
    json.dump(result, open(result_path, "w"), indent=1)


if __name__ == "__main__":
    main()
