// Navigation targets: a named vessel the distal tip of a device must reach
// and stay in. A target is reached when the tip has been at least `depth`
// inside the vessel (path length along its centreline past its origin, see
// geometry/vessel_atlas.h), or half the vessel's length in a vessel shorter
// than twice `depth` (requiredDepth), for `dwell` seconds without a break
// (TargetSpec, in scene/scene_file.h). An aneurysm target is reached when a coil's
// device has been detached and every node of its detached section has lain
// in the aneurysm's sac for `dwell` seconds: outside every vessel's lumen
// (the centrelines' radii: no loop protrudes into the parent artery) and
// within 1.5 dome radii of the dome's centre.
#pragma once

#include <string>
#include <vector>

#include "endovascular_sim/geometry/vessel_atlas.h"
#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/device_state.h"
#include "endovascular_sim/scene/scene_file.h"

namespace evsim {

/// A target resolved against a scene's vessels and devices.
struct Target {
  TargetSpec spec;
  int vessel{-1};             // index in the scene's VesselAtlas (-1: an aneurysm target)
  int device{-1};             // -1: any device
  Vec3 center{Vec3::Zero()};  // [m] an aneurysm target's dome
  double radius{0.0};         // [m]
};

struct TargetProgress {
  bool reached{false};
  double reached_time{-1.0};  // [s] when the dwell was complete (-1: not yet)
  double since{-1.0};         // [s] the tip has been deep enough since (-1: it is not)
  double best_depth{0.0};     // [m] deepest a tip has been in the vessel
  double best_inside{0.0};    // [-] an aneurysm target: the largest share of the coil inside
};

/// How deep [m] a tip must be in `vessel` to hold a target of that depth:
/// `depth`, or half the vessel's length when that is less. (A vessel 8 mm
/// long, three bifurcations down a network, holds no tip 20 mm past its
/// origin: the tip is in one of its branches by then.)
double requiredDepth(const NamedVessel& vessel, double depth);

/// Advances every target's progress to time t [s], given where each
/// device's tip is (and, for an aneurysm target, its nodes). Returns a
/// notice per target reached now.
std::vector<std::string> updateTargets(const std::vector<Target>& targets,
                                       const std::vector<VesselLocation>& tips,
                                       const std::vector<DeviceModel>& models,
                                       const std::vector<DeviceState>& devices,
                                       const VesselAtlas& atlas, double t,
                                       std::vector<TargetProgress>* progress);

}  // namespace evsim
