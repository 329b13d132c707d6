// A patient's centreline from a VTK PolyData file (VMTK `vmtkcenterlines`,
// SimVascular): `.vtp` (XML: ascii, binary, zlib-compressed, appended) or
// legacy `.vtk`, read by VTK's own readers. The radius at every point comes
// from a point-data array (MaximumInscribedSphereRadius by default); units
// are declared by the scene, never guessed. Branch ids come from the file
// (BranchId, else GroupIds, else CenterlineIds: cell data, or point data
// taken per cell) or from the outlet order. The output of
// `vmtkbranchextractor` (each centreline cut into tracts: cell arrays
// CenterlineIds, TractIds, GroupIds, Blanking) is reassembled into one line
// per centreline whose points carry their tract's group: the groups are
// then the branch ids. The tree is built and simplified by
// geometry/centerline_tree.h.
#pragma once

#include <string>

#include "endovascular_sim/geometry/centerline_tree.h"

namespace evsim {

struct VtkCenterlineOptions {
  double unit{1e-3};  // [m] per file unit
  std::string radius_array{"MaximumInscribedSphereRadius"};
  CenterlineTreeOptions tree;
};

/// True for a path the VTK reader takes (.vtp, .vtk).
bool isVtkCenterlinePath(const std::string& path);

/// Reads the polylines (points and radii in metres, lines, branch ids);
/// throws LoadError naming the file and what is wrong (not readable, not
/// PolyData, no radius array: the arrays present are listed).
CenterlinePolylines readVtkPolylines(const std::string& path, const VtkCenterlineOptions& o);

/// readVtkPolylines, then buildCenterlineTree; its errors as LoadError.
Centerline loadVtkCenterline(const std::string& path, const VtkCenterlineOptions& o,
                             CenterlineTreeReport* report);

}  // namespace evsim
