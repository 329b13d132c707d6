// A triangle mesh of the vessel surface g = 0 for display (rviz, files).
//
// Marching tetrahedra (each lattice cube split in six tetrahedra around its
// main diagonal: no ambiguous cases, no holes) over the cubes of the grid
// cells that hold primitives, with vertices shared between neighbouring
// triangles, triangles facing outward and normals from the field gradient.
#pragma once

#include <string>
#include <vector>

#include "endovascular_sim/core/types.h"
#include "endovascular_sim/geometry/vessel_field.h"

namespace evsim {

struct SurfaceMesh {
  std::vector<Vec3> vertices;              // [m]
  std::vector<Vec3> normals;               // unit, outward
  std::vector<Eigen::Vector3i> triangles;  // counter-clockwise seen from outside
};

/// Meshes the surface for a device of radius r (0: the lumen wall) with a
/// lattice spacing [m]. A spacing <= 0 picks a quarter of the thinnest
/// vessel radius, coarsened so that at most ~4e6 lattice cubes are visited.
SurfaceMesh meshVesselSurface(const VesselField& field, double spacing, double device_radius = 0.0,
                              const MotionSnapshot& motion = {});

/// Writes ASCII PLY (.ply) or binary STL (.stl), by the path's extension.
/// Returns false (and why) when the file cannot be written.
bool writeMesh(const SurfaceMesh& mesh, const std::string& path, std::string* why);

}  // namespace evsim
