#!/usr/bin/env bash
# Regenerates the virtual fluoroscopy figures of docs/sensors.md
# (config/images/xray/) with `evsim render`: the autopilot's procedure to the
# left common carotid seen at LAO 30, then an angiogram from the catheter's
# tip and the roadmap after it; and the same arch from three C-arm angles.
# About a minute; not part of CI.
# Usage: scripts/xray_figures.sh
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
evsim=$repo/build/ws/devel/lib/endovascular_sim/evsim
out=$repo/config/images/xray
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"

# The procedure as a clinician sees it: an aortogram (contrast 5 mm into the
# ascending aorta, as from a pigtail catheter, at 0.1 s for 0.5 s), then its
# roadmap under the live image while the autopilot takes the wire and the
# catheter into the left common carotid; at 4.5 s, a selective angiogram
# from the catheter's tip. Frames at 4 per second.
"$evsim" render arch_to_left_common_carotid --navigate left_common_carotid --duration 6 \
  --rate 4 --inject 0.1,0.5 --inject-vessel ascending_aorta --roadmap --out "$work/procedure"
f() { printf '%s/procedure/frame_%05d.png' "$work" "$1"; }
# t = 0.5 s (the aortogram), 2 s and 3.5 s (the roadmap, the wire in the
# arch, then in the target), 6 s (the wire held in the target).
convert "$(f 2)" "$(f 8)" "$(f 14)" "$(f 24)" +append -resize 50% "$out/procedure.png"

# The aortogram from RAO 30, AP and LAO 30: LAO opens the arch.
for angle in -30 0 30; do
  "$evsim" render arch_to_left_common_carotid --duration 0.5 --rate 4 --lao "$angle" \
    --inject 0.0,1 --inject-vessel ascending_aorta --out "$work/lao$angle" > /dev/null
  cp "$work/lao$angle/frame_00002.png" "$work/view$angle.png"
done
convert "$work/view-30.png" "$work/view0.png" "$work/view30.png" +append -resize 50% "$out/views.png"
echo "wrote $out/procedure.png $out/views.png"
