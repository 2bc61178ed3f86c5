# Sourced by the replay tests (headless_record.sh, clean_shutdown.sh) after they set `build`
# and `bag`: fail(), a scratch folder $work removed at exit (a launch in $launch_pid stopped
# first), the devel space sourced, and a ROS master of their own on a port of their own, so
# that a roscore already running is not disturbed.
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
port=$((20000 + ($$ + ${port_offset:-0}) % 20000))
export ROS_MASTER_URI=http://localhost:$port ROS_HOSTNAME=localhost
export ROS_HOME="$work/ros_home" ROS_LOG_DIR="$work/ros_home/log"
