#!/usr/bin/python3
"""Writes the anatomical centrelines of the shipped scenes (SWC, millimetres).

Frame: x toward the patient's left, y anterior, z superior; origin at the
centre of the aortic arch. Each vessel is a Catmull-Rom curve through control
points, resampled every ~1.2 radii; a branch's first point is its parent's
centreline point (a junction).

Dimensions (lumen diameters; typical adult values):
  ascending aorta 30 mm, arch 28 -> 25 mm, descending aorta 24 mm
      (Hager et al., Z Kardiol 2002; Wolak et al., JACC Imaging 2008)
  brachiocephalic trunk 12 mm, 40 mm long; subclavian arteries 9 mm
  common carotid arteries 7 mm; internal carotid 4.8 mm; external 3.8 mm
      (Krejza et al., Stroke 2006)
  ICA siphon segment for the aneurysm scene 4.4 mm, saccular aneurysm dome
  7 mm with a 3.0 mm neck (small-to-medium aneurysm, dome/neck > 2: a
  typical candidate for coiling; measured by AneurysmScene test)
Run: python3 scripts/make_vessels.py  (rewrites config/vessels/*.swc)
"""
import math
import pathlib

OUT = pathlib.Path(__file__).resolve().parent.parent / "config" / "vessels"


def catmull_rom(points, spacing):
    """Resamples a Catmull-Rom curve through points at about `spacing`."""
    pts = [points[0]] + list(points) + [points[-1]]
    out = []
    for i in range(1, len(pts) - 2):
        p0, p1, p2, p3 = pts[i - 1], pts[i], pts[i + 1], pts[i + 2]
        seg = math.dist(p1, p2)
        n = max(1, round(seg / spacing))
        for k in range(n):
            t = k / n
            t2, t3 = t * t, t * t * t
            out.append(tuple(
                0.5 * (2 * p1[j] + (-p0[j] + p2[j]) * t +
                       (2 * p0[j] - 5 * p1[j] + 4 * p2[j] - p3[j]) * t2 +
                       (-p0[j] + 3 * p1[j] - 3 * p2[j] + p3[j]) * t3)
                for j in range(3)))
    out.append(points[-1])
    return out


class Tree:
    def __init__(self):
        self.rows = []  # (id, type, x, y, z, r, parent)
        self.names = []  # (name, id of its first point)

    def vessel(self, control, r0, r1, parent, kind, name):
        """Adds a vessel named `name`; returns the ids of its points."""
        self.names.append((name, len(self.rows) + 1))
        curve = catmull_rom(control, 1.2 * min(r0, r1))
        ids = []
        total = sum(math.dist(curve[i], curve[i + 1]) for i in range(len(curve) - 1))
        s = 0.0
        for i, p in enumerate(curve):
            if i > 0:
                s += math.dist(curve[i - 1], p)
            if i == 0 and parent >= 0:
                ids.append(parent)  # the junction point belongs to the parent
                continue
            r = r0 + (r1 - r0) * (s / total if total else 0.0)
            pid = len(self.rows) + 1
            self.rows.append((pid, kind, *p, r, ids[-1] if ids else parent))
            ids.append(pid)
        return ids

    def point(self, pid):
        return self.rows[pid - 1][2:5]

    def write(self, path, comment, frame="LAS"):
        with open(path, "w") as f:
            for line in comment.strip().splitlines():
                f.write(f"# {line}\n")
            f.write("# units: mm\n")
            # the anatomical frame: LAS, x toward the patient's left, y anterior,
            # z superior (supine: -y down); LSA for a segment lying in the
            # axial plane (supine: -z down)
            if frame:  # (the arch's: none, see config/scenes/README.md)
                f.write(f"# frame: {frame}\n")
            for name, first in self.names:
                f.write(f"# vessel: {name} {first}\n")
            f.write("# id type x y z radius parent\n")
            for pid, kind, x, y, z, r, parent in self.rows:
                f.write(f"{pid} {kind} {x:.3f} {y:.3f} {z:.3f} {r:.3f} {parent}\n")


def arch_point(theta_deg):
    t = math.radians(theta_deg)
    return (-25 * math.cos(t), 20 * math.cos(t), 30 * math.sin(t))


