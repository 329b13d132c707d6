#!/usr/bin/env bash
# Sets up the machine, builds, and runs the main job: the default scene under
# evsim (a progress line per 0.1 s of simulated time).
# Usage: scripts/run.sh [SCENE] [evsim run options]
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
bash "$repo/scripts/setup.sh"
bash "$repo/scripts/build.sh" -j2
scene=${1:-carotid}
shift || true
exec "$repo/build/ws/devel/lib/endovascular_sim/evsim" run "$scene" --steps 5000 "$@"
