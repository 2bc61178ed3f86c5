"""Same input, same output: one rendered sequence through hope_extract --sequence and through
hope.Pipeline gives the same planes, ids, objects and events frame by frame, with poses (the
surface map), with the accelerometer (the tracker, gravity averaged over its window) and with
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
    pipeline = hope.Pipeline(
        tracking_mode="map" if mode == "poses" else "improved",
        levelling="estimate" if mode == "scene" else "off",
    )
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
            compared_planes += len(planes)
            compared_objects += len(objects)
        # The scene holds a floor, a table, a book, a cabinet, two treads and the pattern
        # object's faces: several planes and objects in every frame.
        self.assertGreater(compared_planes, 3 * len(cli), mode)
        self.assertGreater(compared_objects, len(cli), mode)

    def test_poses_and_the_surface_map(self):
        self.check_mode("poses")

    def test_accelerometer_and_the_tracker(self):
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


class ObstaclesParity(unittest.TestCase):
    """hope_extract --obstacles and Pipeline.process(obstacles=True) on the demo room give the
    same points, and they are the room's points between 5 cm and 2 m above its floor (z = 0 in
    the pose's world), 1 cm either side of each bound left to the floor's estimate."""

    def test_obstacles_are_the_same_points_and_the_rooms_band(self):
        with tempfile.TemporaryDirectory() as tmp:
            room = os.path.join(tmp, "room")
            subprocess.run([SYNTH, "--out", room], check=True, stdout=subprocess.DEVNULL)
            with open(os.path.join(room, "pose.txt")) as f:
                pose = [float(v) for v in f.read().split()]
            out = os.path.join(tmp, "obstacles.pcd")
            subprocess.run([EXTRACT, "--depth", os.path.join(room, "depth.png"), "--pose",
                            " ".join(map(str, pose)), "--obstacles", out, "--quiet"], check=True)
            cli = hope.read_cloud(out).reshape(-1, 3)
            depth = cv2.imread(os.path.join(room, "depth.png"), cv2.IMREAD_UNCHANGED)
        # hope_extract --depth's default intrinsics (TUM freiburg1), as hope_synth renders.
        points = hope.depth_to_cloud(depth, (517.3, 516.5, 318.6, 255.3), 5000.0).reshape(-1, 3)
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


if __name__ == "__main__":
    unittest.main()
