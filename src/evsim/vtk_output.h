// What evsim writes for ParaView, with VTK's own XML writer (binary, zlib):
// the vessel surface (.vtp), and a run's frames (`evsim run --vtk DIR`):
//   DIR/devices_NNNNNNN.vtp   each device's centreline: a polyline through its
//                             nodes; point data radius [m], device (index),
//                             velocity [m/s]; field data time [s]
//   DIR/contacts_NNNNNNN.vtp  the contacts: a vertex at each wall (or other
//                             device) point; point data normal, force [N]
//                             (normal force + friction, a vector for glyphs),
//                             normal_force [N], gap [m], device (index)
//   DIR/devices.pvd, DIR/contacts.pvd   the time series ParaView opens
// NNNNNNN is the step. Coordinates in metres.
#pragma once

#include <string>
#include <vector>

#include "endovascular_sim/geometry/surface_mesh.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim {

/// The surface as VTK XML PolyData with its normals.
bool writeSurfaceVtp(const SurfaceMesh& mesh, const std::string& path, std::string* why);

/// A run's frames in a folder (which must exist and be writable).
class VtkSeries {
 public:
  explicit VtkSeries(std::string folder) : folder_(std::move(folder)) {}
  /// Writes the frame of `data` and notes it for the .pvd files.
  bool write(const SceneModel& model, const SimData& data, std::string* why);
  /// Writes devices.pvd and contacts.pvd (call after the last frame).
  bool finish(std::string* why) const;

 private:
  std::string folder_;
  std::vector<std::pair<double, std::string>> devices_, contacts_;  // (time, file name)
};

}  // namespace evsim
