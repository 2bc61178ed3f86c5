#!/usr/bin/env bash
# Regenerates the objects pictures of docs/evaluation.md: docs/objects_{test57,test45,learn34}.png,
# hope_extract's overlay of three mOSD scenes (objects boxed, placements of a 0.10 x 0.10 m
# footprint with 0.02 m clearance painted green), each with the up ../shared/tools/objects_score.py
# gives it (the labelled table's normal). Usage: scripts/object_pictures.sh (after scripts/build.sh);
# SCENES="learn37 learn40" picks other scenes, OUT_DIR=/tmp writes the pictures there.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
data=${HOPE_SHARED_DATA:-$root/../shared/data}
tools=$root/../shared/tools
for need in "$data/mosd_dev" "$tools/objects_score.py" "$root/build/devel/lib/hope/hope_extract"; do
  [ -e "$need" ] || { echo "object_pictures: needs $need (scripts/build.sh, ../shared)" >&2; exit 1; }
done
for scene in ${SCENES:-test57 test45 learn34}; do
  up=$(python3 - "$tools" "$data/mosd_dev/$scene.pcd" <<'PY'
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
import objects_score, pcd
A, _, _ = pcd.read(sys.argv[2])
P = pcd.xyz(A)
table = np.isfinite(P).all(1) & (A['label'] >= 1) & (A['label'] <= 9)
print(' '.join(f'{u:.6f}' for u in objects_score.up_from(P[table])))
PY
)
  "$root/build/devel/lib/hope/hope_extract" --input "$data/mosd_dev/$scene.pcd" --gravity "$up" \
    --place "0.1 0.1 0.02" --overlay "${OUT_DIR:-$root/docs}/objects_$scene.png" --quiet
  echo "wrote ${OUT_DIR:-docs}/objects_$scene.png"
done
