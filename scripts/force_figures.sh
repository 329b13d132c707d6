#!/usr/bin/env bash
# Regenerates the insertion-force plots of docs/model.md ("Drive forces"):
# the force each drive applies during the autopilot's procedure to the left
# common carotid, and while the coil of `aneurysm` fills the dome. A few
# minutes; not part of CI.
# Usage: scripts/force_figures.sh
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
evsim=$repo/build/ws/devel/lib/endovascular_sim/evsim
out=$repo/config/images/forces
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
"$evsim" navigate arch_to_left_common_carotid --quiet --steps-json "$work/navigate.json" > /dev/null
/usr/bin/python3 "$repo/scripts/plot_forces.py" "$work/navigate.json" "$out/navigate_left_common_carotid.png" \
  "arch_to_left_common_carotid: the autopilot's procedure (evsim navigate)"
"$evsim" run aneurysm --json > "$work/aneurysm.json"
/usr/bin/python3 "$repo/scripts/plot_forces.py" "$work/aneurysm.json" "$out/coil_aneurysm.png" \
  "aneurysm: a 10 cm coil pushed at 10 mm/s into a 7 mm dome (evsim run)"
