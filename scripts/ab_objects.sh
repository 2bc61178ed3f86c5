#!/usr/bin/env bash
# A/B of the objects stage (the JSON's timings_ms.objects, steady state of 20 calls) on the
# mOSD test57 scene, the TUM frame and a synthetic HDL-64E street scan (hope_synth's, the
# benchmark's third input), two hope_extract builds interleaved three times.
# Usage: bash scripts/ab_objects.sh OLD_HOPE_EXTRACT NEW_HOPE_EXTRACT
set -euo pipefail
A=$1; B=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
data=${HOPE_SHARED_DATA:-$(cd "$(dirname "$0")/.." && pwd)/../shared/data}
f=$data/mosd_dev/test57.pcd
D=$data/tum_fr1_desk/1305031459.274941.png
P="-0.2171 -0.0799 1.3959 -0.8445 -0.0451 0.0954 0.5251"
# One scan for both builds, rendered by this tree's hope_synth.
synth=$(cd "$(dirname "$0")/.." && pwd)/build/devel/lib/hope/hope_synth
"$synth" --out "$tmp/scan" --lidar hdl64 >/dev/null
for i in 1 2 3; do
  for X in A B; do
    if [ $X = A ]; then bin=$A; else bin=$B; fi
    $bin --input $f --gravity "0 -0.8 -0.6" --json "$tmp/m.json" --repeat 20 --quiet
    m=$(grep -o '"objects": [0-9][0-9.]*' "$tmp/m.json" | cut -d' ' -f2)
    $bin --depth $D --pose "$P" --json "$tmp/t.json" --repeat 20 --quiet
    t=$(grep -o '"objects": [0-9][0-9.]*' "$tmp/t.json" | cut -d' ' -f2)
    $bin --input "$tmp/scan/scan.pcd" --viewpoint "0 0 0" --r-xy 0.3 --r-z 0.1 --json "$tmp/s.json" \
      --repeat 20 --quiet
    s=$(grep -o '"objects": [0-9][0-9.]*' "$tmp/s.json" | cut -d' ' -f2)
    echo "$X mosd_test57 $m ms  tum_fr1_desk $t ms  hdl64_street $s ms"
  done
done
