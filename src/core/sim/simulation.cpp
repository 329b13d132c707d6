#include "endovascular_sim/sim/simulation.h"

#include <algorithm>
#include <chrono>

namespace evsim {
namespace {

using Clock = std::chrono::steady_clock;

void applyScript(const SceneModel& model, SimData* data) {
  while (data->next_script_entry < model.script.size() &&
         model.script[data->next_script_entry].time <= data->time + 1e-12) {
    const ScriptedCommand& c = model.script[data->next_script_entry++];
    data->commands[c.device] = c.command;
  }
}

/// Detection without response (until contacts are resolved): device nodes
/// past the collision surface, and the deepest, -g / |grad g| [m].
void measurePenetration(const SceneModel& model, const std::vector<DeviceState>& devices, double t,
                        StepStats* stats) {
  const MotionSnapshot motion =
      model.effects.vessel_motion ? model.vessels->motionAt(t) : MotionSnapshot{};
  for (size_t i = 0; i < devices.size(); ++i) {
    const DeviceModel& dm = model.devices[i];
    const int first = lastHeldNode(dm, devices[i].inserted_length) + 1;
    for (int n = first; n < dm.num_nodes; ++n) {
      const FieldSample g =
          model.vessels->evaluate(devices[i].position[n], dm.node_radius[n], motion);
      if (g.value >= 0.0) continue;
      ++stats->contacts;
      const double depth = g.gradient.norm() > 0 ? -g.value / g.gradient.norm() : 0.0;
      stats->max_penetration_m = std::max(stats->max_penetration_m, depth);
    }
  }
}

}  // namespace

SceneModel buildSceneModel(const SceneSpec& spec) {
  SceneModel m;
  m.name = spec.name;
  m.file = spec.file;
  m.time_step = spec.time_step;
  for (const auto& e : spec.effects)
    if (e == "gravity")
      m.effects.gravity = true;
    else if (e == "vessel_motion")
      m.effects.vessel_motion = true;
  if (m.effects.gravity) m.gravity = spec.gravity;
  if (spec.vessels.present)
    m.vessels = std::make_shared<const VesselField>(
        buildVesselField(spec.vessels, m.effects.vessel_motion));
  for (const auto& d : spec.devices) {
    m.devices.push_back(buildDeviceModel(d.device));
    m.introducers.push_back(d.introducer);
    m.initial_inserted_length.push_back(d.inserted_length);
    m.initial_rotation.push_back(d.rotation);
  }
  m.script = spec.script;
  return m;
}

SceneModel loadScene(const std::string& name_or_path) {
  return buildSceneModel(loadSceneFile(resolveScenePath(name_or_path)));
}

SimData makeData(const SceneModel& model) {
  SimData d;
  const size_t n = model.devices.size();
  for (size_t i = 0; i < n; ++i)
    d.devices.push_back(placeDevice(model.devices[i], model.introducers[i],
                                    model.initial_inserted_length[i], model.initial_rotation[i]));
  d.commands.assign(n, DriveCommand{});
  d.workspaces = std::vector<DeviceWorkspace>(n);
  return d;
}

int findDevice(const SceneModel& model, const std::string& name) {
  for (size_t i = 0; i < model.devices.size(); ++i)
    if (model.devices[i].name == name) return static_cast<int>(i);
  return -1;
}

std::string setCommand(const SceneModel& model, SimData* data, const std::string& device,
                       const DriveCommand& command) {
  const int i = findDevice(model, device);
  if (i < 0) return "unknown device '" + device + "'";
  std::string why = validateDriveCommand(command, model.devices[i]);
  if (why.empty()) data->commands[i] = command;
  return why;
}

StepStatus step(const SceneModel& model, SimData* data) {
  const auto t0 = Clock::now();
  const double dt = model.time_step;
  data->stats = StepStats{};
  applyScript(model, data);

  // Free motion of every device from the state at the start of the step.
  std::vector<DeviceState> next = data->devices;
  for (size_t i = 0; i < model.devices.size(); ++i) {
    advanceDrive(data->commands[i], model.devices[i], dt, &next[i]);
    FreeMotionTimes t;
    if (!computeFreeMotion(model.devices[i], model.introducers[i], model.gravity, dt, next[i],
                           &data->workspaces[i], &t)) {
      data->last_error = "device '" + model.devices[i].name +
                         "': the system matrix is not positive definite or the solve diverged";
      return StepStatus::kSolverFailure;
    }
    data->stats.assembly_ms += t.assembly_ms;
    data->stats.factorization_ms += t.factorization_ms;
    data->stats.solve_ms += t.solve_ms;
  }

  for (size_t i = 0; i < model.devices.size(); ++i)
    commitMotion(data->workspaces[i].dq, dt, &next[i]);
  if (model.vessels) measurePenetration(model, next, data->time + dt, &data->stats);
  data->devices.swap(next);
  data->time += dt;
  ++data->step;
  data->stats.wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  return StepStatus::kOk;
}

}  // namespace evsim
