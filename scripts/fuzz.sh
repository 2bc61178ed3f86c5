#!/usr/bin/env bash
# Builds the libFuzzer targets in fuzz/ with clang (ASan + UBSan), writes their seed corpus and
# runs each for a bounded time. Fails on any crash, sanitizer report, leak, timeout (10 s for
# one input) or out-of-memory (2 GB). Needs a catkin build first (scripts/build.sh) for the
# generated message headers. Usage: scripts/fuzz.sh [seconds per target, default 60]
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
out=$root/build/fuzz
CC=clang CXX=clang++ cmake -S "$root/fuzz" -B "$out" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DHOPE_GENERATED_INCLUDE="$root/build/devel/include" >/dev/null
cmake --build "$out" -j2 >/dev/null
corpus=$out/corpus
rm -rf "$corpus"
mkdir -p "$corpus"/{pointcloud2,cloud_file,depth_image}
"$out/make_seeds" "$corpus"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for target in pointcloud2 cloud_file depth_image; do
  echo "== fuzz_$target for ${seconds} s"
  mkdir -p "$out/findings/$target"
  # -close_fd_mask=1: stdout closed (the targets print nothing worth keeping there).
  "$out/fuzz_$target" "$corpus/$target" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -max_len=65536 -close_fd_mask=1 \
    -artifact_prefix="$out/findings/$target/" -print_final_stats=1 2>&1 | tail -n 12
done
echo "fuzz: no crash, leak, timeout or out-of-memory in any target"
