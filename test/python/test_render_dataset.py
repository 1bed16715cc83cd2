#!/usr/bin/python3
"""render_dataset's bench scenes (--bench-fraction) against its random scenes; the classes come from
a catalog (--catalog), in its order; appearance randomisation (--textures, --camera-effects, --photos) changes
the pixels only; a catalog's colour is its class's in the renders; --depth writes the registered depth image;
--scenarios renders frames of generated scenarios, labelled with their objects' poses.

  /usr/bin/python3 test/python/test_render_dataset.py --tool=PATH/render_dataset [--xml=RESULT.xml]

With --xml a JUnit result for catkin's run_tests (make test) is written.
"""
import glob
import hashlib
import json
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import junit_runner  # noqa: E402
from detector_export import dataset_names  # noqa: E402

TOOL = None


def render(out, count, seed, fraction=None):
    args = [TOOL, "--output", out, "--count", str(count), "--seed", str(seed)]
    if fraction is not None:
        args += ["--bench-fraction", str(fraction)]
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    poses = [json.load(open(p)) for p in sorted(glob.glob(os.path.join(out, "poses", "*.json")))]
    return poses


def digest(out, sub):
    h = hashlib.md5()
    for p in sorted(glob.glob(os.path.join(out, sub, "*"))):
        h.update(open(p, "rb").read())
    return h.hexdigest()


