#!/usr/bin/python3
"""How much of a run's id score is lost to the scorer's horizon. ../shared/tools/id_accuracy.py
joins two planes into one surface only when they are at most WINDOW frames apart (default 30,
the improved tracker's memory), directly or through planes between: a surface out of view for
longer comes back as a new surface, and an id that stayed on it (as the surface map's ids do
with no memory limit, --map-forget 0; by default they end after 30 frames unseen) is scored as
one id on two surfaces. This prints
- the ids seen again after more than WINDOW frames unseen, and how many of those came back to
  the same place (world heights within 3 cm and boxes sharing >= 30 % of the smaller, the
  scorer's own test, between the id's last plane before the gap and its first after it);
- the scorer's figures for the run as it is, and for the same run with each such id renamed
  where it comes back (what the run would score had every id ended after WINDOW unseen frames,
  as the tracker's lost planes do). The planes, their surfaces and the frames are the same.
Usage: id_horizon.py RUN.jsonl [--window N] [--scorer id_accuracy.py]   (RUN.jsonl from
hope_extract --sequence with world poses; the scorer defaults to $HOPE_SHARED_TOOLS/id_accuracy.py,
else ../shared/tools/id_accuracy.py)"""
import importlib.util
import json
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def scorer(path):
    if not path:
        tools = os.environ.get('HOPE_SHARED_TOOLS', os.path.join(ROOT, '..', 'shared', 'tools'))
        path = os.path.join(tools, 'id_accuracy.py')
    if not os.path.exists(path):
        sys.exit(f'id_horizon.py: the scorer {path} is missing (set HOPE_SHARED_TOOLS or --scorer)')
    spec = importlib.util.spec_from_file_location('id_accuracy', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def id_field(record):
    planes = record.get('planes') or []
    return 'surface_id' if planes and 'surface_id' in planes[0] else 'id'


def main(path, window, scorer_path=None):
    accuracy = scorer(scorer_path)
    records = [json.loads(line) for line in open(path) if line.strip()]
    records = [r for r in records if 'planes' in r]  # skipped frames carry none
    last_frame, last_place, renamed = {}, {}, {}
    next_name = 1 + max([p[id_field(r)] for r in records for p in r['planes']] + [0])
    returns = same = 0
    for frame, record in enumerate(records):
        field = id_field(record)
        places = {}
        for plane in record['planes']:
            place = (plane['height'], plane['bbox'])
            ident = plane[field]
            # The frame's largest plane of the id stands for it (pieces share a surface id).
            if ident not in places or plane.get('area', 0) > places[ident][1]:
                places[ident] = (place, plane.get('area', 0))
        for ident, (place, _) in places.items():
            if ident in last_frame and frame - last_frame[ident] > window:
                returns += 1
                # The scorer's own test for one surface: heights within 3 cm, boxes sharing
                # >= 30 % of the smaller one.
                before = last_place[ident]
                same += (abs(before[0] - place[0]) < 0.03
                         and accuracy.overlap(before[1], place[1]) >= 0.3)
                renamed[ident] = next_name
                next_name += 1
            last_frame[ident], last_place[ident] = frame, place
        for plane in record['planes']:
            plane[field] = renamed.get(plane[field], plane[field])
    print(f'ids seen again after more than {window} frames unseen: {returns}, '
          f'{same} of them at the same place (within 3 cm, boxes sharing >= 30 %)')
    print('as run:', end=' ', flush=True)
    accuracy.main(path, None, True, window)
    with tempfile.NamedTemporaryFile('w', suffix='.jsonl', delete=False) as out:
        for record in records:
            out.write(json.dumps(record) + '\n')
    try:
        print(f'ids ended after {window} unseen frames:', end=' ', flush=True)
        accuracy.main(out.name, None, True, window)
    finally:
        os.unlink(out.name)


if __name__ == '__main__':
    args = sys.argv[1:]
    if not args or args[0].startswith('-'):
        sys.exit(__doc__)
    main(args[0], int(args[args.index('--window') + 1]) if '--window' in args else 30,
         args[args.index('--scorer') + 1] if '--scorer' in args else None)
