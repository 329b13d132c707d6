// Everything the node publishes for a frame, stamped with the simulation's
// clock: the wall time at the node's start plus the simulated time, carried
// on without a jump backwards across resets and scene switches. Like
// Gazebo, the node publishes that clock on /clock (~publish_clock), so that
// nodes with /use_sim_time (rviz in navigation_rviz.launch) follow the
// simulation however far it falls behind real time:
//   /clock                        rosgraph_msgs/Clock, every frame that advanced
//   stats                         endovascular_sim/StepStats
//   contacts                      endovascular_sim/ContactArray
//   device_states                 endovascular_sim/DeviceStatusArray
//   devices/<name>/path           nav_msgs/Path (node poses)
//   markers                       visualization_msgs/MarkerArray
//   vessels                       visualization_msgs/Marker, sent to each new subscriber
//                                 (republished when the vessels move)
//   tf                            <name>/tip and <name>/access under frame_id
//   /diagnostics                  loop rate, real-time factor, overruns (every second)
#pragma once

#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>
#include <visualization_msgs/Marker.h>

#include <memory>
#include <string>
#include <vector>

#include "endovascular_sim/geometry/surface_mesh.h"
#include "endovascular_sim/ros/frame_snapshot.h"
#include "endovascular_sim/ros/scene_markers.h"

namespace evsim {

class FramePublisher {
 public:
  /// publish_clock: send /clock (off when another simulator owns it).
  FramePublisher(ros::NodeHandle nh, std::string frame_id, MarkerStyle style,
                 double vessel_mesh_period_s, bool publish_clock);

  /// A new scene: per-device topics, the vessel mesh (may be null); its
  /// simulated time 0 is stamped just after the last stamp (restartClock).
  void setScene(const SceneModel& model, std::shared_ptr<const SurfaceMesh> mesh);
  /// Simulated time 0 (a reset) is stamped just after the last stamp: the
  /// clock never runs backwards.
  void restartClock();
  /// The clock at simulated time t of the current scene.
  ros::Time clockAt(double t) const { return epoch_ + ros::Duration(t); }

  /// refused_commands: malformed commands refused since the node started.
  void publish(const FrameSnapshot& frame, const LoopTiming& timing, int driven_device,
               long refused_commands);
  /// Every step's drive wrench on devices/NAME/drive_wrench, stamped with
  /// its step's time (the simulation's rate, in bursts of a frame).
  void publishWrenches(const std::vector<std::vector<WrenchSample>>& samples);
  /// One DiagnosticStatus for the loop: OK, WARN when frames overran or the
  /// real-time factor fell below 0.9 since the last call, ERROR after a
  /// rejected step; with the count of refused commands.
  void publishDiagnostics(const FrameSnapshot& frame, const LoopTiming& timing,
                          double publish_rate_hz, const std::string& last_error,
                          long refused_commands);

 private:
  void publishTransforms(const FrameSnapshot& frame, const std_msgs::Header& header);
  void publishVesselMesh(const FrameSnapshot& frame, const std_msgs::Header& header);
  /// The last vessels message to one new subscriber (vessels_pub_'s connect callback).
  void sendVesselMesh(const ros::SingleSubscriberPublisher& subscriber) const;

  ros::NodeHandle nh_;
  std::string frame_id_;
  MarkerStyle style_;
  double vessel_mesh_period_s_;
  ros::Time epoch_;
  ros::Publisher stats_pub_, contacts_pub_, states_pub_, markers_pub_, vessels_pub_,
      diagnostics_pub_, clock_pub_;
  ros::Time last_clock_;  // the last stamp sent
  std::vector<ros::Publisher> path_pubs_;
  std::vector<ros::Publisher> wrench_pubs_;         // devices/NAME/drive_wrench
  std::vector<ros::Publisher> detached_path_pubs_;  // empty publisher: the device cannot detach
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  std::shared_ptr<const SurfaceMesh> mesh_;
  // The last vessels message: the mesh, or DELETE for a scene without
  // vessels (null: the scene's mesh is not published yet).
  visualization_msgs::MarkerConstPtr vessels_msg_;
  double last_mesh_time_{-1.0};  // simulated time of the last published mesh [s]
  double last_tf_time_{-1.0};    // tf is sent only when simulated time advanced
  long last_overruns_{0};
};

}  // namespace evsim
