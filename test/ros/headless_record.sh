#!/usr/bin/env bash
# A headless replay recorded as the README says: `roslaunch hope tum.launch bag:=… record:=…`,
# launched by package name from the devel space. Every depth frame of the bag that has a pose
# must become one recorded /hope/planes message (none lost while the recorder connects, none
# while it falls behind), with the planes of
# the scene's ground truth, and /diagnostics must be readable by `rostopic echo` (the Python
# message classes installed) and count every frame. Run by ctest.
# Both front-ends keep their default tracking mode (auto): with tf into the bag's fixed frame
# (world) and with the folder's world poses, each keeps the surface map.
# --accelerometer: the same replay with the bag's accelerometer alone (orientation_source imu;
# heights then relative to the camera), against hope_extract --accelerometer: by default both
# keep the map in the frame of the scene's odometry, and give the same ids.
# Usage: headless_record.sh [--accelerometer] BUILD_DIR BAG EXPECTED_HEIGHTS...
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
accelerometer=false
if [ "${1:-}" = --accelerometer ]; then
  accelerometer=true
  shift
fi
build=$(cd "$1" && pwd)
bag=$2
shift 2
expected_heights=("$@")
# shellcheck source=test/ros/replay_env.sh
source "$(dirname "$0")/replay_env.sh"

# At a fifth of the recorded rate (6 frames a second), so that hope keeps up even when built
# with sanitizers: a replay faster than hope drops frames, and counts them in /diagnostics.
launch_args=() cli_args=()
if $accelerometer; then
  launch_args=(orientation_source:=imu)
fi
roslaunch -p "$port" hope tum.launch bag:="$bag" record:="$work/planes.bag" rate:=0.2 \
  "${launch_args[@]}" >"$work/launch.log" 2>&1 &
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

# The same frames through hope_extract --sequence (the folder the bag was made from, beside
# it): the nodelet and the command line run one pipeline, so planes and ids agree frame by frame.
# tf never extrapolates: the frames outside the poses' span (the first one, 4 ms before them)
# reach the nodelet without a transform; hope_extract takes the nearest pose within 0.02 s.
# The run below is given the frames inside the span only, as the nodelet was (with the
# accelerometer, every frame).
source_folder="${bag%.bag}"
[ -s "$source_folder/depth.txt" ] || fail "no folder $source_folder beside the bag"
folder="$work/frames"
mkdir "$folder"
ln -s "$source_folder/depth" "$folder/depth"
cp "$source_folder/groundtruth.txt" "$source_folder/intrinsics.txt" \
  "$source_folder/accelerometer.txt" "$folder/"
if $accelerometer; then
  cli_args=(--accelerometer "$folder/accelerometer.txt")
