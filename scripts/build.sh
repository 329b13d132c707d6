#!/usr/bin/env bash
# Builds the package in a catkin workspace under build/ (outside git's view).
# Usage: scripts/build.sh [extra catkin_make arguments]
# EVSIM_WS=DIR builds in another workspace (scripts/sanitize.sh: build/asan_ws).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
ws="${EVSIM_WS:-$repo/build/ws}"
pkg="$ws/src/endovascular_sim"
mkdir -p "$ws/src"
touch "$repo/build/CATKIN_IGNORE"
# The package in the workspace links each top-level entry of the repository
# but build/: a link to the repository itself would hold the workspace inside
# the package, a loop that rosrun and roslaunch walk without end.
[ -L "$pkg" ] && rm "$pkg"
mkdir -p "$pkg"
for entry in "$repo"/* "$repo"/.clang-format; do
  [ "$(basename "$entry")" = build ] || ln -sfn "$entry" "$pkg/$(basename "$entry")"
done
find "$pkg" -maxdepth 1 -xtype l -delete  # entries removed from the repository
# Debian's catkin needs the system python (catkin_pkg lives there).
export PATH="/usr/bin:$PATH"
cd "$ws"
# catkin_make's status, not the filter's (grep fails when it keeps no line).
set +e
catkin_make -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DCATKIN_ENABLE_TESTING=ON "$@" 2>&1 | grep -vE '^-- |^\[ *[0-9]+%\] (Built|Generating|Building|Linking)|^####|^Base path|^Source space|^Build space|^Devel space|^Install space|^make|^Scanning'
status=${PIPESTATUS[0]}
set -e
exit "$status"
