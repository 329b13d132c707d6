#!/usr/bin/env bash
# Builds the package in a catkin workspace under build/ (outside git's view).
# Usage: scripts/build.sh [extra catkin_make arguments]
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
ws="$repo/build/ws"
mkdir -p "$ws/src"
touch "$repo/build/CATKIN_IGNORE"
ln -sfn "$repo" "$ws/src/endovascular_sim"
# Debian's catkin needs the system python (catkin_pkg lives there).
export PATH="/usr/bin:$PATH"
cd "$ws"
catkin_make -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DCATKIN_ENABLE_TESTING=ON "$@" 2>&1 | grep -vE '^-- |^\[ *[0-9]+%\] (Built|Generating|Building|Linking)|^####|^Base path|^Source space|^Build space|^Devel space|^Install space|^make|^Scanning' || true
test "${PIPESTATUS[0]}" -eq 0
