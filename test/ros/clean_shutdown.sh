#!/usr/bin/env bash
# Ctrl-C in the middle of a replay ends every node cleanly, in every orientation mode: the
# nodelet manager that holds hope exits without "terminate called" (a tf buffer destroyed
# before the message filter reading it aborted it with boost::lock_error) and roslaunch reports
# no process that died. The bag is given by a path relative to the current folder, as a user
# types it. Run by ctest.
# Usage: clean_shutdown.sh BUILD_DIR BAG
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
build=$(cd "$1" && pwd)
bag=$2
port_offset=7
# shellcheck source=test/ros/replay_env.sh
source "$(dirname "$0")/replay_env.sh"
cp "$bag" "$work/replay.bag"
cd "$work"

for source in tf imu scene; do
  log="$work/$source.log"
  roslaunch -p "$port" hope tum.launch bag:=replay.bag orientation_source:="$source" \
    record:="$source.bag" rate:=0.01 >"$log" 2>&1 &
  launch_pid=$!
  # Mid-stream: once the recorder writes (hope's output lines are buffered until it exits),
  # and long before the player is done (8 frames over 20 s).
  for _ in $(seq 1 60); do
    [ -s "$source.bag.active" ] && break
    kill -0 "$launch_pid" 2>/dev/null || { cat "$log"; fail "$source: roslaunch ended early"; }
    sleep 1
  done
  sleep 4
  grep -q "Done\." "$log" && fail "$source: the player finished before the stop (not mid-stream)"
  kill -INT "$launch_pid"
  for _ in $(seq 1 30); do
    kill -0 "$launch_pid" 2>/dev/null || break
    sleep 1
  done
  kill -0 "$launch_pid" 2>/dev/null && fail "$source: roslaunch did not stop on SIGINT"
  wait "$launch_pid" || true
  launch_pid=""
  if grep -E "terminate called|lock_error|process has died|Aborted|Segmentation" "$log"; then
    cat "$log"
    fail "$source: a node did not shut down cleanly"
  fi
  # Buffered log lines reach the log only when the manager exits normally.
  grep -q "hope: subscribed to" "$log" || { cat "$log"; fail "$source: hope's log was lost"; }
  echo "$source: clean shutdown mid-stream"
done
