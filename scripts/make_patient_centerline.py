#!/usr/bin/python3
"""Writes config/vessels/example_patient.vtp: a generated stand-in for a
patient's centreline as `vmtkcenterlines` writes it (no patient data: the
licences of public patient models vary).

The geometry is the shipped aortic arch (config/vessels/carotid.swc), seen as
VMTK sees a segmented lumen: one polyline per outlet, each starting at the
inlet (the end of the descending aorta, where a femoral access comes up),
overlapping along the shared paths; points every 0.25 mm; every line's axis
jittered by up to 20 um and its radius (MaximumInscribedSphereRadius) by up
to 5 %, like the inscribed spheres of a voxel segmentation; a CenterlineIds
cell array. Millimetres. The outlets in the order written (their indices name
the vessels in config/scenes/patient_example.yaml):
  0 ascending_aorta, then one per SWC leaf in the file's order.
Run: python3 scripts/make_patient_centerline.py   (prints the outlet table)
"""
import math
import pathlib
import random

import vtk

ROOT = pathlib.Path(__file__).resolve().parent.parent
SWC = ROOT / "config" / "vessels" / "carotid.swc"
OUT = ROOT / "config" / "vessels" / "example_patient.vtp"
SPACING = 0.25  # mm between points
JITTER = 0.02  # mm
RADIUS_NOISE = 0.05  # relative


def read_swc(path):
    points, names = {}, {}
    for line in path.read_text().splitlines():
        if line.startswith("# vessel:"):
            _, _, name, start = line.split()
            names[int(start)] = name
        if not line or line.startswith("#"):
            continue
        i, _, x, y, z, r, parent = line.split()
        points[int(i)] = ((float(x), float(y), float(z)), float(r), int(parent))
    return points, names


def vessel_of(points, names, i):
    while i not in names:
        i = points[i][2]
    return names[i]


def path_between(points, a, b):
    """The tree path a -> b (point ids)."""
    def up(i):
        chain = [i]
        while points[chain[-1]][2] != -1:
            chain.append(points[chain[-1]][2])
        return chain
    ua, ub = up(a), up(b)
    common = next(i for i in ua if i in set(ub))
    return ua[:ua.index(common) + 1] + list(reversed(ub[:ub.index(common)]))


def resample(points, ids, rng):
    out = []
    for a, b in zip(ids, ids[1:]):
        (pa, ra, _), (pb, rb, _) = points[a], points[b]
        n = max(1, round(math.dist(pa, pb) / SPACING))
        for k in range(n):
            t = k / n
            p = [pa[j] + t * (pb[j] - pa[j]) + rng.uniform(-JITTER, JITTER) for j in range(3)]
            out.append((p, (ra + t * (rb - ra)) * (1 + rng.uniform(-RADIUS_NOISE, RADIUS_NOISE))))
    p, r, _ = points[ids[-1]]
    out.append((list(p), r))
    return out


def main():
    points, names = read_swc(SWC)
    children = {i: [] for i in points}
    for i, (_, _, parent) in points.items():
        if parent != -1:
            children[parent].append(i)
    leaves = [i for i in points if not children[i]]
    inlet = next(i for i in leaves if vessel_of(points, names, i) == "descending_aorta")
    root = next(i for i, p in points.items() if p[2] == -1)
    outlets = [root] + [i for i in leaves if i != inlet]
    rng = random.Random(20261126)
    vtk_points = vtk.vtkPoints()
    radius = vtk.vtkDoubleArray()
    radius.SetName("MaximumInscribedSphereRadius")
    lines = vtk.vtkCellArray()
    ids = vtk.vtkIntArray()
    ids.SetName("CenterlineIds")
    for index, outlet in enumerate(outlets):
        samples = resample(points, path_between(points, inlet, outlet), rng)
        line = vtk.vtkPolyLine()
        for p, r in samples:
            line.GetPointIds().InsertNextId(vtk_points.InsertNextPoint(*p))
            radius.InsertNextValue(r)
        lines.InsertNextCell(line)
        ids.InsertNextValue(index)
        name = "ascending_aorta" if outlet == root else vessel_of(points, names, outlet)
        print(f"outlet {index}: {name} ({len(samples)} points)")
    data = vtk.vtkPolyData()
    data.SetPoints(vtk_points)
    data.SetLines(lines)
    data.GetPointData().AddArray(radius)
    data.GetCellData().AddArray(ids)
    writer = vtk.vtkXMLPolyDataWriter()
    writer.SetFileName(str(OUT))
    writer.SetInputData(data)
    writer.SetDataModeToBinary()
    writer.SetCompressorTypeToZLib()
    if not writer.Write():
        raise SystemExit(f"cannot write {OUT}")
    p = points[inlet][0]
    print(f"wrote {OUT.relative_to(ROOT)}: {vtk_points.GetNumberOfPoints()} points; "
          f"inlet at ({p[0]:.1f}, {p[1]:.1f}, {p[2]:.1f}) mm")


if __name__ == "__main__":
    main()
