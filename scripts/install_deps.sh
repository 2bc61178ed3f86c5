#!/usr/bin/env bash
# Installs everything hope needs on Debian 12 from Debian's own archive (ROS 1 lives in /usr).
# Safe to run again: when every package is already present it does nothing.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH

packages=(
  build-essential cmake pkg-config git
  ros-core-dev python3-rostest rosbash catkin-lint
  libnodeletlib-dev libnodeletlib-tools
  libpcl-ros-dev libpcl-conversions-dev libpcl-dev
  libcv-bridge-dev libopencv-dev libflann-dev libeigen3-dev
  libtf2-ros-dev libtf2-eigen-dev
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  python3-sensor-msgs python3-rosbag python3-tf2-msgs python3-opencv
  python3-diagnostic-msgs  # rostopic echo /diagnostics (the messages' Python classes)
  libdepth-image-proc-dev libimage-transport-dev libdiagnostic-updater-dev
  libvisualization-msgs-dev rviz xvfb imagemagick
  libshape-msgs-dev python3-shape-msgs  # planes and object boxes in the standard shapes
  libnav-msgs-dev python3-nav-msgs  # ~floor_grid (nav_msgs/OccupancyGrid)
  libgtest-dev libbenchmark-dev clang-format time  # time: peak memory in scripts/benchmark.sh
  pybind11-dev python3-dev python3-numpy python3-setuptools  # the Python bindings
  python3-scipy  # ../shared/tools/id_accuracy.py (the quality guard's identity figures)
  libboost-program-options-dev  # the command-line tools' arguments
  clang libclang-rt-14-dev  # libFuzzer and the sanitizer runtimes (scripts/fuzz.sh)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages already installed"
  exit 0
fi
echo "install_deps: installing ${#missing[@]} packages: ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO=sudo
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install_deps: done"
