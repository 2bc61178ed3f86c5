#!/usr/bin/python3
"""The README's Results quote the quality guard's figures as docs/quality_latest.txt holds them
(the output of `bash scripts/quality.sh`, committed when the figures move): a figure that moves
there and stays old in the README fails here. Reads text only. Run by ctest (readme_figures)."""

import os
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# Each figure as the README writes it: a format and the guard's figures it is made of.
QUOTED = [
    ('IoU worst {:.3f}, mean {:.3f}', ['mosd.table_iou.worst', 'mosd.table_iou.mean']),
    ('median error {:.2f}° on the 50 mOSD scenes, {:.2f}° on kitchen_dev',
     ['mosd.up_error_deg.median', 'kitchen.up_error_deg.median']),
    ('recall {:.3f} / {:.3f} / {:.3f} / {:.3f} at 0–10 / 10–20 / 20–40 / 40–80 m, precision {:.3f}',
     ['lidar_street.hdl64.ground.recall_0_10m', 'lidar_street.hdl64.ground.recall_10_20m',
      'lidar_street.hdl64.ground.recall_20_40m', 'lidar_street.hdl64.ground.recall_40_80m',
      'lidar_street.hdl64.ground.precision']),
    ('weighted overlap {:.3f} per labelled part', ['mosd.objects.wov']),
    ('parts found at IoU ≥ 0.5 {:.3f}', ['mosd.objects.parts_found']),
    ('{:.3f} per whole object', ['mosd.whole_objects.wov']),
    ('a median {:g} and {:g} objects a frame',
     ['kitchen.objects_per_frame.median', 'studyroom.objects_per_frame.median']),
    ("the demo room's {:g} things as {:g} objects",
     ['demo.objects.things_found', 'demo.objects.count']),
    ('IDF1 {:.1f} % (area-weighted {:.1f} %)', ['kitchen.poses.idf1', 'kitchen.poses.idf1_area']),
    ('studyroom_dev (50 frames) {:.1f} % ({:.1f} %)',
     ['studyroom.poses.idf1', 'studyroom.poses.idf1_area']),
    ('accelerometer IDF1 {:.1f} % ({:.1f} %), up from the scene {:.1f} % ({:.1f} %), '
     'rotation-only poses {:.1f} % ({:.1f} %)',
     ['kitchen.accel.idf1', 'kitchen.accel.idf1_area', 'kitchen.level.idf1',
      'kitchen.level.idf1_area', 'kitchen.rotation.idf1', 'kitchen.rotation.idf1_area']),
    ('studyroom_dev (30 Hz): {:.1f} % ({:.1f} %), {:.1f} % ({:.1f} %), {:.1f} % ({:.1f} %)',
     ['studyroom.accel.idf1', 'studyroom.accel.idf1_area', 'studyroom.level.idf1',
      'studyroom.level.idf1_area', 'studyroom.rotation.idf1', 'studyroom.rotation.idf1_area']),
]


def latest_figures():
    figures = {}
    with open(os.path.join(ROOT, 'docs', 'quality_latest.txt')) as f:
        for line in f:
            fields = line.split()
            if len(fields) >= 4 and not line.startswith('#'):
                figures[fields[0]] = fields[1]
    return figures


class ReadmeFigures(unittest.TestCase):
    def test_the_results_quote_the_latest_guard_run(self):
        with open(os.path.join(ROOT, 'README.md')) as f:
            readme = f.read()
        figures = latest_figures()
        for text, names in QUOTED:
            with self.subTest(figures=names):
                for name in names:
                    self.assertIn(name, figures, 'docs/quality_latest.txt has no ' + name)
                    # A skipped figure (its data absent on the machine that ran the guard)
                    # cannot be quoted.
                    self.assertNotEqual(figures[name], 'skipped', name)
                quoted = text.format(*(float(figures[name]) for name in names))
                self.assertTrue(quoted in readme, 'README.md should say "%s" (%s in '
                                'docs/quality_latest.txt)' % (quoted, ', '.join(names)))


if __name__ == '__main__':
    unittest.main()
