#!/usr/bin/env bash
# Takes docs/rviz_tum.png: the TUM freiburg1_desk frame (../shared/data, as the rostest bag
# built by `bash scripts/test.sh`) replayed into the hope nodelet, shown by RViz under Xvfb
# with rviz/hope.rviz (labeled cloud coloured by plane id, plane areas and outlines, "id: height"
# labels).
# Needs: rviz xvfb imagemagick (apt-get install -y rviz xvfb imagemagick).
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
roscore -p 11399 >/dev/null 2>&1 & pids+=($!)
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
mkdir -p "$root/docs"
import -window root "$root/docs/rviz_tum.png"
echo "wrote docs/rviz_tum.png"
