#!/usr/bin/env bash
# Configures and builds hope (Release) into ./build. Usage: scripts/build.sh [extra cmake args]
# `cmake --install build` then installs into build/install (as catkin_make does into
# ws/install), where the downstream test (test/downstream/check_install.sh) installs too.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH  # Debian's python3 first (catkin needs it)
root=$(cd "$(dirname "$0")/.." && pwd)
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DCMAKE_INSTALL_PREFIX="$root/build/install" "$@" >/dev/null
cmake --build "$root/build" -j2
cmake --build "$root/build" -j2 --target tests  # catkin leaves test executables out of "all"
