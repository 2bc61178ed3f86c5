#!/usr/bin/env bash
# Installs dependencies, builds hope with its tests, and runs every test. Also checks
# formatting (clang-format) and the package manifest (catkin_lint). Exit code: non-zero on
# any failure.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
bash scripts/install_deps.sh
bash scripts/build.sh
echo "== clang-format"
git ls-files '*.cpp' '*.h' | xargs clang-format --dry-run --Werror
echo "== catkin_lint"
catkin_lint --strict -W2 --ignore package_path_name "$root"
echo "== tests"
# rostests start their own master; keep their logs inside the build tree.
export ROS_HOSTNAME=localhost ROS_HOME="$root/build/ros_home" ROS_LOG_DIR="$root/build/ros_home/log"
if [ ! -d ../shared/data ]; then
  echo "note: ../shared/data is absent; tests that need real data will be skipped"
fi
cd build
ctest --output-on-failure
