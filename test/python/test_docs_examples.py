"""The examples of docs/cli.md and docs/python.md run as a user would paste them, and print what
the docs say they print (as test_readme_examples.py does for the README). Placeholders a user
fills in (d.png, depth.png, a pose, map.pcd, DIR, `frames`) are filled with files hope_synth
writes; commands on ../shared/data are skipped with a message when it is absent. docs/ros.md's
commands are the launch files the rostests start (test/ros). Run by ctest
(python_docs_examples)."""

import os
import re
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DOCS = os.path.join(ROOT, "docs")
SHARED = os.path.join(os.path.dirname(ROOT), "shared")
SYNTH = os.environ.get("HOPE_SYNTH_BIN", "hope_synth")


def blocks(language, text):
    return re.findall(r"```" + language + r"\n(.*?)```", text, re.S)


def commands_with_output(script):
    """(command, promised output lines) of a shell block: continuation lines joined; the
    comment lines right after a command that are indented by two or more spaces (`#   …`) are
    what it prints, "…" standing for anything; other comments are prose."""
    out = []
    for line in script.splitlines():
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            printed = re.match(r"#\s{2,}(.*)", stripped)
            if printed and out and not out[-1][0].endswith("\\"):
                out[-1][1].append(printed.group(1).strip())
            continue
        if out and out[-1][0].endswith("\\"):
            out[-1][0] = out[-1][0][:-1] + " " + stripped
        else:
            out.append([stripped, []])
    return out


def pattern(promised):
    """A promised line as a regular expression: "…" for anything."""
    return ".*".join(re.escape(part) for part in promised.split("…"))


class DocsExamples(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.work = os.path.join(cls.tmp.name, "main")
        os.mkdir(cls.work)
        if os.path.exists(SHARED):
            os.symlink(SHARED, os.path.join(cls.tmp.name, "shared"))
        # The placeholders' files: the demo room (a depth image with its pose), a z-up room
        # scan, a rendered sequence with poses and an accelerometer.
        cls.room = os.path.join(cls.tmp.name, "room")
        subprocess.run([SYNTH, "--out", cls.room], check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(cls.room, "pose.txt")) as f:
            cls.pose = f.read().split()
        cls.scan = os.path.join(cls.tmp.name, "scan")
        subprocess.run([SYNTH, "--out", cls.scan, "--room-scan", "0.02"], check=True,
                       stdout=subprocess.DEVNULL)
        cls.sequence = os.path.join(cls.tmp.name, "seq")
        subprocess.run([SYNTH, "--out", cls.sequence, "--sequence", "pan", "--frames", "5",
                        "--width", "320"], check=True, stdout=subprocess.DEVNULL)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def filled(self, command):
        """The command with the docs' placeholders filled in."""
        clouds = [f for f in os.listdir(self.scan) if f.endswith(".pcd")]
        replacements = [
            ("/tmp/", self.tmp.name + "/"),  # first: the paths below lie in the scratch folder
            (" d.png", " " + os.path.join(self.room, "depth.png")),
            (" depth.png", " " + os.path.join(self.room, "depth.png")),
            (" rgb.png", " " + os.path.join(self.room, "rgb.png")),
            ('"tx ty tz qx qy qz qw"', '"%s"' % " ".join(self.pose)),
            (" map.pcd", " " + os.path.join(self.scan, clouds[0])),
            ("DIR/", self.sequence + "/"),
            (" DIR", " " + self.sequence),
        ]
        for placeholder, value in replacements:
            command = command.replace(placeholder, value)
        return command

    def run_block(self, script, env):
        """Runs a block's commands; returns how many ran and how many promised lines held."""
        ran = checked = 0
        for command, promised in commands_with_output(script):
            if command.startswith("export PATH="):
                continue
            if "../shared/" in command and not os.path.exists(SHARED):
                print("skipped (no ../shared/data): " + command)
                continue
            command = self.filled(command)
            run = subprocess.run(["bash", "-c", command], cwd=self.work, env=env,
                                 capture_output=True, text=True, timeout=900)
            self.assertEqual(run.returncode, 0, command + "\n" + run.stderr[-3000:])
            printed = run.stdout + run.stderr
            for line in promised:
                self.assertRegex(printed, pattern(line), "the docs promise this of: " + command)
                checked += 1
            ran += 1
        return ran, checked

    def test_command_line_examples(self):
        with open(os.path.join(DOCS, "cli.md")) as f:
            text = f.read()
        scripts = blocks("sh", text)
        self.assertGreaterEqual(len(scripts), 4)
        bin_dir = os.path.dirname(os.environ["HOPE_EXTRACT_BIN"])
        # python3: this test's own interpreter, which has what the scorers import.
        env = dict(os.environ, PATH=os.pathsep.join(
            [bin_dir, os.path.dirname(sys.executable), os.environ["PATH"]]))
        counts = [self.run_block(script, env) for script in scripts]
        # The demo room, the room scan, the LiDAR and the rendered sequences need no data.
        self.assertGreaterEqual(sum(ran for ran, _ in counts), 7)
        if os.path.exists(SHARED):
            # office1's levelling, the TUM frame's objects and placements, kitchen_dev's ids.
            self.assertGreaterEqual(sum(checked for _, checked in counts), 7)

    def python_blocks(self):
        with open(os.path.join(DOCS, "python.md")) as f:
            return blocks("python", f.read())

    def run_python(self, code):
        run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                             text=True, timeout=300)
        self.assertEqual(run.returncode, 0, code + "\n" + run.stderr[-3000:])
        return run.stdout

    def test_python_extract_prints_what_it_says(self):
        first, _, tracking, _ = self.python_blocks()
        frame = re.search(r'"(\.\./shared/data/[^"]+)"', first).group(1)
        if not os.path.exists(os.path.join(ROOT, frame)):
            self.skipTest("no %s (../shared/data absent)" % frame)
        promised = re.findall(r"^# (\d+ -?[\d.]+ [\d.]+)", first, re.M)
        self.assertGreaterEqual(len(promised), 3)
        printed = self.run_python(first + "\n" + tracking).splitlines()
        self.assertEqual(printed[:len(promised)], promised)

    def test_python_read_cloud(self):
        _, reading, _, _ = self.python_blocks()
        cloud = re.search(r'"(\.\./shared/data/[^"]+)"', reading).group(1)
        if not os.path.exists(os.path.join(ROOT, cloud)):
            self.skipTest("no %s (../shared/data absent)" % cloud)
        printed = self.run_python(reading + "\nprint(len(result.planes))\n")
        self.assertGreater(int(printed.split()[-1]), 0)

    def test_python_pipeline_over_frames(self):
        *_, pipeline = self.python_blocks()
        # `frames`, the reader's own, from the rendered sequence: stamp, points, pose.
        frames = """
import cv2, hope
def read(name):
    with open(%r + "/" + name) as f:
        return [l.split() for l in f if l.strip() and not l.startswith("#")]
k = [float(v) for v in open(%r + "/intrinsics.txt").read().split()]
poses = read("groundtruth.txt")
frames = []
for (stamp, name), pose in zip(read("depth.txt"), poses):
    depth = cv2.imread(%r + "/" + name, cv2.IMREAD_UNCHANGED)
    frames.append((float(stamp), hope.depth_to_cloud(depth, k, 5000.0),
                   [float(v) for v in pose[1:]]))
""" % (self.sequence, self.sequence, self.sequence)
        printed = self.run_python(frames + pipeline).splitlines()
        self.assertEqual(len(printed), 5, "one line per frame")
        self.assertIn("(", printed[0])  # (id, height) pairs


if __name__ == "__main__":
    unittest.main()
