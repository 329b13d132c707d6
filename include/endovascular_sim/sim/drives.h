// The drives between steps: what each drive reads before a step, the end
// of its travel, its wrench with the introducer valve's friction, its stall
// against the scene's limits, and the tips' contact forces. step()
// (sim/simulation.cpp) calls them after every accepted step.
#pragma once

#include <vector>

#include "endovascular_sim/sim/simulation.h"

namespace evsim {

/// A drive's position before a step.
struct DriveReading {
  double inserted;  // [m]
  double angle;     // [rad]
};

/// What every drive reads now (before a step).
std::vector<DriveReading> readDrives(const SimData& data);

/// A drive that reached the end of its travel in the last step: its
/// velocity command goes on, clamped (a notice once, when the end is reached).
void noteDriveLimits(const SceneModel& model, const std::vector<DriveReading>& before,
                     SimData* data);

/// The motions a drive cannot impose: a resistance at or beyond its limit.
DriveStall stallOf(const DriveWrench& w, const DriveSpec& limits);

/// The sense (+1, -1, 0) in which a command moves a drive now.
int commandedSense(DriveCommand::Mode mode, double command, double current);

/// The introducer valve's friction against the motion the drive made this
/// step (from `before` to now), added to what the drive applies; a drive
/// stalled against its command keeps feeling it (the valve holds the
/// device as firmly as it drags it).
void addValveFriction(const DriveSpec& spec, const Introducer& introducer,
                      const DriveReading& before, const DeviceState& now,
                      const DriveCommand& command, const DriveStall& stalled, DriveWrench* w);

/// The drives' wrenches (with the valves' friction against the motion since
/// `before`, when given), their stalls with a notice, and the tips' contact
/// forces (measureForces: without `before`).
void measureForcesSince(const SceneModel& model, SimData* data,
                        const std::vector<DriveReading>* before);

}  // namespace evsim
