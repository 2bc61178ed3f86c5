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
# CPU time the hypervisor took from this VM during the run (the steal column of /proc/stat):
# on a shared host it makes figures slower and, worse, uneven between threads.
cpu_times() { awk '/^cpu /{print $2+$3+$4+$5+$6+$7+$8+$9, $9}' /proc/stat; }
read -r total_before steal_before < <(cpu_times)
# Google Benchmark's own header carries the date, the command and the machine. By default every
# case runs 10 times in random order and the median is reported: on a shared VM whose speed
# drifts by 1.5x within minutes, cases run one after another would each catch a different
# phase (Google Benchmark >= 1.6; older ones run each case once, in order).
flags=("$@")
if [ ${#flags[@]} -eq 0 ] &&
  ./build/devel/lib/hope/hope_benchmark --help | grep -q benchmark_enable_random_interleaving; then
  flags=(--benchmark_repetitions=10 --benchmark_enable_random_interleaving=true
    --benchmark_report_aggregates_only=true)
fi
./build/devel/lib/hope/hope_benchmark "${flags[@]}" 2>&1 | tee docs/benchmark_latest.txt
# The Python binding's cost over the C++ call, same machine, same run.
PYTHONPATH=$root/build/devel/lib/python3/dist-packages /usr/bin/python3 bench/python_overhead.py \
  2>&1 | tee -a docs/benchmark_latest.txt
# Cold first call against the steady state, and the whole hope_extract process's peak memory,
# on the benchmark's 6.0 M-point cloud written to a file (one thread, then every core), and on
# the TUM frame.
large=$root/build/bench_data
./build/devel/lib/hope/hope_synth --out "$large" --room-scan 0.00245 | tee -a docs/benchmark_latest.txt
# A cold call is one sample: three processes each, and the median of their cold / steady ratios.
cold_over_steady() {
  sed -nE 's/^cold first call ([0-9.]+) ms, steady state ([0-9.]+) ms.*/\1 \2/p' "$1" |
    awk '{ print $1 / $2 }' | sort -g | awk '{ r[NR] = $1 } END { printf "median of %d processes: cold / steady %.2fx\n", NR, r[int((NR + 1) / 2)] }'
}
for threads in 1 0; do
  echo "hope_extract --input room_scan.pcd --repeat 5 --threads $threads, 3 processes" | tee -a docs/benchmark_latest.txt
  : > "$large/cold.txt"
  for run in 1 2 3; do
    /usr/bin/time -v ./build/devel/lib/hope/hope_extract --input "$large/room_scan.pcd" --repeat 5 \
      --threads "$threads" 2> "$large/time.txt" | grep -E "^cold" | tee -a "$large/cold.txt" |
      tee -a docs/benchmark_latest.txt
    grep -E "Maximum resident" "$large/time.txt" | sed 's/^\s*/  /' | tee -a docs/benchmark_latest.txt
  done
  cold_over_steady "$large/cold.txt" | tee -a docs/benchmark_latest.txt
done
tum=$HOPE_SHARED_DATA/tum_fr1_desk/1305031459.274941.png
if [ -f "$tum" ]; then
  # The ground truth's last pose, as the benchmark takes.
  pose=$(grep -v '^#' "$(dirname "$tum")/groundtruth.txt" | tail -1 | cut -d' ' -f2-8)
  echo "hope_extract --depth (TUM frame) --pose (last ground-truth line) --repeat 20 --threads 1, 3 processes" |
    tee -a docs/benchmark_latest.txt
  : > "$large/cold.txt"
  for run in 1 2 3; do
    ./build/devel/lib/hope/hope_extract --depth "$tum" --pose "$pose" --repeat 20 --threads 1 |
      grep -E "^cold" | tee -a "$large/cold.txt" | tee -a docs/benchmark_latest.txt
  done
  cold_over_steady "$large/cold.txt" | tee -a docs/benchmark_latest.txt
fi
# The whole hope_extract process on a small file (a VLP-16 scan), where starting the program
# outweighs the pipeline: wall time and peak memory of 5 runs. A .pcd run loads no image codecs
# (include/hope/tools/image_codecs.h); the depth-image run above does.
small=$root/build/bench_small
./build/devel/lib/hope/hope_synth --out "$small" --lidar vlp16 >/dev/null
echo "hope_extract --input (VLP-16 scan, $(stat -c %s "$small/scan.pcd") bytes) --quiet, whole process, 5 runs" |
  tee -a docs/benchmark_latest.txt
for run in 1 2 3 4 5; do
  start=$(date +%s%N)
  /usr/bin/time -f "%M" -o "$small/rss.txt" ./build/devel/lib/hope/hope_extract \
    --input "$small/scan.pcd" --viewpoint "0 0 0" --r-xy 0.3 --r-z 0.1 --quiet
  end=$(date +%s%N)
  echo "  run $run: $(((end - start) / 1000000)) ms wall, peak $(($(cat "$small/rss.txt") / 1024)) MB" |
    tee -a docs/benchmark_latest.txt
done
read -r total_after steal_after < <(cpu_times)
awk -v t=$((total_after - total_before)) -v s=$((steal_after - steal_before)) \
  'BEGIN { printf "CPU time stolen by the hypervisor during this run: %.0f %%\n", (t > 0 ? 100 * s / t : 0) }' |
  tee -a docs/benchmark_latest.txt
