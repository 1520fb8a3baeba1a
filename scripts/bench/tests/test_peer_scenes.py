"""Tests of bench.peer_scenes' own OBJ/MTL reading and writing (what pmc,
Blender and Mitsuba are given in bench.peers), against hand-counted answers."""
import json
import os
import tempfile
import unittest

from bench import peer_scenes

OBJ = """mtllib a.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vn 0 0 1
vn 0 0 0
usemtl red
f 1/1/1 2/2/1 3/3/1 4/1/1
usemtl lamp
f -4 -3 -2
v 2 0 0
f 1//2 2//2 5//2
"""
MTL = """newmtl red
Kd 0.5 0 0
map_Kd .\\tex\\red.png
newmtl lamp
Kd 0 0 0
Ke 3 2 1
map_d -bm 1 mask.png
"""


def read_faces(path):
    v, f = [], []
    with open(path) as fh:
        lines = fh.readlines()
    for line in lines:
        p = line.split()
        if p and p[0] == "v":
            v.append(tuple(float(x) for x in p[1:]))
        elif p and p[0] == "f":
            f.append([v[int(c.split("/")[0]) - 1] for c in p[1:]])
    return f


class PeerScenes(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        d = self.tmp.name
        with open(os.path.join(d, "a.obj"), "w") as f:
            f.write(OBJ)
        with open(os.path.join(d, "a.mtl"), "w") as f:
            f.write(MTL)
        self.spec = {"what": "test", "objs": [os.path.join(d, "a.obj")], "camera": ((0, 0, 5), (0, 0, 0), 40.0),
                     "lights": [{"type": "point", "position": [0, 0, 1], "intensity": [1, 1, 1]}],
                     "environment": {"radiance": [0.5, 0.5, 0.5]}}
        self.job = peer_scenes.write_scene_files("t", os.path.join(d, "out"), self.spec)

    def tearDown(self):
        self.tmp.cleanup()

    def test_polygons_fan_into_triangles_and_negative_indices_resolve(self):
        # the quad gives 2 triangles, the negative-index and the degenerate one 1 each
        self.assertEqual(self.job["triangles"], 4)
        faces = read_faces(self.job["obj"])
        self.assertEqual(len(faces), 4)
        self.assertEqual(faces[2], [(0, 0, 0), (1, 0, 0), (1, 1, 0)])  # f -4 -3 -2 after v 1..4

    def test_materials_are_diffuse_stand_ins_with_absolute_maps(self):
        m = self.job["materials"]
        self.assertEqual(sorted(m), ["lamp", "red"])
        self.assertEqual(m["red"]["kd"], [0.5, 0.0, 0.0])
        self.assertEqual(m["red"]["map_kd"], os.path.join(self.tmp.name, "tex", "red.png"))
        self.assertEqual(m["lamp"]["ke"], [3.0, 2.0, 1.0])
        self.assertEqual(m["lamp"]["map_d"], os.path.join(self.tmp.name, "mask.png"))
        with open(os.path.join(os.path.dirname(self.job["obj"]), "scene.mtl")) as f:
            mtl = f.read()
        self.assertIn("Ks 0 0 0", mtl)
        self.assertIn("Ke 3 2 1", mtl)

    def test_parts_hold_one_material_each_and_drop_what_mitsuba_rejects(self):
        parts = {p["material"]: p["obj"] for p in self.job["parts"]}
        self.assertEqual(len(read_faces(parts["red"])), 2)
        # the lamp's degenerate triangle is dropped; its zero normals do not appear
        with open(parts["lamp"]) as f:
            lamp = f.read()
        self.assertEqual(len(read_faces(parts["lamp"])), 1)
        self.assertNotIn("vn 0 0 0", lamp)
        self.assertEqual(lamp.count("\nv "), 3 - 1)  # re-indexed: only the 3 used positions

    def test_lights_file_holds_the_lights_and_the_environment(self):
        with open(self.job["lights_file"]) as f:
            lights = json.load(f)
        self.assertEqual(lights["lights"], self.spec["lights"])
        self.assertEqual(lights["environment"], {"radiance": [0.5, 0.5, 0.5]})

    def test_generated_objs_are_written_into_the_folder_and_merged(self):
        spec = dict(self.spec, generated={"box.obj": "v 0 0 9\nv 1 0 9\nv 0 1 9\nusemtl far\nf 1 2 3\n"})
        job = peer_scenes.write_scene_files("t", os.path.join(self.tmp.name, "gen"), spec)
        self.assertTrue(os.path.exists(os.path.join(self.tmp.name, "gen", "box.obj")))
        self.assertEqual(job["triangles"], 5)
        self.assertIn("far", job["materials"])  # a material no MTL defines: the default stand-in
        self.assertEqual(job["materials"]["far"]["kd"], [0.8, 0.8, 0.8])
        self.assertIn([(0, 0, 9), (1, 0, 9), (0, 1, 9)], read_faces(job["obj"]))


class InteriorScene(unittest.TestCase):
    """The many-lights interior: the default room, data/default/many.lights.json's lights and
    world colour, and the stray box far above (issue 36's held-out interior, in kind)."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
        cwd = os.getcwd()
        os.chdir(root)  # the scenes name their OBJs from the repository's root, as bench.peers runs
        try:
            self.job = peer_scenes.write_scene_files("interior", self.tmp.name)
        finally:
            os.chdir(cwd)
        with open(os.path.join(root, "data", "default", "many.lights.json")) as f:
            self.many = json.load(f)

    def tearDown(self):
        self.tmp.cleanup()

    def test_lights_and_world_colour_come_from_the_many_lights_file(self):
        self.assertEqual(self.job["lights"], self.many["lights"])
        self.assertEqual(self.job["environment"], self.many["environment"])
        kinds = [l["type"] for l in self.job["lights"]]
        self.assertEqual((kinds.count("point"), kinds.count("spot"), kinds.count("quad")), (12, 8, 10))

    def test_the_stray_box_is_closed_and_18_m_above_the_roof(self):
        faces = read_faces(self.job["obj"])
        box = [f for f in faces if min(p[1] for p in f) >= 21.0]
        self.assertEqual(len(box), 12)  # six quads, two triangles each
        room_top = max(p[1] for f in faces if f not in box for p in f)
        self.assertAlmostEqual(room_top, 3.0)
        # closed: every edge of the box is shared by exactly two of its triangles
        edges = {}
        for f in box:
            for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
                key = tuple(sorted((a, b)))
                edges[key] = edges.get(key, 0) + 1
        self.assertEqual(set(edges.values()), {2})


if __name__ == "__main__":
    unittest.main()
