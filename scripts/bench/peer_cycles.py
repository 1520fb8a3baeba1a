"""bench.peer_cycles — renders one bench.peers job with Blender Cycles (PyPI
`bpy`), in its own process:

    .venv/bin/python scripts/bench/peer_cycles.py JOB.json RESULT.json

JOB.json is bench.peer_scenes' job description plus "renders" (a list of
{"spp", "out"}), "width", "height", "max_depth", "threads" and "seed".
RESULT.json gets, per render, the wall seconds of bpy.ops.render.render (scene
sync and BVH included) and, once, the seconds of a 1-sample render, so the
caller can subtract the fixed cost.

Conversions (pmc's lights file -> Blender; measured for issue 36):
  point      power P = 4 pi I (a Blender point of P watts has intensity P/(4 pi) W/sr), radius 0
  spot       spot, power P = 4 pi I as a point's, spot_size = cone_angle_deg,
             spot_blend = blend (Cycles fades the last `blend` of the cone's
             cosine range by a smoothstep, pmc the last `blend` of its half
             angle: the penumbrae differ slightly; each renderer is measured
             against its own reference)
  quad       rectangular area light, power P = pi L |edge_u| |edge_v|; a
             two-sided quad is two lights back to back
  directional sun, strength = irradiance (W/m^2), angle = angle_deg
  environment world background: constant colour, or the map through an
             Environment Texture turned -90 degrees about Blender's Z so that
             pmc's lat-long convention and Blender's agree
Geometry goes through Blender's own OBJ importer (Y up -> Z up: a point
(x, y, z) of pmc is (x, -z, y) in Blender). Every material is rebuilt as a
Diffuse BSDF (Kd x map_Kd), plus an Emission of Ke, mixed with a Transparent
BSDF by map_d. Cycles settings: box pixel filter of 1 pixel, no adaptive
sampling, no denoising, no clamping, no glossy filter, max_bounces =
max_depth - 1 (pmc counts surface hits; Cycles counts bounces after the
first), the given threads. With "denoise" in the job, every render is denoised
by Open Image Denoise (albedo and normal, prefiltered) and RESULT.json gets
"denoise_seconds".
"""
import json
import math
import sys
import time

import bpy
from mathutils import Matrix, Vector


def bl(p):
    return Vector((p[0], -p[2], p[1]))


def look_at_matrix(eye, target, up):
    """A camera/light world matrix whose -Z looks from eye to target."""
    f = (target - eye).normalized()
    r = f.cross(up).normalized()
    u = r.cross(f)
    m = Matrix.Identity(4)
    for i in range(3):
        m[i][0], m[i][1], m[i][2], m[i][3] = r[i], u[i], -f[i], eye[i]
    return m


def frame_from_z(direction_minus_z, origin):
    """World matrix whose local -Z is `direction_minus_z`."""
    z = -direction_minus_z.normalized()
    helper = Vector((0.0, 0.0, 1.0)) if abs(z.z) < 0.9 else Vector((1.0, 0.0, 0.0))
    x = helper.cross(z).normalized()
    y = z.cross(x)
    m = Matrix.Identity(4)
    for i in range(3):
        m[i][0], m[i][1], m[i][2], m[i][3] = x[i], y[i], z[i], origin[i]
    return m


def build_material(mat, m):
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*m["kd"], 1.0)
    if m["map_kd"]:
        tex = nt.nodes.new("ShaderNodeTexImage")
        tex.image = bpy.data.images.load(m["map_kd"], check_existing=True)
        mul = nt.nodes.new("ShaderNodeMix")
        mul.data_type = "RGBA"
        mul.blend_type = "MULTIPLY"
        mul.inputs["Factor"].default_value = 1.0
        nt.links.new(tex.outputs["Color"], mul.inputs[6])
        mul.inputs[7].default_value = (*m["kd"], 1.0)
        nt.links.new(mul.outputs[2], diffuse.inputs["Color"])
    shader = diffuse.outputs["BSDF"]
    if any(m["ke"]):
        emit = nt.nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = (*m["ke"], 1.0)
        emit.inputs["Strength"].default_value = 1.0
        add = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(shader, add.inputs[0])
        nt.links.new(emit.outputs["Emission"], add.inputs[1])
        shader = add.outputs["Shader"]
    if m["map_d"]:
        alpha = nt.nodes.new("ShaderNodeTexImage")
        alpha.image = bpy.data.images.load(m["map_d"], check_existing=True)
        alpha.image.colorspace_settings.name = "Non-Color"
        clear = nt.nodes.new("ShaderNodeBsdfTransparent")
        mix = nt.nodes.new("ShaderNodeMixShader")
        nt.links.new(alpha.outputs["Color"], mix.inputs["Fac"])
        nt.links.new(clear.outputs["BSDF"], mix.inputs[1])
        nt.links.new(shader, mix.inputs[2])
        shader = mix.outputs["Shader"]
    nt.links.new(shader, out.inputs["Surface"])