fi
span=$folder/groundtruth.txt
! $accelerometer || span=$source_folder/depth.txt  # every frame
read -r first last < <(awk '!/^#/ && NF { if (first == "") first = $1; last = $1 }
  END { print first, last }' "$span")
awk -v first="$first" -v last="$last" '/^#/ || ($1 >= first && $1 <= last)' \
  "$source_folder/depth.txt" >"$folder/depth.txt"
"$build/devel/lib/hope/hope_extract" --sequence "$folder" "${cli_args[@]}" \
  --jsonl "$work/cli.jsonl" --quiet 2>"$work/cli.log" || { cat "$work/cli.log"; fail "hope_extract"; }

/usr/bin/python3 - "$accelerometer" "$bag" "$work/planes.bag" "$work/cli.jsonl" \
  "${expected_heights[@]}" <<'PYTHON'
import json
import sys

import rosbag
from diagnostic_msgs.msg import DiagnosticArray  # noqa: F401 (installed with install_deps.sh)

accelerometer = sys.argv[1] == "true"
source, recording, cli_lines = sys.argv[2], sys.argv[3], sys.argv[4]
expected = [float(h) for h in sys.argv[5:]]
with rosbag.Bag(source) as bag:
    depth_stamps = [m.header.stamp for _, m, _ in bag.read_messages(topics=["/camera/depth/image"])]
    tf_stamps = [m.transforms[0].header.stamp for _, m, _ in bag.read_messages(topics=["/tf"])]
# tf2 interpolates and never extrapolates: a frame before the first pose or after the last one
# has no transform (the synthetic poses start 4 ms after the first frame, as motion capture's
# may). Every other frame must be recorded. With the accelerometer, every frame, though the
# last may wait for a sample after it that never comes (the clouds and the IMU are paired by
# approximate time, which decides on a pair once a later message arrives).
if not accelerometer:
    depth_stamps = [s for s in depth_stamps if tf_stamps[0] <= s <= tf_stamps[-1]]
with rosbag.Bag(recording) as bag:
    planes = [m for _, m, _ in bag.read_messages(topics=["/hope/planes"])]
    diagnostics = [m for _, m, _ in bag.read_messages(topics=["/diagnostics"])]
print("depth frames in the bag: %d, PlaneArrays recorded: %d" % (len(depth_stamps), len(planes)))
assert depth_stamps, "the source bag has no depth frames"
recorded_stamps = [m.header.stamp for m in planes]
if accelerometer and len(recorded_stamps) == len(depth_stamps) - 1:
    depth_stamps = depth_stamps[:-1]
assert recorded_stamps == depth_stamps, (
    "recorded PlaneArrays are not one per depth frame, from the first: %s vs %s"
    % ([s.to_sec() for s in recorded_stamps], [s.to_sec() for s in depth_stamps]))
for message in planes:
    heights = sorted(p.height for p in message.planes)
    for h in expected:
        assert any(abs(x - h) < 0.03 for x in heights), "no plane at %.2f m: %s" % (h, heights)
# The nodelet against hope_extract --sequence on the same frames: the same planes with the same
# ids. The nodelet's cloud comes through depth_image_proc and its pose through tf, whose
# arithmetic differs from hope's by rounding only: heights agree to 0.1 mm, and a point on a
# voxel's edge may fall on either side of it.
with open(cli_lines) as f:
    cli = {round(line["stamp"], 4): line for line in map(json.loads, f) if "planes" in line}
compared = 0
for message in planes:
    line = cli.get(round(message.header.stamp.to_sec(), 4))
    assert line is not None, "hope_extract has no frame at %.4f" % message.header.stamp.to_sec()
    nodelet_planes = [(p.id, p.num_points) for p in message.planes]
    cli_planes = [(p["id"], p["num_points"]) for p in line["planes"]]
    what = "frame %.4f: nodelet %s, hope_extract %s" % (
        message.header.stamp.to_sec(), nodelet_planes, cli_planes)
    assert [i for i, _ in nodelet_planes] == [i for i, _ in cli_planes], what
    for p, q in zip(message.planes, line["planes"]):
        # A point on a voxel's edge may fall either side of it: a few points of thousands.
        assert abs(p.num_points - q["num_points"]) <= max(2, 0.002 * p.num_points), what
        assert abs(p.height - q["height"]) < 1e-4, (p.height, q["height"])
    compared += len(nodelet_planes)
assert compared >= 2 * len(planes), "too few planes compared: %d" % compared
print("nodelet and hope_extract agree on %d planes in %d frames" % (compared, len(planes)))
processed = followed = None
for array in diagnostics:
    for status in array.status:
        for kv in status.values:
            if kv.key.startswith("frames processed"):
                processed = int(kv.value)
            if kv.key == "odometry: frames followed":
                followed = int(kv.value)
assert processed is not None, "no 'frames processed' in the recorded /diagnostics"
print("diagnostics: frames processed %d" % processed)
assert processed >= len(depth_stamps) - 1, processed  # the last update may precede the last frame
if accelerometer:
    assert followed is not None and followed >= len(depth_stamps) - 1, (
        "odometry: frames followed %s in the recorded /diagnostics" % followed)
PYTHON
echo "OK: every frame recorded headless, planes at ${expected_heights[*]}"
