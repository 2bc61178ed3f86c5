#!/usr/bin/env bash
# A/B of the core library: builds libhope_core at two revisions and runs this tree's
# hope_benchmark with each in turn (LD_LIBRARY_PATH before the binary's RUNPATH), round after
# round, so both see the same phases of a shared host; prints, per case and revision, the
# median over the rounds of the time and of every stage counter, and each stage as a share of
# the stages both revisions leave alone (REFERENCE), which cancels the host's drift between
# rounds. The revisions' core must keep this tree's headers (a change inside .cpp files).
# Usage: scripts/ab_benchmark.sh BEFORE AFTER [ROUNDS] [FILTER] [REFERENCE]
#   e.g. scripts/ab_benchmark.sh 4c69e74 52c08d0 6 'BM_Hope/(0|2|3)/1/1/' merge,cand+clust,describe
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
if [ $# -lt 2 ]; then
  sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
before=$1 after=$2 rounds=${3:-6} filter=${4:-BM_Hope/0/1/1/} reference=${5:-merge,cand+clust}
bench=$root/build/devel/lib/hope/hope_benchmark
[ -x "$bench" ] || { echo "ab_benchmark: build first (bash scripts/build.sh)" >&2; exit 1; }
export HOPE_SHARED_DATA=${HOPE_SHARED_DATA:-$root/../shared/data}
# A dot-folder: roslaunch looks for a package's launch files in every folder below the package
# except those, and each revision's source tree here has its own launch/.
work=$root/build/.ab
mkdir -p "$work"
for rev in "$before" "$after"; do
  commit=$(git -C "$root" rev-parse --verify "$rev^{commit}")
  if [ ! -f "$work/$commit/lib/libhope_core.so" ]; then
    rm -rf "$work/$commit"
    mkdir -p "$work/$commit/src"
    git -C "$root" archive "$commit" | tar -x -C "$work/$commit/src"
    cmake -S "$work/$commit/src" -B "$work/$commit/build" -DCMAKE_BUILD_TYPE=Release \
      -DPYTHON_EXECUTABLE=/usr/bin/python3 >/dev/null
    cmake --build "$work/$commit/build" -j2 --target hope_core >/dev/null
    mkdir -p "$work/$commit/lib"
    cp "$work/$commit/build/devel/lib/libhope_core.so" "$work/$commit/lib/"
  fi
done
results=$work/results.txt
: >"$results"
for round in $(seq "$rounds"); do
  for rev in "$before" "$after"; do
    commit=$(git -C "$root" rev-parse --verify "$rev^{commit}")
    LD_LIBRARY_PATH=$work/$commit/lib "$bench" --benchmark_filter="$filter" \
      --benchmark_min_time=0.3 2>/dev/null | grep '^BM_' | sed "s|^|$rev |" >>"$results"
  done
  echo "round $round of $rounds done" >&2
done
echo "hope_benchmark --benchmark_filter='$filter', $rounds rounds, libhope_core of $before and $after alternating; medians over the rounds"
/usr/bin/python3 - "$results" "$reference" <<'PY'
import collections, statistics, sys
rows = collections.defaultdict(lambda: collections.defaultdict(list))
reference = sys.argv[2].split(",")
for line in open(sys.argv[1]):
    fields = line.split()
    rev, name = fields[0], fields[1]
    values = {"time_ms": float(fields[2])}
    for field in fields[6:]:
        key, _, value = field.partition("=")
        if not key.endswith("_ms") or key.startswith("points") or not value:
            continue
        scale = 1e-3 if value.endswith("m") else 1.0
        values[key] = float(value.rstrip("m")) * scale
    for key, value in values.items():
        rows[(name, rev)][key].append(value)
    stages = [values.get(k + "_ms") for k in reference]
    if all(s is not None for s in stages) and sum(stages) > 0:
        for key, value in values.items():
            rows[(name, rev)]["share:" + key].append(value / sum(stages))
for (name, rev), table in sorted(rows.items(), key=lambda item: item[0][0]):
    plain = " ".join(f"{k[:-3]}={statistics.median(v):.3f}" for k, v in table.items()
                     if not k.startswith("share:"))
    print(f"{name} {rev}: {plain}")
    shares = " ".join(f"{k[6:-3]}={statistics.median(v):.3f}" for k, v in table.items()
                      if k.startswith("share:"))
    if shares:
        print(f"  as shares of {'+'.join(reference)}: {shares}")
PY
