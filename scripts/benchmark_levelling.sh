#!/usr/bin/env bash
# The cost of up from the scene (BM_UpFromScene: the estimate with no prior and the refinement
# of a given pose on the TUM frame, the estimate on the HDL-64E scan), each beside the
# pipeline's own time on the same input measured in the same process (its share_of_pipeline
# counter), with BM_Hope on the TUM frame interleaved. Writes docs/benchmark_levelling.txt,
# where the README's levelling cost comes from. Usage: scripts/benchmark_levelling.sh
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
bash scripts/build.sh >/dev/null
export HOPE_SHARED_DATA=${HOPE_SHARED_DATA:-$root/../shared/data}
out=docs/benchmark_levelling.txt
flags=("--benchmark_filter=BM_UpFromScene|BM_Hope/0/1/1/" --benchmark_repetitions=10
  --benchmark_report_aggregates_only=true)
if ./build/devel/lib/hope/hope_benchmark --help | grep -q benchmark_enable_random_interleaving; then
  flags+=(--benchmark_enable_random_interleaving=true)
fi
./build/devel/lib/hope/hope_benchmark "${flags[@]}" 2>&1 | grep -v "_stddev\|_mean" | tee "$out"
echo "$(nproc) cores; $(date -u +%Y-%m-%dT%H:%M:%SZ); commit $(git rev-parse --short HEAD)" | tee -a "$out"
