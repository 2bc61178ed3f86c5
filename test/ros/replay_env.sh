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
# The master's port: below the kernel's ephemeral range (32768 up), where every node's own
# XML-RPC and topic servers take theirs (a master on 37226 once found a node of another test
# there), and free when checked.
port=
for _ in $(seq 1 50); do
  candidate=$((20000 + (RANDOM + $$ + ${port_offset:-0}) % 12000))
  if /usr/bin/python3 -c "import socket; s = socket.socket(); s.bind(('localhost', $candidate))" \
    2>/dev/null; then
    port=$candidate
    break
  fi
done
[ -n "$port" ] || { echo "replay_env: no free port for a ROS master in 20000-31999" >&2; exit 1; }
export ROS_MASTER_URI=http://localhost:$port ROS_HOSTNAME=localhost
export ROS_HOME="$work/ros_home" ROS_LOG_DIR="$work/ros_home/log"
