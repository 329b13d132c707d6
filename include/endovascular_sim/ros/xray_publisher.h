// Virtual fluoroscopy on ROS: a thread of its own renders the latest
// simulation snapshot (imaging/xray_renderer.h) at the X-ray frame rate and
// publishes it through image_transport, so that the simulation keeps its
// rate. Nothing is rendered while nobody subscribes.
//
// Publishes: xray/image (sensor_msgs/Image, mono8) with xray/camera_info
//   (sensor_msgs/CameraInfo: the C-arm's projection as a pinhole camera,
//   frame xray_source, z along the beam), and the tf frame_id -> xray_source.
// Services: xray/set_c_arm (endovascular_sim/SetCArm),
//   xray/inject_contrast (endovascular_sim/InjectContrast).
// dynamic_reconfigure: ~xray (config/reconfigure/Xray.cfg).
#pragma once

#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "endovascular_sim/InjectContrast.h"
#include "endovascular_sim/SetCArm.h"
#include "endovascular_sim/XrayConfig.h"
#include "endovascular_sim/imaging/xray_renderer.h"
#include "endovascular_sim/ros/simulation_loop.h"

namespace evsim {

class XrayPublisher {
 public:
  XrayPublisher(ros::NodeHandle nh, ros::NodeHandle private_nh, const SimulationLoop* loop,
                std::string frame_id);
  ~XrayPublisher();
  XrayPublisher(const XrayPublisher&) = delete;
  XrayPublisher& operator=(const XrayPublisher&) = delete;

 private:
  void run();
  /// The renderer of the loop's current scene (a new one after a scene switch).
  bool follow(const std::shared_ptr<const SceneModel>& model);
  bool onSetCArm(endovascular_sim::SetCArm::Request& req, endovascular_sim::SetCArm::Response& res);
  bool onInject(endovascular_sim::InjectContrast::Request& req,
                endovascular_sim::InjectContrast::Response& res);
  void onReconfigure(endovascular_sim::XrayConfig& config, uint32_t level);
  void showSettings();
  /// The reconfigure values of the renderer's settings (mutex_ held, renderer_ set).
  endovascular_sim::XrayConfig settingsInForce() const;

  ros::NodeHandle nh_;
  const SimulationLoop* loop_;
  std::string frame_id_;
  image_transport::ImageTransport transport_;
  image_transport::CameraPublisher camera_pub_;
  tf2_ros::TransformBroadcaster tf_;
  ros::ServiceServer c_arm_srv_, inject_srv_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<endovascular_sim::XrayConfig>> reconfigure_;

  std::mutex mutex_;  // renderer_, roadmap settings, between the thread and the services
  std::shared_ptr<const SceneModel> model_;
  std::unique_ptr<XrayRenderer> renderer_;
  bool roadmap_{false};
  std::vector<float> angiogram_;  // the strongest contrast image since the last injection
  double angiogram_sum_{0.0};
  long frames_{0};
  std::atomic<bool> stop_{false};
  std::condition_variable wake_;
  std::thread thread_;
};

}  // namespace evsim
