#!/usr/bin/python3
"""Renders a PLY mesh written by `evsim mesh` to a PNG (shaded vertex splats).

Usage: render_mesh.py MESH.ply OUT.png [--view AZIMUTH ELEVATION] [--title T]
A quick look for humans and for the README; rviz shows the real thing.
"""
import argparse

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_ply(path):
    with open(path) as f:
        n_vertices = 0
        while True:
            line = f.readline()
            if line.startswith("element vertex"):
                n_vertices = int(line.split()[2])
            if line.strip() == "end_header":
                break
        data = np.loadtxt(f, max_rows=n_vertices)
    return data[:, :3], data[:, 3:6]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mesh")
    ap.add_argument("out")
    ap.add_argument("--view", nargs=2, type=float, default=[-60.0, 15.0])
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    p, n = read_ply(a.mesh)
    az, el = np.radians(a.view)
    # Camera: looking along -d, with z up.
    d = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    right = np.cross([0.0, 0.0, 1.0], d)
    right /= np.linalg.norm(right)
    up = np.cross(d, right)
    u, v, depth = p @ right, p @ up, p @ d
    facing = n @ d > 0.0
    light = np.clip(n @ (0.6 * d + 0.4 * up), 0.0, 1.0)
    order = np.argsort(depth[facing])
    fig, ax = plt.subplots(figsize=(8, 8), dpi=100)
    ax.scatter(1e3 * u[facing][order], 1e3 * v[facing][order], c=light[facing][order],
               cmap="Reds_r", vmin=-0.3, vmax=1.1, s=0.6, linewidths=0)
    ax.set_aspect("equal")
    ax.set_xlabel("mm")
    ax.set_ylabel("mm")
    ax.set_title(a.title)
    fig.tight_layout()
    fig.savefig(a.out)


if __name__ == "__main__":
    main()
