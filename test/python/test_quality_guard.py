#!/usr/bin/python3
"""The quality guard (scripts/quality.py) itself: it fails a figure below its floor or above its
ceiling, one that was not measured (a scorer missing beside its data too), and a malformed
floors or figures file; it skips, without failing, figures whose data is absent; --raise tightens a floor a figure beats and never loosens one;
and every floor in quality/floors.txt names a figure the guard measures.
Needs the built hope_quality (HOPE_BIN_DIR, default build/devel/lib/hope)."""
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GUARD = os.path.join(ROOT, 'scripts', 'quality.py')


def guard(*args, floors=None, data=None):
    env = dict(os.environ)
    if floors is not None:
        env['QUALITY_FLOORS'] = floors
    if data is not None:
        env['HOPE_SHARED_DATA'] = data
    # The synthetic parts (demo room, pattern, streets; 210 staircase renderings; the cabinet room)
    # take about 35 s here on two cores; the limit is for a hang.
    r = subprocess.run([sys.executable, GUARD, *args], capture_output=True, text=True, env=env,
                       timeout=1800)
    return r.returncode, r.stdout, r.stderr


class QualityGuard(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)

    def write(self, name, text):
        path = os.path.join(self.tmp.name, name)
        with open(path, 'w') as f:
            f.write(text)
        return path

    def test_each_floor_is_one_line_and_a_breach_fails(self):
        figures = self.write('figures.txt', 'a.iou 0.9\nb.noise 3\nc.idf1 70\nd.far skipped\n')
        floors = self.write('floors.txt', '# comment\na.iou >= 0.85  # trailing comment\n'
                            'b.noise <= 2\n\nc.idf1 >= 70\nd.far >= 1\ne.gone <= 1\n')
        code, out, _ = guard('--figures', figures, floors=floors)
        self.assertEqual(code, 1)
        self.assertEqual(out.splitlines(), [
            'a.iou 0.9 0.85 ok',
            'b.noise 3 2 FAIL',
            'c.idf1 70 70 ok',  # the bound itself passes
            'd.far - 1 skipped',
            'e.gone - 1 FAIL (not measured)',
        ])

    def test_all_floors_met_exits_zero_and_absent_data_only_skips(self):
        figures = self.write('figures.txt', 'a.iou 0.9\nd.far skipped\n')
        floors = self.write('floors.txt', 'a.iou >= 0.9\nd.far <= 1\n')
        code, out, err = guard('--figures', figures, floors=floors)
        self.assertEqual(code, 0, out + err)
        self.assertIn('1 ok, 0 failed, 1 skipped', err)

    def test_a_malformed_floor_is_refused_with_its_line(self):
        figures = self.write('figures.txt', 'a.iou 0.9\n')
        floors = self.write('floors.txt', 'a.iou >= 0.9\na.iou > 0.5\n')
        code, _, err = guard('--figures', figures, floors=floors)
        self.assertEqual(code, 2)
        self.assertIn('floors.txt:2', err)

    def test_a_malformed_figures_file_is_refused_and_blank_lines_are_not(self):
        floors = self.write('floors.txt', 'a.iou >= 0.9\n')
        code, out, err = guard('--figures', self.write('ok.txt', '\na.iou 0.95\n\n'), floors=floors)
        self.assertEqual(code, 0, out + err)
        code, _, err = guard('--figures', self.write('bad.txt', 'a.iou 0.95\nb.noise\n'), floors=floors)
        self.assertEqual(code, 2)
        self.assertIn('bad.txt:2', err)

    def test_a_scorer_missing_beside_present_data_fails_rather_than_skips(self):
        data = os.path.join(self.tmp.name, 'data')
        os.makedirs(os.path.join(data, 'mosd_dev'))
        env_tools = os.path.join(self.tmp.name, 'no_tools')
        os.environ['HOPE_SHARED_TOOLS'] = env_tools
        try:
            code, out, err = guard(data=data)
        finally:
            del os.environ['HOPE_SHARED_TOOLS']
        self.assertEqual(code, 1, out + err)
        self.assertIn('objects_score.py is not', err)
        self.assertRegex(out, r'mosd\.objects\.wov - \S+ FAIL \(not measured\)')

    def test_raise_tightens_what_a_figure_beats_and_loosens_nothing(self):
        figures = self.write('figures.txt', 'a.iou 0.95\nb.noise 1\nc.idf1 60\nd.count 7\n')
        floors = self.write('floors.txt', '# kept\na.iou >= 0.9  # kept too\nb.noise <= 2\n'
                            'c.idf1 >= 70\nd.count <= 7\n')
        code, _, _ = guard('--figures', figures, '--raise', floors=floors)
        self.assertEqual(code, 1)  # c.idf1 is below its floor, and stays there
        with open(floors) as f:
            self.assertEqual(f.read(), '# kept\na.iou >= 0.947  # kept too\nb.noise <= 1\n'
                             'c.idf1 >= 70\nd.count <= 7\n')

    def test_raise_tightens_counts_measured_as_ints_too(self):
        # The objects a frame are counted in quality.py itself (ints), not read from a file.
        import importlib.util
        spec = importlib.util.spec_from_file_location('quality_guard', GUARD)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        floors = self.write('floors.txt', 'a.objects_per_frame.max <= 26\nb.flag <= 3\n')
        module.raise_floors(floors, {'a.objects_per_frame.max': 21, 'b.flag': True})
        with open(floors) as f:
            self.assertEqual(f.read(), 'a.objects_per_frame.max <= 21\nb.flag <= 3\n')

    def test_without_data_the_synthetic_figures_are_guarded_and_the_rest_skipped(self):
        code, out, err = guard(data=os.path.join(self.tmp.name, 'no_data'))
        self.assertEqual(code, 0, out + err)
        lines = [line.split() for line in out.splitlines()]
        measured = {fields[0] for fields in lines if fields[-1] == 'ok'}
        skipped = {fields[0] for fields in lines if fields[-1] == 'skipped'}
        self.assertIn('pattern.scan.correct', measured)
        self.assertIn('demo.planes.correct', measured)
        self.assertIn('lidar_street.hdl64.ground.pieces', measured)
        self.assertIn('kitchen.poses.idf1', skipped)
        self.assertIn('mosd.objects.wov', skipped)
        self.assertIn('studyroom.up_error_deg.median', skipped)
        # Every floor of quality/floors.txt was measured or skipped: none names a figure the
        # guard does not make.
        with open(os.path.join(ROOT, 'quality', 'floors.txt')) as f:
            floors = [line.split()[0] for line in f if line.strip() and not line.startswith('#')]
        self.assertGreaterEqual(len(floors), 60)
        self.assertEqual(set(floors), measured | skipped)


if __name__ == '__main__':
    unittest.main(verbosity=2)
