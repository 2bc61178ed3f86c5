#!/usr/bin/env bash
# Plane ids and map extents on the real kitchen sequence (../shared/data/kitchen_dev, world poses
# from its groundtruth.txt): the paper's NNPM, the improved tracker and the surface map (the
# default with poses; a surface unseen in 30 frames in a row takes a new id), each scored by
# ../shared/tools/id_accuracy.py --world (surfaces derived from the poses: planes of frames at
# most 30 frames apart, heights within 3 cm, boxes overlapping >= 30 %), and once more with the
# window over the whole run (85 frames). Beside them the map with no memory limit
# (--map-forget 0: ids kept however long a surface is out of view, which the scorer's window
# counts as one id on two surfaces), the best any id assignment could reach on the same planes
# (scripts/id_bound.py), the runs with each id ended after the scorer's window unseen
# (scripts/id_horizon.py: at 30 frames, and at 3, the 1 s a 30 Hz recording's 30 frames are),
# the map with a memory of 3 frames scored at window 3, and the map's extents against the
# points (hope_extract --map-extents).
# Writes docs/map_kitchen.md; scripts/evaluate_tracking.sh puts it into docs/tracking.md.
# Usage: scripts/map_kitchen.sh
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
data=${HOPE_SHARED_DATA:-$root/../shared/data}
scorer=$root/../shared/tools/id_accuracy.py
if [ ! -f "$scorer" ] || [ ! -d "$data/kitchen_dev" ]; then
  echo "map_kitchen: needs $scorer and $data/kitchen_dev" >&2
  exit 1
fi
bash scripts/build.sh >/dev/null
extract=$root/build/devel/lib/hope/hope_extract
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
{
  echo '```'
  for mode in paper improved map; do
    extra=()
    [ "$mode" = map ] && extra=(--map-extents "$tmp/extents.md")
    echo "# hope_extract --sequence kitchen_dev --intrinsics \"585 585 320 240\" --tracking $mode"
    "$extract" --sequence "$data/kitchen_dev" --intrinsics "585 585 320 240" --tracking "$mode" \
      --jsonl "$tmp/$mode.jsonl" "${extra[@]}" --quiet 2>/dev/null
    echo "  window 30: $(python3 "$scorer" "$tmp/$mode.jsonl" --world)"
    echo "  window 85: $(python3 "$scorer" "$tmp/$mode.jsonl" --world --window 85)"
  done
  echo "# scripts/id_bound.py on the map's run: the ceiling of any id assignment on these planes"
  echo "  $(python3 scripts/id_bound.py "$tmp/map.jsonl")"
  echo "  $(python3 scripts/id_bound.py "$tmp/map.jsonl" --window 85)"
  # The map's memory (--map-forget, frames): none (0), and the 3 frames of window 3.
  echo "# hope_extract --sequence kitchen_dev --intrinsics \"585 585 320 240\" --tracking map --map-forget 0"
  "$extract" --sequence "$data/kitchen_dev" --intrinsics "585 585 320 240" --tracking map \
    --map-forget 0 --jsonl "$tmp/permanent.jsonl" --quiet 2>/dev/null
  echo "  window 30: $(python3 "$scorer" "$tmp/permanent.jsonl" --world)"
  echo "  window 85: $(python3 "$scorer" "$tmp/permanent.jsonl" --world --window 85)"
  echo "# hope_extract --sequence kitchen_dev --intrinsics \"585 585 320 240\" --tracking map --map-forget 3"
  "$extract" --sequence "$data/kitchen_dev" --intrinsics "585 585 320 240" --tracking map \
    --map-forget 3 --jsonl "$tmp/forget.jsonl" --quiet 2>/dev/null
  echo "  window 3: $(python3 "$scorer" "$tmp/forget.jsonl" --world --window 3)"
  # The scorer's horizon: each id ended where it comes back after more than the window unseen.
  # Window 3 at 3 Hz is the 1 s that 30 frames are at 30 Hz (a contiguous Kinect recording).
  for window in 30 3; do
    for mode in improved map permanent; do
      echo "# scripts/id_horizon.py on the $mode run, window $window"
      python3 scripts/id_horizon.py "$tmp/$mode.jsonl" --window "$window" --scorer "$scorer" |
        sed 's/^/  /'
    done
  done
  echo '```'
  echo
  echo "The map's largest entries: each outline against the union of all points given its id"
  echo "(\`hope_extract --map-extents\`, 2 cm grid, the points' cells closed over their 8"
  echo "neighbours so a far floor's sparse rows leave no holes):"
  echo
  cat "$tmp/extents.md"
  echo
  echo "$(nproc) cores; $(date -u +%Y-%m-%dT%H:%M:%SZ); commit $(git rev-parse --short HEAD)"
} >docs/map_kitchen.md
cat docs/map_kitchen.md
