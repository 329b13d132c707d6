// One JSON object per simulation step. Declared and documented in
// endovascular_sim/sim/step_json.h. Written by nlohmann/json (Debian's
// nlohmann-json3-dev): strings escaped whatever they hold, numbers in the
// shortest form that reads back to the same double, NaN as null.
#include "endovascular_sim/sim/step_json.h"

#include <nlohmann/json.hpp>

namespace evsim {

using Json = nlohmann::ordered_json;

namespace {

Json xyz(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json deviceJson(const SceneModel& model, const SimData& data, size_t i) {
  const DeviceState& d = data.devices[i];
  Json o;
  o["name"] = model.devices[i].name;
  o["tip"] = xyz(d.position.back());
  o["inserted_m"] = d.inserted_length;
  o["rotation_rad"] = d.rotation_angle;
  o["kinetic_energy_J"] = kineticEnergy(model.devices[i], d);
  if (i < data.drives.size()) {
    o["drive_force_N"] = data.drives[i].axial_force;
    o["drive_torque_Nm"] = data.drives[i].axial_torque;
    o["tip_force_N"] = xyz(data.tip_forces[i]);
  }
  if (i < data.stalls.size()) o["drive_stalled"] = data.stalls[i].against_command;
  if (model.atlas && i < data.tips.size()) {
    const VesselLocation& where = data.tips[i];
    o["tip_vessel"] = model.atlas->vessels()[where.vessel].name;
    o["tip_depth_m"] = where.depth;
    o["tip_in_lumen"] = where.inside;
  }
  return o;
}

Json targetJson(const Target& target, const TargetProgress& p) {
  const TargetSpec& spec = target.spec;
  Json o;
  if (spec.aneurysm >= 0)
    o["aneurysm"] = spec.aneurysm;
  else
    o["vessel"] = spec.vessel;
  o["reached"] = p.reached;
  o["reached_time"] = p.reached_time;
  if (spec.aneurysm >= 0)
    o["best_inside"] = p.best_inside;
  else
    o["best_depth_m"] = p.best_depth;
  return o;
}

}  // namespace

std::string jsonLine(const Json& object) {
  // Invalid UTF-8 in a name (a file's bytes) is replaced, never thrown.
  return object.dump(-1, ' ', false, Json::error_handler_t::replace);
}

std::string stepJson(const SceneModel& model, const SimData& data) {
  const StepStats& s = data.stats;
  Json o;
  o["step"] = data.step;
  o["t"] = data.time;
  o["wall_ms"] = s.wall_ms;
  o["assembly_ms"] = s.assembly_ms;
  o["factorization_ms"] = s.factorization_ms;
  o["solve_ms"] = s.solve_ms;
  o["detection_ms"] = s.detection_ms;
  o["delassus_ms"] = s.delassus_ms;
  o["lcp_ms"] = s.lcp_ms;
  o["correction_ms"] = s.correction_ms;
  o["curvature_ms"] = s.curvature_ms;
  o["vessel_motion_ms"] = s.vessel_motion_ms;
  o["device_contact_ms"] = s.device_contact_ms;
  o["coaxial_ms"] = s.coaxial_ms;
  o["contacts"] = s.contacts;
  o["active_contacts"] = s.active_contacts;
  o["activation_loops"] = s.activation_loops;
  o["lcp_iterations"] = s.lcp_iterations;
  o["lcp_residual"] = s.lcp_residual;
  o["subdivisions"] = s.subdivisions;
  o["max_penetration_m"] = s.max_penetration_m;
  o["tunnels"] = s.tunnels;
  o["on_demand_loops"] = s.on_demand_loops;
  o["first_rows"] = s.first_rows;
  o["kept_rows"] = s.kept_rows;
  o["slid_forces"] = s.slid_forces;
  o["late_rows"] = {
      {"wall", s.late_rows.wall}, {"pair", s.late_rows.pair}, {"lumen", s.late_rows.lumen}};
  o["asleep"] = s.asleep;
  Json devices = Json::array();
  for (size_t i = 0; i < model.devices.size(); ++i) devices.push_back(deviceJson(model, data, i));
  o["devices"] = std::move(devices);
  if (!model.targets.empty()) {
    Json targets = Json::array();
    for (size_t k = 0; k < model.targets.size(); ++k)
      targets.push_back(targetJson(model.targets[k],
                                   k < data.targets.size() ? data.targets[k] : TargetProgress{}));
    o["targets"] = std::move(targets);
  }
  return jsonLine(o);
}

std::string autopilotJson(const SceneModel& model, const SimData& data, int target, int device,
                          const AutopilotReport& report) {
  const VesselAtlas& atlas = *model.atlas;
  Json o;
  o["scene"] = model.name;
  o["target"] = atlas.vessels()[target].name;
  o["device"] = model.devices[device].name;
  o["reached"] = report.reached;
  o["reason"] = report.reason;
  o["time_s"] = report.time;
  o["retries"] = report.retries;
  o["peak_wall_force_N"] = report.peak_wall_force;
  o["failed_steps"] = report.failed_steps;
  o["remaining_path_m"] = report.remaining_path;
  const int at = data.tips[device].vessel;
  o["final_vessel"] = at >= 0 ? atlas.vessels()[at].name : "";
  return jsonLine(o);
}

}  // namespace evsim
