// Vessel centrelines: a forest of points with radii, read from SWC files.
//
// SWC layout, one point per line: id type x y z radius parent (parent -1 for
// a root); '#' starts a comment. A header comment "# units: mm" (or m, um)
// states the unit of x, y, z and radius; otherwise the caller's default
// applies. Each point with a parent makes one segment (parent -> point).
//
// A header comment "# frame: LAS" declares the anatomical frame
// (geometry/patient_frame.h): which way x, y and z point in the patient.
//
// Named vessels: a header comment "# vessel: NAME ID" says that the vessel
// NAME (snake_case) starts at point ID; every point belongs to the vessel of
// its nearest ancestor (itself included) that starts one. A root no line
// names starts a vessel "vessel_ID".
#pragma once

#include <string>
#include <vector>

#include "endovascular_sim/core/types.h"

namespace evsim {

/// The largest vessel radius a centreline may give [m] (the aorta's is
/// about 15 mm): a larger one is a unit mistake, and a field of such
/// kernels would take minutes to build.
constexpr double kMaxVesselRadius = 0.1;
/// The largest coordinate a centreline point may have [m].
constexpr double kMaxCoordinate = 10.0;

struct Centerline {
  std::vector<Vec3> position;  // [m]
  std::vector<double> radius;  // lumen radius [m]
  std::vector<int> parent;     // index of the parent point, -1 for roots
  std::vector<int> type;       // SWC type (free use: region labels)
  std::vector<int> vessel;     // index into vessel_names per point (see nameVessels)
  std::vector<std::string> vessel_names;
  std::string frame;  // anatomical orientation code (patient_frame.h); "": undeclared

  int numPoints() const { return static_cast<int>(position.size()); }
  int numSegments() const;
  /// Appends another centreline (indices shifted).
  void append(const Centerline& other);
};

/// Completes `vessel` for points without one (a centreline built by hand,
/// or points appended): a point takes its parent's vessel, a root without
/// one starts "vessel_<index + 1>".
void nameVessels(Centerline* centerline);

/// True for a valid vessel name: [a-z][a-z0-9_]*.
bool isVesselName(const std::string& name);

/// Reads an SWC file; default_unit [m per file unit] applies when the file
/// has no "# units:" header. Throws LoadError naming the file and line.
Centerline loadCenterlineFile(const std::string& path, double default_unit = 1e-3);

/// Writes an SWC file in millimetres.
void saveCenterlineFile(const Centerline& centerline, const std::string& path,
                        const std::string& comment);

}  // namespace evsim
