#!/usr/bin/env bash
# How much the objects on mosd_dev turn on where the crease split's patch grid falls: builds
# hope_extract from this tree's tracked files in a scratch folder with the grid moved OFFSET
# patches along x and y (src/core/crease_splitting.cpp, kLatticeNudge), for each OFFSET in turn,
# and scores each build with ../shared/tools/objects_score.py (one summary line per offset).
# A change to the objects stage that helps at one offset and not at the others fits the grid,
# not the scenes. Usage: scripts/crease_grid_offsets.sh [OFFSET ...]   (default 0 0.25 0.5 0.75)
# Takes about ten minutes on two cores (one build of hope_extract, then one file per offset).
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH  # Debian's python3 (numpy) and catkin's
root=$(cd "$(dirname "$0")/.." && pwd)
data=${HOPE_SHARED_DATA:-$root/../shared/data}
scorer=$root/../shared/tools/objects_score.py
for need in "$data/mosd_dev" "$scorer"; do
  [ -e "$need" ] || { echo "crease_grid_offsets: needs $need (../shared)" >&2; exit 1; }
done
offsets=("$@")
[ ${#offsets[@]} -gt 0 ] || offsets=(0 0.25 0.5 0.75)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/src"
git -C "$root" ls-files -z | (cd "$root" && xargs -0 tar -c) | tar -x -C "$work/src"
file=$work/src/src/core/crease_splitting.cpp
cp "$file" "$work/crease_splitting.cpp"
grep -q 'q.x() + kLatticeNudge' "$file" ||
  { echo "crease_grid_offsets: $file no longer keys patches by kLatticeNudge" >&2; exit 1; }
cmake -S "$work/src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 >/dev/null
for offset in "${offsets[@]}"; do
  sed -e "s/q\.x() + kLatticeNudge/q.x() + kLatticeNudge + static_cast<float>(${offset})/" \
    -e "s/q\.y() + kLatticeNudge/q.y() + kLatticeNudge + static_cast<float>(${offset})/" \
    "$work/crease_splitting.cpp" >"$file"
  cmake --build "$work/build" -j2 --target hope_extract >/dev/null
  echo "offset $offset: $(python3 "$scorer" "$work/build/devel/lib/hope/hope_extract" \
    --data "$data/mosd_dev" | grep '^hope:')"
done
