#!/usr/bin/python3
"""hope from Python on one TUM RGB-D frame: depth image -> points -> horizontal planes, with
the camera pose from the sequence's ground truth (heights are then real heights above the
floor of the motion-capture frame).

    source build/devel/setup.bash   # or an install space's setup.bash
    scripts/python_example.py ../shared/data/tum_fr1_desk --overlay planes.png

Prints one line per plane and, with --overlay, writes the depth image with every plane's
pixels in its id's colour.
"""

import argparse
import bisect
import os
import sys

import cv2
import numpy as np

import hope

TUM_FREIBURG1 = (517.3, 516.5, 318.6, 255.3)  # fx fy cx cy


def nearest_pose(groundtruth, stamp):
    """The ground-truth line (tx ty tz qx qy qz qw) nearest in time to `stamp`."""
    stamps, poses = [], []
    with open(groundtruth) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            values = [float(v) for v in line.split()]
            stamps.append(values[0])
            poses.append(values[1:8])
    i = bisect.bisect_left(stamps, stamp)
    best = min((j for j in (i - 1, i) if 0 <= j < len(stamps)),
               key=lambda j: abs(stamps[j] - stamp))
    return poses[best]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder", help="a folder with a TUM depth PNG and groundtruth.txt")
    parser.add_argument("--depth", help="which depth PNG (default: the last one by name)")
    parser.add_argument("--overlay", help="write a picture of the planes here (PNG)")
    parser.add_argument("--r-xy", type=float, default=0.05)
    parser.add_argument("--r-z", type=float, default=0.02)
    args = parser.parse_args()

    pngs = sorted(f for f in os.listdir(args.folder) if f.endswith(".png"))
    depth_name = args.depth or (pngs[-1] if pngs else None)
    if depth_name is None:
        sys.exit(f"python_example: no depth PNG in {args.folder}")
    depth = cv2.imread(os.path.join(args.folder, depth_name), cv2.IMREAD_UNCHANGED)
    if depth is None:
        sys.exit(f"python_example: cannot read {depth_name}")
    stamp = float(os.path.splitext(os.path.basename(depth_name))[0])
    pose = nearest_pose(os.path.join(args.folder, "groundtruth.txt"), stamp)

    points = hope.depth_to_cloud(depth, TUM_FREIBURG1, scale=5000.0)  # H x W x 3, metres
    extractor = hope.Extractor(r_xy=args.r_xy, r_z=args.r_z)
    result = extractor.extract(points, pose=pose)

    print(f"{len(result.planes)} planes in {result.timings_ms['total']:.1f} ms "
          f"({result.stats['finite_points']} points, {result.stats['voxels']} voxels)")
    for plane in result.planes:
        print(f"  id {plane.id}: height {plane.height:.3f} m, area {plane.area:.2f} m², "
              f"{plane.num_points} points, facing {plane.facing}")

    if args.overlay:
        grey = cv2.normalize(depth, None, 0, 255, cv2.NORM_MINMAX).astype(np.uint8)
        picture = cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR)
        for index, plane in enumerate(result.planes):
            r, g, b = hope.plane_color(plane.id)
            picture[result.labels == index] = (b, g, r)
        cv2.imwrite(args.overlay, picture)
        print(f"wrote {args.overlay}")


if __name__ == "__main__":
    main()
