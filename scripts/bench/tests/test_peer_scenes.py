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


if __name__ == "__main__":
    unittest.main()
