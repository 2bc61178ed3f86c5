"""Copies of the mOSD scenes labelled by whole object, as the dataset's README-mOSD.md prescribes for
methods that connect disjoint parts of one object ("merging object parts"): the table's parts 1-9 become 1,
and the parts 20-29, 30-39, ... of each object become 20, 30, ... (one label per object, still >= 20, so
../shared/tools/objects_score.py scores them unchanged). Writes label x y z as binary PCD, organized as read.
Usage: scripts/mosd_whole_objects.py MOSD_DIR OUT_DIR"""
import glob, os, sys

import numpy as np

SHARED_TOOLS = os.environ.get('HOPE_SHARED_TOOLS') or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), '..', '..', 'shared', 'tools')
sys.path.insert(0, SHARED_TOOLS)
import pcd  # noqa: E402  (the shared tools' PCD reader, beside objects_score.py)


def write_whole_object_scenes(source, target):
    """Writes each scene of `source` to `target` labelled by whole object; returns how many."""
    os.makedirs(target, exist_ok=True)
    scenes = sorted(glob.glob(os.path.join(source, '*.pcd')))
    if not scenes:
        raise RuntimeError(f'mosd_whole_objects: no .pcd in {source}')
    for path in scenes:
        cloud, width, height = pcd.read(path)
        label = cloud['label'].astype(np.uint32)
        merged = np.where((label >= 1) & (label <= 9), 1, np.where(label >= 20, label // 10 * 10, label))
        out = np.zeros(len(cloud), dtype=[('label', '<u4'), ('x', '<f4'), ('y', '<f4'), ('z', '<f4')])
        out['label'] = merged
        for axis in 'xyz':
            out[axis] = cloud[axis]
        header = ('# .PCD v0.7 - mOSD labelled by whole object (scripts/mosd_whole_objects.py)\n'
                  'VERSION 0.7\nFIELDS label x y z\nSIZE 4 4 4 4\nTYPE U F F F\nCOUNT 1 1 1 1\n'
                  f'WIDTH {width}\nHEIGHT {height}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(out)}\nDATA binary\n')
        with open(os.path.join(target, os.path.basename(path)), 'wb') as f:
            f.write(header.encode('ascii'))
            f.write(out.tobytes())
    return len(scenes)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    try:
        count = write_whole_object_scenes(sys.argv[1], sys.argv[2])
    except RuntimeError as error:
        sys.exit(str(error))
    print(f'{count} scenes labelled by whole object in {sys.argv[2]}')


if __name__ == '__main__':
    main()
