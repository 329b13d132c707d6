#include "endovascular_sim/ros/navigation_node.h"

#include <nav_msgs/Path.h>

#include <cmath>

#include "endovascular_sim/StepStats.h"
#include "endovascular_sim/core/load_error.h"

namespace evsim {

NavigationNode::NavigationNode(ros::NodeHandle nh, ros::NodeHandle private_nh)
    : nh_(nh), private_nh_(private_nh) {
  readParameters();
  std::string message;
  if (!loadSceneNamed(scene_name_, &message)) throw std::runtime_error(message);
  stats_pub_ = nh_.advertise<endovascular_sim::StepStats>("stats", 10);
  command_sub_ = nh_.subscribe("command", 10, &NavigationNode::onCommand, this);
  load_srv_ = nh_.advertiseService("load_scene", &NavigationNode::onLoadScene, this);
  list_srv_ = nh_.advertiseService("list_scenes", &NavigationNode::onListScenes, this);
  timer_ = nh_.createTimer(ros::Duration(1.0 / rate_hz_), &NavigationNode::onTimer, this);
}

void NavigationNode::readParameters() {
  private_nh_.param<std::string>("scene", scene_name_, "free_insertion");
  private_nh_.param<std::string>("frame_id", frame_id_, "world");
  private_nh_.param("rate", rate_hz_, 25.0);
  if (!std::isfinite(rate_hz_) || rate_hz_ <= 0.0 || rate_hz_ > 1000.0)
    throw std::runtime_error("parameter ~rate must lie in (0, 1000] Hz");
  if (frame_id_.empty()) throw std::runtime_error("parameter ~frame_id must not be empty");
}

bool NavigationNode::loadSceneNamed(const std::string& scene, std::string* message) {
  try {
    auto model = std::make_unique<SceneModel>(loadScene(scene));
    model_ = std::move(model);
  } catch (const LoadError& e) {
    *message = e.what();
    return false;  // the current scene keeps running
  }
  data_ = makeData(*model_);
  substeps_ = std::max(1, static_cast<int>(std::lround(1.0 / (rate_hz_ * model_->time_step))));
  path_pubs_.clear();
  for (const auto& d : model_->devices)
    path_pubs_.push_back(nh_.advertise<nav_msgs::Path>("devices/" + d.name + "/path", 1));
  *message = "loaded scene '" + model_->name + "' (" + std::to_string(model_->devices.size()) +
             " devices, " + std::to_string(substeps_) + " steps per frame)";
  ROS_INFO_STREAM(*message);
  return true;
}

void NavigationNode::onTimer(const ros::TimerEvent&) {
  for (int k = 0; k < substeps_; ++k) {
    if (step(*model_, &data_) != StepStatus::kOk) {
      ROS_WARN_STREAM_THROTTLE(1.0, "step rejected, state kept: " << data_.last_error);
      break;
    }
  }
  publish();
}

void NavigationNode::onCommand(const endovascular_sim::DeviceCommand& msg) {
  DriveCommand cmd;
  cmd.mode = msg.mode == endovascular_sim::DeviceCommand::POSITION ? DriveCommand::Mode::kPosition
                                                                   : DriveCommand::Mode::kVelocity;
  cmd.insertion = msg.insertion;
  cmd.rotation = msg.rotation;
  const std::string why = setCommand(*model_, &data_, msg.device, cmd);
  if (!why.empty()) ROS_WARN_STREAM("command refused: " << why);
}

bool NavigationNode::onLoadScene(endovascular_sim::LoadScene::Request& req,
                                 endovascular_sim::LoadScene::Response& res) {
  res.success = loadSceneNamed(req.scene, &res.message);
  return true;
}

bool NavigationNode::onListScenes(endovascular_sim::ListScenes::Request&,
                                  endovascular_sim::ListScenes::Response& res) {
  res.scenes = shippedScenes();
  return true;
}

void NavigationNode::publish() {
  const ros::Time stamp = ros::Time::now();
  endovascular_sim::StepStats s;
  s.header.stamp = stamp;
  s.header.frame_id = frame_id_;
  s.step = static_cast<uint32_t>(data_.step);
  s.sim_time = data_.time;
  s.wall_time_ms = data_.stats.wall_ms;
  s.assembly_ms = data_.stats.assembly_ms;
  s.factorization_ms = data_.stats.factorization_ms;
  s.solve_ms = data_.stats.solve_ms;
  s.contacts = data_.stats.contacts;
  s.max_penetration = data_.stats.max_penetration_m;
  s.real_time_factor = data_.stats.wall_ms > 0 ? model_->time_step * 1e3 / data_.stats.wall_ms : 0;
  stats_pub_.publish(s);
  for (size_t i = 0; i < path_pubs_.size(); ++i) {
    nav_msgs::Path path;
    path.header = s.header;
    const DeviceState& d = data_.devices[i];
    for (size_t n = 0; n < d.position.size(); ++n) {
      geometry_msgs::PoseStamped p;
      p.header = s.header;
      p.pose.position.x = d.position[n].x();
      p.pose.position.y = d.position[n].y();
      p.pose.position.z = d.position[n].z();
      p.pose.orientation.w = d.rotation[n].w();
      p.pose.orientation.x = d.rotation[n].x();
      p.pose.orientation.y = d.rotation[n].y();
      p.pose.orientation.z = d.rotation[n].z();
      path.poses.push_back(p);
    }
    path_pubs_[i].publish(path);
  }
}

}  // namespace evsim
