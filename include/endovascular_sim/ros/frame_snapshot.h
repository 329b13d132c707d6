// What one published frame shows: a copy of the simulation taken under the
// node's lock, so that messages are built while the simulation steps on.
#pragma once

#include <memory>
#include <vector>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {

struct FrameSnapshot {
  std::shared_ptr<const SceneModel> model;
  double time{0.0};  // simulated [s]
  long step{0};
  bool paused{false};
  std::vector<DeviceState> devices;
  std::vector<Contact> contacts;
  StepStats stats;
  std::vector<VesselLocation> tips;     // per device: the named vessel its tip is in
  std::vector<TargetProgress> targets;  // per scene target
  std::vector<DriveWrench> drives;      // per device: what its drive applies (last step)
  std::vector<Vec3> tip_forces;         // per device: contact force on its tip [N]
  std::vector<DriveStall> stalls;       // per device: what its drive cannot impose
  MotionSnapshot motion;                // of the vessels at `time` (empty when they do not move)
};

/// One step's drive wrench (the node publishes every step's).
struct WrenchSample {
  double time{0.0};  // [s] simulated
  DriveWrench wrench;
};

/// Timing of the simulation loop, as the diagnostics and stats report it.
struct LoopTiming {
  int steps_per_frame{1};
  double frame_ms{0.0};          // wall time of the last frame's steps [ms]
  double real_time_factor{0.0};  // simulated / wall time over the last second
  long frames{0};
  long overruns{0};  // frames that ended more than one period late
};

}  // namespace evsim
