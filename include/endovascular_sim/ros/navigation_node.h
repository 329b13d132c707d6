// Thin ROS adapter of the core simulation: parameters, topics and services.
// No physics here.
#pragma once

#include <ros/ros.h>

#include <memory>
#include <string>

#include "endovascular_sim/DeviceCommand.h"
#include "endovascular_sim/ListScenes.h"
#include "endovascular_sim/LoadScene.h"
#include "endovascular_sim/sim/simulation.h"

namespace evsim {

class NavigationNode {
 public:
  /// Reads ~scene, ~rate [Hz], ~frame_id; throws std::runtime_error naming an
  /// invalid parameter.
  NavigationNode(ros::NodeHandle nh, ros::NodeHandle private_nh);

 private:
  void readParameters();
  bool loadSceneNamed(const std::string& scene, std::string* message);
  void onTimer(const ros::TimerEvent&);
  void onCommand(const endovascular_sim::DeviceCommand& msg);
  bool onLoadScene(endovascular_sim::LoadScene::Request& req,
                   endovascular_sim::LoadScene::Response& res);
  bool onListScenes(endovascular_sim::ListScenes::Request& req,
                    endovascular_sim::ListScenes::Response& res);
  void publish();

  ros::NodeHandle nh_, private_nh_;
  std::string scene_name_, frame_id_;
  double rate_hz_{25.0};
  int substeps_{1};
  std::unique_ptr<SceneModel> model_;
  SimData data_;
  ros::Publisher stats_pub_;
  std::vector<ros::Publisher> path_pubs_;
  ros::Subscriber command_sub_;
  ros::ServiceServer load_srv_, list_srv_;
  ros::Timer timer_;
};

}  // namespace evsim
