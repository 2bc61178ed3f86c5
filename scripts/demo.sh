#!/usr/bin/env bash
# Installs dependencies, builds hope, renders the synthetic demo room and extracts its
# horizontal planes. Result: out/demo/overlay.png (planes tinted, "id: height" on each),
# out/demo/planes.json, and a table on stdout.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/install_deps.sh"
bash "$root/scripts/build.sh" >/dev/null
bin="$root/build/devel/lib/hope"
out="$root/out/demo"
mkdir -p "$out"
"$bin/hope_synth" --out "$out"
"$bin/hope_extract" --depth "$out/depth.png" --rgb "$out/rgb.png" --pose "$(cat "$out/pose.txt")" \
  --json "$out/planes.json" --labels "$out/labels.pcd" --overlay "$out/overlay.png"
echo
echo "True planes (from the scene): see $out/truth.txt"
echo "Picture: $out/overlay.png"
