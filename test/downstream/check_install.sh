#!/usr/bin/env bash
# hope as another package sees it: installs the build into its install prefix (by default
# build/install, see CMakeLists.txt), then, from that install space only: builds and runs a
# small catkin package that links the core and hope_ros and loads the nodelet with pluginlib
# (test/downstream/hope_downstream), imports the Python bindings and runs one extraction,
# and checks every launch file with roslaunch-check. Run by ctest.
# The install is scratch: it is removed when this script ends, pass or fail. Left inside the
# source tree, it would give roslaunch two copies of every launch file of the package found
# in the source folder (`roslaunch hope tum.launch` → "multiple files named [tum.launch]"):
# roslaunch looks for a package's files in every folder below it, build/ included. The last
# check below launches by package name from the devel space, as the README does.
# Usage: check_install.sh BUILD_DIR INSTALL_PREFIX
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
here=$(cd "$(dirname "$0")" && pwd)
build=$(cd "$1" && pwd)
prefix=$2
case "$prefix" in
  "$build"/*) ;;
  *)
    echo "SKIP: the install prefix $prefix lies outside the build tree $build; this test" \
      "installs into it and runs only when it is a scratch folder there (the default)"
    exit 77
    ;;
esac
fail() {
  echo "FAIL: $*"
  exit 1
}

echo "== installing into $prefix"
rm -rf "$prefix"
work=$(mktemp -d)
trap 'rm -rf "$work" "$prefix"' EXIT
cmake --install "$build" >"$build/check_install.log" 2>&1 || {
  cat "$build/check_install.log"
  fail "cmake --install"
}
for f in include/hope/extractor.h include/hope/frame_pipeline.h \
  include/hope_ros/cloud_conversion.h lib/libhope_core.so lib/libhope_synthetic.so \
  lib/libhope_image_codecs.so lib/hope/hope_synth \
  lib/libhope_ros.so lib/libhope_nodelet.so lib/hope/hope_extract lib/hope/hope_node \
  share/hope/package.xml share/hope/nodelet_plugins.xml share/hope/msg/Plane.msg \
  share/hope/config/hope.yaml share/hope/rviz/hope.rviz share/hope/cmake/hopeConfig.cmake \
  setup.bash; do
  [ -e "$prefix/$f" ] || fail "$f is not installed"
done
# Private to the package: the stages', the tools', the evaluation's and the synthetic scenes'
# headers (the tools' and the evaluation's libraries are static and not exported).
for f in include/hope/tools include/hope/evaluation include/hope/synthetic \
  src/core/include/hope/grid_filter.h src/core/include/hope/up_estimation.h lib/libhope_io.so \
  lib/libhope_evaluation.so; do
  [ ! -e "$prefix/$f" ] || fail "$f is installed but private"
done
# The public API: exactly these hand-written headers (the messages' and dynamic_reconfigure's
# generated ones, named in CamelCase, aside), each compiling on its own with -Wall -Wextra.
public="hope/depth_image.h hope/extractor.h hope/frame_pipeline.h hope/orientation.h
hope/parameters.h hope/params.h hope/plane.h hope/plane_tracker.h hope/points_view.h
hope/surface_map.h hope_ros/cloud_conversion.h hope_ros/object_conversion.h"
installed=$(cd "$prefix/include" && find hope hope_ros -name '*.h' | grep -v '/[A-Z][^/]*\.h$' | sort)
[ "$installed" = "$(echo "$public" | tr ' ' '\n' | sort)" ] ||
  fail "the installed headers are not the public API: $(echo "$installed" | tr '\n' ' ')"
[ "$(echo "$installed" | wc -l)" -le 12 ] || fail "more than 12 public headers"
pcl_include=$(find /usr/include -maxdepth 1 -name 'pcl-*' | sort | tail -1)
for h in $installed; do
  echo "#include <$h>" | g++ -std=c++17 -fsyntax-only -Wall -Wextra -Werror -x c++ - \
    -I"$prefix/include" -isystem /usr/include/eigen3 -isystem "$pcl_include" \
    -isystem /usr/include/opencv4 >"$work/header.log" 2>&1 || {
    cat "$work/header.log"
    fail "$h does not compile on its own from the install space"
  }
done
echo "ok the public API: $(echo "$installed" | wc -l) headers, each compiling on its own"

set +u
# shellcheck disable=SC1091
source "$prefix/setup.bash"
set -u
[ "$(rospack find hope)" = "$prefix/share/hope" ] || fail "rospack finds hope at $(rospack find hope)"

echo "== a downstream catkin package against the install space"
cp -r "$here/hope_downstream" "$work/"
cmake -S "$work/hope_downstream" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 >"$work/configure.log" 2>&1 || {
  cat "$work/configure.log"
  fail "configuring the downstream package"
}
cmake --build "$work/build" -j2 >"$work/build.log" 2>&1 || {
  cat "$work/build.log"
  fail "building the downstream package"
}
if grep -q "warning:" "$work/build.log"; then
  cat "$work/build.log"
  fail "warnings in the downstream build (hope's headers must compile cleanly with -Wall -Wextra)"
fi
"$work/build/devel/lib/hope_downstream/hope_downstream" "$prefix" || fail "the downstream program"

echo "== the tools from the install space: images through the image module"
tools="$prefix/lib/hope"
"$tools/hope_synth" --out "$work/demo" >"$work/synth.log" 2>&1 || {
  cat "$work/synth.log"
  fail "hope_synth from the install space"
}
"$tools/hope_extract" --depth "$work/demo/depth.png" --rgb "$work/demo/rgb.png" \
  --pose "$(cat "$work/demo/pose.txt")" --overlay "$work/overlay.png" >"$work/extract.log" 2>&1 || {
  cat "$work/extract.log"
  fail "hope_extract --depth from the install space"
}
[ -s "$work/overlay.png" ] || fail "hope_extract wrote no overlay"
# Without the module beside it (a program copied elsewhere, with only the core library): a
# clear error naming the module, exit code 1, no crash.
mkdir -p "$work/moved/lib/hope"
cp "$tools/hope_extract" "$work/moved/lib/hope/"
cp "$prefix/lib/libhope_core.so" "$work/moved/lib/"
set +e
LD_LIBRARY_PATH="$work/moved/lib" "$work/moved/lib/hope/hope_extract" \
  --depth "$work/demo/depth.png" >"$work/moved.log" 2>&1
code=$?
set -e
[ "$code" = 1 ] || { cat "$work/moved.log"; fail "without the image module: exit code $code, not 1"; }
grep -q "needs hope's image module libhope_image_codecs.so" "$work/moved.log" || {
  cat "$work/moved.log"
  fail "without the image module: the error does not name it"
}
echo "ok hope_synth, hope_extract --depth --overlay; a clear error without the module"

echo "== Python from the install space"
/usr/bin/python3 - "$prefix" <<'PYTHON' || fail "python"
import sys

import numpy as np

import hope
import hope.msg

prefix = sys.argv[1]
assert hope.__file__.startswith(prefix), hope.__file__
assert hope.Extractor.__module__.startswith("hope"), hope.Extractor.__module__
# A floor at 0 and a box top at 0.5 m (20 x 20 cm), 1 cm apart, seen from above.
x, y = np.meshgrid(np.arange(0, 2, 0.01), np.arange(0, 2, 0.01))
z = np.where((x >= 0.9) & (x < 1.1) & (y >= 0.9) & (y < 1.1), 0.5, 0.0)
points = np.stack([x, y, z], -1).reshape(-1, 3)
result = hope.Extractor().extract(points)
heights = sorted(round(p.height, 4) for p in result.planes)
print("python planes:", heights, "from", hope.__file__)
assert heights == [0.0, 0.5], heights
message = hope.msg.Plane()
message.height = result.planes[0].height
PYTHON

echo "== launch files"
export ROS_HOME="$work/ros_home"  # roslaunch-check writes a result file there
for f in "$prefix"/share/hope/launch/*.launch; do
  args=()
  [ "$(basename "$f")" != tum.launch ] || args=(bag:=/tmp/a_tum_sequence.bag)  # required
  /usr/bin/python3 /usr/share/roslaunch/scripts/roslaunch-check "$f" "${args[@]}" \
    >"$work/check.log" 2>&1 || {
    cat "$work/check.log"
    fail "roslaunch-check $f"
  }
  roslaunch --files "$f" "${args[@]}" >/dev/null || fail "roslaunch --files $f"
  echo "ok $(basename "$f")"
done
echo "ok: hope works from its install space"

echo "== launching by package name from the devel space, after the install"
rm -rf "$prefix"
(
  set +u
  # shellcheck disable=SC1091
  source "$build/devel/setup.bash"
  set -u
  source_dir=$(cd "$here/../.." && pwd)
  [ "$(rospack find hope)" = "$source_dir" ] || fail "rospack finds hope at $(rospack find hope)"
  for f in "$source_dir"/launch/*.launch; do
    name=$(basename "$f")
    found=$(roslaunch --files hope "$name" bag:=/tmp/a_tum_sequence.bag 2>&1) ||
      fail "roslaunch hope $name: $found"
    # --files lists the launch file and those it includes; the named one must be the source's.
    echo "$found" | grep -qx "$f" || fail "roslaunch hope $name resolved to: $found"
    echo "ok roslaunch hope $name"
  done
) || exit 1
echo "OK: hope works from its install space, and launches by name afterwards"
