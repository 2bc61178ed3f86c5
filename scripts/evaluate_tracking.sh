#!/usr/bin/env bash
# Regenerates docs/tracking.md: plane identities on the synthetic tracking sequences (the
# paper's NNPM, the improved tracker and the surface map; about 2 minutes on one core), then
# the real kitchen sequence (scripts/map_kitchen.sh, about 1 minute) when ../shared/data holds
# it; without it the kitchen section is the last run's docs/map_kitchen.md, and says so.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build/devel/lib/hope/hope_track_eval --frames 90 --markdown docs/tracking.md
data=${HOPE_SHARED_DATA:-../shared/data}
fresh=yes
if ! bash scripts/map_kitchen.sh >/dev/null; then
  fresh=no
  echo "evaluate_tracking: kitchen_dev not scored; keeping the last docs/map_kitchen.md" >&2
fi
{
  cat <<'TEXT'

## The real kitchen sequence (kitchen_dev), with world poses

85 frames of a real Kinect sequence in a kitchen (every 10th frame of a recording, 3 Hz; TUM
layout with `groundtruth.txt` in a gravity-aligned world; research use only, read from
`../shared/data/kitchen_dev`, never committed). No per-point ground truth exists:
`../shared/tools/id_accuracy.py --world` derives the surfaces from the poses (planes of frames
at most 30 frames apart whose heights differ < 3 cm and whose xy boxes overlap ≥ 30 % of the
smaller are one surface, joined transitively). With its 30-frame window a surface unseen for
longer counts as a new surface; the map's ids end there too (a surface unseen in 30 frames in
a row takes a new id), and `--map-forget 0` keeps them however long, which the scorer counts as one
id on two surfaces; the second line of each mode scores with the window over the whole run.
`id_bound.py` gives the ceiling of any id assignment on the same planes: within a frame ids are
distinct, so a surface the extraction gives two planes in one frame loses one of them whatever
the tracker or the map does. `id_horizon.py` scores each run again with every id ended where it
comes back after more than the window unseen (as the tracker's lost planes end): what the
window costs a run that keeps its ids. Window 3 at 3 Hz is the second that 30 frames are in a
30 Hz recording: there the map with a memory of 3 frames scores above the tracker, with none
below it.
Made by `bash scripts/map_kitchen.sh` (→ docs/map_kitchen.md), run by this script.

TEXT
  [ "$fresh" = no ] && echo "_kitchen_dev was not found in this run ($data): the figures below are the last run's._" && echo
  cat docs/map_kitchen.md
} >>docs/tracking.md
echo "wrote docs/tracking.md"
