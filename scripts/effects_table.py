#!/usr/bin/env python3
"""What each effect costs, for every shipped scene.

Runs `evsim bench` on each scene as shipped, with each of its effects taken
out, and with each effect it does not name put in (where the scene can have
it: vessel_motion needs motion regions, coaxial a device inside another).
Prints a Markdown table of median and p99 step times, or the reason a
variant could not run (an effect the scene needs).

usage: scripts/effects_table.py [EVSIM] [--csv FILE] [--scenes A,B] [--timeout S]

A variant that takes more than the timeout (default 300 s) is reported as
such. The figures are the `whole` line of `evsim bench` over the steps
measured (median and p99 of the step's wall time).
"""
import csv
import os
import re
import subprocess
import sys

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
EVSIM = os.path.join(HERE, "..", "build", "ws", "devel", "lib", "endovascular_sim", "evsim")
SCENES = os.path.join(HERE, "..", "config", "scenes")
OPTIONAL = ["gravity", "device_contact", "subdivision", "friction", "blood_drag"]
# Steps measured (after a warm-up) for the stability scenes, whose whole
# procedure takes minutes; every other scene is measured over its whole
# procedure (its `duration`).
STEPS = {"large_step": (100, 0), "dead_end": (1000, 1500), "tortuous": (1000, 1000),
         "aneurysm_packed": (1000, 2000)}
# `evsim bench`'s summary: phase, steps, median, mean, p99, worst, RTF.
LINE = re.compile(r"^\s*whole\s+\d+\s+([0-9.]+)\s+[0-9.]+\s+([0-9.]+)", re.MULTILINE)


def variants(spec):
    shipped = list(spec.get("effects", []))
    yield "as shipped", shipped
    for e in shipped:
        yield "without " + e, [x for x in shipped if x != e]
    possible = list(OPTIONAL)
    if spec.get("vessels", {}).get("motion"):
        possible.append("vessel_motion")
    if any("inside" in d for d in spec.get("devices", [])):
        possible.append("coaxial")
    for e in possible:
        if e not in shipped:
            yield "with " + e, shipped + [e]


def bench(evsim, scene, effects, timeout):
    cmd = [evsim, "bench", scene, "--effects", ",".join(effects)]
    if scene in STEPS:
        steps, warmup = STEPS[scene]
        cmd += ["--steps", str(steps), "--warmup", str(warmup)]
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, None, "over %g s" % timeout
    m = LINE.search(out.stdout)
    if out.returncode == 0 and m:
        return float(m.group(1)), float(m.group(2)), ""
    why = (out.stderr.strip().splitlines() or ["exit %d" % out.returncode])[-1]
    return None, None, why.replace("evsim: ", "")


def option(args, name, default):
    if name not in args:
        return default
    i = args.index(name)
    value = args[i + 1]
    del args[i:i + 2]
    return value


def main():
    args = sys.argv[1:]
    csv_path = option(args, "--csv", None)
    only = option(args, "--scenes", None)
    timeout = float(option(args, "--timeout", "300"))
    evsim = args[0] if args else EVSIM
    shipped = subprocess.run([evsim, "list"], capture_output=True, text=True, check=True)
    scenes = only.split(",") if only else shipped.stdout.split()
    rows = []
    print("| scene (steps after warm-up) | effects | median step | p99 |")
    print("| --- | --- | --- | --- |")
    for scene in scenes:
        with open(os.path.join(SCENES, scene + ".yaml")) as f:
            spec = yaml.safe_load(f)
        steps, warmup = STEPS.get(scene, (0, 0))
        label = ("`%s` (%d%s)" % (scene, steps, ", after %d" % warmup if warmup else "")
                 if steps else "`%s` (whole)" % scene)
        for name, effects in variants(spec):
            median, p99, why = bench(evsim, scene, effects, timeout)
            shown = ", ".join(effects) or "none"
            if median is None:
                print("| %s | %s: %s | does not run: %s | |" % (label, name, shown, why))
            else:
                print("| %s | %s: %s | %.3f ms | %.2f ms |" % (label, name, shown, median, p99))
            sys.stdout.flush()
            rows.append([scene, steps, warmup, name, " ".join(effects), median, p99, why])
            label = ""
    if csv_path:
        with open(csv_path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["scene", "steps", "warmup", "variant", "effects", "median_ms", "p99_ms",
                        "why_not"])
            w.writerows(rows)


if __name__ == "__main__":
    main()
