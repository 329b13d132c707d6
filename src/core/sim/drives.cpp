// The drives between steps. Declared and documented in
// endovascular_sim/sim/drives.h.
#include "endovascular_sim/sim/drives.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "endovascular_sim/contact/coaxial.h"
#include "endovascular_sim/contact/contact_solver.h"

namespace evsim {
namespace {

/// Marks a drive stalled against its command, with a notice (at most one a
/// second per device: a drive at its limit slips and holds by turns).
void noteStall(const SceneModel& model, size_t i, SimData* data) {
  DriveStall& now = data->stalls[i];
  if (i >= data->commands.size()) return;
  const DriveCommand& c = data->commands[i];
  const DeviceState& x = data->devices[i];
  const bool insertion =
      now.insertion != 0 && now.insertion == commandedSense(c.mode, c.insertion, x.inserted_length);
  const bool rotation =
      now.rotation != 0 && now.rotation == commandedSense(c.mode, c.rotation, x.rotation_angle);
  now.against_command = insertion || rotation;
  if (!now.against_command) return;
  double& last = data->stall_noticed[i];
  if (data->time - last < 1.0) return;
  last = data->time;
  const DriveWrench& w = data->drives[i];
  std::ostringstream m;
  m << "t = " << data->time << " s: device '" << model.devices[i].name << "' slips in its drive: ";
  if (insertion)
    m << std::abs(w.axial_force) << " N resists its "
      << (now.insertion > 0 ? "insertion" : "retraction") << " (limit "
      << model.drive_specs[i].max_force << " N)";
  if (insertion && rotation) m << ", ";
  if (rotation)
    m << std::abs(w.axial_torque) << " N m resists its rotation (limit "
      << model.drive_specs[i].max_torque << " N m)";
  m << "; it follows the command again once the resistance falls below the limit";
  data->notices.push_back(m.str());
}

}  // namespace

std::vector<DriveReading> readDrives(const SimData& data) {
  std::vector<DriveReading> before;
  before.reserve(data.devices.size());
  for (const DeviceState& d : data.devices) before.push_back({d.inserted_length, d.rotation_angle});
  return before;
}

void noteDriveLimits(const SceneModel& model, const std::vector<DriveReading>& before,
                     SimData* data) {
  for (size_t i = 0; i < before.size(); ++i) {
    const DriveCommand& c = data->commands[i];
    if (c.mode != DriveCommand::Mode::kVelocity || c.insertion == 0.0) continue;
    const double now = data->devices[i].inserted_length, full = model.devices[i].length;
    const double was = before[i].inserted;
    const bool out = c.insertion < 0.0 && now <= 0.0 && was > 0.0;
    const bool in = c.insertion > 0.0 && now >= full && was < full;
    if (!out && !in) continue;
    std::ostringstream m;
    m << "t = " << data->time << " s: device '" << model.devices[i].name << "' "
      << (out ? "fully retracted (inserted length 0)" : "fully inserted")
      << ": its drive stops there while the command of " << c.insertion << " m/s stands";
    data->notices.push_back(m.str());
  }
}

DriveStall stallOf(const DriveWrench& w, const DriveSpec& limits) {
  DriveStall s;
  s.insertion = w.axial_force >= limits.max_force ? 1 : w.axial_force <= -limits.max_force ? -1 : 0;
  s.rotation = w.axial_torque >= limits.max_torque    ? 1
               : w.axial_torque <= -limits.max_torque ? -1
                                                      : 0;
  return s;
}

int commandedSense(DriveCommand::Mode mode, double command, double current) {
  const double move = mode == DriveCommand::Mode::kVelocity ? command : command - current;
  return move > 0.0 ? 1 : move < 0.0 ? -1 : 0;
}

void addValveFriction(const DriveSpec& spec, const Introducer& introducer,
                      const DriveReading& before, const DeviceState& now,
                      const DriveCommand& command, const DriveStall& stalled, DriveWrench* w) {
  if (now.released) return;
  const Vec3 axis = introducer.frame.col(0);
  auto sense = [](double moved, int stalled_sense, int commanded) {
    if (moved != 0.0) return moved > 0.0 ? 1 : -1;
    return stalled_sense != 0 && stalled_sense == commanded ? commanded : 0;
  };
  const int in = sense(now.inserted_length - before.inserted, stalled.insertion,
                       commandedSense(command.mode, command.insertion, now.inserted_length));
  const int turn = sense(now.rotation_angle - before.angle, stalled.rotation,
                         commandedSense(command.mode, command.rotation, now.rotation_angle));
  const double f = in * spec.valve_friction, m = turn * spec.valve_torque;
  w->axial_force += f;
  w->force += f * axis;
  w->axial_torque += m;
  w->moment += m * axis;
}

void measureForcesSince(const SceneModel& model, SimData* data,
                        const std::vector<DriveReading>* before) {
  const size_t n = model.devices.size();
  data->drives.resize(n);
  data->stalls.resize(n);
  data->stall_noticed.resize(n, -std::numeric_limits<double>::infinity());
  data->tip_forces.assign(n, Vec3::Zero());
  for (size_t i = 0; i < n; ++i) {
    data->drives[i] = driveWrench(model.devices[i], model.introducers[i], data->devices[i]);
    if (i >= model.drive_specs.size()) continue;
    if (before && i < data->commands.size())
      addValveFriction(model.drive_specs[i], model.introducers[i], (*before)[i], data->devices[i],
                       data->commands[i], data->stalls[i], &data->drives[i]);
    data->stalls[i] = stallOf(data->drives[i], model.drive_specs[i]);
    noteStall(model, i, data);
  }
  auto atTip = [&](int device, const SamplePoint& s) {
    const DeviceModel& d = model.devices[device];
    return materialCoordinate(d, s) >= d.length - kTipLength;
  };
  for (const Contact& c : data->contacts) {
    const Vec3 f = c.force * c.normal + c.friction;  // on c.device's point
    if (atTip(c.device, contactPointOf(c, model.samples))) data->tip_forces[c.device] += f;
    if (c.other_device >= 0 && !c.lumen && atTip(c.other_device, c.other))
      data->tip_forces[c.other_device] -= f;
  }
}

void measureForces(const SceneModel& model, SimData* data) {
  measureForcesSince(model, data, nullptr);
}

}  // namespace evsim
