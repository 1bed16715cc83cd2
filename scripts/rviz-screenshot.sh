#!/usr/bin/env bash
# Headless rviz screenshot of replay.launch: scripts/rviz-screenshot.sh BAG OUT.png [SECONDS [ARG:=VALUE ...]]
# (extra arguments go to replay.launch, e.g. detector:=false)
# Starts Xvfb, replays BAG through the tracker with rviz (config/replay.rviz), waits SECONDS of
# replay, grabs the screen and stops everything it started (by PID).
set -eo pipefail
bag="$(realpath "$1")"; out="$2"; wait_s="${3:-12}"; extra=("${@:4}")
root="$(cd "$(dirname "$0")/.." && pwd)"
export PATH=/usr/bin:/bin:$PATH
set +u; source "$root/build/devel/setup.bash"; set -u
export ROS_PACKAGE_PATH="$root:${ROS_PACKAGE_PATH:-}"
display=":97"
Xvfb "$display" -screen 0 1280x800x24 >/dev/null 2>&1 & xvfb=$!
export DISPLAY="$display" LIBGL_ALWAYS_SOFTWARE=1
roslaunch -p 11397 scene_graph_tracker replay.launch bag:="$bag" rviz:=false "${extra[@]}" > /tmp/rviz-screenshot.log 2>&1 &
launch=$!
export ROS_MASTER_URI=http://localhost:11397
sleep 4
rviz -d "$root/config/replay.rviz" > /tmp/rviz-screenshot-rviz.log 2>&1 &
rviz=$!
trap 'kill $rviz 2>/dev/null; kill -INT $launch 2>/dev/null; sleep 3; kill $xvfb 2>/dev/null || true' EXIT
sleep "$wait_s"
xwd -root -display "$display" -silent > /tmp/rviz-screenshot.xwd
/usr/bin/convert xwd:/tmp/rviz-screenshot.xwd "$out"
echo "wrote $out"
