// Core types to ROS messages (geometry, stats, contacts, device states,
// paths). Declared and documented in
// endovascular_sim/ros/message_conversions.h.
#include "endovascular_sim/ros/message_conversions.h"

#include <algorithm>

namespace evsim {

namespace {

/// Any message with x, y, z fields.
template <typename Xyz>
Xyz toXyz(const Vec3& v) {
  Xyz m;
  m.x = v.x();
  m.y = v.y();
  m.z = v.z();
  return m;
}

}  // namespace

geometry_msgs::Point toPoint(const Vec3& p) { return toXyz<geometry_msgs::Point>(p); }

geometry_msgs::Vector3 toVector3(const Vec3& v) { return toXyz<geometry_msgs::Vector3>(v); }

geometry_msgs::Quaternion toQuaternion(const Quat& q) {
  geometry_msgs::Quaternion m;
  m.w = q.w();
  m.x = q.x();
  m.y = q.y();
  m.z = q.z();
  return m;
}

geometry_msgs::Pose toPose(const Vec3& p, const Quat& q) {
  geometry_msgs::Pose m;
  m.position = toPoint(p);
  m.orientation = toQuaternion(q);
  return m;
}

endovascular_sim::StepStats toStepStatsMsg(const FrameSnapshot& f, const LoopTiming& timing,
                                           long refused_commands, const std_msgs::Header& header) {
  const StepStats& s = f.stats;
  endovascular_sim::StepStats m;
  m.header = header;
  m.scene = f.model->name;
  m.step = static_cast<uint32_t>(f.step);
  m.sim_time = f.time;
  m.paused = f.paused;
  m.wall_time_ms = s.wall_ms;
  m.assembly_ms = s.free_motion.assembly_ms;
  m.factorization_ms = s.free_motion.factorization_ms;
  m.solve_ms = s.free_motion.solve_ms;
  const ContactTimes& t = s.contact.times;
  m.detection_ms = t.detection_ms;
  m.delassus_ms = t.delassus_ms;
  m.lcp_ms = t.lcp_ms;
  m.correction_ms = t.correction_ms;
  m.curvature_ms = t.curvature_ms;
  m.vessel_motion_ms = s.vessel_motion_ms;
  m.other_ms = s.other_ms;
  m.device_contact_ms = t.device_contact_ms;
  m.coaxial_ms = t.coaxial_ms;
  const ContactStats& c = s.contact;
  m.contacts = static_cast<uint32_t>(c.contacts);
  m.active_contacts = static_cast<uint32_t>(c.active_contacts);
  m.activation_loops = static_cast<uint32_t>(c.activation_loops);
  m.lcp_iterations = static_cast<uint32_t>(c.lcp_iterations);
  m.lcp_residual = c.lcp_residual;
  m.subdivisions = static_cast<uint32_t>(s.subdivisions);
  m.asleep = s.asleep;
  for (const DriveStall& stall : f.stalls) m.stalled_drives += stall.against_command ? 1 : 0;
  m.max_penetration = c.max_penetration_m;
  m.steps_per_frame = static_cast<uint32_t>(timing.steps_per_frame);
  m.frame_ms = timing.frame_ms;
  m.real_time_factor = timing.real_time_factor;
  m.refused_commands = static_cast<uint32_t>(refused_commands);
  return m;
}

endovascular_sim::ContactArray toContactArrayMsg(const FrameSnapshot& f,
                                                 const std_msgs::Header& header) {
  endovascular_sim::ContactArray m;
  m.header = header;
  m.contacts.reserve(f.contacts.size());
  for (const Contact& c : f.contacts) {
    endovascular_sim::Contact mc;
    mc.device = f.model->devices[c.device].name;
    mc.sample = static_cast<uint32_t>(c.sample);
    if (c.other_device >= 0) mc.other_device = f.model->devices[c.other_device].name;
    mc.point = toPoint(c.point);
    mc.normal = toVector3(c.normal);
    mc.force = c.force;
    mc.friction = toVector3(c.friction);
    mc.lumen = c.lumen;
    mc.gap = c.gap;
    m.contacts.push_back(mc);
  }
  return m;
}

endovascular_sim::DeviceStatusArray toDeviceStatusMsg(const FrameSnapshot& f, int driven,
                                                      const std_msgs::Header& header) {
  endovascular_sim::DeviceStatusArray m;
  m.header = header;
  for (size_t i = 0; i < f.devices.size(); ++i) {
    const DeviceState& d = f.devices[i];
    endovascular_sim::DeviceStatus s;
    s.name = f.model->devices[i].name;
    s.inserted_length = d.inserted_length;
    s.rotation = d.rotation_angle;
    s.tip = toPose(d.position.back(), d.rotation.back());
    s.released = d.released;
    s.driven = static_cast<int>(i) == driven;
    if (i < f.drives.size()) {
      s.drive_force = f.drives[i].axial_force;
      s.drive_torque = f.drives[i].axial_torque;
      s.tip_force.x = f.tip_forces[i].x();
      s.tip_force.y = f.tip_forces[i].y();
      s.tip_force.z = f.tip_forces[i].z();
    }
    if (i < f.stalls.size()) s.drive_stalled = f.stalls[i].against_command;
    if (f.model->atlas && i < f.tips.size() && f.tips[i].vessel >= 0) {
      s.tip_vessel = f.model->atlas->vessels()[f.tips[i].vessel].name;
      s.tip_depth = f.tips[i].depth;
      s.tip_in_lumen = f.tips[i].inside;
    }
    m.devices.push_back(s);
  }
  return m;
}

namespace {

/// Nodes [first, last) of a device as a path.
nav_msgs::Path pathOfNodes(const DeviceState& device, size_t first, size_t last,
                           const std_msgs::Header& header) {
  nav_msgs::Path path;
  path.header = header;
  for (size_t n = first; n < last; ++n) {
    path.poses.emplace_back();
    path.poses.back().header = header;
    path.poses.back().pose = toPose(device.position[n], device.rotation[n]);
  }
  return path;
}

}  // namespace

nav_msgs::Path toPathMsg(const DeviceState& device, const std_msgs::Header& header) {
  const size_t nodes = device.position.size();
  const size_t end = device.cut_element >= 0 ? static_cast<size_t>(device.cut_element) + 1 : nodes;
  return pathOfNodes(device, 0, std::min(end, nodes), header);
}

nav_msgs::Path toDetachedPathMsg(const DeviceState& device, const std_msgs::Header& header) {
  const size_t nodes = device.position.size();
  const size_t first =
      device.cut_element >= 0 ? static_cast<size_t>(device.cut_element) + 1 : nodes;
  return pathOfNodes(device, std::min(first, nodes), nodes, header);
}

}  // namespace evsim
