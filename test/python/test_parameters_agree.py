"""Each parameter is defined once, in include/hope/parameters.h (hope.parameters() reads it);
every other place that names one agrees with it: the dynamic_reconfigure definition
(cfg/Hope.cfg), the nodelet's defaults (config/hope.yaml), the launch files' arguments, the
nodelet's parameter table (docs/ros.md), hope_extract's options (--help) and hope.Pipeline's
keywords. Run by ctest (python_parameters_agree)."""

import math
import os
import re
import subprocess
import sys
import types
import unittest
import xml.etree.ElementTree as ElementTree

import yaml

import hope

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# What the nodelet writes for "no limit" where ROS takes no infinity (cfg/Hope.cfg, hope.yaml).
OFF = 1000.0


def same(spec, value):
    """`value` (from a file) is the table's default."""
    default = spec["default"]
    if spec["type"] == "bool":
        return value is default or str(value).lower() == str(default).lower()
    if spec["type"] == "choice":
        return str(value) == default
    value = float(value)
    if math.isinf(default):
        return math.copysign(1, value) == math.copysign(1, default) and abs(value) >= OFF
    return math.isclose(value, default, rel_tol=1e-9, abs_tol=1e-12)


def reconfigure_entries():
    """cfg/Hope.cfg's gen.add() calls, read by running it against a stand-in generator."""
    entries = {}

    class Generator:
        def add(self, name, kind, level, doc, default=None, low=None, high=None,
                edit_method=""):
            entries[name] = {"type": kind, "default": default, "min": low, "max": high,
                             "edit_method": edit_method}

        def const(self, name, kind, value, doc):
            return value

        def enum(self, constants, doc):
            return constants

        def generate(self, *args):
            return 0

    module = types.ModuleType("dynamic_reconfigure.parameter_generator_catkin")
    module.ParameterGenerator = Generator
    module.bool_t, module.double_t, module.str_t, module.int_t = "bool", "double", "str", "int"
    saved = {k: sys.modules.get(k) for k in ("dynamic_reconfigure",
                                             "dynamic_reconfigure.parameter_generator_catkin")}
    sys.modules["dynamic_reconfigure"] = types.ModuleType("dynamic_reconfigure")
    sys.modules["dynamic_reconfigure.parameter_generator_catkin"] = module
    try:
        with open(os.path.join(ROOT, "cfg", "Hope.cfg")) as f:
            code = f.read()
        try:
            exec(compile(code, "Hope.cfg", "exec"), {"__name__": "__main__", "exit": sys.exit})
        except SystemExit:
            pass
    finally:
        for k, v in saved.items():
            if v is None:
                sys.modules.pop(k, None)
            else:
                sys.modules[k] = v
    return entries


class ParametersAgree(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.table = hope.parameters()
        cls.names = [p["name"] for p in cls.table]

    def test_the_table_is_whole(self):
        self.assertGreaterEqual(len(self.table), 16)
        for p in self.table:
            if p["type"] == "bool":
                # hope_extract switches a default-on part off with a --no-... flag.
                self.assertTrue(p["default"], p["name"])
                self.assertTrue(p["option"].startswith("--no-"), p["name"])

    def test_dynamic_reconfigure_takes_every_live_parameter_with_its_default(self):
        entries = reconfigure_entries()
        kinds = {"double": "double", "int": "int", "bool": "bool", "choice": "str"}
        for p in self.table:
            if not p["live"]:
                self.assertNotIn(p["name"], entries, p["name"] + " is start-up only")
                continue
            self.assertIn(p["name"], entries, "cfg/Hope.cfg lacks " + p["name"])
            entry = entries[p["name"]]
            self.assertEqual(entry["type"], kinds[p["type"]], p["name"])
            self.assertTrue(same(p, entry["default"]), (p["name"], entry["default"]))
            if p["type"] in ("double", "int"):
                # The slider's range lies within what the pipeline accepts (or is "off").
                low, high = entry["min"], entry["max"]
                self.assertTrue(low > p["min"] or (low == p["min"] and not p["min_excluded"])
                                or (math.isinf(p["min"]) and low <= -OFF), (p["name"], low))
                self.assertTrue(high <= p["max"] or (math.isinf(p["max"]) and high >= OFF),
                                (p["name"], high))
            if p["type"] == "choice":
                self.assertEqual(sorted(entry["edit_method"]), sorted(p["choices"]), p["name"])
        # The nodelet's own live parameters beyond the pipeline's.
        self.assertEqual(set(entries) - set(self.names), {"placements", "object_points", "publish_tf"})

    def test_config_hope_yaml_holds_every_default(self):
        with open(os.path.join(ROOT, "config", "hope.yaml")) as f:
            config = yaml.safe_load(f)
        for p in self.table:
            self.assertIn(p["name"], config, "config/hope.yaml lacks " + p["name"])
            self.assertTrue(same(p, config[p["name"]]), (p["name"], config[p["name"]]))

    def test_launch_arguments_default_to_the_table(self):
        checked = 0
        for name in ("hope.launch", "rgbd.launch", "tum.launch"):
            root = ElementTree.parse(os.path.join(ROOT, "launch", name)).getroot()
            for arg in root.iter("arg"):
                if arg.get("name") in self.names and arg.get("default") is not None:
                    p = self.table[self.names.index(arg.get("name"))]
                    self.assertTrue(same(p, arg.get("default")), (name, arg.attrib))
                    checked += 1
        self.assertGreaterEqual(checked, 8)

    def test_docs_ros_md_documents_every_parameter_with_its_default(self):
        with open(os.path.join(ROOT, "docs", "ros.md")) as f:
            rows = {}
            for line in f:
                m = re.match(r"\|\s*`(\w+)`\s*\|\s*(\w+)\s*\|\s*([^|]*)\|", line)
                if m:
                    rows[m.group(1)] = m.group(3).strip()
        for p in self.table:
            self.assertIn(p["name"], rows, "docs/ros.md has no row for " + p["name"])
            written = rows[p["name"]].replace("−", "-").strip("`")
            value = written.split()[0].strip("`")
            self.assertTrue(same(p, value), (p["name"], written))

    def test_hope_extract_takes_every_option(self):
        helptext = subprocess.run([os.environ["HOPE_EXTRACT_BIN"], "--help"],
                                  capture_output=True, text=True).stdout
        for p in self.table:
            self.assertIn(p["option"], helptext, p["name"])

    def test_pipeline_takes_every_parameter_and_no_other(self):
        for p in self.table:
            hope.Pipeline(**{p["name"]: p["default"]})
        with self.assertRaises(TypeError) as caught:
            hope.Pipeline(gravity_window=0.1)
        self.assertIn("gravity_window_s", str(caught.exception))
        with self.assertRaises(ValueError):
            hope.Pipeline(r_xy=-1.0)
        for p in self.table:
            self.assertIn(p["name"] + " = ", hope.Pipeline.__doc__)


if __name__ == "__main__":
    unittest.main()
