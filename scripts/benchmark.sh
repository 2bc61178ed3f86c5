#!/usr/bin/env bash
# Runs the whole benchmark (hope beside PCL's reference stages, the nodelet's work per frame,
# tracking with 50 and 1,000 planes) and writes it to docs/benchmark_latest.txt, where the
# README's speed figures come from. Usage: scripts/benchmark.sh [extra benchmark flags]
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
bash scripts/build.sh
# The TUM frame comes from the shared data beside the checkout unless HOPE_SHARED_DATA says.
export HOPE_SHARED_DATA=${HOPE_SHARED_DATA:-$root/../shared/data}
# Google Benchmark's own header carries the date, the command and the machine.
./build/devel/lib/hope/hope_benchmark "$@" 2>&1 | tee docs/benchmark_latest.txt
# The Python binding's cost over the C++ call, same machine, same run.
PYTHONPATH=$root/build/devel/lib/python3/dist-packages /usr/bin/python3 bench/python_overhead.py \
  2>&1 | tee -a docs/benchmark_latest.txt
