#!/usr/bin/env bash
# Regenerates the two pictures at the top of the README and prints the tables they show:
# docs/demo_overlay.png (the demo room, as scripts/demo.sh makes it) and
# docs/tum_fr1_desk_overlay.png (the TUM freiburg1_desk frame in ../shared/data with its
# ground-truth pose).
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/demo.sh"
cp "$root/out/demo/overlay.png" "$root/docs/demo_overlay.png"
tum="$root/../shared/data/tum_fr1_desk"
if [ ! -d "$tum" ]; then
  echo "readme_pictures: no TUM frame at $tum; docs/tum_fr1_desk_overlay.png left as it is" >&2
  exit 0
fi
pose=$(grep -v '^#' "$tum/groundtruth.txt" | head -n 1 | cut -d' ' -f2-)
"$root/build/devel/lib/hope/hope_extract" --depth "$tum/1305031459.274941.png" \
  --rgb "$tum/1305031459.259760.png" --pose "$pose" --overlay "$root/docs/tum_fr1_desk_overlay.png"
echo "wrote docs/demo_overlay.png and docs/tum_fr1_desk_overlay.png"
