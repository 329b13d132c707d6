#!/usr/bin/env bash
# Regenerates the figures of docs/performance.md: every shipped navigation
# and stability scene stepped over its whole scripted procedure by
# `evsim bench` (one core, per phase: free, contact, inserted), then the ROS
# node itself on the navigation scenes (scripts/node_benchmark.py). Long (a
# few minutes), not part of CI; run it alone on the machine.
# Usage: scripts/performance_tables.sh [OUT_DIR]   (default: build/performance)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$repo/build/performance}
mkdir -p "$out"
export PATH="/usr/bin:$PATH"
evsim=$repo/build/ws/devel/lib/endovascular_sim/evsim
for scene in carotid carotid_selective carotid_catheter network aneurysm aneurysm_coiling \
             patient_example dead_end tortuous large_step; do
  echo "== evsim bench $scene"
  "$evsim" bench "$scene" | tee "$out/bench_$scene.txt" || true  # a failed step is reported
done
echo "== evsim bench carotid --no-sleep"
"$evsim" bench carotid --no-sleep | tee "$out/bench_carotid_no_sleep.txt"
echo "== evsim bench aneurysm_packed --min-rows 300 --against carotid"
"$evsim" bench aneurysm_packed --min-rows 300 --against carotid | tee "$out/bench_aneurysm_packed.txt"
echo "== evsim bench aneurysm_packed --warmup 11000 --steps 3000 --against carotid"
"$evsim" bench aneurysm_packed --warmup 11000 --steps 3000 --against carotid \
  | tee "$out/bench_aneurysm_packed_11_14.txt"
echo "== evsim bench aneurysm_packed --warmup 14400 --steps 900 --min-rows 300 --against carotid"
"$evsim" bench aneurysm_packed --warmup 14400 --steps 900 --min-rows 300 --against carotid \
  | tee "$out/bench_aneurysm_packed_14_15.txt"
echo "== scripts/whip_knobs.sh (aneurysm's hardest stretch, paired)"
bash "$repo/scripts/whip_knobs.sh" "$out"
# The autopilot's procedures from the femoral access (docs/navigation.md):
# every step, summed up by scripts/step_summary.py.
for target in left_common_carotid left_subclavian right_common_carotid right_subclavian; do
  echo "== evsim navigate arch_to_$target"
  "$evsim" navigate "arch_to_$target" --timeout 30 --quiet --steps-json "$out/navigate_$target.json" \
    | tee "$out/navigate_$target.txt" || true  # not reached: reported in its JSON
  /usr/bin/python3 "$repo/scripts/step_summary.py" "$out/navigate_$target.json" | tee -a "$out/navigate_$target.txt"
done
set +u; source "$repo/build/ws/devel/setup.bash"; set -u
if [ ! -x "$repo/build/ws/devel/lib/endovascular_sim/navigation_node" ]; then
  echo "performance_tables.sh: the node is not built (bash scripts/build.sh builds the whole package)" >&2
  exit 1
fi
echo "== scripts/node_benchmark.py"
/usr/bin/python3 "$repo/scripts/node_benchmark.py" | tee "$out/node_benchmark.txt"
