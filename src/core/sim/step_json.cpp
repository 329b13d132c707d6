// One JSON object per simulation step. Declared and documented in
// endovascular_sim/sim/step_json.h.
#include "endovascular_sim/sim/step_json.h"

#include <cstdio>
#include <sstream>

namespace evsim {
namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  return buf;
}

}  // namespace

std::string stepJson(const SceneModel& model, const SimData& data) {
  const StepStats& s = data.stats;
  std::ostringstream o;
  o << "{\"step\":" << data.step << ",\"t\":" << num(data.time) << ",\"wall_ms\":" << num(s.wall_ms)
    << ",\"assembly_ms\":" << num(s.assembly_ms)
    << ",\"factorization_ms\":" << num(s.factorization_ms) << ",\"solve_ms\":" << num(s.solve_ms)
    << ",\"detection_ms\":" << num(s.detection_ms) << ",\"delassus_ms\":" << num(s.delassus_ms)
    << ",\"lcp_ms\":" << num(s.lcp_ms) << ",\"correction_ms\":" << num(s.correction_ms)
    << ",\"vessel_motion_ms\":" << num(s.vessel_motion_ms)
    << ",\"device_contact_ms\":" << num(s.device_contact_ms)
    << ",\"coaxial_ms\":" << num(s.coaxial_ms) << ",\"contacts\":" << s.contacts
    << ",\"active_contacts\":" << s.active_contacts
    << ",\"activation_loops\":" << s.activation_loops << ",\"lcp_iterations\":" << s.lcp_iterations
    << ",\"lcp_residual\":" << num(s.lcp_residual) << ",\"subdivisions\":" << s.subdivisions
    << ",\"max_penetration_m\":" << num(s.max_penetration_m) << ",\"tunnels\":" << s.tunnels
    << ",\"on_demand_loops\":" << s.on_demand_loops << ",\"first_rows\":" << s.first_rows
    << ",\"kept_rows\":" << s.kept_rows << ",\"slid_forces\":" << s.slid_forces
    << ",\"late_rows\":{\"wall\":" << s.late_rows.wall << ",\"pair\":" << s.late_rows.pair
    << ",\"lumen\":" << s.late_rows.lumen << "}"
    << ",\"asleep\":" << (s.asleep ? "true" : "false") << ",\"devices\":[";
  for (size_t i = 0; i < model.devices.size(); ++i) {
    const DeviceState& d = data.devices[i];
    const Vec3& tip = d.position.back();
    o << (i ? "," : "") << "{\"name\":\"" << model.devices[i].name << "\",\"tip\":[" << num(tip.x())
      << "," << num(tip.y()) << "," << num(tip.z()) << "],\"inserted_m\":" << num(d.inserted_length)
      << ",\"rotation_rad\":" << num(d.rotation_angle)
      << ",\"kinetic_energy_J\":" << num(kineticEnergy(model.devices[i], d));
    if (i < data.drives.size()) {
      const Vec3& f = data.tip_forces[i];
      o << ",\"drive_force_N\":" << num(data.drives[i].axial_force)
        << ",\"drive_torque_Nm\":" << num(data.drives[i].axial_torque) << ",\"tip_force_N\":["
        << num(f.x()) << "," << num(f.y()) << "," << num(f.z()) << "]";
    }
    if (i < data.stalls.size())
      o << ",\"drive_stalled\":" << (data.stalls[i].against_command ? "true" : "false");
    if (model.atlas && i < data.tips.size()) {
      const VesselLocation& where = data.tips[i];
      o << ",\"tip_vessel\":\"" << model.atlas->vessels()[where.vessel].name
        << "\",\"tip_depth_m\":" << num(where.depth)
        << ",\"tip_in_lumen\":" << (where.inside ? "true" : "false");
    }
    o << "}";
  }
  o << "]";
  if (!model.targets.empty()) {
    o << ",\"targets\":[";
    for (size_t k = 0; k < model.targets.size(); ++k) {
      const TargetProgress p = k < data.targets.size() ? data.targets[k] : TargetProgress{};
      const TargetSpec& spec = model.targets[k].spec;
      o << (k ? "," : "") << "{";
      if (spec.aneurysm >= 0)
        o << "\"aneurysm\":" << spec.aneurysm;
      else
        o << "\"vessel\":\"" << spec.vessel << "\"";
      o << ",\"reached\":" << (p.reached ? "true" : "false")
        << ",\"reached_time\":" << num(p.reached_time);
      if (spec.aneurysm >= 0)
        o << ",\"best_inside\":" << num(p.best_inside) << "}";
      else
        o << ",\"best_depth_m\":" << num(p.best_depth) << "}";
    }
    o << "]";
  }
  o << "}";
  return o.str();
}

}  // namespace evsim
