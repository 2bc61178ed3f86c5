"""Same input, same output: one rendered sequence through hope_extract --sequence and through
hope.Pipeline gives the same planes, ids, objects and events frame by frame, with poses (the
surface map), with the accelerometer (the odometry's map, gravity averaged over its window) and with
up from the scene (smoothed and held). Both front-ends call the core's FramePipeline; this is
what keeps them from deciding anything apart. Run by ctest (python_parity)."""

import bisect
import json
import os
import subprocess
import tempfile
import unittest
import warnings

import cv2
import numpy as np

import hope

SYNTH = os.environ.get("HOPE_SYNTH_BIN", "hope_synth")
EXTRACT = os.environ.get("HOPE_EXTRACT_BIN", "hope_extract")

# hope_extract's pairing of a frame with its pose or accelerometer sample (TUM's 0.02 s).
MAX_TIME_DIFFERENCE = 0.02


def read_stamped(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                fields = line.split()
                rows.append((float(fields[0]), fields[1:]))
    return sorted(rows, key=lambda r: r[0])


def nearest(rows, stamp):
    stamps = [r[0] for r in rows]
    k = bisect.bisect_left(stamps, stamp)
    best = min((i for i in (k - 1, k) if 0 <= i < len(rows)), key=lambda i: abs(stamps[i] - stamp))
    return rows[best] if abs(stamps[best] - stamp) <= MAX_TIME_DIFFERENCE else None


def python_run(folder, mode):
    """Every frame of `folder` through hope.Pipeline: a list of (stamp, result or None)."""
    with open(os.path.join(folder, "intrinsics.txt")) as f:
        intrinsics = [float(v) for v in f.read().split()]
    poses = read_stamped(os.path.join(folder, "groundtruth.txt"))
    accel = read_stamped(os.path.join(folder, "accelerometer.txt"))
    # Both front-ends at their default tracking mode, auto: the map with poses, the odometry's
    # map with an orientation only (hope::defaultIdentity), which the first frame decides.
    pipeline = hope.Pipeline(levelling="estimate" if mode == "scene" else "off")
    assert pipeline.tracking_mode == "auto", pipeline.tracking_mode
    frames = []
    for stamp, (name,) in read_stamped(os.path.join(folder, "depth.txt")):
        depth = cv2.imread(os.path.join(folder, name), cv2.IMREAD_UNCHANGED)
        points = hope.depth_to_cloud(depth, intrinsics, 5000.0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if mode == "poses":
                pose = nearest(poses, stamp)
                if pose is None:
                    continue
                result = pipeline.process(points, stamp, pose=[float(v) for v in pose[1]])
            elif mode == "accel":
                sample = nearest(accel, stamp)
                if sample is None:
                    continue
                result = pipeline.process(points, stamp, gravity=[float(v) for v in sample[1]])
            else:
                result = pipeline.process(points, stamp)
        frames.append((stamp, result))
    expected = "map" if mode == "poses" else "odometry"
    assert pipeline.tracking_mode == expected, (mode, pipeline.tracking_mode)
    return frames


def cli_run(folder, mode, jsonl):
    args = {"poses": [], "accel": ["--accelerometer", os.path.join(folder, "accelerometer.txt")],
            "scene": ["--orientation-source", "scene"]}[mode]
    subprocess.run([EXTRACT, "--sequence", folder, "--jsonl", jsonl, "--quiet"] + args,
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(jsonl) as f:
        return [json.loads(line) for line in f]


class FrontEndParity(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.folder = os.path.join(cls.tmp.name, "pan")
        subprocess.run([SYNTH, "--out", cls.folder, "--sequence", "pan", "--frames", "30",
                        "--width", "320"], check=True, stdout=subprocess.DEVNULL)
        # The poses and samples at the frames' own stamps (hope_synth writes them 4 ms later,
        # as motion capture may): the comparison is of the pipeline, not of interpolation,
        # which hope_extract does between poses and this test would have to copy.
        stamps = [stamp for stamp, _ in read_stamped(os.path.join(cls.folder, "depth.txt"))]
        for name in ("groundtruth.txt", "accelerometer.txt"):
            path = os.path.join(cls.folder, name)
            rows = read_stamped(path)
            assert len(rows) == len(stamps), name
            with open(path, "w") as f:
                for stamp, (_, values) in zip(stamps, rows):
                    f.write("%.6f %s\n" % (stamp, " ".join(values)))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def check_mode(self, mode):
        cli = cli_run(self.folder, mode, os.path.join(self.tmp.name, mode + ".jsonl"))
        py = python_run(self.folder, mode)
        self.assertEqual(len(cli), len(py), "one record per frame in both")
        self.assertGreaterEqual(len(cli), 25, "most of the 30 frames have an orientation")
        compared_planes = compared_objects = 0
        for line, (stamp, result) in zip(cli, py):
            where = f"{mode}, frame {stamp:.6f}"
            self.assertAlmostEqual(line["stamp"], stamp, places=6, msg=where)
            if "skipped" in line:
                self.assertIsNotNone(result.skipped, where + ": skipped by the CLI only")
                continue
            self.assertIsNone(result.skipped, where + ": skipped by Python only")
            planes = [(p["id"], p["num_points"]) for p in line["planes"]]
            self.assertEqual(planes, [(p.id, p.num_points) for p in result.planes], where)
            # The JSON holds six significant digits.
            for written, plane in zip(line["planes"], result.planes):
                self.assertAlmostEqual(written["height"], plane.height, delta=1e-5, msg=where)
            objects = [(o["plane_id"], o["num_points"]) for o in line["objects"]]
            self.assertEqual(objects, [(o["plane_id"], o["num_points"]) for o in result.objects],
                             where)
            events = [(e["kind"], e["id"], e["other_id"]) for e in line["events"]]
            self.assertEqual(events, [(e.kind, e.id, e.other_id) for e in result.events], where)
            self.assertEqual("level_held" in line, result.level_held, where)
            self.assertEqual("odometry" in line, result.odometry is not None, where)
            if result.odometry is not None:
                self.assertEqual(line["odometry"]["tracked"], result.odometry["tracked"], where)
                # The JSON holds nine significant digits.
                np.testing.assert_allclose(line["odometry"]["world_from_frame"],
                                           result.odometry["world_from_frame"], atol=1e-7,
                                           err_msg=where)
            compared_planes += len(planes)
            compared_objects += len(objects)
        # The scene holds a floor, a table, a book, a cabinet, two treads and the pattern
        # object's faces: several planes and objects in every frame.
        self.assertGreater(compared_planes, 3 * len(cli), mode)
        self.assertGreater(compared_objects, len(cli), mode)

    def test_poses_and_the_surface_map(self):
        self.check_mode("poses")

    def test_accelerometer_and_the_odometry(self):
        self.check_mode("accel")

    def test_up_from_the_scene(self):
        self.check_mode("scene")

    def test_read_cloud_reads_what_hope_extract_reads(self):
        pcd = os.path.join(self.tmp.name, "cloud.pcd")
        rng = np.random.default_rng(1)
        xyz = np.c_[rng.uniform(0, 2, (500, 2)), np.full(500, 0.75)].astype(np.float32)
        with open(pcd, "w") as f:
            f.write("VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                    f"WIDTH {len(xyz)}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(xyz)}\n"
                    "DATA ascii\n")
            for p in xyz:
                f.write(f"{p[0]!r} {p[1]!r} {p[2]!r}\n")
        points = hope.read_cloud(pcd)
        self.assertEqual(points.shape, (500, 3))
        np.testing.assert_array_equal(points, xyz)
        with self.assertRaises((ValueError, RuntimeError)):
            hope.read_cloud(os.path.join(self.tmp.name, "missing.pcd"))


def rotation(qx, qy, qz, qw):
    """The rotation matrix of a unit quaternion (x, y, z, w)."""
    return np.array([
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
        [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
        [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]])


def demo_room_through_cli(tmp, *options):
    """hope_synth's demo room run through hope_extract --depth with its pose and `options`
    (paths in them relative to `tmp`); returns the pose and the room's points (hope_extract
    --depth's default intrinsics, TUM freiburg1, as hope_synth renders)."""
    room = os.path.join(tmp, "room")
    subprocess.run([SYNTH, "--out", room], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(room, "pose.txt")) as f:
        pose = [float(v) for v in f.read().split()]
    subprocess.run([EXTRACT, "--depth", os.path.join(room, "depth.png"), "--pose",
                    " ".join(map(str, pose)), "--quiet"] + list(options), check=True, cwd=tmp)
    depth = cv2.imread(os.path.join(room, "depth.png"), cv2.IMREAD_UNCHANGED)
    points = hope.depth_to_cloud(depth, (517.3, 516.5, 318.6, 255.3), 5000.0).reshape(-1, 3)
    return pose, points


class ObstaclesParity(unittest.TestCase):
    """hope_extract --obstacles and Pipeline.process(obstacles=True) on the demo room give the
    same points, and they are the room's points between 5 cm and 2 m above its floor (z = 0 in
    the pose's world), 1 cm either side of each bound left to the floor's estimate."""

    def test_obstacles_are_the_same_points_and_the_rooms_band(self):
        with tempfile.TemporaryDirectory() as tmp:
            pose, points = demo_room_through_cli(tmp, "--obstacles", "obstacles.pcd")
            cli = hope.read_cloud(os.path.join(tmp, "obstacles.pcd")).reshape(-1, 3)
        frame = hope.Pipeline().process(points, 0.0, pose=pose, obstacles=True)
        self.assertGreaterEqual(frame.floor_id, 0)
        np.testing.assert_array_equal(points[frame.obstacles], cli)
        world_z = points @ rotation(*pose[3:])[2] + pose[2]
        finite = np.isfinite(world_z)
        in_band = finite & (world_z > 0.06) & (world_z <= 1.99)
        self.assertGreater(in_band.sum(), 10000)
        chosen = np.zeros(len(points), bool)
        chosen[frame.obstacles] = True
        self.assertGreaterEqual((chosen & in_band).sum(), 0.99 * in_band.sum(), "recall")
        near_band = (world_z > 0.04) & (world_z <= 2.01)
        self.assertGreaterEqual((chosen & near_band).sum(), 0.99 * chosen.sum(), "precision")



def read_map(yaml_path):
    """A map as map_server reads it (trinary, negate 0): cells as OccupancyGrid holds them, row 0
    the smallest y, and the YAML's keys."""
    keys = {}
    with open(yaml_path) as f:
        for line in f:
            if ":" in line and not line.startswith("#"):
                key, value = line.split(":", 1)
                keys[key.strip()] = value.strip()
    with open(os.path.join(os.path.dirname(yaml_path), keys["image"]), "rb") as f:
        data = f.read()
    magic, width, height, maximum = data.split(maxsplit=4)[:4]
    assert magic == b"P5" and int(maximum) == 255, (magic, maximum)
    pixels = np.frombuffer(data[-int(width) * int(height):], np.uint8)
    pixels = pixels.reshape(int(height), int(width))[::-1]
    occupancy = (255 - pixels.astype(float)) / 255
    cells = np.full(pixels.shape, -1, np.int8)
    cells[occupancy > float(keys["occupied_thresh"])] = 100
    cells[occupancy < float(keys["free_thresh"])] = 0
    return cells, keys


class FloorGridParity(unittest.TestCase):
    """hope_extract --floor-grid, read as map_server reads it, is Pipeline.process(floor_grid=True)'s
    grid, cell for cell, at the same origin and resolution; and the room's table top (0.75 m up,
    x 1.3-2.2, y -0.9-0.1, hope_synth's demo room) is occupied under it."""

    def test_the_map_file_is_the_pythons_grid_and_the_table_stands_in_it(self):
        with tempfile.TemporaryDirectory() as tmp:
            pose, points = demo_room_through_cli(tmp, "--floor-grid", "grid.pgm",
                                                 "--grid-resolution", "0.1")
            cells, keys = read_map(os.path.join(tmp, "grid.yaml"))
        grid = hope.Pipeline(grid_resolution=0.1).process(points, 0.0, pose=pose,
                                                          floor_grid=True).floor_grid
        self.assertEqual(float(keys["resolution"]), 0.1)
        origin = [float(v) for v in keys["origin"].strip("[]").split(",")]
        np.testing.assert_allclose(origin[:2], grid["origin"], atol=1e-6)
        np.testing.assert_array_equal(cells, grid["cells"])
        x0, y0 = grid["origin"]
        table = cells[int(round((-0.8 - y0) / 0.1)):int(round((0.0 - y0) / 0.1)),
                      int(round((1.4 - x0) / 0.1)):int(round((2.1 - x0) / 0.1))]
        self.assertEqual(table.size, 8 * 7)
        self.assertTrue((table == 100).all(), table)
        self.assertGreater((cells == 0).sum(), 500, "the floor seen free")


if __name__ == "__main__":
    unittest.main()
