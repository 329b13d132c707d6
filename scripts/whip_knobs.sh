#!/usr/bin/env bash
# What the contact knobs cost where `aneurysm` is hardest (its coil whipping
# round the dome, t = 11.4-12.0 s), as a paired comparison: the scene and a
# variant per knob stepped 10 steps from each of 24 states of the scene's run
# (`evsim bench --windows`; docs/performance.md, "What accuracy costs").
# Each variant is the shipped scene with one contact option changed.
# Usage: scripts/whip_knobs.sh [OUT_DIR]   (default: build/performance)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$repo/build/performance}
mkdir -p "$out/whip_knobs"
evsim=$repo/build/ws/devel/lib/endovascular_sim/evsim
scene=$repo/config/scenes/aneurysm.yaml
absolute="s#\.\./vessels/#$repo/config/vessels/#; s#\.\./devices/#$repo/config/devices/#"
sed -e "$absolute" "$scene" > "$out/whip_knobs/shipped.yaml"
# variant NAME SED-EXPRESSION: the scene with its paths made absolute, changed
# (refused when the expression changed nothing: the scene's text moved).
args=()
variant() {
  sed -e "$absolute" -e "$2" "$scene" > "$out/whip_knobs/$1.yaml"
  if cmp -s "$out/whip_knobs/shipped.yaml" "$out/whip_knobs/$1.yaml"; then
    echo "whip_knobs.sh: '$2' changes nothing in $scene" >&2
    exit 1
  fi
  args+=(--variant "$out/whip_knobs/$1.yaml")
}
variant penetration_2um 's/^contact:/contact:\n  penetration_tolerance: 2.0e-6/'
variant penetration_5um 's/^contact:/contact:\n  penetration_tolerance: 5.0e-6/'
variant penetration_10um 's/^contact:/contact:\n  penetration_tolerance: 1.0e-5/'
variant pair_overlap_5um 's/^contact:/contact:\n  pair_tolerance: 5.0e-6/'
variant curvature_every_loop 's/curvature_loops: 1 /curvature_loops: 1000 /'
variant no_predicted_iterate 's/predict_first_iterate: true/predict_first_iterate: false/'
"$evsim" bench aneurysm --warmup 11400 --steps 600 --windows 24 "${args[@]}" \
  | tee "$out/whip_knobs.txt"
