#!/usr/bin/env bash
# make latency: replays BAG (default: build/demo/workbench.bag, simulated when missing) at 1x
# through replay.launch (no rviz) and measures image stamp -> tracked objects published.
# LATENCY_LAUNCH_ARGS="detector:=false" passes arguments to replay.launch.
set -eo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bag="${1:-$root/build/demo/workbench.bag}"
out="${2:-$root/build/latency.json}"
export PATH=/usr/bin:/bin:$PATH
tools="$root/build/devel/lib/scene_graph_tracker"
if [ ! -f "$bag" ]; then
  mkdir -p "$(dirname "$bag")"
  "$tools/simulate" --scenario "$root/config/scenarios/workbench.yaml" --output "$bag" --quiet
fi
# replay.launch takes the static world from beside the bag (as `make demo` writes it).
map_dir="$(dirname "$bag")"
if [ ! -f "$map_dir/static_map.ply" ] || [ ! -f "$map_dir/furniture.yaml" ]; then
  "$tools/write_map" --scenario "$root/config/scenarios/workbench.yaml" --mesh "$map_dir/static_map.ply" \
    --furniture "$map_dir/furniture.yaml"
fi
set +u; source "$root/build/devel/setup.bash"; set -u
export ROS_PACKAGE_PATH="$root:${ROS_PACKAGE_PATH:-}"
port=11398
export ROS_MASTER_URI=http://localhost:$port
# The bag starts paused: the tracker loads the static map first (about 0.5 s for the demo's), and
# frames played before it subscribes would count as unanswered although no tracker was running.
roslaunch -p $port scene_graph_tracker replay.launch bag:="$(realpath "$bag")" rviz:=false paused:=true \
  ${LATENCY_LAUNCH_ARGS:-} > "$root/build/latency_launch.log" 2>&1 &
launch=$!
trap 'kill -INT $launch 2>/dev/null || true; wait $launch 2>/dev/null || true' EXIT
# The probe must start after replay.launch set /use_sim_time (the clock is read at node start).
for _ in $(seq 50); do rosparam get /use_sim_time >/dev/null 2>&1 && break; sleep 0.2; done
subscribed() { rostopic info "$1" 2>/dev/null | sed -n '/Subscribers:/,$p' | grep -q "$2"; }
# The tracker subscribes to the LiDAR last, once its map is loaded.
for _ in $(seq 300); do subscribed /velodyne_points scene_graph_tracker_manager && break; sleep 0.1; done
"$tools/latency_probe" --duration 26 --output "$out" &
probe=$!
for _ in $(seq 100); do subscribed /tracker/tracked_objects latency_probe && break; sleep 0.1; done
rosservice call /player/pause_playback false > /dev/null
wait $probe
echo "written: $out (launch log: build/latency_launch.log)"
