// Navigation targets: a named vessel the distal tip of a device must reach
// and stay in. A target is reached when the tip has been at least `depth`
// inside the vessel (path length along its centreline past its origin, see
// geometry/vessel_atlas.h) for `dwell` seconds without a break (TargetSpec,
// in scene/scene_file.h).
#pragma once

#include <string>
#include <vector>

#include "endovascular_sim/geometry/vessel_atlas.h"
#include "endovascular_sim/scene/scene_file.h"

namespace evsim {

/// A target resolved against a scene's vessels and devices.
struct Target {
  TargetSpec spec;
  int vessel{-1};  // index in the scene's VesselAtlas
  int device{-1};  // -1: any device
};

struct TargetProgress {
  bool reached{false};
  double reached_time{-1.0};  // [s] when the dwell was complete (-1: not yet)
  double since{-1.0};         // [s] the tip has been deep enough since (-1: it is not)
  double best_depth{0.0};     // [m] deepest a tip has been in the vessel
};

/// Advances every target's progress to time t [s], given where each
/// device's tip is. Returns a notice per target reached now.
std::vector<std::string> updateTargets(const std::vector<Target>& targets,
                                       const std::vector<VesselLocation>& tips,
                                       const std::vector<std::string>& device_names,
                                       const VesselAtlas& atlas, double t,
                                       std::vector<TargetProgress>* progress);

}  // namespace evsim
