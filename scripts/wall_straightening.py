#!/usr/bin/env python3
"""How far a scene's devices straighten its vessels (effect 'vessel_deformation').

Runs `evsim run SCENE --save-state F`, reads the wall's shape from the state
file (its `wall_point` records, one per centreline point) and the scene's SWC
centreline, and prints per named vessel its length and tortuosity index (path
length over the distance between its ends) at rest and as the wall ended.

    python3 scripts/wall_straightening.py EVSIM SCENE_FILE
"""
import math
import os
import subprocess
import sys
import tempfile

import yaml


def read_swc(path):
    """Points (x, y, z in m), parents (indices) and the vessel of each point."""
    unit = 1e-3
    starts = {}
    ids, points, parents = [], [], []
    with open(path) as f:
        for line in f:
            text = line.strip()
            if text.startswith("#"):
                words = text[1:].split()
                if words[:1] == ["units:"]:
                    unit = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "cm": 1e-2}[words[1]]
                elif words[:1] == ["vessel:"]:
                    starts[int(words[2])] = words[1]
                continue
            if not text:
                continue
            w = text.split()
            ids.append(int(w[0]))
            points.append([float(v) for v in w[2:5]])
            parents.append(int(w[6]))
    index = {i: k for k, i in enumerate(ids)}
    points = [[unit * v for v in p] for p in points]
    parent = [index.get(p, -1) for p in parents]
    vessel = []
    for k, i in enumerate(ids):
        at = k
        while ids[at] not in starts and parent[at] >= 0:
            at = parent[at]
        vessel.append(starts.get(ids[at], "vessel_%d" % ids[at]))
    return points, parent, vessel


def read_wall(path):
    """The wall's displacement of every centreline point [m] (None at rest)."""
    with open(path) as f:
        lines = f.read().splitlines()
    for k, line in enumerate(lines):
        if line.startswith("wall "):
            count = int(line.split()[1])
            return [[float(v) for v in lines[k + 1 + i].split()[1:4]] for i in range(count)] or None
    return None


def measure(points, parent, vessel, name):
    """Length and tortuosity index of one named vessel's chain of points."""
    chain = [k for k in range(len(points)) if vessel[k] == name]
    length = 0.0
    for k in chain:
        if parent[k] >= 0:
            length += math.dist(points[k], points[parent[k]])
    first = parent[chain[0]] if parent[chain[0]] >= 0 else chain[0]
    chord = math.dist(points[first], points[chain[-1]])
    return length, length / chord


def main():
    evsim, scene = sys.argv[1], sys.argv[2]
    with open(scene) as f:
        spec = yaml.safe_load(f)
    swc = os.path.join(os.path.dirname(os.path.abspath(scene)), spec["vessels"]["centerline"])
    points, parent, vessel = read_swc(swc)
    with tempfile.TemporaryDirectory() as tmp:
        state = os.path.join(tmp, "end.state")
        subprocess.run([evsim, "run", scene, "--save-state", state], check=True,
                       stdout=subprocess.DEVNULL)
        wall = read_wall(state)
    if wall is None:
        sys.exit("the wall is at rest: does the scene name the effect vessel_deformation?")
    moved = [[p[i] + u[i] for i in range(3)] for p, u in zip(points, wall)]
    print("| vessel | length at rest [mm] | deformed [mm] | tortuosity at rest | deformed |")
    print("| --- | --- | --- | --- | --- |")
    for name in sorted(set(vessel)):
        l0, t0 = measure(points, parent, vessel, name)
        l1, t1 = measure(moved, parent, vessel, name)
        print("| %s | %.2f | %.2f | %.4f | %.4f |" % (name, 1e3 * l0, 1e3 * l1, t0, t1))


if __name__ == "__main__":
    main()
