#!/usr/bin/env bash
# Sets up the machine, builds, and runs the main job: the ROS node on a scene
# with its scripted insertion (default: carotid). Headless, it prints a
# progress line per second (inserted length, tip, contacts, rate, real-time
# factor); with a display ($DISPLAY set) rviz opens too. Ctrl-C stops it.
# roslaunch starts a master when none is running.
# Usage: scripts/run.sh [SCENE] [roslaunch arguments, e.g. use_script:=false]
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
bash "$repo/scripts/setup.sh"
bash "$repo/scripts/build.sh" -j2
scene=${1:-carotid}
shift || true
export PATH="/usr/bin:$PATH"
set +u; source "$repo/build/ws/devel/setup.bash"; set -u
launch=navigation.launch
[ -n "${DISPLAY:-}" ] && launch=navigation_rviz.launch
exec roslaunch endovascular_sim "$launch" scene:="$scene" "$@"
