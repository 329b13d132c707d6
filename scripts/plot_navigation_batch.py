#!/usr/bin/env python3
"""The navigation batch's rows as a figure: each run's simulated time to
its target (reached: filled; not reached: hollow, at its time out) and its
peak wall force, the arch's procedures and the network's targets apart.

    bash scripts/python.sh -m endovascular_sim.batch navigation --out build/nav.csv
    bash scripts/python.sh scripts/plot_navigation_batch.py build/nav.csv config/images/batch/navigation.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(rows_csv, png):
    rows = [r for r in csv.DictReader(open(rows_csv)) if r["ok"] == "True"]
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6))
    for k, group in enumerate(("arch", "network")):
        rs = sorted((r for r in rows if r["task"].startswith(group + "/")),
                    key=lambda r: float(r["time_s"]))
        x = [i + 1 for i in range(len(rs))]
        reached = [r["reached"] == "True" for r in rs]
        for ax, column, label in ((axes[0], "time_s", "simulated time [s]"),
                                  (axes[1], "peak_wall_force_N", "peak wall force [N]")):
            ys = [float(r[column]) for r in rs]
            color = "tab:blue" if group == "arch" else "tab:orange"
            ax.scatter([xi for xi, ok in zip(x, reached) if ok],
                       [y for y, ok in zip(ys, reached) if ok], color=color, s=14,
                       label=f"{group}: {sum(reached)} of {len(rs)} reached")
            ax.scatter([xi for xi, ok in zip(x, reached) if not ok],
                       [y for y, ok in zip(ys, reached) if not ok], facecolors="none",
                       edgecolors=color, s=20)
            ax.set_ylabel(label)
            ax.set_xlabel("run, by time to target")
            ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("the autopilot's navigation batch (hollow: not reached)", fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main(*sys.argv[1:3])
