#!/usr/bin/env bash
# Regenerates docs/tracking.md: plane identities on the synthetic tracking sequences, the
# paper's NNPM vs the improved tracker (about 1.5 minutes on one core).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build/devel/lib/hope/hope_track_eval --frames 90 --markdown docs/tracking.md
echo "wrote docs/tracking.md"
