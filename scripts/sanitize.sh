#!/usr/bin/env bash
# Builds hope and its tests with AddressSanitizer + UndefinedBehaviorSanitizer (GCC) into
# build_asan and runs the whole suite there, rostests included. Any sanitizer report fails the
# run (UBSan does not recover; ASan aborts). The nodelet manager and the other ROS binaries
# from Debian are not instrumented, so the ASan runtime is preloaded into every process of
# the run; leak checking is on for hope's own executables and off for the preloaded ones.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
out=$root/build_asan
# GCC warns of maybe-uninitialized falsely under ASan (boost::optional, std::regex).
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -Wno-maybe-uninitialized"
cmake -S "$root" -B "$out" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_MODULE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$out" -j2 >/dev/null
cmake --build "$out" -j2 --target tests >/dev/null
export ROS_HOSTNAME=localhost ROS_HOME="$out/ros_home" ROS_LOG_DIR="$out/ros_home/log"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
asan_runtime=$(gcc -print-file-name=libasan.so)
cd "$out"
# The downstream test installs and builds against the install space; an instrumented install
# is no use to an uninstrumented downstream build, so it runs in the ordinary suite only.
# The quality guard measures every figure over whole data sets, and the docs-examples test runs
# every command the docs print: 24 and 9 minutes under ASan on the CI machine; the ordinary
# (release) suite runs both. Under the sanitizers the same code paths run in the unit,
# CLI and hostile-input tests; these two would push the CI past its 90-minute limit.
echo "== unit tests under ASan + UBSan"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 ctest --output-on-failure \
  -E "rostest|python_|downstream_install|quality_guard"
echo "== rostests under ASan + UBSan (runtime preloaded into the ROS processes)"
LD_PRELOAD=$asan_runtime ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:verify_asan_link_order=0 \
  ctest --output-on-failure -R rostest
# python3 loads libstdc++ only with the bindings, after the ASan runtime has looked for the
# real __cxa_throw (ASan then aborts on the first C++ exception): preload libstdc++ too.
echo "== the Python tests under ASan + UBSan (runtime preloaded into the interpreter)"
LD_PRELOAD="$asan_runtime $(gcc -print-file-name=libstdc++.so.6)" \
  ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:verify_asan_link_order=0 \
  ctest --output-on-failure -R "^python_" -E "^python_docs_examples$"
