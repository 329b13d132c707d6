#!/usr/bin/env bash
# Regenerates docs/performance.md: runs the measurements, saves their raw
# output in OUT_DIR, and writes OUT_DIR/tables.md from them
# (scripts/performance_markdown.py); docs/performance.md is that file:
#   cp build/performance/tables.md docs/performance.md
# Not part of CI; run it alone on the machine (about 18 minutes on 2 cores).
#
# Usage: scripts/performance_tables.sh [--skip PART,...] [OUT_DIR]
#   (default OUT_DIR: build/performance). PARTs: scenes, procedures,
#   effects, stages, accuracy, options, python, node. A skipped part keeps whatever
#   OUT_DIR already holds for it; --skip all only rewrites tables.md.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
skip=","
if [ "${1:-}" = "--skip" ]; then
  skip=",$2,"
  shift 2
fi
out=${1:-$repo/build/performance}
mkdir -p "$out"
export PATH="/usr/bin:$PATH"
bin=$repo/build/ws/devel/lib/endovascular_sim
evsim=$bin/evsim
run() { [[ $skip != *",$1,"* && $skip != *",all,"* ]]; }
started=$(date +%s)
if [ "$skip" != ",all," ]; then  # the machine the figures come from
  {
    echo "cpu: $(sed -n 's/^model name\t*: //p' /proc/cpuinfo | head -1)"
    echo "cores: $(nproc)"
    echo "memory: $(awk '/MemTotal/ {printf "%.0f GiB", $2 / 1048576}' /proc/meminfo)"
    echo "os: $(. /etc/os-release && echo "$PRETTY_NAME")"
    echo "date: $(date -u +%Y-%m-%d)"
    echo "load: load average $(cut -d' ' -f1 /proc/loadavg) at the start"
  } > "$out/machine.txt"
fi
"$evsim" schema > "$out/schema.md"  # the contact options' units, defaults and ranges

if run scenes; then
  # Every shipped scene over its whole scripted procedure (evsim bench).
  for scene in carotid carotid_selective carotid_catheter network aneurysm aneurysm_coiling \
               patient_example dead_end tortuous large_step; do
    echo "== evsim bench $scene"
    "$evsim" bench "$scene" | tee "$out/bench_$scene.txt" || true  # a failed step is reported
  done
  echo "== evsim bench aneurysm_packed --min-rows 300 --against carotid"
  "$evsim" bench aneurysm_packed --min-rows 300 --against carotid | tee "$out/bench_aneurysm_packed.txt"
  echo "== evsim bench aneurysm_packed --warmup 14400 --steps 900 --min-rows 300 --against carotid"
  "$evsim" bench aneurysm_packed --warmup 14400 --steps 900 --min-rows 300 --against carotid \
    | tee "$out/bench_aneurysm_packed_full.txt"
  echo "== evsim bench carotid --no-sleep"
  "$evsim" bench carotid --no-sleep | tee "$out/bench_carotid_no_sleep.txt"
fi

if run procedures; then
  # The autopilot's procedures from the femoral access (docs/navigation.md).
  for target in left_common_carotid left_subclavian right_common_carotid right_subclavian; do
    echo "== evsim navigate arch_to_$target"
    "$evsim" navigate "arch_to_$target" --timeout 30 --quiet --steps-json "$out/navigate_$target.json" \
      | tee "$out/navigate_$target.txt" || true  # not reached: reported in its JSON
    /usr/bin/python3 "$repo/scripts/step_summary.py" "$out/navigate_$target.json" \
      | tee "$out/navigate_${target}_summary.txt"
  done
fi

if run effects; then
  echo "== scripts/effects_table.py (navigation scenes)"
  /usr/bin/python3 "$repo/scripts/effects_table.py" "$evsim" --csv "$out/effects.csv" \
    --scenes carotid,carotid_selective,carotid_catheter,network,aneurysm,aneurysm_coiling,patient_example
fi

if run stages; then
  # The parts of the step alone (Google Benchmark, test/benchmark/).
  echo "== evsim_benchmarks (free motion, field, Delassus, LCP, friction)"
  "$bin/evsim_benchmarks" --benchmark_out_format=json \
    --benchmark_out="$out/stages.json" --benchmark_min_time=0.2 \
    --benchmark_filter='^BM_(FreeMotionStep|FieldAndGradient|FirstRootQuery|BuildNetworkScene|DelassusBandFromFactor|DelassusSweep|DelassusTrailingSolve|DelassusChain|DelassusBlockSolve|DelassusSeparateSolves|SceneStatusMethod|SceneSiconosLemke|FrictionNewton|FrictionNsgs|FrictionSiconosNsnAc)(/|$)' \
    | tee "$out/stages.txt"
fi

if run accuracy; then
  # Each contact option's cost and error against a fine run.
  for spec in carotid:3 aneurysm:0.5 carotid_catheter:0.5; do
    scene=${spec%%:*}
    echo "== evsim bench accuracy $scene --duration ${spec#*:}"
    "$evsim" bench accuracy "$scene" --duration "${spec#*:}" --csv "$out/accuracy_$scene.csv"
  done
  for what in beam root; do
    echo "== evsim bench accuracy $what"
    "$evsim" bench accuracy "$what" --csv "$out/accuracy_$what.csv"
  done
