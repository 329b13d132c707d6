// Where the devices lie at the start. Each device's inserted length runs
// from its access point as it lies after an insertion: the part that fits
// the lumen in its rest shape keeps it (a straight stretch of vessel), and a
// device that would leave the lumen so is laid along the vessels' path
// instead, the way a device pushed in goes: from the access point along the
// insertion direction, at each fork the straightest way on. A device inside
// another (effect 'coaxial') follows its outer device to that one's tip, and
// the same path beyond.
#pragma once

#include <string>
#include <vector>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {

/// The centreline path a device pushed in from `intro` follows.
struct InsertionPath {
  std::vector<Vec3> points;  // [m]; points[0] the access point
  std::vector<double> arc;   // [m] path length from the access point
  int end_point{-1};         // the centreline point where the path ends (a vessel's end)
  double length() const { return arc.empty() ? 0.0 : arc.back(); }
  /// Position [m] and unit tangent at path length `a` [m] (clamped to the path).
  Vec3 at(double a, Vec3* tangent = nullptr) const;
};

/// From the access point along the insertion direction (the introducer
/// frame's x axis), over the nearest centreline segment, then from point to
/// point the straightest way on, for at most `length` [m] or to a vessel's
/// end.
InsertionPath insertionPath(const Centerline& centerline, const Introducer& intro,
                            double length);

/// The devices placed at the start (makeData's). Returns "" or why device
/// *bad's inserted length cannot lie inside the lumen, with the length that
/// fits (the path ends first).
std::string placeDevices(const SceneModel& model, std::vector<DeviceState>* devices,
                         int* bad = nullptr);

}  // namespace evsim
