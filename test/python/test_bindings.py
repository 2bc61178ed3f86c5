#!/usr/bin/python3
"""The Python bindings (import hope) against the demo room's ground truth and against the C++
command-line tool on the same input. Run by ctest; needs HOPE_SYNTH_BIN and HOPE_EXTRACT_BIN
(the built tools) and the bindings on PYTHONPATH."""

import json
import os
import subprocess
import tempfile
import unittest
import warnings

import cv2
import numpy as np

import hope

TUM_FREIBURG1 = (517.3, 516.5, 318.6, 255.3)  # the demo camera's intrinsics (hope_synth)


def up_in_sensor(pose):
    """The world's +z in the frame of a sensor at pose (tx ty tz qx qy qz qw): R^T z."""
    x, y, z, w = pose[3:]
    # The third row of R(q), which is R^T's third column.
    return np.array([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)])


def degrees_between(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    cosine = np.dot(a, b) / np.linalg.norm(a) / np.linalg.norm(b)
    return np.degrees(np.arccos(np.clip(cosine, -1, 1)))


def read_truth(path):
    """(height, name) of every plane the demo room holds, from hope_synth's truth.txt."""
    surfaces = []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            _, height, name = line.split(maxsplit=2)
            surfaces.append((float(height), name.strip()))
    return surfaces


def read_pcd_labels(path, field="label"):
    """A field (`label` or `object`) of a PCD written by hope_extract --labels (ascii or binary)."""
    with open(path, "rb") as f:
        header = {}
        while True:
            line = f.readline().decode("ascii").strip()
            key, _, value = line.partition(" ")
            header[key] = value.split()
            if key == "DATA":
                break
        body = f.read()
    fields = header["FIELDS"]
    types = {("F", "4"): "<f4", ("U", "4"): "<u4", ("I", "4"): "<i4"}
    dtype = np.dtype([(name, types[(t, s)]) for name, t, s in
                      zip(fields, header["TYPE"], header["SIZE"])])
    count = int(header["POINTS"][0])
    if header["DATA"][0] == "ascii":
        rows = np.loadtxt(body.decode("ascii").splitlines(), ndmin=2)
        return rows[:, fields.index(field)].astype(np.int64)
    return np.frombuffer(body, dtype=dtype, count=count)[field].astype(np.int64)


class DemoRoom(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = cls.tmp.name
        subprocess.run([os.environ["HOPE_SYNTH_BIN"], "--out", cls.dir], check=True,
                       stdout=subprocess.DEVNULL)
        cls.depth = cv2.imread(os.path.join(cls.dir, "depth.png"), cv2.IMREAD_UNCHANGED)
        with open(os.path.join(cls.dir, "pose.txt")) as f:
            cls.pose = [float(v) for v in f.read().split()]
        cls.truth = read_truth(os.path.join(cls.dir, "truth.txt"))
        cls.points = hope.depth_to_cloud(cls.depth, TUM_FREIBURG1, 5000.0)
        cls.result = hope.Extractor(r_xy=0.05, r_z=0.02).extract(cls.points, pose=cls.pose)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_depth_to_cloud_is_organized_metres(self):
        self.assertEqual(self.depth.dtype, np.uint16)
        self.assertEqual(self.points.shape, (480, 640, 3))
        self.assertEqual(self.points.dtype, np.float32)
        valid = self.depth > 0
        # z (forward) is the depth in metres at every pixel with a depth, NaN elsewhere.
        np.testing.assert_allclose(self.points[..., 2][valid], self.depth[valid] / 5000.0,
                                   rtol=1e-6)
        self.assertTrue(np.isnan(self.points[..., 2][~valid]).all())

    def test_every_true_surface_is_one_plane_at_its_height(self):
        heights = sorted(p.height for p in self.result.planes)
        self.assertEqual(len(heights), len(self.truth), heights)
        for true_height, name in self.truth:
            nearest = min(heights, key=lambda h: abs(h - true_height))
            self.assertLess(abs(nearest - true_height), 0.01, name)

    def test_labels_are_per_pixel_and_count_each_planes_points(self):
        labels = self.result.labels
        self.assertEqual(labels.shape, (480, 640))
        self.assertEqual(labels.dtype, np.int32)
        for index, plane in enumerate(self.result.planes):
            self.assertEqual(int((labels == index).sum()), plane.num_points)
        self.assertTrue((labels[np.isnan(self.points[..., 2])] == -1).all())

    def test_same_planes_and_labels_as_the_command_line_tool(self):
        json_path = os.path.join(self.dir, "planes.json")
        labels_path = os.path.join(self.dir, "labels.pcd")
        subprocess.run([os.environ["HOPE_EXTRACT_BIN"], "--depth",
                        os.path.join(self.dir, "depth.png"), "--pose",
                        " ".join(repr(v) for v in self.pose), "--json", json_path,
                        "--labels", labels_path, "--quiet"], check=True)
        with open(json_path) as f:
            cli = json.load(f)
        ours = self.result.to_dict()
        self.assertEqual(len(ours["planes"]), len(cli["planes"]))
        self.assertEqual(set(ours["planes"][0]), set(cli["planes"][0]))  # every JSON field
        for a, b in zip(ours["planes"], cli["planes"]):
            self.assertEqual(a["id"], b["id"])
            self.assertEqual(a["num_points"], b["num_points"])
            self.assertEqual(a["num_voxels"], b["num_voxels"])
            self.assertEqual(a["facing"], b["facing"])
            # The JSON carries 6 significant digits.
            for key in ("height", "bbox", "centroid", "normal", "area", "hull"):
                np.testing.assert_allclose(a[key], np.array(b[key]), rtol=1e-5, atol=1e-6,
                                           err_msg=key)
        self.assertEqual(ours["stats"], cli["stats"])
        # The CLI writes label k + 1 for plane id k, 0 for none.
        cli_labels = read_pcd_labels(labels_path)
        np.testing.assert_array_equal(self.result.labels.ravel().astype(np.int64) + 1, cli_labels)

    def test_every_array_layout_gives_identical_planes(self):
        # depth_to_cloud returns a float32 view with 16-byte points (read in place); a packed
        # float32 copy is read in place too; float64 and Fortran order take the conversion
        # path. The answer must not depend on the layout.
        extractor = hope.Extractor()
        for points in (np.ascontiguousarray(self.points), self.points.astype(np.float64),
                       np.asfortranarray(self.points)):
            other = extractor.extract(points, pose=self.pose)
            self.assertEqual([p.num_points for p in other.planes],
                             [p.num_points for p in self.result.planes])
            self.assertEqual([p.height for p in other.planes],
                             [p.height for p in self.result.planes])
            np.testing.assert_array_equal(other.labels, self.result.labels)

    def test_two_threads_give_identical_planes_and_labels(self):
        other = hope.Extractor(r_xy=0.05, r_z=0.02, threads=2).extract(self.points, pose=self.pose)
        self.assertEqual(len(other.planes), len(self.result.planes))
        for mine, reference in zip(other.planes, self.result.planes):
            a, b = mine.to_dict(), reference.to_dict()
            self.assertEqual(sorted(a), sorted(b))
            for key in a:
                if key == "outline":  # rings of different lengths
                    self.assertEqual(len(a[key]), len(b[key]))
                    for ring_a, ring_b in zip(a[key], b[key]):
                        np.testing.assert_array_equal(ring_a, ring_b, err_msg=key)
                else:
                    np.testing.assert_array_equal(a[key], b[key], err_msg=key)
        np.testing.assert_array_equal(other.labels, self.result.labels)

    def test_an_unorganized_copy_finds_the_same_surfaces(self):
        # N x 3 drops the image layout (the scan-gap bridging then applies), so point counts
        # may differ slightly; the surfaces and their heights may not.
        finite = self.points.reshape(-1, 3)
        finite = finite[np.isfinite(finite).all(axis=1)]
        result = hope.Extractor().extract(finite, pose=self.pose)
        self.assertEqual(result.labels.shape, (len(finite),))
        heights = sorted(p.height for p in result.planes)
        self.assertEqual(len(heights), len(self.truth), heights)
        for true_height, name in self.truth:
            self.assertLess(min(abs(h - true_height) for h in heights), 0.01, name)

    def test_level_finds_up_from_the_scene(self):
        # No orientation: up from the floor, table, cabinet and treads; heights relative to the
        # camera, which hope_synth puts 1.5 m above the floor.
        result = hope.Extractor().extract(self.points, level=True)
        truth = up_in_sensor(self.pose)
        self.assertLess(degrees_between(result.up_in_sensor, truth), 0.5)
        self.assertLess(degrees_between(result.levelling["up_in_sensor"], truth), 0.5)
        self.assertEqual(result.levelling["source"], "scene")
        self.assertEqual(result.levelling["prior"], "camera")
        self.assertGreater(result.levelling["support_area_m2"], 1.0)
        heights = [p.height for p in result.planes]
        for true_height, name in self.truth:
            relative = true_height - self.pose[2]
            self.assertLess(min(abs(h - relative) for h in heights), 0.02, name)
        self.assertEqual(result.to_dict()["levelling"]["source"], "scene")
        np.testing.assert_allclose(result.to_dict()["up_in_sensor"], result.up_in_sensor)

    def test_level_refines_a_given_gravity_within_its_bound(self):
        truth = up_in_sensor(self.pose)
        axis = np.cross(truth, [0.3, 0.5, 0.8])
        axis /= np.linalg.norm(axis)
        angle = np.radians(3.0)  # Rodrigues: truth turned 3° about axis
        off = (truth * np.cos(angle) + np.cross(axis, truth) * np.sin(angle) +
               axis * np.dot(axis, truth) * (1 - np.cos(angle)))
        refined = hope.Extractor().extract(self.points, gravity=tuple(off), level=True)
        self.assertEqual(refined.levelling["source"], "refined")
        self.assertTrue(refined.levelling["applied"])
        self.assertAlmostEqual(refined.levelling["correction_deg"], 3.0, delta=0.5)
        self.assertLess(degrees_between(refined.up_in_sensor, truth), 0.5)
        # A bound under the error keeps the given gravity, and says so.
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            kept = hope.Extractor().extract(self.points, gravity=tuple(off), level=True,
                                            level_bound=1.0)
        self.assertFalse(kept.levelling["applied"])
        self.assertLess(degrees_between(kept.up_in_sensor, off), 1e-6)
        self.assertTrue(any("kept the given orientation" in str(w.message) for w in caught))
        self.assertRaisesRegex(ValueError, "max_correction", hope.Extractor().extract,
                               self.points, level=True, level_bound=60.0)

    def test_no_orientation_on_a_camera_cloud_warns_and_names_the_options(self):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = hope.Extractor().extract(self.points)
        self.assertEqual(len(result.warnings), 1, result.warnings)
        self.assertIn("optical frame", result.warnings[0])
        self.assertIn("level=True", result.warnings[0])
        self.assertTrue(any(issubclass(w.category, UserWarning) and
                            "optical frame" in str(w.message) for w in caught))
        # With an orientation there is nothing to say.
        self.assertEqual(hope.Extractor().extract(self.points, pose=self.pose).warnings, [])

    def test_tracker_keeps_every_id_on_a_second_view(self):
        for mode in ("improved", "paper"):
            tracker = hope.PlaneTracker(mode=mode)
            first = hope.Extractor().extract(self.points, pose=self.pose)
            events = tracker.update(first, 0.0)
            self.assertEqual(sorted(e.id for e in events if e.kind == "new"),
                             list(range(len(self.truth))))
            second = hope.Extractor().extract(self.points, pose=self.pose)
            tracker.update(second, 1.0 / 30)
            by_height = {round(p.height, 3): p.id for p in first.planes}
            for plane in second.planes:
                self.assertEqual(plane.id, by_height[round(plane.height, 3)], mode)
                self.assertEqual(plane.age, 2)

    def test_surface_map_keeps_each_surface_one_id_and_refuses_bad_options(self):
        surface_map = hope.SurfaceMap(cell=0.05)
        first = hope.Extractor().extract(self.points, pose=self.pose)
        events = surface_map.update(first, 0.0, viewpoint=self.pose[:3])
        self.assertEqual(len([e for e in events if e.kind == "new"]), len(self.truth))
        second = hope.Extractor().extract(self.points, pose=self.pose)
        surface_map.update(second, 1.0)
        by_height = {round(p.height, 3): p.id for p in first.planes}
        for plane in second.planes:
            self.assertEqual(plane.id, by_height[round(plane.height, 3)])
        surfaces = surface_map.surfaces()
        self.assertEqual(len(surface_map), len(self.truth))
        for surface in surfaces:
            self.assertEqual(surface.age, 2)
            self.assertTrue(surface.outline)
        with self.assertRaisesRegex(ValueError, "cell"):
            hope.SurfaceMap(cell=0.0)
        with self.assertRaisesRegex(ValueError, "tilt_error_deg"):
            hope.SurfaceMap(tilt_error_deg=-1.0)
        hope.SurfaceMap(tilt_error_deg=0.0, height_error=0.0)  # heights as measured: accepted
        with self.assertRaisesRegex(ValueError, "forget_after_frames"):
            hope.SurfaceMap(forget_after_frames=-1)

    def test_surface_map_forgets_a_surface_unseen_for_its_memory(self):
        surface_map = hope.SurfaceMap(forget_after_frames=1)
        seen = hope.Extractor().extract(self.points, pose=self.pose)
        surface_map.update(seen, 0.0)
        _, events = surface_map.update([], 1.0)  # a frame without them: within the memory
        self.assertFalse([e for e in events if e.kind == "ended"])
        again = hope.Extractor().extract(self.points, pose=self.pose)
        events = surface_map.update(again, 2.0)  # unseen in 1 frame: the memory has passed
        self.assertEqual(len([e for e in events if e.kind == "ended"]), len(self.truth))
        self.assertFalse({p.id for p in seen.planes} & {p.id for p in again.planes})

    def test_tracker_takes_a_list_of_planes(self):
        tracker = hope.PlaneTracker()
        planes, events = tracker.update(self.result.planes, 0.0)
        self.assertEqual(len(planes), len(self.truth))
        self.assertEqual(len(events), len(self.truth))


def sheet(x0, y0, x1, y1, z, step=0.005):
    x, y = np.meshgrid(np.arange(x0, x1 + 1e-9, step), np.arange(y0, y1 + 1e-9, step))
    return np.stack([x.ravel(), y.ravel(), np.full(x.size, z)], 1)


class ObjectsAndPlacements(unittest.TestCase):
    """A 1 x 0.8 m table 0.7 m up with a 0.2 x 0.2 x 0.3 m box at (0.5, 0.3); the table under the
    box unseen, as a camera above it would see it."""

    @classmethod
    def setUpClass(cls):
        table = sheet(0, 0, 1.0, 0.8, 0.7)
        table = table[~((np.abs(table[:, 0] - 0.5) <= 0.1) & (np.abs(table[:, 1] - 0.3) <= 0.1))]
        top = sheet(0.4, 0.2, 0.6, 0.4, 1.0)
        sides = []
        for z in np.arange(0.705, 1.0, 0.005):
            for t in np.arange(-0.1, 0.1 + 1e-9, 0.005):
                sides += [(0.5 + t, 0.2, z), (0.5 + t, 0.4, z), (0.4, 0.3 + t, z), (0.6, 0.3 + t, z)]
        cls.box_points = len(top) + len(sides)
        cls.points = np.vstack([table, top, np.array(sides)]).astype(np.float32)
        cls.extractor = hope.Extractor()
        cls.result = cls.extractor.extract(cls.points, objects=True)

    def test_the_box_is_one_object_on_the_table(self):
        self.assertEqual(len(self.result.objects), 1)
        box = self.result.objects[0]
        table = min(self.result.planes, key=lambda p: abs(p.height - 0.7))
        self.assertAlmostEqual(table.height, 0.7, places=3)
        self.assertEqual(box["plane_id"], table.id)
        self.assertAlmostEqual(box["height_above_plane"], 0.3, delta=0.01)
        np.testing.assert_allclose(sorted(box["box"]["size"][:2]), [0.2, 0.2], atol=0.05)
        np.testing.assert_allclose(box["box"]["centre"][:2], [0.5, 0.3], atol=0.01)
        labels = self.result.object_labels
        self.assertEqual(labels.shape, (len(self.points),))
        self.assertEqual(int((labels == 0).sum()), box["num_points"])
        self.assertTrue((labels[: len(self.points) - self.box_points] == -1).all())
        self.assertGreater(table.free_area, 0.7)

    def test_placements_keep_off_the_box_and_on_the_table(self):
        placements = self.extractor.place(0.15, 0.1, clearance=0.03)
        self.assertGreaterEqual(len(placements), 2)
        for p in placements:
            self.assertAlmostEqual(p["z"], 0.7, places=3)
            c, s = np.cos(p["yaw"]), np.sin(p["yaw"])
            for u in (-0.075, 0.075):
                for v in (-0.05, 0.05):
                    x, y = p["x"] + c * u - s * v, p["y"] + s * u + c * v
                    self.assertTrue(0 <= x <= 1.0 and 0 <= y <= 0.8, (x, y))
                    gap = np.hypot(max(0.4 - x, 0, x - 0.6), max(0.2 - y, 0, y - 0.4))
                    self.assertGreaterEqual(gap, 0.025, (x, y))

    def test_same_objects_as_the_command_line_tool(self):
        with tempfile.TemporaryDirectory() as tmp:
            cloud = os.path.join(tmp, "scene.pcd")
            with open(cloud, "wb") as f:
                f.write(("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                         "COUNT 1 1 1\nWIDTH %d\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\n"
                         "DATA binary\n" % (len(self.points), len(self.points))).encode("ascii"))
                f.write(self.points.tobytes())
            labels, report = os.path.join(tmp, "l.pcd"), os.path.join(tmp, "r.json")
            subprocess.run([os.environ["HOPE_EXTRACT_BIN"], "--input", cloud, "--labels", labels,
                            "--json", report, "--quiet"], check=True, capture_output=True)
            with open(report) as f:
                cli = json.load(f)
            np.testing.assert_array_equal(read_pcd_labels(labels, "object"),
                                          self.result.object_labels.astype(np.int64) + 1)
            self.assertEqual(len(cli["objects"]), len(self.result.objects))
            self.assertEqual(set(cli["objects"][0]), set(self.result.objects[0]))

    def test_bad_footprints_and_a_missing_extraction_are_value_errors(self):
        for width, depth, clearance in ((0, 0.1, 0.02), (0.1, -1, 0.02), (float("nan"), 0.1, 0),
                                        (0.1, 0.1, -1), (5, 5, 0)):
            with self.assertRaises(ValueError):
                self.extractor.place(width, depth, clearance=clearance)
        with self.assertRaises(ValueError):
            hope.Extractor().place(0.1, 0.1)


class Obstacles(unittest.TestCase):
    """Pipeline.process(obstacles=True) on ObjectsAndPlacements' table and box: the table is the
    lowest large level surface, so the obstacles are the box's points more than 5 cm above it."""

    def test_the_box_above_the_band_floor_is_the_obstacle(self):
        scene = ObjectsAndPlacements
        scene.setUpClass()
        pipeline = hope.Pipeline()
        frame = pipeline.process(scene.points, 0.0, viewpoint=(0.5, 0.4, 2.0), obstacles=True)
        table = [p for p in frame.planes if abs(p.height - 0.7) < 0.01]
        self.assertEqual(frame.floor_id, table[0].id)
        expected = np.flatnonzero(scene.points[:, 2] > 0.7 + 0.05)
        self.assertGreater(len(expected), 1000)
        np.testing.assert_array_equal(frame.obstacles, expected)
        self.assertEqual(frame.obstacles.dtype, np.uint32)
        self.assertIsNone(pipeline.process(scene.points, 0.1, viewpoint=(0.5, 0.4, 2.0)).obstacles)


class FloorGrid(unittest.TestCase):
    """Pipeline.process(floor_grid=True) on the same table and box: the box's footprint is
    occupied, the rest of the table free, in 5 cm cells."""

    def test_the_box_stands_on_the_table_seen_free(self):
        scene = ObjectsAndPlacements
        scene.setUpClass()
        frame = hope.Pipeline().process(scene.points, 0.0, viewpoint=(0.5, 0.4, 2.0),
                                        floor_grid=True)
        grid = frame.floor_grid
        table = [p for p in frame.planes if abs(p.height - 0.7) < 0.01]
        self.assertEqual(frame.floor_id, table[0].id)
        self.assertAlmostEqual(grid["floor_height"], 0.7, delta=0.005)
        self.assertEqual(grid["resolution"], 0.05)
        cells = grid["cells"]
        self.assertEqual(cells.dtype, np.int8)
        self.assertGreaterEqual(cells.shape[0] * 0.05, 0.8)  # rows along y: the table's 0.8 m
        self.assertGreaterEqual(cells.shape[1] * 0.05, 1.0)
        x0, y0 = grid["origin"]
        counted = {100: 0, 0: 0}
        for row in range(cells.shape[0]):
            for column in range(cells.shape[1]):
                x, y = x0 + (column + 0.5) * 0.05, y0 + (row + 0.5) * 0.05
                in_box = 0.4 < x < 0.6 and 0.2 < y < 0.4
                off_box = max(0.4 - x, x - 0.6, 0.2 - y, y - 0.4) > 0.05
                on_table = 0 < x < 1.0 and 0 < y < 0.8
                if in_box:
                    self.assertEqual(cells[row, column], 100, (x, y))
                    counted[100] += 1
                elif on_table and off_box:
                    self.assertEqual(cells[row, column], 0, (x, y))
                    counted[0] += 1
        self.assertEqual(counted[100], 16)  # 4 x 4 cells under the 0.2 m box
        self.assertGreater(counted[0], 200)
        self.assertIsNone(hope.Pipeline().process(scene.points, 0.0).floor_grid)


class BadInput(unittest.TestCase):
    def setUp(self):
        self.extractor = hope.Extractor()
        self.floor = np.stack(np.meshgrid(np.arange(0, 2, 0.01), np.arange(0, 2, 0.01)) +
                              [np.zeros((200, 200))], -1).reshape(-1, 3).astype(np.float32)

    def assertRaisesWith(self, error, text, call, *args, **kwargs):
        with self.assertRaises(error) as caught:
            call(*args, **kwargs)
        self.assertIn(text, str(caught.exception))

    def test_a_floor_is_found_at_zero(self):
        result = self.extractor.extract(self.floor)
        self.assertEqual(len(result.planes), 1)
        self.assertAlmostEqual(result.planes[0].height, 0.0, delta=1e-6)
        self.assertEqual(result.planes[0].num_points, len(self.floor))

    def test_wrong_shape(self):
        self.assertRaisesWith(ValueError, "(N, 3) or (H, W, 3), got (5, 4)",
                              self.extractor.extract, np.zeros((5, 4), np.float32))
        self.assertRaisesWith(ValueError, "got (12,)", self.extractor.extract,
                              np.zeros(12, np.float32))

    def test_wrong_dtype(self):
        self.assertRaisesWith(TypeError, "float32 or float64, got int64",
                              self.extractor.extract, np.zeros((5, 3), np.int64))

    def test_empty(self):
        self.assertRaisesWith(ValueError, "points is empty", self.extractor.extract,
                              np.zeros((0, 3), np.float32))

    def test_nan_only(self):
        self.assertRaisesWith(ValueError, "no finite point (all 7 are NaN or infinite)",
                              self.extractor.extract, np.full((7, 3), np.nan))

    def test_bad_orientation(self):
        self.assertRaisesWith(ValueError, "at most one of", self.extractor.extract, self.floor,
                              gravity=(0, 0, 9.8), quaternion=(0, 0, 0, 1))
        self.assertRaisesWith(ValueError, "quaternion must have 4 numbers",
                              self.extractor.extract, self.floor, quaternion=(0, 0, 1))
        self.assertRaisesWith(ValueError, "quaternion", self.extractor.extract, self.floor,
                              quaternion=(0, 0, 0, 0))

    def test_level_refuses_a_wall_and_names_the_other_sources(self):
        # A wall 3 m in front of a camera, and nothing else: no evidence of up.
        u, v = np.meshgrid(np.arange(-1, 1, 0.01), np.arange(-1, 1, 0.01))
        wall = np.stack([u, v, np.full_like(u, 3.0)], -1).reshape(-1, 3).astype(np.float32)
        self.assertTrue(issubclass(hope.LevellingError, ValueError))
        self.assertRaisesWith(hope.LevellingError, "gravity", self.extractor.extract, wall,
                              level=True)

    def test_bad_parameters_name_the_parameter(self):
        self.assertRaisesWith(ValueError, "r_xy", hope.Extractor, r_xy=-1.0)
        self.assertRaisesWith(ValueError, "threads", hope.Extractor, threads=-1)
        self.assertRaisesWith(ValueError, "unknown tracking mode", hope.PlaneTracker, mode="nearest")

    def test_plane_colours_are_the_voc_map(self):
        # Plane id k takes Pascal VOC colour k + 1: (128, 0, 0), (0, 128, 0), (128, 128, 0).
        self.assertEqual(hope.plane_color(0), (128, 0, 0))
        self.assertEqual(hope.plane_color(1), (0, 128, 0))
        self.assertEqual(hope.plane_color(2), (128, 128, 0))


if __name__ == "__main__":
    unittest.main()
