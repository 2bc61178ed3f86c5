#!/usr/bin/python3
"""The quality guard: every figure hope is judged by on the data the project has, compared
with its floor in quality/floors.txt (or the file $QUALITY_FLOORS names).

The tests assert behaviour on known answers; this watches figures on real data that has no
single right answer (identities on a kitchen, objects on 50 tabletops), so that a change that
helps one figure and hurts another is seen before it lands. Run it after the build
(bash scripts/build.sh): bash scripts/quality.sh.

Figures, each one line "NAME VALUE BOUND ok|FAIL" (docs/quality.md says what each measures):
- hope_quality (C++, in-process): the demo room's planes and objects against its truth, the
  pattern object's 26 faces, the simulated LiDAR streets' ground, up from the scene on
  synthetic staircases, mOSD's table tops, up from the scene on mosd_dev, kitchen_dev and
  studyroom_dev, and objects per frame in those rooms;
- ../shared/tools/objects_score.py on mosd_dev: objects and placements, with the parts of one
  object scored apart (the issue's protocol) and as one whole object (the dataset's own merge
  scheme, scripts/mosd_whole_objects.py: what "one object per thing a person would name" asks);
- ../shared/tools/id_accuracy.py on kitchen_dev and studyroom_dev, run with the world poses,
  (the surface map and the improved tracker), with the accelerometer and with --level, and
  scripts/id_bound.py and scripts/id_horizon.py on the pose runs: plane identities, the
  extraction's ceiling, and the map's ids scored with each one ended after the scorer's window;
  and the objects a frame in the accelerometer and --level runs (an up with its error).
Floors file: "NAME >= BOUND" or "NAME <= BOUND" a line, "#" starts a comment. A figure whose
data is absent is reported "skipped" and does not fail; a floor whose figure was not measured
although its data is there fails. Exit 1 when any figure fails, 2 on a malformed floors file or
a missing build.
Usage: quality.py [--figures-only | --raise] [--figures FILE]
  --figures-only  print "NAME VALUE" for every figure and compare nothing;
  --figures FILE  compare the figures of FILE (as --figures-only prints them) instead of
                  measuring: for checking a floors file, and for the guard's own test;
  --raise         after the comparison, tighten in the floors file every bound a figure now
                  beats by more than its margin (margin(): run-to-run and rounding slack) to
                  the figure less that margin; never loosens one. Commit the change with the
                  change that earned it.
"""
import concurrent.futures
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get('HOPE_BIN_DIR') or os.path.join(ROOT, 'build', 'devel', 'lib', 'hope')
DATA = os.environ.get('HOPE_SHARED_DATA') or os.path.join(ROOT, '..', 'shared', 'data')
TOOLS = os.environ.get('HOPE_SHARED_TOOLS') or os.path.join(os.path.dirname(os.path.abspath(DATA)),
                                                              'tools')
SKIPPED = 'skipped'
# The recorded sequences: figure prefix -> folder under the shared data (each has its own intrinsics.txt).
SEQUENCES = {'kitchen': 'kitchen_dev', 'studyroom': 'studyroom_dev'}


def run(cmd, timeout=600):
    """Runs cmd; its stdout, or an exception that says what failed."""
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if r.returncode != 0:
        raise RuntimeError(f'{" ".join(cmd)} exited {r.returncode}: {r.stderr.strip()[-400:]}')
    return r.stdout


def number(pattern, text, what):
    m = re.search(pattern, text)
    if not m:
        raise RuntimeError(f'{what}: no match for {pattern!r} in {text[-300:]!r}')
    return float(m.group(1))


def parse_figures(lines, where):
    """'NAME VALUE' lines (blank ones skipped) as {name: value or SKIPPED}."""
    figures = {}
    for number_, line in enumerate(lines, 1):
        fields = line.split()
        if not fields:
            continue
        if len(fields) != 2 or not (fields[1] == SKIPPED or re.fullmatch(r'-?[0-9.]+(?:e[-+]?\d+)?|nan|inf', fields[1])):
            raise ValueError(f'{where}:{number_}: expected "NAME VALUE", got {line.strip()!r}')
        figures[fields[0]] = SKIPPED if fields[1] == SKIPPED else float(fields[1])
    return figures


def hope_quality(part):
    out = run([os.path.join(BIN, 'hope_quality'), '--part', part, '--data', DATA])
    return parse_figures(out.splitlines(), f'hope_quality --part {part}')


