#!/usr/bin/env bash
# Renders the real rviz window under a virtual display (Xvfb) and saves a
# screenshot of the running node: vessels, device, contacts, force arrows and
# tangent planes.
# Usage: scripts/screenshot_rviz.sh [SCENE] [SECONDS] [OUT.png]
#   SECONDS: wall time to let the scripted insertion run before the shot.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
scene=${1:-carotid}
seconds=${2:-12}
out=${3:-$repo/config/images/rviz_$scene.png}
export PATH="/usr/bin:$PATH"
set +u; source "$repo/build/ws/devel/setup.bash"; set -u

display=:$((90 + RANDOM % 9))
Xvfb "$display" -screen 0 1400x900x24 >/dev/null 2>&1 &
xvfb_pid=$!
export DISPLAY=$display LIBGL_ALWAYS_SOFTWARE=1
export ROS_MASTER_URI=http://localhost:$((12000 + RANDOM % 1000))
roslaunch -p "${ROS_MASTER_URI##*:}" endovascular_sim navigation_rviz.launch scene:="$scene" \
  >/tmp/evsim_screenshot_launch.log 2>&1 &
launch_pid=$!
trap 'kill $launch_pid 2>/dev/null; wait $launch_pid 2>/dev/null; kill $xvfb_pid 2>/dev/null' EXIT
sleep "$seconds"
import -window root "$out"
echo "screenshot: $out"
grep -E "t=[0-9.]+ s" /tmp/evsim_screenshot_launch.log | tail -1 || true
