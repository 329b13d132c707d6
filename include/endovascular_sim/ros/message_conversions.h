// Core types to ROS messages (geometry, stats, contacts, device states, paths).
#pragma once

#include <geometry_msgs/Point.h>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Quaternion.h>
#include <geometry_msgs/Vector3.h>
#include <nav_msgs/Path.h>
#include <std_msgs/Header.h>

#include "endovascular_sim/ContactArray.h"
#include "endovascular_sim/DeviceStatusArray.h"
#include "endovascular_sim/StepStats.h"
#include "endovascular_sim/ros/frame_snapshot.h"

namespace evsim {

geometry_msgs::Point toPoint(const Vec3& p);
geometry_msgs::Vector3 toVector3(const Vec3& v);
geometry_msgs::Quaternion toQuaternion(const Quat& q);
geometry_msgs::Pose toPose(const Vec3& p, const Quat& q);

/// refused_commands: malformed commands the node refused since it started.
endovascular_sim::StepStats toStepStatsMsg(const FrameSnapshot& frame, const LoopTiming& timing,
                                           long refused_commands, const std_msgs::Header& header);
endovascular_sim::ContactArray toContactArrayMsg(const FrameSnapshot& frame,
                                                 const std_msgs::Header& header);
/// driven: index of the device the joystick drives.
endovascular_sim::DeviceStatusArray toDeviceStatusMsg(const FrameSnapshot& frame, int driven,
                                                      const std_msgs::Header& header);
/// The node poses of one device, proximal to distal; after a detach, up to
/// the cut only (the pusher: nodes 0 ... cut_element).
nav_msgs::Path toPathMsg(const DeviceState& device, const std_msgs::Header& header);
/// After a detach, the detached part's node poses (cut_element + 1 ... the
/// tip); before it, an empty path.
nav_msgs::Path toDetachedPathMsg(const DeviceState& device, const std_msgs::Header& header);

}  // namespace evsim