def scorer(name, data_folder):
    """The shared scorer `name`, or None when its data is absent (its figures are skipped); an
    error when the data is there and the scorer is not: a figure must not skip silently."""
    if not os.path.isdir(data_folder):
        return None
    path = os.path.join(TOOLS, name)
    if not os.path.isfile(path):
        raise RuntimeError(f'{data_folder} is there but {path} is not (set HOPE_SHARED_TOOLS)')
    return path


OBJECT_FIGURES = ['mosd.objects.wov', 'mosd.objects.parts_found', 'mosd.objects.parts_found_0.8',
                  'mosd.objects.under', 'mosd.objects.over', 'mosd.objects.false',
                  'mosd.objects.failed_scenes', 'mosd.placements.valid', 'mosd.placements.scenes_missed']


def segmentation_figures(out, names, what):
    """objects_score.py's summary line as figures `names`: weighted overlap, parts found at IoU
    0.5 and 0.8, under- and over-segmented parts."""
    patterns = [r'mean WOv ([0-9.]+)', r'correct@0\.5 ([0-9.]+)', r'@0\.8 ([0-9.]+)',
                r'under (\d+), over', r'over (\d+), false']
    return {name: number(pattern, out, what) for name, pattern in zip(names, patterns)}


def mosd_objects():
    score = scorer('objects_score.py', os.path.join(DATA, 'mosd_dev'))
    if not score:
        return {name: SKIPPED for name in OBJECT_FIGURES}
    out = run([sys.executable, score, os.path.join(BIN, 'hope_extract'), '--data',
               os.path.join(DATA, 'mosd_dev')], timeout=900)
    what = 'objects_score.py'
    return {
        **segmentation_figures(out, OBJECT_FIGURES[:5], what),
        'mosd.objects.false': number(r'false objects (\d+)', out, what),
        'mosd.objects.failed_scenes': number(r'scenes \((\d+) failed', out, what),
        'mosd.placements.valid': number(r'valid ([0-9.]+), scenes missed', out, what),
        'mosd.placements.scenes_missed': number(r'scenes missed (\d+)', out, what),
    }


WHOLE_OBJECT_FIGURES = ['mosd.whole_objects.wov', 'mosd.whole_objects.found',
                        'mosd.whole_objects.found_0.8', 'mosd.whole_objects.under',
                        'mosd.whole_objects.over']


def mosd_whole_objects():
    """objects_score.py on copies of mosd_dev labelled by whole object."""
    score = scorer('objects_score.py', os.path.join(DATA, 'mosd_dev'))
    if not score:
        return {name: SKIPPED for name in WHOLE_OBJECT_FIGURES}
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    os.environ.setdefault('HOPE_SHARED_TOOLS', TOOLS)
    import mosd_whole_objects
    with tempfile.TemporaryDirectory() as tmp:
        mosd_whole_objects.write_whole_object_scenes(os.path.join(DATA, 'mosd_dev'), tmp)
        out = run([sys.executable, score, os.path.join(BIN, 'hope_extract'), '--data', tmp],
                  timeout=900)
    return segmentation_figures(out, WHOLE_OBJECT_FIGURES, 'objects_score.py (whole objects)')


# The orientation each identity run is given, and how id_accuracy.py maps its planes into the
# world: poses (full, the sequence's groundtruth.txt: planes already in the world; the surface
# map, the default with poses, and the improved tracker), the accelerometer alone and up from
# the scene alone (--orientation-source scene), both scored through the true poses.
ID_MODES = {'poses': [], 'improved': ['--tracking', 'improved'],
            'accel': ['--accelerometer', '{dir}/accelerometer.txt'],
            'level': ['--orientation-source', 'scene'],
            'rotation': ['--groundtruth', '{rotation}']}
ID_FIGURES = ['idf1', 'idf1_area', 'ids_per_surface']