fi

if run options; then
  # The contact options that `evsim bench accuracy` does not sweep: each a
  # copy of a shipped scene with one option changed. Whole procedures
  # (`evsim bench FILE`), or, where a coil's path is chaotic, paired windows
  # (`evsim bench SCENE --windows`: every variant stepped from the same
  # states of the scene's own run).
  vdir=$out/variants
  mkdir -p "$vdir"
  absolute="s#\.\./vessels/#$repo/config/vessels/#; s#\.\./devices/#$repo/config/devices/#"
  # variant SCENE NAME KEY VALUE: the scene's file with contact.KEY set to VALUE.
  variant() {
    local file=$vdir/$1.$2.yaml
    sed -e "$absolute" "$repo/config/scenes/$1.yaml" > "$file"
    if grep -q "^  $3:" "$file"; then
      sed -i -e "s/^  $3: *[^ #]*/  $3: $4/" "$file"
    elif grep -q "^contact:" "$file"; then
      sed -i -e "s/^contact:.*/contact:\n  $3: $4/" "$file"
    else
      printf 'contact:\n  %s: %s\n' "$3" "$4" >> "$file"
    fi
    echo "$file"
  }
  for spec in carotid.scene carotid.spacing_0.5mm:contact_spacing:5.0e-4 \
              carotid.spacing_2mm:contact_spacing:2.0e-3 carotid.keep_gap_10um:keep_gap:1.0e-5 \
              carotid.predict:predict_first_iterate:true carotid.no_wall_curvature:wall_curvature:false \
              network.scene network.keep_gap_0:keep_gap:0; do
    scene=${spec%%.*}; rest=${spec#*.}; name=${rest%%:*}
    if [ "$name" = scene ]; then
      file=$vdir/$scene.scene.yaml
      sed -e "$absolute" "$repo/config/scenes/$scene.yaml" > "$file"
    else
      kv=${rest#*:}
      file=$(variant "$scene" "$name" "${kv%%:*}" "${kv#*:}")
    fi
    echo "== evsim bench $file"
    "$evsim" bench "$file" | tee "$out/option_$scene.$name.txt" || true
  done
  args=()
  for v in predict:predict_first_iterate:false element_pairs:element_pairs:true \
           pair_tol_5um:pair_tolerance:5.0e-6 new_pair_2.5um:new_pair_overlap:2.5e-6 \
           curvature_every_loop:curvature_loops:1000 penetration_5um:penetration_tolerance:5.0e-6; do
    kv=${v#*:}
    args+=(--variant "$(variant aneurysm "${v%%:*}" "${kv%%:*}" "${kv#*:}")")
  done
  echo "== evsim bench aneurysm --warmup 11400 --steps 600 --windows 24 --window-steps 10 --variant ..."
  "$evsim" bench aneurysm --warmup 11400 --steps 600 --windows 24 --window-steps 10 "${args[@]}" \
    | tee "$out/option_windows_aneurysm.txt"
  args=()
  for v in predict:predict_first_iterate:false sample_point_pairs:element_pairs:false \
           pair_tol_1um:pair_tolerance:1.0e-6 new_pair_0:new_pair_overlap:0 \
           curvature_every_loop:curvature_loops:1000; do
    kv=${v#*:}
    args+=(--variant "$(variant aneurysm_packed "${v%%:*}" "${kv%%:*}" "${kv#*:}")")
  done
  echo "== evsim bench aneurysm_packed --warmup 14400 --steps 900 --windows 6 --window-steps 150 --variant ..."
  "$evsim" bench aneurysm_packed --warmup 14400 --steps 900 --windows 6 --window-steps 150 "${args[@]}" \
    | tee "$out/option_windows_aneurysm_packed.txt"
fi

if run python; then
  echo "== scripts/env_benchmark.py"
  bash "$repo/scripts/python.sh" "$repo/scripts/env_benchmark.py" | tee "$out/env_benchmark.txt"
fi

if run node; then
  set +u; source "$repo/build/ws/devel/setup.bash"; set -u
  if [ ! -x "$bin/navigation_node" ]; then
    echo "performance_tables.sh: the node is not built (bash scripts/build.sh builds the whole package)" >&2
    exit 1
  fi
  echo "== scripts/node_benchmark.py"
  # (a scene whose node did not report is left out of its table)
  /usr/bin/python3 "$repo/scripts/node_benchmark.py" | tee "$out/node_benchmark.txt" || true
  echo "== scripts/node_benchmark.py --xray carotid network"
  /usr/bin/python3 "$repo/scripts/node_benchmark.py" --xray carotid network \
    | tee "$out/node_benchmark_xray.txt" || true
fi

echo "performance_tables.sh: measured in $(( $(date +%s) - started )) s"
/usr/bin/python3 "$repo/scripts/performance_markdown.py" "$out" > "$out/tables.md"
echo "wrote $out/tables.md (docs/performance.md is a copy of it)"