def add_light(spec, index):
    kind = spec["type"]
    name = f"light_{index}"
    if kind in ("point", "spot"):
        data = bpy.data.lights.new(name, kind.upper())
        i = spec["intensity"]
        peak = max(i)
        data.energy = 4.0 * math.pi * peak  # a spot's power counts the whole sphere too
        data.color = [c / peak for c in i]
        data.shadow_soft_size = 0.0
        matrix = Matrix.Translation(bl(spec["position"]))
        if kind == "spot":
            data.spot_size = math.radians(spec.get("cone_angle_deg", 45.0))
            data.spot_blend = spec.get("blend", 0.15)
            matrix = frame_from_z(bl(spec["direction"]), bl(spec["position"]))
    elif kind == "quad" and spec.get("two_sided"):
        one = dict(spec, two_sided=False)
        add_light(one, f"{index}_front")
        # the back: the same rectangle with edge_v reversed (from the far corner), so it emits the other way
        c, v = spec["corner"], spec["edge_v"]
        add_light(dict(one, corner=[c[k] + v[k] for k in range(3)], edge_v=[-x for x in v]), f"{index}_back")
        return
    elif kind == "quad":
        data = bpy.data.lights.new(name, "AREA")
        u, v = bl(spec["edge_u"]), bl(spec["edge_v"])
        corner = bl(spec["corner"])
        data.shape = "RECTANGLE"
        data.size, data.size_y = u.length, v.length
        l = spec["radiance"]
        peak = max(l)
        data.energy = math.pi * peak * u.length * v.length
        data.color = [c / peak for c in l]
        n = u.cross(v).normalized()  # pmc's quad emits toward edge_u x edge_v
        x, y, z = u.normalized(), -v.normalized(), -n  # Blender's area light emits along -Z
        matrix = Matrix.Identity(4)
        centre = corner + 0.5 * (u + v)
        for k in range(3):
            matrix[k][0], matrix[k][1], matrix[k][2], matrix[k][3] = x[k], y[k], z[k], centre[k]
    elif kind == "directional":
        data = bpy.data.lights.new(name, "SUN")
        e = spec["irradiance"]
        peak = max(e)
        data.energy = peak
        data.color = [c / peak for c in e]
        data.angle = math.radians(spec.get("angle_deg", 0.0))
        matrix = frame_from_z(bl(spec["direction"]), Vector((0.0, 0.0, 0.0)))
    else:
        raise SystemExit(f"peer_cycles: light type {kind} is not converted")
    obj = bpy.data.objects.new(name, data)
    obj.visible_camera = True  # pmc's quads and sun disk are seen by camera rays; Blender's default hides lights
    obj.matrix_world = matrix
    bpy.context.scene.collection.objects.link(obj)


def setup_world(env):
    world = bpy.data.worlds.new("peers")
    bpy.context.scene.world = world
    world.use_nodes = True
    nt = world.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputWorld")
    bg = nt.nodes.new("ShaderNodeBackground")
    bg.inputs["Strength"].default_value = 1.0
    if env is None:
        bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    elif "radiance" in env:
        bg.inputs["Color"].default_value = (*env["radiance"], 1.0)
    else:
        coords = nt.nodes.new("ShaderNodeTexCoord")
        mapping = nt.nodes.new("ShaderNodeMapping")
        mapping.inputs["Rotation"].default_value = (0.0, 0.0, -0.5 * math.pi)
        tex = nt.nodes.new("ShaderNodeTexEnvironment")
        tex.image = bpy.data.images.load(env["map"], check_existing=True)
        tex.interpolation = "Closest"  # pmc looks texels up nearest
        nt.links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
        nt.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
        nt.links.new(tex.outputs["Color"], bg.inputs["Color"])
        bg.inputs["Strength"].default_value = env.get("scale", 1.0)
    nt.links.new(bg.outputs["Background"], out.inputs["Surface"])


def main():
    job = json.load(open(sys.argv[1]))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.wm.obj_import(filepath=job["obj"])
    for name, m in job["materials"].items():
        mat = bpy.data.materials.get(name)
        if mat is None:
            raise SystemExit(f"peer_cycles: the OBJ importer made no material {name}")
        build_material(mat, m)
    for i, light in enumerate(job["lights"]):
        add_light(light, i)
    setup_world(job["environment"])

    cam = job["camera"]
    cam_data = bpy.data.cameras.new("camera")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(cam["vfov"])
    cam_data.clip_start = 1e-3
    cam_data.clip_end = 1e6
    cam_obj = bpy.data.objects.new("camera", cam_data)
    cam_obj.matrix_world = look_at_matrix(bl(cam["from"]), bl(cam["at"]), bl(cam["up"]))
    scene.collection.objects.link(cam_obj)
    scene.camera = cam_obj

    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y, r.resolution_percentage = job["width"], job["height"], 100
    r.threads_mode = "FIXED"
    r.threads = job["threads"]
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    r.image_settings.color_mode = "RGB"
    c = scene.cycles
    c.device = "CPU"
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    bounces = max(job["max_depth"] - 1, 0)
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = bounces
    c.transparent_max_bounces = 64
    c.seed = job["seed"]
    scene.view_settings.view_transform = "Standard"

    result = {"renders": []}
    c.samples = 1
    r.filepath = job["renders"][0]["out"] + ".warm.exr"
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=False)
    result["fixed_seconds"] = time.perf_counter() - t0  # one sample and every fixed cost
    if job.get("denoise"):
        # Open Image Denoise with albedo and normal, prefiltered (pmc --denoise's counterpart); its
        # time: a denoised 1-sample render's less the plain one's
        scene.view_layers[0].cycles.denoising_store_passes = False
        c.use_denoising = True
        c.denoiser = "OPENIMAGEDENOISE"
        c.denoising_input_passes = "RGB_ALBEDO_NORMAL"
        c.denoising_prefilter = "ACCURATE"
        c.denoising_use_gpu = False
        t0 = time.perf_counter()
        bpy.ops.render.render(write_still=False)
        denoised = time.perf_counter() - t0
        result["denoise_seconds"] = max(denoised - result["fixed_seconds"], 0.0)
        result["fixed_seconds"] = denoised
    for job_render in job["renders"]:
        c.samples = job_render["spp"]
        r.filepath = job_render["out"]
        t0 = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        result["renders"].append({"spp": job_render["spp"], "seconds": time.perf_counter() - t0})
    json.dump(result, open(sys.argv[2], "w"), indent=1)


if __name__ == "__main__":
    main()
