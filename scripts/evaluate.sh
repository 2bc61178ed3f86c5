#!/usr/bin/env bash
# Regenerates docs/evaluation.md and docs/evaluation/*.png: the paper's experiments on
# synthetic scenes with exact ground truth, hope beside PCL RANSAC and region growing.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build/devel/lib/hope/hope_eval --out docs >/dev/null  # prints the headline claims
echo "wrote docs/evaluation.md and docs/evaluation/"
