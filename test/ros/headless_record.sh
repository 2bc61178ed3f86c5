#!/usr/bin/env bash
# A headless replay recorded as the README says: `roslaunch hope tum.launch bag:=… record:=…`,
# launched by package name from the devel space. Every depth frame of the bag that has a pose
# must become one recorded /hope/planes message (none lost while the recorder connects, none
# while it falls behind), with the planes of
# the scene's ground truth, and /diagnostics must be readable by `rostopic echo` (the Python
# message classes installed) and count every frame. Run by ctest.
# Usage: headless_record.sh BUILD_DIR BAG EXPECTED_HEIGHTS...
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
build=$(cd "$1" && pwd)
bag=$2
shift 2
expected_heights=("$@")
fail() {
  echo "FAIL: $*"
  exit 1
}
[ -s "$bag" ] || fail "no bag $bag (built by the hope_test_bags target)"

work=$(mktemp -d)
launch_pid=""
cleanup() {
  [ -z "$launch_pid" ] || kill -INT "$launch_pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
set +u
# shellcheck disable=SC1091
source "$build/devel/setup.bash"
set -u
# A master of our own on a port of our own, so that a roscore already running is not disturbed.
port=$((20000 + $$ % 20000))
export ROS_MASTER_URI=http://localhost:$port ROS_HOSTNAME=localhost
export ROS_HOME="$work/ros_home" ROS_LOG_DIR="$work/ros_home/log"

# At a fifth of the recorded rate (6 frames a second), so that hope keeps up even when built
# with sanitizers: a replay faster than hope drops frames, and counts them in /diagnostics.
roslaunch -p "$port" hope tum.launch bag:="$bag" record:="$work/planes.bag" rate:=0.2 \
  >"$work/launch.log" 2>&1 &
launch_pid=$!
# The player says "Done." when the bag has been played; give hope and the recorder a moment
# for the last frame, then stop the launch as a user would (Ctrl-C).
for _ in $(seq 1 120); do
  grep -q "Done\." "$work/launch.log" && break
  kill -0 "$launch_pid" 2>/dev/null || { cat "$work/launch.log"; fail "roslaunch ended early"; }
  sleep 1
done
grep -q "Done\." "$work/launch.log" || { cat "$work/launch.log"; fail "the player never finished"; }
sleep 3
kill -INT "$launch_pid"
for _ in $(seq 1 30); do
  kill -0 "$launch_pid" 2>/dev/null || break
  sleep 1
done
kill -0 "$launch_pid" 2>/dev/null && fail "roslaunch did not stop on SIGINT"
wait "$launch_pid" || true
launch_pid=""
[ -s "$work/planes.bag" ] || { cat "$work/launch.log"; fail "no recording $work/planes.bag"; }

# What a user reads first: rostopic echo of the recorded diagnostics.
rostopic echo -b "$work/planes.bag" -n 1 -p /diagnostics >"$work/diagnostics.txt" 2>&1 || {
  cat "$work/diagnostics.txt"
  fail "rostopic echo /diagnostics"
}

/usr/bin/python3 - "$bag" "$work/planes.bag" "${expected_heights[@]}" <<'PYTHON'
import sys

import rosbag
from diagnostic_msgs.msg import DiagnosticArray  # noqa: F401 (installed with install_deps.sh)

source, recording = sys.argv[1], sys.argv[2]
expected = [float(h) for h in sys.argv[3:]]
with rosbag.Bag(source) as bag:
    depth_stamps = [m.header.stamp for _, m, _ in bag.read_messages(topics=["/camera/depth/image"])]
    tf_stamps = [m.transforms[0].header.stamp for _, m, _ in bag.read_messages(topics=["/tf"])]
# tf2 interpolates and never extrapolates: a frame before the first pose or after the last one
# has no transform (the synthetic poses start 4 ms after the first frame, as motion capture's
# may). Every other frame must be recorded.
depth_stamps = [s for s in depth_stamps if tf_stamps[0] <= s <= tf_stamps[-1]]
with rosbag.Bag(recording) as bag:
    planes = [m for _, m, _ in bag.read_messages(topics=["/hope/planes"])]
    diagnostics = [m for _, m, _ in bag.read_messages(topics=["/diagnostics"])]
print("depth frames in the bag: %d, PlaneArrays recorded: %d" % (len(depth_stamps), len(planes)))
assert depth_stamps, "the source bag has no depth frames"
recorded_stamps = [m.header.stamp for m in planes]
assert recorded_stamps == depth_stamps, (
    "recorded PlaneArrays are not one per depth frame, from the first: %s vs %s"
    % ([s.to_sec() for s in recorded_stamps], [s.to_sec() for s in depth_stamps]))
for message in planes:
    heights = sorted(p.height for p in message.planes)
    for h in expected:
        assert any(abs(x - h) < 0.03 for x in heights), "no plane at %.2f m: %s" % (h, heights)
processed = None
for array in diagnostics:
    for status in array.status:
        for kv in status.values:
            if kv.key.startswith("frames processed"):
                processed = int(kv.value)
assert processed is not None, "no 'frames processed' in the recorded /diagnostics"
print("diagnostics: frames processed %d" % processed)
assert processed >= len(depth_stamps) - 1, processed  # the last update may precede the last frame
PYTHON
echo "OK: every frame recorded headless, planes at ${expected_heights[*]}"
