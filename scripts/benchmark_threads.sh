#!/usr/bin/env bash
# More threads against one, on an idle machine and with cores kept busy (as other nodes keep a
# robot's): the core's BM_HopeThreads (TUM frame, 6 M-point room, HDL-64E scan; 0, 1 or 2
# cores kept busy by spinning threads), then hope_extract on the TUM frame with --threads 1
# and 0 (every core) while 0 or 1 other processes spin. Writes docs/benchmark_threads.txt, where
# the README's thread figures come from. Usage: scripts/benchmark_threads.sh
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
bash scripts/build.sh
export HOPE_SHARED_DATA=${HOPE_SHARED_DATA:-$root/../shared/data}
out=docs/benchmark_threads.txt
flags=(--benchmark_filter=BM_HopeThreads --benchmark_repetitions=10
  --benchmark_report_aggregates_only=true)
if ./build/devel/lib/hope/hope_benchmark --help | grep -q benchmark_enable_random_interleaving; then
  flags+=(--benchmark_enable_random_interleaving=true)
fi
./build/devel/lib/hope/hope_benchmark "${flags[@]}" 2>&1 | grep -v "_stddev\|_cv\|_mean" | tee "$out"

tum=$HOPE_SHARED_DATA/tum_fr1_desk/1305031459.274941.png
if [ -f "$tum" ]; then
  pose=$(grep -v '^#' "$(dirname "$tum")/groundtruth.txt" | tail -1 | cut -d' ' -f2-8)
  spinners=()
  stop_spinners() {
    for p in "${spinners[@]}"; do kill "$p" 2>/dev/null || true; done
    spinners=()
  }
  trap stop_spinners EXIT
  for busy in 0 1; do
    [ "$busy" = 0 ] || { bash -c 'while :; do :; done' & spinners+=($!); }
    for threads in 1 0 1 0; do
      echo "hope_extract --depth (TUM frame) --repeat 40 --threads $threads, $busy other process(es) spinning: $(
        ./build/devel/lib/hope/hope_extract --depth "$tum" --pose "$pose" --repeat 40 \
          --threads "$threads" | grep -E '^cold')" | tee -a "$out"
    done
    stop_spinners
  done
fi
echo "$(nproc) cores; $(date -u +%Y-%m-%dT%H:%M:%SZ); commit $(git rev-parse --short HEAD)" | tee -a "$out"
