#!/usr/bin/env python3
"""Sums up a file of per-step JSON lines (`evsim run --json`, `evsim navigate
--steps-json`): steps, simulated time, median / p99 / worst step [ms], the
real-time factor, and the mean activation loops and LCP rows.

Usage: scripts/step_summary.py FILE [FILE...]
"""
import json
import sys


def summary(path):
    rows = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            line = line.strip()
            if not line:
                continue
            try:
                rows.append(json.loads(line))
            except json.JSONDecodeError as e:
                sys.exit(f"{path}:{number}: not a JSON object ({e})")
    if not rows:
        sys.exit(f"{path}: no steps")
    wall = sorted(r["wall_ms"] for r in rows)
    n = len(wall)
    simulated = rows[-1]["t"] - rows[0]["t"] + (rows[1]["t"] - rows[0]["t"] if n > 1 else 0.0)
    total = sum(wall) / 1e3
    loops = sum(r["activation_loops"] for r in rows) / n
    contacts = sum(r["contacts"] for r in rows) / n
    return (f"{path}: {n} steps, {simulated:.3f} s simulated; step median {wall[n // 2]:.3f} "
            f"p99 {wall[min(n - 1, int(0.99 * n))]:.3f} worst {wall[-1]:.2f} ms; "
            f"RTF {simulated / total if total > 0 else float('inf'):.2f}; "
            f"mean loops {loops:.2f}, mean contacts {contacts:.1f}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for p in sys.argv[1:]:
        print(summary(p))
