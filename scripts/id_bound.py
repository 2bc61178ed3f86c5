#!/usr/bin/python3
"""The best IDF1 any id assignment could reach on a sequence run's planes, as
../shared/tools/id_accuracy.py scores it (its README: planes of frames at most WINDOW frames apart
whose world heights differ < 3 cm and whose xy boxes overlap >= 30 % of the smaller box are one
surface, joined transitively; IDF1 pairs surfaces and ids one to one). Within a frame ids are
distinct, so when the extraction gives one surface two planes in a frame, only one of them can
carry the surface's id: every further plane is lost whatever the tracker or the map does. This
prints that ceiling, per observation and area-weighted, to read the scorer's figures against.
Usage: id_bound.py RUN.jsonl [--window N]   (RUN.jsonl from hope_extract --sequence with world
poses; N defaults to 30, as the scorer's)"""
import json
import sys


def main(path, window):
    frames = []
    for line in open(path):
        if not line.strip():
            continue
        record = json.loads(line)
        frames.append([(p['height'], p['bbox'], p.get('area', 0.0)) for p in record.get('planes', [])])
    nodes = [(f, k) for f, planes in enumerate(frames) for k in range(len(planes))]
    parent = {n: n for n in nodes}

    def root(n):
        while parent[n] != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n

    def shared(a, b):
        w = max(0.0, min(a[2], b[2]) - max(a[0], b[0]))
        h = max(0.0, min(a[3], b[3]) - max(a[1], b[1]))
        smaller = min((a[2] - a[0]) * (a[3] - a[1]), (b[2] - b[0]) * (b[3] - b[1])) or 1e-9
        return w * h / smaller

    for i, (fa, ka) in enumerate(nodes):
        for fb, kb in nodes[i + 1:]:
            if fb - fa > window:
                break
            a, b = frames[fa][ka], frames[fb][kb]
            if abs(a[0] - b[0]) < 0.03 and shared(a[1], b[1]) >= 0.3:
                parent[root((fa, ka))] = root((fb, kb))
    kept = kept_area = total_area = 0.0
    surfaces = set()
    for f, planes in enumerate(frames):
        best = {}  # per surface in this frame: the one plane that can carry its id
        for k, plane in enumerate(planes):
            s = root((f, k))
            surfaces.add(s)
            total_area += plane[2]
            best[s] = max(best.get(s, 0.0), plane[2])
        kept += len(best)
        kept_area += sum(best.values())
    print(f'{len(nodes)} plane observations, {len(surfaces)} surfaces (window {window}): '
          f'best reachable IDF1 {100 * kept / max(len(nodes), 1):.1f} % '
          f'(area-weighted {100 * kept_area / max(total_area, 1e-12):.1f} %)')


if __name__ == '__main__':
    args = sys.argv[1:]
    if not args or args[0].startswith('-'):
        sys.exit(__doc__)
    main(args[0], int(args[args.index('--window') + 1]) if '--window' in args else 30)
