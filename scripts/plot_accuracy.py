#!/usr/bin/python3
"""Plots what accuracy costs: error against time for each knob of a sweep.

Reads the CSV of `evsim bench accuracy ...` and writes a PNG: one marker per
setting, coloured by knob, log-log; the Pareto front (settings that no other
beats on both cost and error) is joined by a line and its points ringed.
Usage: scripts/plot_accuracy.py SWEEP.csv OUT.png [TITLE]
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

UNITS = {"s_per_sim_s": "wall time per simulated second [s/s]",
         "ms_per_step": "wall time per free-motion step [ms]",
         "us_per_query": "wall time per first-root query [µs]"}
ERRORS = {"s_per_sim_s": "tip error against the fine reference run [m]",
          "ms_per_step": "tip error against 800 elements [m]",
          "us_per_query": "largest root position error against 1e-13 m [m]"}


def pareto(rows):
    """Rows not dominated in (cost, error), sorted by cost; a run with rejected
    steps did not finish and is never on the front."""
    front, best = [], float("inf")
    finished = [r for r in rows if r["rejected"] == "0"]
    for r in sorted(finished, key=lambda r: (r["cost"], r["error"])):
        if r["error"] < best:
            front.append(r)
            best = r["error"]
    return front


def main(path, out, title):
    with open(path) as f:
        rows = [dict(r, cost=float(r["cost"]), error=max(float(r["error_m"]), 1e-15))
                for r in csv.DictReader(f)]
    scene = rows[0]["cost_unit"] == "s_per_sim_s"
    panels = [("error", ERRORS.get(rows[0]["cost_unit"], "error [m]"))]
    if scene:  # the contact accuracy too
        for r in rows:
            r["penetration"] = max(float(r["max_penetration_m"]), 1e-12)
        panels.append(("penetration", "largest penetration after a step [m]"))
    fig, axes = plt.subplots(1, len(panels), figsize=(8 * len(panels), 5.5), squeeze=False)
    knobs = sorted({r["knob"] for r in rows})
    markers = "osD^v<>pPX*h"
    for ax, (key, ylabel) in zip(axes[0], panels):
        for i, knob in enumerate(knobs):
            pts = [r for r in rows if r["knob"] == knob]
            ax.scatter([r["cost"] for r in pts], [r[key] for r in pts], label=knob,
                       marker=markers[i % len(markers)], s=40, zorder=3)
            for r in pts:
                label = r["setting"] + (" (rejected %s)" % r["rejected"]
                                        if r["rejected"] != "0" else "")
                ax.annotate(label, (r["cost"], r[key]), fontsize=6, xytext=(3, 3),
                            textcoords="offset points")
        front = pareto([dict(r, error=r[key]) for r in rows])
        ax.plot([r["cost"] for r in front], [r["error"] for r in front], "k--", lw=1,
                label="Pareto front", zorder=2)
        ax.scatter([r["cost"] for r in front], [r["error"] for r in front], s=140,
                   facecolors="none", edgecolors="k", zorder=4)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(UNITS.get(rows[0]["cost_unit"], rows[0]["cost_unit"]))
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    fig.suptitle(title)
    front = pareto(rows)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote %s (%d settings, %d on the Pareto front)" % (out, len(rows), len(front)))


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3] if len(sys.argv) > 3 else sys.argv[1])
