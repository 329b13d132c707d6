#!/usr/bin/env bash
# Runs the Python that has endovascular_sim (the built package), Gymnasium
# and Stable-Baselines3: the project's virtual environment (scripts/setup.sh)
# with the catkin workspace's Python path (scripts/build.sh).
# Usage: scripts/python.sh [python arguments], e.g.
#   bash scripts/python.sh -c 'import endovascular_sim'
#   bash scripts/python.sh scripts/train_ppo.py --help
set -euo pipefail
repo=$(cd "$(dirname "$(readlink -f "$0")")/.." && pwd)  # (through the workspace's links)
venv="$repo/build/venv"
ws="$repo/build/ws"
if [ ! -x "$venv/bin/python" ]; then
  echo "python.sh: no virtual environment at $venv: run 'bash scripts/setup.sh' first" >&2
  exit 2
fi
if [ ! -f "$ws/devel/setup.bash" ]; then
  echo "python.sh: the package is not built: run 'bash scripts/build.sh' first" >&2
  exit 2
fi
export PATH="/usr/bin:$PATH"
# shellcheck disable=SC1091
set +u; source "$ws/devel/setup.bash"; set -u
exec "$venv/bin/python" "$@"