def identities(sequence, mode):
    folder = os.path.join(DATA, SEQUENCES[sequence])
    names = [f'{sequence}.{mode}.{f}' for f in ID_FIGURES]
    if mode == 'poses':
        names += [f'{sequence}.poses.id_ceiling', f'{sequence}.poses.id_ceiling_area',
                  f'{sequence}.poses.horizon_idf1', f'{sequence}.poses.horizon_idf1_area']
    # With an orientation only, the objects a frame too: the up's error (an accelerometer's,
    # the scene's) tilts the planes in the frame, and a tilted floor's far side must not become
    # things (the rooms part counts them with the true poses).
    objects_names = ([f'{sequence}.{mode}.objects_per_frame.median',
                      f'{sequence}.{mode}.objects_per_frame.max'] if mode in ('accel', 'level') else [])
    names += objects_names
    accuracy = scorer('id_accuracy.py', folder)
    if not accuracy:
        return {name: SKIPPED for name in names}
    with tempfile.TemporaryDirectory() as tmp:
        jsonl = os.path.join(tmp, 'run.jsonl')
        # rotation: the true poses with their position zeroed, an orientation written as poses.
        rotation = os.path.join(tmp, 'rotation_only.txt')
        with open(os.path.join(folder, 'groundtruth.txt')) as f, open(rotation, 'w') as out:
            for line in f:
                fields = line.split()
                if len(fields) == 8 and not line.startswith('#'):
                    out.write(' '.join([fields[0], '0', '0', '0'] + fields[4:]) + '\n')
        run([os.path.join(BIN, 'hope_extract'), '--sequence', folder, '--jsonl', jsonl, '--quiet']
            + [a.format(dir=folder, rotation=rotation) for a in ID_MODES[mode]], timeout=900)
        score = [sys.executable, accuracy, jsonl] + (
            ['--world'] if mode in ('poses', 'improved') else ['--poses', os.path.join(folder, 'groundtruth.txt')])
        out = run(score)
        what = f'id_accuracy.py on {sequence} ({mode})'
        surfaces = number(r'surfaces (\d+)', out, what)
        figures = {
            names[0]: number(r'IDF1 ([0-9.]+) %', out, what),
            names[1]: number(r'area-weighted ([0-9.]+) %', out, what),
            names[2]: number(r'ids (\d+)', out, what) / max(surfaces, 1),
        }
        if objects_names:
            with open(jsonl) as f:
                counts = [len(json.loads(line).get('objects', [])) for line in f if line.strip()]
            if not counts:
                raise RuntimeError(f'{jsonl}: no frames for {sequence} ({mode})')
            figures[objects_names[0]] = statistics.median(counts)
            figures[objects_names[1]] = max(counts)
        if mode == 'poses':
            out = run([sys.executable, os.path.join(ROOT, 'scripts', 'id_bound.py'), jsonl])
            what = f'id_bound.py on {sequence}'
            figures[names[3]] = number(r'best reachable IDF1 ([0-9.]+) %', out, what)
            figures[names[4]] = number(r'area-weighted ([0-9.]+) %', out, what)
            # By default the map's ids never end for not being seen; the scorer joins planes
            # at most 30 frames apart: the same run with each id ended after 30 unseen frames.
            out = run([sys.executable, os.path.join(ROOT, 'scripts', 'id_horizon.py'), jsonl,
                       '--scorer', accuracy])
            what = f'id_horizon.py on {sequence}'
            figures[names[5]] = number(r'ids ended after.*?IDF1 ([0-9.]+) %', out, what)
            figures[names[6]] = number(r'ids ended after.*?area-weighted ([0-9.]+) %', out, what)
    return figures


def measure():
    jobs = [(hope_quality, ('levelling',)), (mosd_objects, ()), (mosd_whole_objects, ())]
    jobs += [(identities, (s, m)) for s in SEQUENCES for m in ID_MODES]
    jobs += [(hope_quality, (part,)) for part in ('rooms', 'tables', 'synthetic', 'stairs', 'cabinet')]
    figures, errors = {}, []
    # Two at a time: the tools run on one thread each, and the machine has two cores.
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        futures = {pool.submit(f, *a): f'{f.__name__}{a}' for f, a in jobs}
        for future in concurrent.futures.as_completed(futures):
            try:
                figures.update(future.result())
            except Exception as e:  # one failed measurement must not hide the others
                errors.append(f'{futures[future]}: {e}')
    return figures, errors


def margin(name, value):
    """The slack a floor keeps below (or above) today's figure. Every figure is deterministic
    (one thread, seeded synthetic noise, no -march): the same build on the same data prints the
    same value, so the margin covers only rounding in the scorers' printouts and floating-point
    differences between compilers, never a real change. Counts get none."""
    if name.endswith(('idf1', 'idf1_area', 'id_ceiling', 'id_ceiling_area')):
        return 0.3  # percentage points, printed to 0.1; ~2 of a sequence's ~800 observations
    if '_deg.' in name:
        return 0.05  # degrees
    if name.endswith('height_error_mm'):
        return 0.1
    if name.endswith('ids_per_surface'):
        return 0.02
    if float(value).is_integer():
        return 0.0  # a count
    return 0.003  # a share or an IoU in [0, 1]


