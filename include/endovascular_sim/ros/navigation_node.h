// Thin ROS adapter of the core simulation: parameters, topics, services and
// dynamic_reconfigure. No physics here: the simulation runs in a
// SimulationLoop thread, messages are built by FramePublisher.
//
// Subscribes: command (endovascular_sim/DeviceCommand), joy (sensor_msgs/Joy,
//   with ~joystick set). Services: load_scene, list_scenes, reset
//   (std_srvs/Trigger), pause (std_srvs/SetBool). Parameters: see
//   NavigationNode::Parameters and the README.
#pragma once

#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>
#include <sensor_msgs/Joy.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>

#include <memory>
#include <string>

#include "endovascular_sim/DeviceCommand.h"
#include "endovascular_sim/ListScenes.h"
#include "endovascular_sim/LoadScene.h"
#include "endovascular_sim/SolverConfig.h"
#include "endovascular_sim/ros/frame_publisher.h"
#include "endovascular_sim/ros/joystick_mapping.h"
#include "endovascular_sim/ros/simulation_loop.h"

namespace evsim {

class NavigationNode {
 public:
  struct Parameters {
    std::string scene{"carotid"};        // ~scene: shipped name or path
    double rate_hz{25.0};                // ~rate: published frames per second [Hz]
    std::string frame_id{"world"};       // ~frame_id
    bool use_script{true};               // ~use_script: run the scene's scripted commands
    std::string joystick;                // ~joystick: mapping file ("" = no joystick)
    bool progress{true};                 // ~progress: a progress line per second
    double vessel_mesh_spacing{0.0015};  // ~vessel_mesh_spacing [m]; 0 = no mesh
    double vessel_mesh_rate_hz{2.0};     // ~vessel_mesh_rate: moving vessels [Hz]
    MarkerStyle markers;                 // ~force_scale [m/N], ~plane_size [m]
  };

  /// Reads the parameters (throws std::runtime_error naming every invalid
  /// one) and loads the scene (throws when it cannot be loaded).
  NavigationNode(ros::NodeHandle nh, ros::NodeHandle private_nh);

  static Parameters readParameters(const ros::NodeHandle& private_nh);

 private:
  bool loadSceneNamed(const std::string& scene, std::string* message);
  void onPublishTimer(const ros::WallTimerEvent& event);
  void onProgressTimer(const ros::WallTimerEvent& event);
  void onCommand(const endovascular_sim::DeviceCommand& msg);
  void onJoy(const sensor_msgs::Joy& msg);
  bool onLoadScene(endovascular_sim::LoadScene::Request& req,
                   endovascular_sim::LoadScene::Response& res);
  bool onListScenes(endovascular_sim::ListScenes::Request& req,
                    endovascular_sim::ListScenes::Response& res);
  bool onReset(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool onPause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res);
  void onReconfigure(endovascular_sim::SolverConfig& config, uint32_t level);
  void showContactOptions(const ContactOptions& options);

  ros::NodeHandle nh_, private_nh_;
  Parameters params_;
  SimulationLoop loop_;
  FramePublisher publisher_;
  JoystickMapping joystick_;
  JoystickState joystick_state_;
  ros::Subscriber command_sub_, joy_sub_;
  ros::ServiceServer load_srv_, list_srv_, reset_srv_, pause_srv_;
  ros::WallTimer publish_timer_, progress_timer_;
  ros::WallTime last_publish_;
  double publish_rate_hz_{0.0};  // measured over the last second
  int frames_this_second_{0};
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<endovascular_sim::SolverConfig>> reconfigure_;
};

}  // namespace evsim
