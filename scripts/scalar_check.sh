#!/usr/bin/env bash
# Builds the core with its portable scalar paths instead of the SSE2 ones (CMake option
# hope_SCALAR_ONLY, see src/core/simd.h) into build_scalar and runs the core's unit tests there:
# an ARM robot runs those paths, and the tests that compare optimized and plain results bit for
# bit hold on them too. Assumes the dependencies are installed (scripts/install_deps.sh).
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
out=$root/build_scalar
tests="test_alignment test_stages test_extractor test_bad_input test_tum test_fragment_merging
  test_plane_outline test_lidar test_threads test_reference_pipeline test_tracking test_sequence
  test_cli_io test_up_estimation"
cmake -S "$root" -B "$out" -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -Dhope_SCALAR_ONLY=ON >/dev/null
# shellcheck disable=SC2086
cmake --build "$out" -j2 --target hope_extract hope_synth $tests >/dev/null
cd "$out"
regex=$(echo $tests | sed 's/ /|/g')
ctest --output-on-failure -R "_ctest_hope_gtest_($regex)\$"
