#!/usr/bin/env python3
"""Plots what each device's drive applies along the insertion axis (the force
a hand or a robot feels, `drive_force_N`) over a run, from per-step JSON
lines (`evsim run --json`, `evsim navigate --steps-json`), with a 10 Hz
low-pass as a force sensor would show it (the node's ~wrench_cutoff).

Usage: scripts/plot_forces.py STEPS.json OUT.png "TITLE"
"""
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def low_pass(times, values, cutoff_hz=10.0):
    """The node's WrenchLowPass: y += a (x - y), a = 1 - exp(-2 pi fc dt)."""
    out, y = [], None
    for k, x in enumerate(values):
        if y is None:
            y = x
        else:
            a = 1.0 - math.exp(-2.0 * math.pi * cutoff_hz * (times[k] - times[k - 1]))
            y += a * (x - y)
        out.append(y)
    return out


def main(path, out, title):
    times, forces, names = [], {}, []
    with open(path) as f:
        for line in f:
            if not line.strip():
                continue
            row = json.loads(line)
            times.append(row["t"])
            for d in row["devices"]:
                if d["name"] not in forces:
                    forces[d["name"]] = []
                    names.append(d["name"])
                forces[d["name"]].append(d.get("drive_force_N", 0.0))
    fig, ax = plt.subplots(figsize=(8, 3.2), dpi=100)
    for name in names:
        raw = forces[name]
        line, = ax.plot(times, raw, lw=0.5, alpha=0.35)
        ax.plot(times, low_pass(times, raw), lw=1.6, color=line.get_color(),
                label=f"{name} (10 Hz low-pass)")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("simulated time [s]")
    ax.set_ylabel("drive force along the axis [N]\n(> 0: pushing in)")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out)
    print(f"wrote {out}: {len(times)} steps")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