class BenchScenes(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.bench = render(os.path.join(cls.tmp.name, "bench"), 12, 5, 1.0)
        cls.random = render(os.path.join(cls.tmp.name, "random"), 12, 5)

    def objects(self, poses):
        return [o for p in poses for o in p["objects"]]

    def test_the_fraction_chooses_the_scene_kind(self):
        self.assertEqual({p["scene"] for p in self.bench}, {"bench"})
        self.assertEqual({p["scene"] for p in self.random}, {"random"})
        mixed = render(os.path.join(self.tmp.name, "mixed"), 40, 6, 0.5)
        n = sum(p["scene"] == "bench" for p in mixed)
        self.assertTrue(8 <= n <= 32, n)

    def test_bench_objects_stand_upright_at_the_robots_distances(self):
        objects = self.objects(self.bench)
        self.assertGreaterEqual(len(objects), 20)
        T = np.array([o["T_camera_object"] for o in objects])
        distance = np.linalg.norm(T[:, :3, 3], axis=1)
        # The camera is 0.9-3.4 m (horizontally) from a point on the bench; the objects are around it.
        self.assertTrue(((distance > 0.5) & (distance < 4.5)).all(), distance)
        self.assertTrue(1.5 < np.median(distance) < 2.8, distance)
        # The camera looks down a little with hardly any roll: up is about -y of the optical frame.
        up = -T[:, 1, 2]  # the object's z axis, seen in the camera frame, dotted with "up"
        self.assertGreater(np.mean(up > 0.6), 0.7, up)
        random_up = -np.array([o["T_camera_object"] for o in self.objects(self.random)])[:, 1, 2]
        self.assertLess(np.mean(random_up > 0.6), np.mean(up > 0.6))

    def test_bench_scenes_show_several_classes_side_by_side(self):
        per_image = [len({o["class"] for o in p["objects"]}) for p in self.bench]
        self.assertGreaterEqual(np.mean(per_image), 1.8, per_image)

    def test_fraction_zero_renders_the_images_of_no_fraction(self):
        out = os.path.join(self.tmp.name, "zero")
        render(out, 12, 5, 0.0)
        for sub in ("images", "labels"):
            self.assertEqual(digest(out, sub), digest(os.path.join(self.tmp.name, "random"), sub))

    def test_cuboid_labels_reorder_the_same_corners(self):
        out = os.path.join(self.tmp.name, "cuboid")
        subprocess.run([TOOL, "--output", out, "--count", "12", "--seed", "5", "--labels", "cuboid"], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        random = os.path.join(self.tmp.name, "random")
        self.assertEqual(digest(out, "images"), digest(random, "images"))
        reordered = 0
        for name in sorted(os.listdir(os.path.join(out, "labels"))):
            a = np.loadtxt(os.path.join(random, "labels", name), ndmin=2)
            b = np.loadtxt(os.path.join(out, "labels", name), ndmin=2)
            self.assertEqual(a.shape, b.shape)
            np.testing.assert_array_equal(a[:, :5], b[:, :5])  # class and box
            for ra, rb in zip(a, b):
                if ra[0] == 1:  # the screwdriver: a continuous symmetry, sampled in 5 degree steps
                    continue
                ka, kb = ra[5:].reshape(9, 3), rb[5:].reshape(9, 3)
                for k in kb[kb[:, 2] > 0]:  # every labelled corner is one of the object's corners
                    self.assertLess(np.abs(ka[:, :2] - k[:2]).sum(1).min(), 1e-5)
                np.testing.assert_allclose(ka[8], kb[8], atol=1e-6)  # the centre stays
                reordered += not np.allclose(ka, kb)
        self.assertGreater(reordered, 0)
        self.assertIn("--labels cuboid", open(os.path.join(out, "dataset.yaml")).read())

    def test_the_classes_are_the_catalogs_in_its_order(self):
        self.assertEqual(dataset_names(os.path.join(self.tmp.name, "random")),
                         ["multimeter", "screwdriver", "materialbox", "klt", "relay"])
        catalog = os.path.join(self.tmp.name, "two.yaml")
        with open(catalog, "w") as f:
            f.write("objects:\n"
                    "  relay: {mesh: package://scene_graph_tracker/meshes/relay.stl}\n"
                    "  klt: {mesh: package://scene_graph_tracker/meshes/klt.stl}\n")
        out = os.path.join(self.tmp.name, "two")
        subprocess.run([TOOL, "--output", out, "--count", "8", "--seed", "3", "--catalog", catalog], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.assertEqual(dataset_names(out), ["relay", "klt"])
        objects = [o for p in sorted(glob.glob(os.path.join(out, "poses", "*.json"))) for o in json.load(open(p))["objects"]]
        self.assertGreater(len(objects), 4)
        self.assertEqual({(o["class"], o["class_id"]) for o in objects}, {("relay", 0), ("klt", 1)})
        ids = {int(row[0]) for name in os.listdir(os.path.join(out, "labels"))
               for row in np.loadtxt(os.path.join(out, "labels", name), ndmin=2)}
        self.assertEqual(ids, {0, 1})

    def test_appearance_changes_the_pixels_and_not_the_labels(self):
        out = os.path.join(self.tmp.name, "looks")
        subprocess.run([TOOL, "--output", out, "--count", "12", "--seed", "5", "--textures", "1",
                        "--camera-effects", "1"], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        random = os.path.join(self.tmp.name, "random")
        self.assertEqual(digest(out, "labels"), digest(random, "labels"))
        self.assertEqual(digest(out, "poses"), digest(random, "poses"))
        from PIL import Image
        changed = []
        for name in sorted(os.listdir(os.path.join(out, "images"))):
            a = np.asarray(Image.open(os.path.join(random, "images", name)), dtype=float)
            b = np.asarray(Image.open(os.path.join(out, "images", name)), dtype=float)
            changed.append(np.mean(np.abs(a - b).sum(2) > 30))
        self.assertGreater(min(changed), 0.05, changed)  # every image looks different
        self.assertIn("--textures 1 --camera-effects 1", open(os.path.join(out, "dataset.yaml")).read())

    def test_photos_go_behind_the_scene_and_leave_the_labels(self):
        photos = os.path.join(self.tmp.name, "photos")
        os.makedirs(photos)
        from PIL import Image
        Image.new("RGB", (64, 48), (255, 0, 255)).save(os.path.join(photos, "magenta.png"))
        out = os.path.join(self.tmp.name, "photo")
        subprocess.run([TOOL, "--output", out, "--count", "12", "--seed", "5", "--photos", photos],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        random = os.path.join(self.tmp.name, "random")
        self.assertEqual(digest(out, "labels"), digest(random, "labels"))
        self.assertEqual(digest(out, "poses"), digest(random, "poses"))
        behind = []  # share of pixels that show the photo itself, unshaded
        for name in sorted(os.listdir(os.path.join(out, "images"))):
            img = np.asarray(Image.open(os.path.join(out, "images", name)))
            behind.append(np.mean(np.all(img == (255, 0, 255), axis=2)))
        self.assertGreaterEqual(sum(b > 0.2 for b in behind), 3, behind)  # about half the images
        self.assertIn("--photos " + photos, open(os.path.join(out, "dataset.yaml")).read())
        r = subprocess.run([TOOL, "--output", os.path.join(self.tmp.name, "none"), "--count", "1", "--photos",
                            os.path.join(self.tmp.name, "labels_only")], capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        os.makedirs(os.path.join(self.tmp.name, "empty"))
        r = subprocess.run([TOOL, "--output", os.path.join(self.tmp.name, "none"), "--count", "1", "--photos",
                            os.path.join(self.tmp.name, "empty")], capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn("no readable", r.stderr)

    def test_a_catalog_colour_is_the_classs_and_without_one_colours_vary(self):
        catalog = os.path.join(self.tmp.name, "coloured.yaml")
        with open(catalog, "w") as f:
            f.write("objects:\n"
                    "  red: {mesh: package://scene_graph_tracker/meshes/materialbox.stl, colour: [0.9, 0.05, 0.05]}\n"
                    "  any: {mesh: package://scene_graph_tracker/meshes/materialbox.stl}\n")
        out = os.path.join(self.tmp.name, "coloured")
        subprocess.run([TOOL, "--output", out, "--count", "24", "--seed", "5", "--catalog", catalog],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        from PIL import Image
        colours = {"red": [], "any": []}  # median colour inside each labelled object's box centre
        for path in sorted(glob.glob(os.path.join(out, "poses", "*.json"))):
            img = np.asarray(Image.open(path.replace("poses", "images").replace(".json", ".png")), dtype=float)
            for row in np.loadtxt(path.replace("poses", "labels").replace(".json", ".txt"), ndmin=2):
                if row[3] * 640 < 20 or row[4] * 480 < 20:
                    continue
                u, v = int(row[1] * 640), int(row[2] * 480)
                patch = img[v - 3:v + 4, u - 3:u + 4].reshape(-1, 3)
                colours[["red", "any"][int(row[0])]].append(np.median(patch, axis=0))
        red = [c[0] > 2 * c[1] and c[0] > 2 * c[2] for c in colours["red"]]
        self.assertGreater(len(red), 8)
        self.assertGreater(np.mean(red), 0.7, colours["red"])
        hues = np.array(colours["any"]) / (np.array(colours["any"]).sum(1, keepdims=True) + 1)
        self.assertGreater(len(hues), 8)
        self.assertGreater(hues.std(0).mean(), 0.05, hues)  # no one colour for a class of unknown colour

    def test_depth_is_registered_with_the_image_and_in_millimetres(self):
        out = os.path.join(self.tmp.name, "depth")
        subprocess.run([TOOL, "--output", out, "--count", "12", "--seed", "5", "--bench-fraction", "1",
                        "--depth", "1"], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.assertFalse(os.path.exists(os.path.join(self.tmp.name, "bench", "depth")))  # only on request
        self.assertEqual(digest(out, "images"), digest(os.path.join(self.tmp.name, "bench"), "images"))
        from PIL import Image
        gaps = []  # object centre's z minus the depth at its projection: the surface lies in front of it
        for path in sorted(glob.glob(os.path.join(out, "poses", "*.json"))):
            pose = json.load(open(path))
            depth = np.asarray(Image.open(path.replace("poses", "depth").replace(".json", ".png")))
            self.assertEqual(depth.shape, (pose["height"], pose["width"]))
            self.assertGreater(depth.max(), 500)  # millimetres: the bench is metres away
            K = np.array(pose["K"]).reshape(3, 3)
            for o in pose["objects"]:
                t = np.array(o["T_camera_object"])[:3, 3]
                u, v, _ = K @ (t / t[2])
                if 0 <= round(u) < pose["width"] and 0 <= round(v) < pose["height"] and o["visible_pixels"] > 300:
                    gaps.append(t[2] - depth[round(v), round(u)] / 1000.0)
        self.assertGreater(len(gaps), 10)
        self.assertTrue(0.0 <= np.median(gaps) < 0.15, np.median(gaps))

    def test_a_fraction_outside_zero_to_one_is_refused(self):
        for flag in ("--bench-fraction", "--textures", "--camera-effects", "--scenario-fraction"):
            r = subprocess.run([TOOL, "--output", os.path.join(self.tmp.name, "bad"), "--count", "1", flag, "1.5"],
                               capture_output=True, text=True)
            self.assertEqual(r.returncode, 2, flag)
            self.assertIn(flag, r.stderr)


class ScenarioFrames(unittest.TestCase):
    """Frames of generated scenarios (generate_scenarios beside render_dataset)."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.scenarios = os.path.join(cls.tmp.name, "scenarios")
        subprocess.run([os.path.join(os.path.dirname(TOOL), "generate_scenarios"), "--count", "3", "--seed", "101",
                        "--output", cls.scenarios], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        cls.out = os.path.join(cls.tmp.name, "frames")
        cls.poses = cls.render(cls.out, 1.0)

    @classmethod
    def render(cls, out, fraction):
        subprocess.run([TOOL, "--output", out, "--count", "15", "--seed", "5", "--scenarios", cls.scenarios,
                        "--scenario-fraction", str(fraction)], check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        return [json.load(open(p)) for p in sorted(glob.glob(os.path.join(out, "poses", "*.json")))]

    def scenario_classes(self, k):
        text = open(os.path.join(self.scenarios, "scenario_%03d.yaml" % (k + 1))).read()
        return {line.split(":")[1].strip() for line in text.splitlines() if line.strip().startswith("class:")}

    def test_each_block_of_images_shows_the_objects_of_its_scenario(self):
        self.assertEqual({p["scene"] for p in self.poses}, {"scenario"})
        for k in range(3):  # 15 images, 3 scenarios: five each
            shown = {o["class"] for p in self.poses[5 * k:5 * k + 5] for o in p["objects"]}
            self.assertTrue(shown, k)
            self.assertLessEqual(shown, self.scenario_classes(k), k)

    def test_labels_project_the_objects_pose_into_its_box(self):
        centres = 0
        for i, p in enumerate(self.poses):
            K = np.array(p["K"]).reshape(3, 3)
            lines = open(os.path.join(self.out, "labels", "%06d.txt" % i)).read().split("\n")
            boxes = [[float(x) for x in line.split()[1:5]] for line in lines if line.strip()]
            self.assertEqual(len(boxes), len(p["objects"]), i)
            for o, (cx, cy, w, h) in zip(p["objects"], boxes):
                t = np.array(o["T_camera_object"])[:3, 3]
                self.assertTrue(0.4 < t[2] < 6.0, t)  # in front of the camera, within its range
                u, v, _ = K @ (t / t[2])
                if o["visible_pixels"] > 1500:  # mostly in view: its centre projects into its box
                    centres += 1
                    self.assertLess(abs(u / p["width"] - cx), w / 2 + 0.02, (i, o["class"]))
                    self.assertLess(abs(v / p["height"] - cy), h / 2 + 0.02, (i, o["class"]))
        self.assertGreater(centres, 10)

    def test_the_other_images_stay_as_they_were(self):
        mixed = self.render(os.path.join(self.tmp.name, "mixed"), 0.5)
        plain = render(os.path.join(self.tmp.name, "plain"), 15, 5)
        kinds = [p["scene"] for p in mixed]
        self.assertTrue(2 <= kinds.count("scenario") <= 13, kinds)
        for i, kind in enumerate(kinds):
            same = mixed[i] == plain[i]
            self.assertEqual(same, kind == "random", i)

    def test_depth_is_refused_with_scenarios(self):
        r = subprocess.run([TOOL, "--output", os.path.join(self.tmp.name, "bad"), "--count", "1", "--scenarios",
                            self.scenarios, "--depth", "1"], capture_output=True, text=True)
        self.assertEqual(r.returncode, 2)
        self.assertIn("--depth", r.stderr)


if __name__ == "__main__":
    TOOL = junit_runner.argument("tool")
    if not TOOL:
        sys.exit("usage: test_render_dataset.py --tool=PATH/render_dataset [--xml=RESULT.xml]")
    junit_runner.main("render_dataset", BenchScenes, ScenarioFrames)
