// Virtual fluoroscopy on ROS: a thread of its own renders the latest
// simulation snapshot (imaging/xray_renderer.h) at the X-ray frame rate and
// publishes it through image_transport, so that the simulation keeps its rate.
// Declared and documented in endovascular_sim/ros/xray_publisher.h.
#include "endovascular_sim/ros/xray_publisher.h"

#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <chrono>
#include <numeric>

#include "endovascular_sim/imaging/detector.h"
#include "endovascular_sim/ros/message_conversions.h"

namespace evsim {

namespace {

constexpr const char* kSourceFrame = "xray_source";

sensor_msgs::CameraInfo cameraInfo(const XrayCamera& c, const std_msgs::Header& header) {
  sensor_msgs::CameraInfo info;
  info.header = header;
  info.width = c.width;
  info.height = c.height;
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {c.fx, 0, c.cx, 0, 0, c.fy, c.cy, 0, 0, 0, 1, 0};
  return info;
}

}  // namespace

XrayPublisher::XrayPublisher(ros::NodeHandle nh, ros::NodeHandle private_nh,
                             const SimulationLoop* loop, std::string frame_id)
    : nh_(nh), loop_(loop), frame_id_(std::move(frame_id)), transport_(nh) {
  camera_pub_ = transport_.advertiseCamera("xray/image", 1);
  c_arm_srv_ = nh_.advertiseService("xray/set_c_arm", &XrayPublisher::onSetCArm, this);
  inject_srv_ = nh_.advertiseService("xray/inject_contrast", &XrayPublisher::onInject, this);
  follow(loop_->model());
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<endovascular_sim::XrayConfig>>(
      reconfigure_mutex_, ros::NodeHandle(private_nh, "xray"));
  showSettings();
  reconfigure_->setCallback([this](endovascular_sim::XrayConfig& config, uint32_t level) {
    onReconfigure(config, level);
  });
  thread_ = std::thread([this] { run(); });
}

XrayPublisher::~XrayPublisher() {
  stop_ = true;
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

bool XrayPublisher::follow(const std::shared_ptr<const SceneModel>& model) {
  if (!model || (model == model_ && renderer_)) return false;
  // The scene's xray: section was validated at load; the renderer is built
  // before it replaces the current one, so a failure keeps the old scene's.
  auto renderer = std::make_unique<XrayRenderer>(*model, model->xray);
  model_ = model;
  renderer_ = std::move(renderer);
  angiogram_.clear();
  angiogram_sum_ = 0.0;
  return true;
}

void XrayPublisher::showSettings() {
  endovascular_sim::XrayConfig config;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!renderer_) return;
    config = settingsInForce();
  }
  reconfigure_->updateConfig(config);
}

void XrayPublisher::run() {
  auto next = std::chrono::steady_clock::now();
  double late_since = -1.0;  // [s] of wall time frames have missed their period
  while (!stop_) {
    double period = 1.0 / 15.0;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (renderer_) period = 1.0 / renderer_->spec().frame_rate;
      wake_.wait_until(lock, next, [this] { return stop_.load(); });
    }
    if (stop_) break;
    const auto start = std::chrono::steady_clock::now();
    next = std::max(next + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                               std::chrono::duration<double>(period)),
                    start);
    if (camera_pub_.getNumSubscribers() == 0) continue;  // nobody looks: nothing rendered
    const FrameSnapshot snap = loop_->snapshot();
    if (!snap.model) continue;
    sensor_msgs::ImagePtr image = boost::make_shared<sensor_msgs::Image>();
    XrayCamera camera;
    bool switched = false;  // a new scene: its C-arm shown in reconfigure
    {
      std::lock_guard<std::mutex> lock(mutex_);
      try {
        switched = follow(snap.model);
      } catch (const std::exception& e) {  // (a bug: say so, keep the node)
        ROS_ERROR_THROTTLE(10.0, "xray: cannot image scene '%s': %s", snap.model->name.c_str(),
                           e.what());
        continue;
      }
      if (!renderer_) continue;
      std::vector<DevicePose> poses;
      for (const DeviceState& d : snap.devices) poses.push_back({d.position, d.cut_element});
      XrayFrame frame;
      renderer_->render(poses, snap.time, &frame);
      const double contrast = std::accumulate(frame.contrast.begin(), frame.contrast.end(), 0.0);
      if (contrast > angiogram_sum_) angiogram_sum_ = contrast, angiogram_ = frame.contrast;
      const bool roadmap = roadmap_ && !angiogram_.empty() && contrast == 0.0;
      image->data =
          detectorGray(frame, renderer_->spec(), renderer_->referenceAttenuation(), frames_++,
                       roadmap ? &angiogram_ : nullptr, &renderer_->bodyAttenuation());
      image->width = frame.width;
      image->height = frame.height;
      camera = renderer_->camera();
    }
    if (switched) showSettings();  // before the new scene's first image
    image->header.stamp = ros::Time::now();
    image->header.frame_id = kSourceFrame;
    image->encoding = sensor_msgs::image_encodings::MONO8;
    image->step = image->width;
    camera_pub_.publish(
        image, boost::make_shared<sensor_msgs::CameraInfo>(cameraInfo(camera, image->header)));
    geometry_msgs::TransformStamped t;
    t.header.stamp = image->header.stamp;
    t.header.frame_id = frame_id_;
    t.child_frame_id = kSourceFrame;
    t.transform.translation = toVector3(camera.source);
    t.transform.rotation = toQuaternion(Quat(Mat3(camera.rotation.transpose())));
    tf_.sendTransform(t);

    const double spent =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (spent > period) {
      if (late_since < 0.0) late_since = 0.0;
      late_since += spent;
      if (late_since > 2.0)
        ROS_WARN_THROTTLE(
            10.0,
            "xray: a frame takes %.1f ms, more than the period of %.1f ms: the images "
            "come at about %.1f frames/s instead of %.1f (lower ~xray/frame_rate or "
            "the scene's xray.pixels)",
            spent * 1e3, period * 1e3, 1.0 / spent, 1.0 / period);
    } else {
      late_since = -1.0;
    }
  }
}

