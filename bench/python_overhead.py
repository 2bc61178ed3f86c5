#!/usr/bin/python3
"""What the Python binding costs over the C++ call it wraps, on the shared TUM frame (the
same frame and pose as hope_benchmark's BM_Hope/0). Each call's wall time in Python is set
against the core's own total (Result timings, measured inside Extractor::extract); the
difference is the binding: argument checks, the in-place view of the array, the GIL, the
result objects. Run by scripts/benchmark.sh; prints a small table."""

import os
import statistics
import sys
import time

import cv2

import hope

RUNS = 100


def main():
    shared = os.environ.get("HOPE_SHARED_DATA", "../shared/data")
    folder = os.path.join(shared, "tum_fr1_desk")
    depth = cv2.imread(os.path.join(folder, "1305031459.274941.png"), cv2.IMREAD_UNCHANGED)
    if depth is None:
        sys.exit(f"python_overhead: TUM frame not found under {folder} (set HOPE_SHARED_DATA)")
    with open(os.path.join(folder, "groundtruth.txt")) as f:
        lines = [line for line in f if line.strip() and not line.startswith("#")]
    pose = [float(v) for v in lines[-1].split()[1:8]]  # as hope_benchmark: the last line

    points = hope.depth_to_cloud(depth, (517.3, 516.5, 318.6, 255.3), 5000.0)
    extractor = hope.Extractor()
    for _ in range(5):  # warm the buffers, as the C++ benchmark does
        extractor.extract(points, pose=pose)
    wall, core = [], []
    for _ in range(RUNS):
        start = time.perf_counter()
        result = extractor.extract(points, pose=pose)
        wall.append((time.perf_counter() - start) * 1e3)
        core.append(result.timings_ms["total"])
    overhead = [w - c for w, c in zip(wall, core)]
    wall_ms, core_ms = statistics.median(wall), statistics.median(core)
    print(f"Python binding on the TUM frame ({RUNS} calls, {len(result.planes)} planes, medians)")
    print(f"  hope.Extractor.extract, wall time in Python  {wall_ms:8.3f} ms")
    print(f"  the C++ Extractor::extract inside it          {core_ms:8.3f} ms")
    print(f"  binding overhead                              {statistics.median(overhead):8.3f} ms"
          f"  ({100 * statistics.median(overhead) / core_ms:.1f} % of the C++ call)")


if __name__ == "__main__":
    main()