def tightened(op, bound, name, value):
    """The bound `value` earns, or `bound` when it earns none tighter."""
    slack = margin(name, value)
    if op == '>=':
        return max(bound, round(value - slack, 4))
    return min(bound, round(value + slack, 4))


def raise_floors(path, figures):
    lines, raised = open(path).read().splitlines(keepends=True), 0
    for k, line in enumerate(lines):
        m = re.match(r'(\s*)(\S+)(\s*)(>=|<=)(\s*)(-?[0-9.]+(?:e-?\d+)?)(.*)', line, re.S)
        value = figures.get(m.group(2)) if m else None
        # Counts computed here (objects a frame) are ints, the hope_quality figures floats.
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            continue
        bound = float(m.group(6))
        new = tightened(m.group(4), bound, m.group(2), float(value))
        if new != bound:
            lines[k] = ''.join(m.group(1, 2, 3, 4, 5)) + f'{new:g}' + m.group(7)
            print(f'quality: {m.group(2)} {m.group(4)} {bound:g} -> {new:g}', file=sys.stderr)
            raised += 1
    with open(path, 'w') as f:
        f.writelines(lines)
    print(f'quality: {raised} floor(s) raised in {path}', file=sys.stderr)


def read_floors(path):
    floors = []
    for number_, line in enumerate(open(path), 1):
        text = line.split('#', 1)[0].strip()
        if not text:
            continue
        m = re.fullmatch(r'(\S+)\s*(>=|<=)\s*(-?[0-9.]+(?:e-?\d+)?)', text)
        if not m:
            print(f'quality: {path}:{number_}: expected "NAME >= BOUND" or "NAME <= BOUND", got {text!r}',
                  file=sys.stderr)
            sys.exit(2)
        floors.append((m.group(1), m.group(2), float(m.group(3))))
    return floors


def read_figures(path):
    """Figures as --figures-only prints them; exits 2 on a line that is not one."""
    try:
        with open(path) as f:
            return parse_figures(f.read().splitlines(), path)
    except (OSError, ValueError) as e:
        print(f'quality: {e}', file=sys.stderr)
        sys.exit(2)


def compare(floors, figures):
    """Prints one line per floor; the number that failed and the number skipped."""
    failed = skipped = 0
    for name, op, bound in floors:
        value = figures.get(name)
        if value is None:
            print(f'{name} - {bound:g} FAIL (not measured)')
            failed += 1
        elif value == SKIPPED:
            print(f'{name} - {bound:g} skipped')
            skipped += 1
        else:
            ok = value >= bound if op == '>=' else value <= bound
            print(f'{name} {value:.6g} {bound:g} {"ok" if ok else "FAIL"}')
            failed += not ok
    return failed, skipped


def main():
    floors_path = os.environ.get('QUALITY_FLOORS') or os.path.join(ROOT, 'quality', 'floors.txt')
    figures_only = '--figures-only' in sys.argv
    floors = [] if figures_only else read_floors(floors_path)
    if '--figures' in sys.argv:
        figures, errors = read_figures(sys.argv[sys.argv.index('--figures') + 1]), []
    else:
        if not os.path.isfile(os.path.join(BIN, 'hope_quality')):
            print(f'quality: {BIN}/hope_quality not found: build first (bash scripts/build.sh)',
                  file=sys.stderr)
            return 2
        if not os.path.isdir(DATA):
            print(f'quality: {DATA} is absent: the real-data figures are skipped', file=sys.stderr)
        figures, errors = measure()
    for e in errors:
        print(f'quality: measurement failed: {e}', file=sys.stderr)
    if figures_only:
        for name in sorted(figures):
            print(name, figures[name] if figures[name] == SKIPPED else f'{figures[name]:.6g}')
        return 1 if errors else 0
    failed, skipped = compare(floors, figures)
    guarded = {name for name, _, _ in floors}
    for name in sorted(n for n in figures if n not in guarded):
        print(f'quality: {name} = {figures[name]} has no floor in {floors_path}', file=sys.stderr)
    if '--raise' in sys.argv:
        raise_floors(floors_path, figures)
    print(f'quality: {len(floors) - failed - skipped} ok, {failed} failed, {skipped} skipped '
          f'({floors_path})', file=sys.stderr)
    return 1 if failed or errors else 0


if __name__ == '__main__':
    sys.exit(main())
