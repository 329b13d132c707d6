// Thin ROS adapter of the core simulation: parameters, topics, services and
// dynamic_reconfigure. No physics here: the simulation runs in a
// SimulationLoop thread, messages are built by FramePublisher.
//
// Subscribes: command (endovascular_sim/DeviceCommand), joy (sensor_msgs/Joy,
//   with ~joystick set). Services: load_scene, list_scenes, reset
//   (std_srvs/Trigger), pause (std_srvs/SetBool), load_centerline. Action: navigate_to
//   (endovascular_sim/NavigateTo, ros/navigate_action.h). Virtual
//   fluoroscopy: ros/xray_publisher.h. Parameters: see
//   NavigationNode::Parameters and docs/ros_interface.md.
//
// load_scene runs on a thread of its own (its own callback queue): a scene
// is built there while the simulation and the publisher go on with the old
// one, then swapped in. Scene paths: a name is a shipped scene, a relative
// path is taken from the package's config/scenes/, an absolute path must
// lie in the package's config/ or a folder of ~scene_folders (unless
// ~allow_any_scene_path). A centreline file (.vtp, .vtk, .swc) loads as a
// scene with the devices and settings of a base scene
// (scene/centerline_scene.h): through load_centerline, which names its
// units, or load_scene and ~scene, which take them from ~units.
#pragma once

#include <dynamic_reconfigure/server.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/Joy.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "endovascular_sim/DeviceCommand.h"
#include "endovascular_sim/ListScenes.h"
#include "endovascular_sim/LoadCenterline.h"
#include "endovascular_sim/LoadScene.h"
#include "endovascular_sim/SolverConfig.h"
#include "endovascular_sim/ros/frame_publisher.h"
#include "endovascular_sim/ros/joystick_mapping.h"
#include "endovascular_sim/ros/navigate_action.h"
#include "endovascular_sim/ros/simulation_loop.h"
#include "endovascular_sim/ros/xray_publisher.h"

namespace evsim {

class NavigationNode {
 public:
  struct Parameters {
    std::string scene{"carotid"};  // ~scene: shipped name or path, or a centreline
    std::string units;             // ~units: of a ~scene that is a VTK centreline
    std::string anatomical_frame;  // ~anatomical_frame: its orientation code (LPS, RAS, ...)
    std::string radius_array{"MaximumInscribedSphereRadius"};  // ~radius_array: its radius data
    std::string centerline_base{"patient_example"};  // ~centerline_base: devices for a centreline
    double rate_hz{25.0};                            // ~rate: published frames per second [Hz]
    std::string frame_id{"world"};                   // ~frame_id
    bool use_script{true};                   // ~use_script: run the scene's scripted commands
    std::string joystick;                    // ~joystick: mapping file ("" = no joystick)
    bool progress{true};                     // ~progress: a progress line per second
    double vessel_mesh_spacing{0.0015};      // ~vessel_mesh_spacing [m]; 0 = no mesh
    double vessel_mesh_rate_hz{2.0};         // ~vessel_mesh_rate: moving vessels [Hz]
    MarkerStyle markers;                     // ~force_scale [m/N], ~plane_size [m]
    bool publish_clock{true};                // ~publish_clock: /clock from the simulation
    std::vector<std::string> scene_folders;  // ~scene_folders: more folders for load_scene
    bool allow_any_scene_path{false};        // ~allow_any_scene_path
    bool xray{true};  // ~xray: virtual fluoroscopy on xray/image (rendered only when watched)
    double wrench_cutoff_hz{0.0};  // ~wrench_cutoff: low-pass of drive_wrench [Hz]; 0 = raw
  };

  /// The scene (or centreline) file a load_scene request names, or why it
  /// is refused (name: shipped; relative path: from config/scenes/;
  /// absolute: within config/ or one of `folders` unless `any`). Throws
  /// LoadError.
  static std::string sceneFileFor(const std::string& request,
                                  const std::vector<std::string>& folders, bool any);

  /// Reads the parameters (throws std::runtime_error naming every invalid
  /// one) and loads the scene (throws when it cannot be loaded).
  NavigationNode(ros::NodeHandle nh, ros::NodeHandle private_nh);

  static Parameters readParameters(const ros::NodeHandle& private_nh);

 private:
  /// What to load: a scene, or a centreline with its units, radius array
  /// and base scene.
  struct SceneRequest {
    std::string scene;
    std::string units;
    std::string radius_array;
    std::string base;
    std::string frame;
    std::map<int, std::string> names;  // branch id -> vessel name
  };
  /// Malformed commands refused since the node started (for /stats and the diagnostics).
  long refusedCommands() const;
  /// Logs a refused command: a new reason at once, a repeated one at most
  /// once a second, each with the count refused so far.
  void logRefusal(const std::string& what);
  /// A request for `scene` with the parameters' units, radius array, base
  /// and frame (for a centreline).
  SceneRequest requestFor(const std::string& scene) const;
  /// Builds a scene and swaps it in; false (message says why, the current
  /// scene goes on) when it cannot be loaded. from_request: a load_scene
  /// request, whose path must lie in the allowed folders.
  bool loadSceneNamed(const SceneRequest& request, std::string* message, bool from_request);
  /// The scene a request names: a scene file, or a centreline in the
  /// scene ~centerline_base. Throws LoadError.
  SceneModel buildRequestedScene(const SceneRequest& request, bool from_request) const;
  void onPublishTimer(const ros::WallTimerEvent& event);
  void onProgressTimer(const ros::WallTimerEvent& event);
  void onCommand(const endovascular_sim::DeviceCommand& msg);
  void onJoy(const sensor_msgs::Joy& msg);
  bool onLoadScene(endovascular_sim::LoadScene::Request& req,
                   endovascular_sim::LoadScene::Response& res);
  bool onLoadCenterline(endovascular_sim::LoadCenterline::Request& req,
                        endovascular_sim::LoadCenterline::Response& res);
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
  ros::ServiceServer load_srv_, load_centerline_srv_, list_srv_, reset_srv_, pause_srv_;
  ros::CallbackQueue load_queue_;  // load_scene's own queue and thread
  std::unique_ptr<ros::AsyncSpinner> load_spinner_;
  std::mutex publisher_mutex_;        // publisher_ between the timers and a scene swap
  std::mutex load_mutex_;             // one scene load at a time
  mutable std::mutex refusal_mutex_;  // guards the three below
  long refused_commands_{0};          // malformed commands since the start
  std::string last_refusal_;          // the last logged, and when: a repeat waits a second
  ros::WallTime last_refusal_log_;
  int slow_seconds_{0};  // consecutive seconds below real time
  ros::WallTimer publish_timer_, progress_timer_;
  ros::WallTime last_publish_;
  double publish_rate_hz_{0.0};  // measured over the last second
  int frames_this_second_{0};
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<endovascular_sim::SolverConfig>> reconfigure_;
  std::unique_ptr<NavigateActionServer> navigate_;  // (after loop_: destroyed before it)
  std::unique_ptr<XrayPublisher> xray_;             // (after loop_: destroyed before it)
};

}  // namespace evsim
