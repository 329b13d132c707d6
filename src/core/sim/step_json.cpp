// One JSON object per simulation step. Declared and documented in
// endovascular_sim/sim/step_json.h. Written by nlohmann/json (Debian's
// nlohmann-json3-dev): strings escaped whatever they hold, numbers in the
// shortest form that reads back to the same double, NaN as null.
#include "endovascular_sim/sim/step_json.h"

#include <algorithm>
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
  o["assembly_ms"] = s.free_motion.assembly_ms;
  o["factorization_ms"] = s.free_motion.factorization_ms;
  o["solve_ms"] = s.free_motion.solve_ms;
  const ContactTimes& t = s.contact.times;
  o["detection_ms"] = t.detection_ms;
  o["delassus_ms"] = t.delassus_ms;
  o["lcp_ms"] = t.lcp_ms;
  o["correction_ms"] = t.correction_ms;
  o["curvature_ms"] = t.curvature_ms;
  o["vessel_motion_ms"] = s.vessel_motion_ms;
  o["other_ms"] = s.other_ms;
  o["device_contact_ms"] = t.device_contact_ms;
  o["coaxial_ms"] = t.coaxial_ms;
  const ContactStats& c = s.contact;
  o["contacts"] = c.contacts;
  o["active_contacts"] = c.active_contacts;
  o["sliding_contacts"] = c.sliding_contacts;
  o["activation_loops"] = c.activation_loops;
  o["lcp_iterations"] = c.lcp_iterations;
  o["lcp_residual"] = c.lcp_residual;
  o["subdivisions"] = s.subdivisions;
  o["max_penetration_m"] = c.max_penetration_m;
  o["tunnels"] = c.tunnels;
  o["on_demand_loops"] = c.on_demand_loops;
  o["first_rows"] = c.first_rows;
  o["kept_rows"] = c.kept_rows;
  o["slid_forces"] = c.slid_forces;
  o["late_rows"] = {
      {"wall", c.late_rows.wall}, {"pair", c.late_rows.pair}, {"lumen", c.late_rows.lumen}};
  o["asleep"] = s.asleep;
  if (model.wall) {  // effect 'vessel_deformation'
    double moved = 0.0, widened = 0.0;
    if (data.wall)
      for (size_t i = 0; i < data.wall->displacement.size(); ++i) {
        moved = std::max(moved, data.wall->displacement[i].norm());
        widened = std::max(widened, data.wall->radius_change[i]);
      }
    o["wall_max_displacement_m"] = moved;
    o["wall_max_widening_m"] = widened;
  }
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