bool XrayPublisher::onSetCArm(endovascular_sim::SetCArm::Request& req,
                              endovascular_sim::SetCArm::Response& res) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!renderer_) {
      res.success = false;
      res.message = "no scene to image";
      return true;
    }
    CArmSpec c = renderer_->spec().c_arm;
    c.lao = req.lao_deg * M_PI / 180.0;
    c.cranial = req.cranial_deg * M_PI / 180.0;
    if (req.source_detector_distance != 0.0)
      c.source_detector_distance = req.source_detector_distance;
    if (req.source_isocenter_distance != 0.0)
      c.source_isocenter_distance = req.source_isocenter_distance;
    try {
      renderer_->setCArm(c);
      res.success = true;
      res.message = "C-arm at LAO " + std::to_string(req.lao_deg) + ", cranial " +
                    std::to_string(req.cranial_deg) + " deg";
    } catch (const std::invalid_argument& e) {
      res.success = false;
      res.message = std::string(e.what()) + " (the C-arm stays where it was)";
    }
  }
  if (res.success) showSettings();
  return true;
}

bool XrayPublisher::onInject(endovascular_sim::InjectContrast::Request& req,
                             endovascular_sim::InjectContrast::Response& res) {
  const FrameSnapshot snap = loop_->snapshot();
  std::lock_guard<std::mutex> lock(mutex_);
  try {
    follow(snap.model);
  } catch (const std::exception& e) {
    res.success = false;
    res.message = std::string("cannot image the scene: ") + e.what();
    return true;
  }
  if (!model_) {
    res.success = false;
    res.message = "no scene";
    return true;
  }
  int device = req.device.empty() ? 0 : -1;
  for (size_t d = 0; d < model_->devices.size(); ++d)
    if (model_->devices[d].name == req.device) device = static_cast<int>(d);
  if (device < 0 || device >= static_cast<int>(snap.devices.size())) {
    res.success = false;
    res.message = "no device named '" + req.device + "'";
    return true;
  }
  if (!model_->vessels) {
    res.success = false;
    res.message = "the scene has no vessels to fill";
    return true;
  }
  try {
    res.segments =
        renderer_->injectContrast(snap.devices[device].position.back(), snap.time, req.duration);
    angiogram_.clear();
    angiogram_sum_ = 0.0;
    res.success = true;
    res.message = "contrast at " + model_->devices[device].name +
                  "'s tip: " + std::to_string(res.segments) + " segments filled";
  } catch (const std::invalid_argument& e) {
    res.success = false;
    res.message = e.what();
  }
  return true;
}

void XrayPublisher::onReconfigure(endovascular_sim::XrayConfig& config, uint32_t) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!renderer_) return;
  XraySpec spec = renderer_->spec();
  spec.c_arm.lao = config.lao_deg * M_PI / 180.0;
  spec.c_arm.cranial = config.cranial_deg * M_PI / 180.0;
  spec.frame_rate = config.frame_rate;
  spec.photons = config.photons;
  spec.blur = config.blur;
  const std::string refused = validateXray(spec);
  if (refused.empty()) {
    if (spec.c_arm.lao != renderer_->spec().c_arm.lao ||
        spec.c_arm.cranial != renderer_->spec().c_arm.cranial)
      renderer_->setCArm(spec.c_arm);
    renderer_->setDetector(spec.frame_rate, spec.photons, spec.blur);
    roadmap_ = config.roadmap;
    return;
  }
  ROS_WARN_STREAM("xray: refused: " << refused << "; the settings in force are kept");
  // The server publishes what the callback leaves in config: the settings in force.
  config = settingsInForce();
}

endovascular_sim::XrayConfig XrayPublisher::settingsInForce() const {
  endovascular_sim::XrayConfig config;
  const XraySpec& s = renderer_->spec();
  config.lao_deg = s.c_arm.lao * 180.0 / M_PI;
  config.cranial_deg = s.c_arm.cranial * 180.0 / M_PI;
  config.frame_rate = s.frame_rate;
  config.photons = s.photons;
  config.blur = s.blur;
  config.roadmap = roadmap_;
  return config;
}

}  // namespace evsim
