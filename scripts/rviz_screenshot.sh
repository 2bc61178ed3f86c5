#!/usr/bin/env bash
# Takes the README's RViz pictures under Xvfb, with rviz/hope.rviz (labeled cloud coloured by
# plane id, plane areas and outlines, "id: height" labels; the view orbits hope_view):
#   docs/rviz_tum.png  the TUM freiburg1_desk frame (../shared/data, as the rostest bag built by
#                      `bash scripts/test.sh`) replayed into the hope nodelet;
#   docs/rviz_pan.png  another scene, elsewhere in its world: the last frame of a panning
#                      camera's sequence written by hope_synth, replayed by tum.launch as a
#                      user replays a TUM folder (tum_to_bag.py, then roslaunch by name);
#   docs/rviz_kitchen.png  a real recording: ../shared/data/kitchen_dev replayed the same way,
#                      tf into its world keeping the surface map (tracking_mode auto), so the
#                      floor grid is every frame's laid over each other, with ~obstacles
#                      (orange) over the labeled cloud (skipped with a message when the data is
#                      absent);
#   docs/rviz_kitchen_odometry.png  the same recording with its accelerometer alone
#                      (orientation_source:=imu; auto is then odometry): the surface map in
#                      the frame of the scene's own odometry, which RViz holds still.
# Every replay keeps the default tracking mode, auto (the map with tf into a fixed frame).
# Needs: rviz xvfb imagemagick (scripts/install_deps.sh installs them).
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
root=$(cd "$(dirname "$0")/.." && pwd)
bag="$root/build/devel/share/hope/test_bags/tum.bag"
[ -f "$bag" ] || { echo "no $bag: run bash scripts/test.sh first (needs ../shared/data)"; exit 1; }
export ROS_HOSTNAME=localhost ROS_MASTER_URI=http://localhost:11399
export ROS_HOME="$root/build/ros_home" ROS_LOG_DIR="$root/build/ros_home/log"
set +u; source "$root/build/devel/setup.bash"; set -u
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT
Xvfb :77 -screen 0 1280x720x24 >/dev/null 2>&1 & pids+=($!)
export DISPLAY=:77 LIBGL_ALWAYS_SOFTWARE=1
mkdir -p "$root/docs"

# The TUM frame: clouds from the bag straight into the nodelet, heights from tf.
roscore -p 11399 >/dev/null 2>&1 & core=$!
sleep 3
rosparam set use_sim_time true
rosrun nodelet nodelet manager __name:=manager >/dev/null 2>&1 & pids+=($!)
rosrun nodelet nodelet load hope/PlaneExtractorNodelet manager __name:=hope \
  _orientation_source:=tf _reference_frame:=world \
  ~cloud:=/camera/depth/points > "$ROS_LOG_DIR/screenshot_hope.txt" 2>&1 & pids+=($!)
rviz -d "$root/rviz/hope.rviz" -f world >/dev/null 2>&1 & pids+=($!)
sleep 6  # RViz under software rendering takes a while to subscribe
rosbag play --clock -r 0.5 "$bag" >/dev/null 2>&1 & pids+=($!)
sleep 10  # played once: the last frame stays on screen (a loop would reset RViz)
import -window root "$root/docs/rviz_tum.png"
echo "wrote docs/rviz_tum.png"
for p in "${pids[@]:1}"; do kill "$p" 2>/dev/null || true; done
pids=("${pids[0]}")
kill "$core"; wait "$core" 2>/dev/null || true

# Replays BAG through tum.launch with ARGS... (its own master; RViz waits to be there before the
# player starts, as hope is lazy while RViz listens), waits up to SECONDS for the player to
# finish, and takes docs/NAME.png; the launch stays up until the next replay stops it.
replay_and_shoot() {
  local name=$1 bag=$2 seconds=$3
  shift 3
  if [ "${#pids[@]}" -gt 1 ]; then  # the last replay's launch
    kill "${pids[-1]}" 2>/dev/null || true
    wait "${pids[-1]}" 2>/dev/null || true
    unset 'pids[-1]'
  fi
  local log=$ROS_LOG_DIR/screenshot_$name.txt
  roslaunch -p 11399 hope tum.launch bag:="$bag" rate:=0.5 "$@" >"$log" 2>&1 &
  pids+=($!)
  for _ in $(seq 1 "$seconds"); do
    grep -q "Done\." "$log" && break
    sleep 1
  done
  sleep 3
  import -window root "$root/docs/$name.png"
  echo "wrote docs/$name.png"
}

# Another scene, replayed by name as a user replays a TUM folder.
pan=$root/build/rviz_pan
rm -rf "$pan"
"$root/build/devel/lib/hope/hope_synth" --out "$pan" --sequence pan --frames 45 >/dev/null
/usr/bin/python3 "$root/scripts/tum_to_bag.py" "$pan" "$pan.bag"
replay_and_shoot rviz_pan "$pan.bag" 90

# A real kitchen, replayed the same way, the map accumulating the floor grid; then with its
# accelerometer alone, the scene's odometry keeping the map's frame.
kitchen=$root/../shared/data/kitchen_dev
if [ ! -d "$kitchen" ]; then
  echo "no $kitchen: docs/rviz_kitchen.png and rviz_kitchen_odometry.png not made"
  exit 0
fi
/usr/bin/python3 "$root/scripts/tum_to_bag.py" "$kitchen" "$root/build/rviz_kitchen.bag"
replay_and_shoot rviz_kitchen "$root/build/rviz_kitchen.bag" 240
replay_and_shoot rviz_kitchen_odometry "$root/build/rviz_kitchen.bag" 240 orientation_source:=imu
# What the odometry says of the replay: frames followed, frames not aligned with the last.
rostopic echo -n 1 /diagnostics | grep -A1 '"odometry: frames' | grep -o '"[^"]*"' | paste - -
