#!/usr/bin/env bash
# Objects and placements on the labelled mOSD scenes of ../shared/data/mosd_dev, scored by
# ../shared/tools/objects_score.py (per labelled part: weighted overlap, parts found at IoU >= 0.5,
# under/over-segmentation, false objects; placements valid when they rest on labelled table
# points clear of every labelled object point), then the stage's cost on test57 and on the TUM
# frame (the JSON's timings_ms after --repeat 20: the steady state), and beside hope PCL's
# classic tabletop pipeline and LCCP (hope_object_baselines) scored and timed on the same
# scenes, and again with each object's parts labelled as one (scripts/mosd_whole_objects.py).
# Writes docs/objects_mosd.txt,
# where the README's figures for objects and placements come from, and the pictures
# docs/objects_<scene>.png of three scenes (objects boxed, placements of 0.10 x 0.10 m painted).
# Usage: scripts/score_objects.sh
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
data=${HOPE_SHARED_DATA:-$root/../shared/data}
scorer=$root/../shared/tools/objects_score.py
if [ ! -f "$scorer" ] || [ ! -d "$data/mosd_dev" ]; then
  echo "score_objects: needs $scorer and $data/mosd_dev" >&2
  exit 1
fi
bash scripts/build.sh >/dev/null
extract=$root/build/devel/lib/hope/hope_extract
baselines=$root/build/devel/lib/hope/hope_object_baselines
out=docs/objects_mosd.txt
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# Gravity as the scorer gives it: the labelled table's normal, towards the camera.
gravity_of() {
  python3 - "$1" "$root/../shared/tools" <<'PY'
import sys
sys.path.insert(0, sys.argv[2])
import numpy as np
import pcd
cloud, _, _ = pcd.read(sys.argv[1])
xyz = pcd.xyz(cloud)
table = xyz[np.isfinite(xyz).all(1) & (cloud["label"] >= 1) & (cloud["label"] <= 9)]
centre = table.mean(0)
normal = np.linalg.svd(table - centre, full_matrices=False)[2][2]
normal = normal if normal @ -centre > 0 else -normal
print(" ".join("%.6f" % v for v in normal))
PY
}
{
  echo "# python3 ../shared/tools/objects_score.py build/devel/lib/hope/hope_extract (footprint 0.10 x 0.10 m, clearance 0.02 m)"
  python3 "$scorer" "$extract" --data "$data/mosd_dev"
  # The reference pipelines (src/evaluation/object_baselines.cpp) through the same scorer: they
  # propose no placements, so their placement line says 0 proposed and every scene missed.
  for method in tabletop lccp; do
    echo
    echo "# python3 ../shared/tools/objects_score.py build/devel/lib/hope/hope_object_baselines --method $method"
    python3 "$scorer" "$baselines" --data "$data/mosd_dev" --method "$method" | sed "s/^hope:/$method:/"
  done
  # The same, with each object's parts labelled as one (the dataset's own merge scheme,
  # scripts/mosd_whole_objects.py): one object per thing a person would name.
  HOPE_SHARED_TOOLS="$root/../shared/tools" python3 scripts/mosd_whole_objects.py "$data/mosd_dev" \
    "$tmp/whole" >/dev/null
  for method in hope tabletop lccp; do
    echo
    if [ "$method" = hope ]; then
      echo "# whole objects: python3 ../shared/tools/objects_score.py build/devel/lib/hope/hope_extract --data <mosd_dev by whole object>"
      python3 "$scorer" "$extract" --data "$tmp/whole" | grep -E '^(hope|placements)'
    else
      echo "# whole objects: python3 ../shared/tools/objects_score.py build/devel/lib/hope/hope_object_baselines --method $method --data <mosd_dev by whole object>"
      python3 "$scorer" "$baselines" --data "$tmp/whole" --method "$method" | grep '^hope:' |
        sed "s/^hope:/$method:/"
    fi
  done
  echo
  echo "# cost per scene, ms, the same input for all (the last of 5 runs): hope's objects and free"
  echo "# areas, hope's whole extraction (planes, objects, free areas), PCL's tabletop pipeline, LCCP"
  printf "%-8s %8s %8s %9s %8s\n" scene objects hope tabletop lccp
  for pcd in "$data"/mosd_dev/*.pcd; do
    scene=$(basename "$pcd" .pcd)
    up=$(gravity_of "$pcd")
    "$extract" --input "$pcd" --gravity "$up" --json "$tmp/m.json" --repeat 5 --quiet
    hope_objects=$(grep -o '"objects": [0-9.e-]*' "$tmp/m.json" | tail -1 | cut -d' ' -f2)
    hope_total=$(grep -o '"total": [0-9.e-]*' "$tmp/m.json" | tail -1 | cut -d' ' -f2)
    for method in tabletop lccp; do
      "$baselines" --input "$pcd" --gravity "$up" --method "$method" --repeat 5 --json "$tmp/$method.json" --quiet
    done
    printf "%-8s %8.1f %8.1f %9.1f %8.1f\n" "$scene" "$hope_objects" "$hope_total" \
      "$(grep -o '"objects": [0-9.e-]*}' "$tmp/tabletop.json" | tr -dc '0-9.')" \
      "$(grep -o '"objects": [0-9.e-]*}' "$tmp/lccp.json" | tr -dc '0-9.')"
  done | tee "$tmp/cost.txt"
  awk '{o += $2; h += $3; t += $4; l += $5; n++} END {printf "%-8s %8.1f %8.1f %9.1f %8.1f\n", "mean", o / n, h / n, t / n, l / n}' "$tmp/cost.txt"
  echo
  echo "# hope's cost, ms (steady state of 20 calls): objects and free areas, against the whole extraction"
  "$extract" --depth "$data/tum_fr1_desk/1305031459.274941.png" \
    --pose "-0.2171 -0.0799 1.3959 -0.8445 -0.0451 0.0954 0.5251" --json "$tmp/t.json" --repeat 20 --quiet
  echo "tum_fr1_desk (640x480): $(grep -o '"objects": [0-9.e-]*, "total": [0-9.e-]*' "$tmp/t.json")"
  echo "$(nproc) cores; $(date -u +%Y-%m-%dT%H:%M:%SZ); commit $(git rev-parse --short HEAD)"
} | tee "$out"
for scene in test57 learn34 test45; do
  "$extract" --input "$data/mosd_dev/$scene.pcd" --gravity "$(gravity_of "$data/mosd_dev/$scene.pcd")" \
    --place "0.10 0.10 0.02" --overlay "docs/objects_$scene.png" --quiet
done
