"""One vocabulary, with its units: docs/hope_extract.schema.json describes hope_extract's --json
document and its --jsonl lines, and Python's to_dict() gives the same structure. Every number in
the schema names its unit. This test holds hope_extract (one cloud and --sequence) and Python to
the schema, field for field (nothing missing, nothing extra, every type and choice). Run by
ctest (python_json_schema)."""

import json
import os
import subprocess
import tempfile
import unittest
import warnings

import cv2

import hope

SYNTH = os.environ.get("HOPE_SYNTH_BIN", "hope_synth")
EXTRACT = os.environ.get("HOPE_EXTRACT_BIN", "hope_extract")
SCHEMA_PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs",
                           "hope_extract.schema.json")
UNITS = {"m", "m²", "rad", "deg", "ms", "s", "1"}
TYPES = {"object": dict, "array": list, "string": str, "boolean": bool}


def plain(value):
    """numpy arrays and scalars as JSON would hold them."""
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    return value


class Validator:
    """The part of JSON Schema the schema uses: $ref, type, enum, required, properties,
    additionalProperties false, items, minItems, maxItems, oneOf. Returns the errors."""

    def __init__(self, schema):
        self.schema = schema

    def resolve(self, node):
        while "$ref" in node:
            node = self.schema["$defs"][node["$ref"].split("/")[-1]]
        return node

    def errors(self, value, node, path="$"):
        node = self.resolve(node)
        if "oneOf" in node:
            matching = [n for n in node["oneOf"] if not self.errors(value, n, path)]
            return [] if len(matching) == 1 else [
                "%s: matches %d of the oneOf choices" % (path, len(matching))]
        found = []
        kind = node.get("type")
        if kind == "number":
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                return ["%s: %r is not a number" % (path, value)]
        elif kind == "integer":
            if isinstance(value, bool) or not isinstance(value, int):
                return ["%s: %r is not an integer" % (path, value)]
        elif kind is not None and not isinstance(value, TYPES[kind]):
            return ["%s: %r is not of type %s" % (path, value, kind)]
        if "enum" in node and value not in node["enum"]:
            found.append("%s: %r is not one of %s" % (path, value, node["enum"]))
        if isinstance(value, dict):
            for key in node.get("required", []):
                if key not in value:
                    found.append("%s: %s is missing" % (path, key))
            properties = node.get("properties", {})
            for key, item in value.items():
                if key in properties:
                    found += self.errors(item, properties[key], path + "." + key)
                elif node.get("additionalProperties") is False:
                    found.append("%s: %s is not in the schema" % (path, key))
        if isinstance(value, list):
            if len(value) < node.get("minItems", 0) or len(value) > node.get("maxItems", 1 << 30):
                found.append("%s: %d items" % (path, len(value)))
            for i, item in enumerate(value):
                if "items" in node:
                    found += self.errors(item, node["items"], "%s[%d]" % (path, i))
        return found


def number_leaves(node, path="$"):
    """(path, node) of every number the schema describes."""
    if isinstance(node, dict):
        if node.get("type") == "number":
            yield path, node
        for key, child in node.items():
            yield from number_leaves(child, path + "/" + key)
    elif isinstance(node, list):
        for i, child in enumerate(node):
            yield from number_leaves(child, "%s/%d" % (path, i))


class JsonSchemaTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        with open(SCHEMA_PATH) as f:
            cls.schema = json.load(f)
        cls.validator = Validator(cls.schema)
        cls.tmp = tempfile.TemporaryDirectory()
        cls.room = os.path.join(cls.tmp.name, "room")
        subprocess.run([SYNTH, "--out", cls.room], check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(cls.room, "pose.txt")) as f:
            cls.pose = [float(v) for v in f.read().split()]

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def assertValid(self, value, node=None):
        errors = self.validator.errors(value, node or self.schema)
        self.assertEqual(errors, [], "\n".join(errors[:20]))

    def test_every_number_names_its_unit(self):
        leaves = list(number_leaves(self.schema))
        self.assertGreater(len(leaves), 30)
        for path, node in leaves:
            self.assertIn(node.get("unit"), UNITS, path)

    def test_the_validator_rejects_what_the_schema_does_not_allow(self):
        # A missing field, an extra one, a wrong type and a choice out of the list.
        plane = {"id": 0, "height": 0.7}
        self.assertTrue(self.validator.errors(plane, {"$ref": "#/$defs/plane"}))
        document = {"planes": [], "objects": [], "sensor_to_reference": [[1, 0, 0, 0]] * 4,
                    "up_in_sensor": [0, 0, 1], "stats": {}, "warnings": [], "timings_ms": {}}
        self.assertTrue(self.validator.errors(dict(document, extra=1), self.schema))
        event = {"kind": "vanished", "id": 1, "other_id": -1}
        self.assertTrue(self.validator.errors(event, {"$ref": "#/$defs/event"}))
        self.assertTrue(self.validator.errors({"stamp": "0", "file": "a", "skipped": "b"},
                                              {"$ref": "#/$defs/frame_line"}))

    def test_one_cloud_json(self):
        out = os.path.join(self.tmp.name, "room.json")
        subprocess.run([EXTRACT, "--depth", os.path.join(self.room, "depth.png"), "--pose",
                        " ".join(str(v) for v in self.pose), "--level", "--place", "0.1 0.1",
                        "--json", out, "--quiet"], check=True, stderr=subprocess.DEVNULL)
        with open(out) as f:
            document = json.load(f)
        self.assertValid(document)
        # Every part of the schema was exercised: planes, objects, placements, a refinement.
        self.assertGreater(len(document["planes"]), 3)
        self.assertGreater(len(document["objects"]), 3)
        self.assertGreater(len(document["placements"]), 0)
        self.assertEqual(document["levelling"]["source"], "refined")

    def test_sequence_jsonl_lines(self):
        folder = os.path.join(self.tmp.name, "pan")
        subprocess.run([SYNTH, "--out", folder, "--sequence", "pan", "--frames", "6", "--width",
                        "320"], check=True, stdout=subprocess.DEVNULL)
        out = os.path.join(self.tmp.name, "pan.jsonl")
        subprocess.run([EXTRACT, "--sequence", folder, "--jsonl", out, "--quiet"], check=True,
                       stderr=subprocess.DEVNULL)
        with open(out) as f:
            lines = [json.loads(line) for line in f if line.strip()]
        self.assertEqual(len(lines), 6)
        for line in lines:
            self.assertValid(line, {"$ref": "#/$defs/frame_line"})
        self.assertTrue(any(line.get("events") for line in lines))
        self.assertTrue(any(line.get("objects") for line in lines))
        # With the accelerometer alone the scene's odometry keeps the map: its step in each line.
        accel = os.path.join(self.tmp.name, "pan_accel.jsonl")
        subprocess.run([EXTRACT, "--sequence", folder, "--accelerometer",
                        os.path.join(folder, "accelerometer.txt"), "--jsonl", accel, "--quiet"],
                       check=True, stderr=subprocess.DEVNULL)
        with open(accel) as f:
            lines = [json.loads(line) for line in f if line.strip()]
        self.assertEqual(len(lines), 6)
        for line in lines:
            self.assertValid(line, {"$ref": "#/$defs/frame_line"})
        self.assertTrue(all("odometry" in line for line in lines if "skipped" not in line))
        self.assertTrue(any(line.get("odometry", {}).get("tracked") for line in lines))

    def test_python_to_dict(self):
        depth = cv2.imread(os.path.join(self.room, "depth.png"), cv2.IMREAD_UNCHANGED)
        # hope_extract --depth's default intrinsics, TUM's Freiburg 1 camera, as hope_synth renders.
        points = hope.depth_to_cloud(depth, [517.3, 516.5, 318.6, 255.3], 5000.0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = hope.Extractor().extract(points, pose=self.pose, level=True)
        document = plain(result.to_dict())
        self.assertValid(document)
        self.assertGreater(len(document["objects"]), 3)  # objects on by default
        self.assertIn("levelling", document)
        for plane in result.planes:
            self.assertValid(plain(plane.to_dict()), {"$ref": "#/$defs/plane"})


if __name__ == "__main__":
    unittest.main()
