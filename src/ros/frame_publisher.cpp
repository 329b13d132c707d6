// Everything the node publishes for a frame, stamped with the simulation's
// clock: the wall time at the node's start plus the simulated time, carried on
// without a jump backwards across resets and scene switches. Declared and
// documented in endovascular_sim/ros/frame_publisher.h.
#include "endovascular_sim/ros/frame_publisher.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <rosgraph_msgs/Clock.h>

#include <boost/make_shared.hpp>
#include <sstream>

#include "endovascular_sim/ros/message_conversions.h"

namespace evsim {
namespace {

geometry_msgs::TransformStamped transform(const std_msgs::Header& header, const std::string& child,
                                          const Vec3& p, const Quat& q) {
  geometry_msgs::TransformStamped t;
  t.header = header;
  t.child_frame_id = child;
  t.transform.translation = toVector3(p);
  t.transform.rotation = toQuaternion(q);
  return t;
}

diagnostic_msgs::KeyValue keyValue(const std::string& key, double value) {
  diagnostic_msgs::KeyValue kv;
  kv.key = key;
  std::ostringstream s;
  s << value;
  kv.value = s.str();
  return kv;
}

}  // namespace

FramePublisher::FramePublisher(ros::NodeHandle nh, std::string frame_id, MarkerStyle style,
                               double vessel_mesh_period_s, bool publish_clock)
    : nh_(nh),
      frame_id_(std::move(frame_id)),
      style_(style),
      vessel_mesh_period_s_(vessel_mesh_period_s) {
  const ros::WallTime start = ros::WallTime::now();  // (ros::Time may follow /clock)
  epoch_ = ros::Time(start.sec, start.nsec);
  last_clock_ = epoch_;
  if (publish_clock) clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  stats_pub_ = nh_.advertise<endovascular_sim::StepStats>("stats", 10);
  contacts_pub_ = nh_.advertise<endovascular_sim::ContactArray>("contacts", 10);
  states_pub_ = nh_.advertise<endovascular_sim::DeviceStatusArray>("device_states", 10);
  markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("markers", 10);
  // Not latched: roscpp's latch can miss a subscriber whose connection
  // completes while the mesh is being published (Publisher::publish stores
  // the latched message only after queueing it, and the poll thread may add
  // the new link in between: the `vessels` check of rate.test waited 120 s in
  // vain in CI). Each new subscriber gets the last mesh from the connect
  // callback instead, sent on its own link.
  vessels_pub_ = nh_.advertise<visualization_msgs::Marker>(
      "vessels", 1, [this](const ros::SingleSubscriberPublisher& s) { sendVesselMesh(s); });
  diagnostics_pub_ = nh_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
}

void FramePublisher::restartClock() { epoch_ = last_clock_ + ros::Duration(0, 1000); }

void FramePublisher::setScene(const SceneModel& model, std::shared_ptr<const SurfaceMesh> mesh) {
  restartClock();
  path_pubs_.clear();
  detached_path_pubs_.clear();
  wrench_pubs_.clear();
  for (const DeviceModel& d : model.devices) {
    path_pubs_.push_back(nh_.advertise<nav_msgs::Path>("devices/" + d.name + "/path", 1));
    wrench_pubs_.push_back(
        nh_.advertise<geometry_msgs::WrenchStamped>("devices/" + d.name + "/drive_wrench", 200));
    // A device that can detach (a coil on its pusher): the detached part's
    // own path, empty until the detach.
    detached_path_pubs_.push_back(
        d.detach_element >= 0
            ? nh_.advertise<nav_msgs::Path>("devices/" + d.name + "/detached_path", 1)
            : ros::Publisher());
  }
  mesh_ = std::move(mesh);
  vessels_msg_.reset();  // a subscriber arriving now waits for the new scene's mesh
  last_mesh_time_ = -1.0;
  last_tf_time_ = -1.0;
  if (!mesh_) {  // a scene without vessels: clear what a previous scene showed
    auto clear = boost::make_shared<visualization_msgs::Marker>();
    clear->header.frame_id = frame_id_;
    clear->header.stamp = epoch_;
    clear->ns = "vessels";
    clear->action = visualization_msgs::Marker::DELETE;
    vessels_msg_ = clear;  // also to new subscribers: every scene says what its vessels are
    vessels_pub_.publish(vessels_msg_);
  }
}

void FramePublisher::publish(const FrameSnapshot& f, const LoopTiming& timing, int driven,
                             long refused_commands) {
  std_msgs::Header header;
  header.frame_id = frame_id_;
  header.stamp = clockAt(f.time);
  if (header.stamp > last_clock_) {
    last_clock_ = header.stamp;
    if (clock_pub_) {
      rosgraph_msgs::Clock clock;
      clock.clock = header.stamp;
      clock_pub_.publish(clock);
    }
  }
  stats_pub_.publish(toStepStatsMsg(f, timing, refused_commands, header));
  contacts_pub_.publish(toContactArrayMsg(f, header));
  states_pub_.publish(toDeviceStatusMsg(f, driven, header));
  for (size_t i = 0; i < path_pubs_.size() && i < f.devices.size(); ++i) {
    path_pubs_[i].publish(toPathMsg(f.devices[i], header));
    if (detached_path_pubs_[i])
      detached_path_pubs_[i].publish(toDetachedPathMsg(f.devices[i], header));
  }
  if (markers_pub_.getNumSubscribers() > 0) markers_pub_.publish(sceneMarkers(f, style_, header));
  publishTransforms(f, header);
  publishVesselMesh(f, header);
}

void FramePublisher::publishWrenches(const std::vector<std::vector<WrenchSample>>& samples) {
  for (size_t i = 0; i < samples.size() && i < wrench_pubs_.size(); ++i)
    for (const WrenchSample& s : samples[i]) {
      geometry_msgs::WrenchStamped w;
      w.header.frame_id = frame_id_;
      w.header.stamp = clockAt(s.time);
      w.wrench.force = toVector3(s.wrench.force);
      w.wrench.torque = toVector3(s.wrench.moment);
      wrench_pubs_[i].publish(w);
    }
}

void FramePublisher::publishTransforms(const FrameSnapshot& f, const std_msgs::Header& header) {
  if (f.time <= last_tf_time_) return;  // paused: tf2 refuses repeated stamps
  last_tf_time_ = f.time;
  std::vector<geometry_msgs::TransformStamped> transforms;
  for (size_t i = 0; i < f.devices.size(); ++i) {
    const std::string& name = f.model->devices[i].name;
    const DeviceState& d = f.devices[i];
    transforms.push_back(transform(header, name + "/tip", d.position.back(), d.rotation.back()));
    const Introducer& intro = f.model->introducers[i];
    const Quat access(intro.frame *
                      Eigen::AngleAxisd(d.rotation_angle, Vec3::UnitX()).toRotationMatrix());
    transforms.push_back(transform(header, name + "/access", intro.access_point, access));
  }
  tf_broadcaster_.sendTransform(transforms);
}

void FramePublisher::publishVesselMesh(const FrameSnapshot& f, const std_msgs::Header& header) {
  if (!mesh_) return;
  const bool moving = !f.motion.empty();
  if (last_mesh_time_ >= 0.0 && (!moving || f.time - last_mesh_time_ < vessel_mesh_period_s_))
    return;
  last_mesh_time_ = f.time;
  vessels_msg_ = boost::make_shared<const visualization_msgs::Marker>(
      vesselMeshMarker(*mesh_, f.model->vessels.get(), f.motion, header));
  vessels_pub_.publish(vessels_msg_);
}

void FramePublisher::sendVesselMesh(const ros::SingleSubscriberPublisher& subscriber) const {
  // Runs on the spinner thread like publishVesselMesh: a subscriber that
  // connected before the first mesh gets it from that publish instead.
  if (vessels_msg_) subscriber.publish(vessels_msg_);
}

void FramePublisher::publishDiagnostics(const FrameSnapshot& f, const LoopTiming& timing,
                                        double publish_rate_hz, const std::string& last_error,
                                        long refused_commands) {
  diagnostic_msgs::DiagnosticStatus s;
  s.name = ros::this_node::getName() + ": simulation loop";
  s.hardware_id = f.model->name;
  const long new_overruns = timing.overruns - last_overruns_;
  last_overruns_ = timing.overruns;
  if (!last_error.empty()) {
    s.level = diagnostic_msgs::DiagnosticStatus::ERROR;
    s.message = "step rejected (state kept): " + last_error;
  } else if (!f.paused && (new_overruns > 0 || timing.real_time_factor < 0.9)) {
    s.level = diagnostic_msgs::DiagnosticStatus::WARN;
    std::ostringstream m;
    m << "frames overrun: " << new_overruns << " in the last second, real-time factor "
      << timing.real_time_factor << " (the scene is heavier than real time at this rate)";
    s.message = m.str();
  } else {
    s.level = diagnostic_msgs::DiagnosticStatus::OK;
    s.message = f.paused         ? "paused"
                : f.stats.asleep ? "at rest: the scene sleeps until a command changes a drive"
                                 : "running in real time";
  }
  s.values.push_back(keyValue("publish rate [Hz]", publish_rate_hz));
  s.values.push_back(keyValue("steps per frame", timing.steps_per_frame));
  s.values.push_back(keyValue("frame wall time [ms]", timing.frame_ms));
  s.values.push_back(keyValue("real-time factor", timing.real_time_factor));
  s.values.push_back(keyValue("overruns (total)", static_cast<double>(timing.overruns)));
  s.values.push_back(keyValue("simulated time [s]", f.time));
  s.values.push_back(keyValue("contacts", f.stats.contact.contacts));
  s.values.push_back(keyValue("refused commands (total)", static_cast<double>(refused_commands)));
  for (size_t i = 0; f.model->atlas && i < f.tips.size(); ++i) {
    diagnostic_msgs::KeyValue kv;
    kv.key = f.model->devices[i].name + " tip in";
    std::ostringstream where;
    where << f.model->atlas->vessels()[f.tips[i].vessel].name << " at " << f.tips[i].depth * 1e3
          << " mm";
    kv.value = where.str();
    s.values.push_back(kv);
  }
  for (size_t k = 0; k < f.targets.size() && k < f.model->targets.size(); ++k) {
    diagnostic_msgs::KeyValue kv;
    kv.key = "target " + f.model->targets[k].spec.label();
    std::ostringstream state;
    if (f.targets[k].reached)
      state << "reached at t = " << f.targets[k].reached_time << " s";
    else if (f.model->targets[k].spec.aneurysm >= 0)
      state << "not reached (at most " << std::lround(100.0 * f.targets[k].best_inside)
            << " % of the coil inside)";
    else
      state << "not reached (deepest " << f.targets[k].best_depth * 1e3 << " mm)";
    kv.value = state.str();
    s.values.push_back(kv);
  }
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = last_clock_;
  array.status.push_back(s);
  diagnostics_pub_.publish(array);
}

}  // namespace evsim