def carotid():
    t = Tree()
    ascending = t.vessel([(-25, 20, -60), (-25, 20, -30), arch_point(0)], 15, 14, -1, 1, "ascending_aorta")
    arch_ctrl = [arch_point(a) for a in range(0, 181, 15)]
    arch = t.vessel(arch_ctrl, 14, 12.5, ascending[-1], 1, "aortic_arch")
    descending = t.vessel([arch_point(180), (25, -20, -40), (25, -20, -100), (25, -20, -170)],
                          12.5, 12, arch[-1], 1, "descending_aorta")

    def on_arch(theta):  # nearest arch point to a branch origin
        target = arch_point(theta)
        return min(arch, key=lambda pid: math.dist(t.point(pid), target))

    bct = t.vessel([t.point(on_arch(55)), (-20, 13, 45), (-28, 14, 68)], 6, 6, on_arch(55), 2,
                   "brachiocephalic_trunk")
    t.vessel([t.point(bct[-1]), (-45, 12, 74), (-70, 8, 71), (-95, 5, 62)], 4.5, 4.2, bct[-1], 3,
             "right_subclavian")
    rcca = t.vessel([t.point(bct[-1]), (-31, 17, 105), (-33, 19, 140), (-34, 20, 172)],
                    3.5, 3.4, bct[-1], 4, "right_common_carotid")
    t.vessel([t.point(rcca[-1]), (-36, 23, 200), (-37, 25, 240)], 2.4, 2.3, rcca[-1], 5,
             "right_internal_carotid")
    t.vessel([t.point(rcca[-1]), (-31, 14, 195), (-29, 10, 225)], 1.9, 1.8, rcca[-1], 6,
             "right_external_carotid")
    lcca = t.vessel([t.point(on_arch(85)), (5, 5, 70), (12, 12, 120), (14, 15, 172)],
                    3.4, 3.3, on_arch(85), 4, "left_common_carotid")
    t.vessel([t.point(lcca[-1]), (16, 19, 205), (17, 21, 240)], 2.4, 2.3, lcca[-1], 5,
             "left_internal_carotid")
    t.vessel([t.point(lcca[-1]), (11, 10, 198), (9, 7, 226)], 1.9, 1.8, lcca[-1], 6,
             "left_external_carotid")
    t.vessel([t.point(on_arch(115)), (30, -6, 55), (50, -3, 66), (80, 0, 64)], 4.5, 4.2,
             on_arch(115), 3, "left_subclavian")
    t.write(OUT / "carotid.swc", frame=None, comment="""
Aortic arch with its three branches, carotid bifurcations included. Written by
scripts/make_vessels.py (see its header for the dimensions and their sources).
Types: 1 aorta, 2 brachiocephalic trunk, 3 subclavian, 4 common carotid,
5 internal carotid, 6 external carotid. The "# vessel:" lines name the
vessels (each starts at the point id given).
""")


def aneurysm():
    t = Tree()
    # A C-shaped ICA (siphon-like) segment, 4.4 mm lumen, in the x-z plane.
    ctrl = [(0, 0, -40), (0, 0, -15), (4, 0, 0), (14, 0, 8), (24, 0, 4), (28, 0, -6),
            (30, 2, -25)]
    t.vessel(ctrl, 2.2, 2.1, -1, 5, "internal_carotid")
    t.write(OUT / "aneurysm.swc", """
Internal carotid segment (siphon-like C curve), 4.4 mm lumen. The saccular
aneurysm (7 mm dome) is a sphere primitive declared in
config/scenes/aneurysm.yaml. Written by scripts/make_vessels.py.
""", frame="LSA")


def dead_end():
    t = Tree()
    # A straight common-carotid-sized tube (5 mm lumen), 60 mm long, closed at
    # its far end: a wire pushed on buckles and loops (stability suite).
    t.vessel([(0, 0, -5), (0, 0, 25), (0, 0, 55)], 2.5, 2.5, -1, 4, "dead_end_vessel")
    t.write(OUT / "dead_end.swc", """
Straight 5 mm tube, 60 mm long, closed at its end (stability suite: a wire
pushed into a dead end). Written by scripts/make_vessels.py.
""")


def tortuous():
    t = Tree()
    # A 4 mm lumen that winds through four hairpin-like bends whose centreline
    # radius (about 3 mm) is close to the vessel radius (2 mm): concave walls
    # on every outer side (stability suite). Parallel legs are 10 mm apart so
    # that their walls stay separate.
    ctrl = [(0, 0, -10), (0, 0, 15), (2, 0, 19), (5, 0, 20), (8, 0, 19), (10, 0, 15),
            (10, 0, 0), (12, 0, -4), (15, 0, -5), (18, 0, -4), (20, 0, 0), (20, 0, 15),
            (22, 0, 19), (25, 0, 20), (28, 0, 19), (30, 0, 15), (30, 0, -10)]
    t.vessel(ctrl, 2.0, 2.0, -1, 4, "tortuous_vessel")
    t.write(OUT / "tortuous.swc", """
A 4 mm vessel through four tight bends (centreline bend radius about 3 mm,
close to the 2 mm vessel radius), for the stability suite. Written by
scripts/make_vessels.py.
""", frame="LSA")


if __name__ == "__main__":
    OUT.mkdir(parents=True, exist_ok=True)
    carotid()
    aneurysm()
    dead_end()
    tortuous()
