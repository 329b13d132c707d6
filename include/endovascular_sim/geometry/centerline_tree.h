// A vessel tree from the polylines of a patient's centreline (VMTK,
// SimVascular; read by scene/centerline_vtk.h), without VTK.
//
// Two layouts are found in the wild:
//  (a) one polyline per outlet, each from the inlet, overlapping along the
//      shared paths (raw `vmtkcenterlines`): the lines are merged, longest
//      first; a line joins the tree where it last runs within kShared of
//      the local radius of it, and only what lies beyond becomes a branch.
//      When the lines come from `vmtkbranchextractor`'s tracts (reassembled
//      per centreline by scene/centerline_vtk.h), each point carries its
//      tract's group: a point of a group already in the tree is shared
//      whatever its distance, a point of a new group starts a branch, and
//      the geometry decides only inside a bifurcation's blanked tracts;
//  (b) a merged tree of line cells sharing point ids (SimVascular; often
//      thousands of 2-point lines): the cells are joined at shared points
//      (and at points that coincide).
// The largest connected piece is kept (the others are reported); a loop is
// refused. The inlet is the end with the largest radius unless given. Each
// branch (the points between two ends or junctions) is then simplified to
// the tolerances: radii smoothed by a running median over one radius of
// arc length (the noise of the inscribed spheres), then points dropped
// while the polyline stays within `tolerance` of the dropped points and
// its radii within `radius_tolerance` of theirs (Douglas-Peucker on x and r).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "endovascular_sim/geometry/centerline.h"

namespace evsim {

/// Polylines as read from a file: points [m], radii [m], cells of point
/// indices, and per cell a branch id when the file has one (else empty).
struct CenterlinePolylines {
  std::vector<Vec3> points;
  std::vector<double> radius;
  std::vector<std::vector<int>> lines;
  std::vector<int> branch_id;
  /// Per point, when the lines were reassembled from tracts: the group of
  /// its tract (`GroupIds`), -1 in a bifurcation's blanked tract (or when
  /// the file has no groups); else empty.
  std::vector<int> point_group;
  int tracts{0};  // the tracts the lines were reassembled from (0: none)
  std::string frame;  // the anatomical frame the file declares (patient_frame.h; "": none)
};

struct CenterlineTreeOptions {
  double tolerance{0.05e-3};         // [m] the simplified axis stays this close to the file's
  double radius_tolerance{0.03};     // the simplified radii stay within this fraction of the file's
  bool has_inlet{false};             // inlet: the tree's end nearest `inlet`
  Vec3 inlet{Vec3::Zero()};          // [m]
  std::map<int, std::string> names;  // branch id -> vessel name ("branch_<id>" otherwise)
};

/// What building the tree found: the layout, what was merged and dropped,
/// and warnings for a tree that is usable but suspect.
struct CenterlineTreeReport {
  bool overlapping{false};  // layout (a)
  int tracts{0};            // layout (a) reassembled from this many tracts
  bool grouped{false};      // merged by the tracts' group ids
  int file_points{0};
  int points{0};  // after simplification
  int branches{0};
  std::vector<int> branch_ids;        // per vessel of the tree, its branch id
  double max_axis_error{0.0};         // [m] of the simplification
  double max_radius_error{0.0};       // relative, against the smoothed radii
  std::vector<std::string> warnings;  // dropped pieces, radii reaching other branches,
                                      // a group's tracts far apart
};

/// Builds the tree; throws std::invalid_argument saying what is wrong (no
/// lines, a loop, a bad radius or point, a name for no branch).
Centerline buildCenterlineTree(const CenterlinePolylines& lines, const CenterlineTreeOptions& o,
                               CenterlineTreeReport* report);

}  // namespace evsim
