// Thin ROS adapter of the core simulation: parameters, topics, services and
// dynamic_reconfigure. Declared and documented in
// endovascular_sim/ros/navigation_node.h.
#include "endovascular_sim/ros/navigation_node.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/scene/centerline_scene.h"

namespace evsim {
namespace {

/// Reads ~name when set; a value of the wrong type is reported, not ignored.
template <typename T>
void readParam(const ros::NodeHandle& nh, const std::string& name, T* value,
               std::vector<std::string>* problems, const char* expected) {
  if (!nh.hasParam(name)) return;
  if (!nh.getParam(name, *value)) problems->push_back("~" + name + " must be " + expected);
}

/// "xbox" -> config/joystick/xbox.yaml; a path is kept as it is.
std::string resolveJoystickPath(const std::string& name) {
  if (name.find('/') != std::string::npos || std::filesystem::path(name).has_extension())
    return name;
  return std::string(EVSIM_CONFIG_DIR) + "/joystick/" + name + ".yaml";
}

DriveCommand clampToLimits(DriveCommand c, const DeviceModel& device) {
  c.insertion = std::clamp(c.insertion, -device.max_insertion_speed, device.max_insertion_speed);
  c.rotation = std::clamp(c.rotation, -device.max_rotation_speed, device.max_rotation_speed);
  return c;
}

/// The reconfigurable part of the contact options, as dynamic_reconfigure shows it.
void writeConfig(const ContactOptions& o, endovascular_sim::SolverConfig* config) {
  config->solver = lcpSolverName(o.lcp.solver);
  config->lcp_tolerance = o.lcp.tolerance;
  config->lcp_max_iterations = o.lcp.max_iterations;
  config->max_activation_loops = o.max_activation_loops;
  config->max_subdivisions = o.max_subdivisions;
  config->penetration_tolerance = o.penetration_tolerance;
}

}  // namespace

NavigationNode::Parameters NavigationNode::readParameters(const ros::NodeHandle& nh) {
  Parameters p;
  std::vector<std::string> problems;
  readParam(nh, "scene", &p.scene, &problems, "a scene name or path");
  readParam(nh, "units", &p.units, &problems, "m, cm, mm or um");
  readParam(nh, "radius_array", &p.radius_array, &problems, "a point-data array name");
  readParam(nh, "anatomical_frame", &p.anatomical_frame, &problems,
            "an orientation code (LPS, RAS, ...)");
  readParam(nh, "centerline_base", &p.centerline_base, &problems, "a scene name or path");
  readParam(nh, "rate", &p.rate_hz, &problems, "a number [Hz]");
  readParam(nh, "frame_id", &p.frame_id, &problems, "a string");
  readParam(nh, "use_script", &p.use_script, &problems, "true or false");
  readParam(nh, "joystick", &p.joystick, &problems, "a mapping name or path");
  readParam(nh, "progress", &p.progress, &problems, "true or false");
  readParam(nh, "vessel_mesh_spacing", &p.vessel_mesh_spacing, &problems, "a length [m]");
  readParam(nh, "vessel_mesh_rate", &p.vessel_mesh_rate_hz, &problems, "a number [Hz]");
  readParam(nh, "force_scale", &p.markers.force_scale, &problems, "a number [m/N]");
  readParam(nh, "plane_size", &p.markers.plane_size, &problems, "a length [m]");
  readParam(nh, "publish_clock", &p.publish_clock, &problems, "true or false");
  readParam(nh, "scene_folders", &p.scene_folders, &problems, "a list of folder paths");
  readParam(nh, "allow_any_scene_path", &p.allow_any_scene_path, &problems, "true or false");
  readParam(nh, "xray", &p.xray, &problems, "true or false");
  readParam(nh, "wrench_cutoff", &p.wrench_cutoff_hz, &problems, "a frequency [Hz]");
  if (!(p.wrench_cutoff_hz >= 0.0 && p.wrench_cutoff_hz <= 1e4))
    problems.push_back("~wrench_cutoff must lie in [0, 10000] Hz (0: no filter), got " +
                       std::to_string(p.wrench_cutoff_hz));
  if (p.scene.empty()) problems.push_back("~scene must not be empty");
  if (!(p.rate_hz > 0.0 && p.rate_hz <= 1000.0))
    problems.push_back("~rate must lie in (0, 1000] Hz");
  if (p.frame_id.empty()) problems.push_back("~frame_id must not be empty");
  if (!(p.vessel_mesh_spacing == 0.0 ||
        (p.vessel_mesh_spacing >= 2e-4 && p.vessel_mesh_spacing <= 0.01)))
    problems.push_back("~vessel_mesh_spacing must be 0 (no mesh) or lie in [2e-4, 0.01] m");
  if (!(p.vessel_mesh_rate_hz > 0.0 && p.vessel_mesh_rate_hz <= 100.0))
    problems.push_back("~vessel_mesh_rate must lie in (0, 100] Hz");
  if (!(p.markers.force_scale > 0.0 && std::isfinite(p.markers.force_scale)))
    problems.push_back("~force_scale must be a positive number [m/N]");
  if (!(p.markers.plane_size > 0.0 && p.markers.plane_size <= 0.05))
    problems.push_back("~plane_size must lie in (0, 0.05] m");
  if (!problems.empty()) {
    std::string message = "invalid parameters:";
    for (const auto& why : problems) message += "\n  " + why;
    throw std::runtime_error(message);
  }
  if (!p.joystick.empty()) p.joystick = resolveJoystickPath(p.joystick);
  return p;
}

NavigationNode::NavigationNode(ros::NodeHandle nh, ros::NodeHandle private_nh)
    : nh_(nh),
      private_nh_(private_nh),
      params_(readParameters(private_nh)),
      loop_(params_.rate_hz),
      publisher_(nh, params_.frame_id, params_.markers, 1.0 / params_.vessel_mesh_rate_hz,
                 params_.publish_clock) {
  if (!params_.joystick.empty()) {
    try {
      joystick_ = loadJoystickMapping(params_.joystick);
    } catch (const LoadError& e) {
      throw std::runtime_error(std::string("~joystick: ") + e.what());
    }
  }
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<endovascular_sim::SolverConfig>>(
      reconfigure_mutex_, private_nh_);
  std::string message;
  if (!loadSceneNamed(requestFor(params_.scene), &message, /*from_request=*/false))
    throw std::runtime_error(message);
  reconfigure_->setCallback(
      [this](endovascular_sim::SolverConfig& c, uint32_t level) { onReconfigure(c, level); });

  command_sub_ = nh_.subscribe("command", 10, &NavigationNode::onCommand, this);
  if (!params_.joystick.empty()) {
    joy_sub_ = nh_.subscribe("joy", 10, &NavigationNode::onJoy, this);
    ROS_INFO_STREAM("joystick mapping " << params_.joystick);
  }
  // load_scene on its own queue and thread: building a scene (a vessel mesh
  // of 100k triangles takes a quarter of a second) never stalls publishing.
  ros::AdvertiseServiceOptions load_options =
      ros::AdvertiseServiceOptions::create<endovascular_sim::LoadScene>(
          "load_scene",
          [this](endovascular_sim::LoadScene::Request& req,
                 endovascular_sim::LoadScene::Response& res) { return onLoadScene(req, res); },
          ros::VoidConstPtr(), &load_queue_);
  load_srv_ = nh_.advertiseService(load_options);
  ros::AdvertiseServiceOptions centerline_options =
      ros::AdvertiseServiceOptions::create<endovascular_sim::LoadCenterline>(
          "load_centerline",
          [this](endovascular_sim::LoadCenterline::Request& req,
                 endovascular_sim::LoadCenterline::Response& res) {
            return onLoadCenterline(req, res);
          },
          ros::VoidConstPtr(), &load_queue_);
  load_centerline_srv_ = nh_.advertiseService(centerline_options);
  load_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &load_queue_);
  load_spinner_->start();
  list_srv_ = nh_.advertiseService("list_scenes", &NavigationNode::onListScenes, this);
  reset_srv_ = nh_.advertiseService("reset", &NavigationNode::onReset, this);
  pause_srv_ = nh_.advertiseService("pause", &NavigationNode::onPause, this);
  publish_timer_ = nh_.createWallTimer(ros::WallDuration(1.0 / params_.rate_hz),
                                       &NavigationNode::onPublishTimer, this);
  progress_timer_ =
      nh_.createWallTimer(ros::WallDuration(1.0), &NavigationNode::onProgressTimer, this);
  last_publish_ = ros::WallTime::now();
  loop_.setWrenchCutoff(params_.wrench_cutoff_hz);
  loop_.start();
  navigate_ = std::make_unique<NavigateActionServer>(nh_, &loop_);
  if (params_.xray)
    xray_ = std::make_unique<XrayPublisher>(nh_, private_nh_, &loop_, params_.frame_id);
}

std::string NavigationNode::sceneFileFor(const std::string& request,
                                         const std::vector<std::string>& folders, bool any) {
  namespace fs = std::filesystem;
  if (request.empty()) throw LoadError("", 0, "scene", "the scene name is empty");
  const fs::path shipped = fs::path(configDirectory()) / "scenes";
  if (request.find('/') == std::string::npos && !fs::path(request).has_extension())
    return resolveScenePath(request);  // a shipped scene's name
  fs::path path(request);
  if (path.is_relative()) path = shipped / path;
  std::error_code ec;
  const fs::path real = fs::weakly_canonical(path, ec);
  if (ec) throw LoadError(request, 0, "scene", "cannot resolve the path");
  auto within = [&](const fs::path& folder) {
    std::error_code e;
    const fs::path base = fs::weakly_canonical(folder, e);
    if (e) return false;
    const auto rel = real.lexically_relative(base);
    return !rel.empty() && *rel.begin() != "..";
  };
  bool allowed = any || within(configDirectory());
  for (const std::string& f : folders) allowed = allowed || within(f);
  if (!allowed) {
    std::string list = configDirectory();
    for (const std::string& f : folders) list += ", " + f;
    throw LoadError(request, 0, "scene",
                    "outside the scene folders (" + list +
                        "): add its folder to ~scene_folders, or set ~allow_any_scene_path");
  }
  return real.string();
}

SceneModel NavigationNode::buildRequestedScene(const SceneRequest& r, bool from_request) const {
  auto resolve = [&](const std::string& name) {
    return from_request ? sceneFileFor(name, params_.scene_folders, params_.allow_any_scene_path)
                        : resolveScenePath(name);
  };
  const std::string file = resolve(r.scene);
  if (!isCenterlinePath(file)) return loadScene(file);
  const SceneSpec base = loadSceneFile(resolve(r.base));
  return buildSceneModel(centerlineScene(base, {file, r.units, r.radius_array, r.frame, r.names}));
}

bool NavigationNode::loadSceneNamed(const SceneRequest& request, std::string* message,
                                    bool from_request) {
  std::shared_ptr<const SceneModel> model;
  std::shared_ptr<const SurfaceMesh> mesh;
  try {
    model = std::make_shared<const SceneModel>(buildRequestedScene(request, from_request));
    if (model->vessels && params_.vessel_mesh_spacing > 0.0)
      mesh = std::make_shared<const SurfaceMesh>(
          meshVesselSurface(*model->vessels, params_.vessel_mesh_spacing));
  } catch (const std::exception& e) {  // LoadError, or a scene too large to build
    *message = std::string("cannot load scene: ") + e.what();
    ROS_ERROR_STREAM(*message);
    return false;  // the current scene keeps running
  }
  // The swap: the loop takes the new scene between two steps, the publisher
  // between two frames.
  std::lock_guard<std::mutex> lock(publisher_mutex_);
  loop_.setScene(model, params_.use_script);
  publisher_.setScene(*model, mesh);
  joystick_state_ = JoystickState{};
  showContactOptions(model->contact);
  std::ostringstream m;
  m << "loaded scene '" << model->name << "' (" << model->devices.size() << " device"
    << (model->devices.size() == 1 ? "" : "s") << ", " << loop_.timing().steps_per_frame
    << " steps of " << model->time_step * 1e3 << " ms per frame";
  if (mesh) m << ", vessel mesh of " << mesh->triangles.size() << " triangles";
  m << ")";
  *message = m.str();
  ROS_INFO_STREAM(*message);
  return true;
}

void NavigationNode::onPublishTimer(const ros::WallTimerEvent&) {
  {
    std::lock_guard<std::mutex> lock(publisher_mutex_);
    publisher_.publishWrenches(loop_.takeWrenches());
    publisher_.publish(loop_.snapshot(), loop_.timing(), joystick_state_.device, refusedCommands());
  }
  ++frames_this_second_;
  for (const std::string& notice : loop_.takeNotices()) ROS_WARN_STREAM(notice);
}

void NavigationNode::onProgressTimer(const ros::WallTimerEvent&) {
  const ros::WallTime now = ros::WallTime::now();
  publish_rate_hz_ = frames_this_second_ / std::max(1e-9, (now - last_publish_).toSec());
  frames_this_second_ = 0;
  last_publish_ = now;
  const FrameSnapshot f = loop_.snapshot();
  const LoopTiming timing = loop_.timing();
  {
    std::lock_guard<std::mutex> lock(publisher_mutex_);
    publisher_.publishDiagnostics(f, timing, publish_rate_hz_, loop_.lastError(),
                                  refusedCommands());
  }
  const std::string error = loop_.lastError();
  if (!error.empty()) ROS_WARN_STREAM_THROTTLE(5.0, "simulation: " << error);
  // (0.95: a loop that keeps pace measures 0.98-1.0 over a second)
  slow_seconds_ = !f.paused && timing.real_time_factor < 0.95 ? slow_seconds_ + 1 : 0;
  if (slow_seconds_ >= 3)
    ROS_WARN_STREAM_THROTTLE(
        10.0, "scene '" << f.model->name << "' runs at " << std::fixed << std::setprecision(2)
                        << timing.real_time_factor
                        << "x real time: stamps and /clock follow the simulation (use_sim_time "
                           "nodes keep up); a coarser scene or lower ~rate lightens it");
  if (!params_.progress || f.devices.empty()) return;
  std::ostringstream line;
  line << std::fixed << std::setprecision(2) << "t=" << f.time << " s";
  for (size_t i = 0; i < f.devices.size(); ++i) {
    const Vec3 tip = 1e3 * f.devices[i].position.back();
    line << " | " << f.model->devices[i].name << ": " << std::setprecision(1)
         << 1e3 * f.devices[i].inserted_length << " mm in, tip (" << tip.x() << ", " << tip.y()
         << ", " << tip.z() << ") mm";
  }
  line << " | " << f.stats.contact.contacts << " contacts | " << std::setprecision(1)
       << publish_rate_hz_ << " Hz | RTF " << std::setprecision(2) << timing.real_time_factor
       << (f.paused ? " | paused" : "");
  ROS_INFO_STREAM(line.str());
}

void NavigationNode::logRefusal(const std::string& what) {
  // A new reason at once; the same one again at most once a second,
  // however fast it comes (a runaway client would flood /rosout), with the
  // count of all refused.
  std::lock_guard<std::mutex> lock(refusal_mutex_);
  ++refused_commands_;
  const ros::WallTime now = ros::WallTime::now();
  if (what == last_refusal_ && (now - last_refusal_log_).toSec() < 1.0) return;
  last_refusal_ = what;
  last_refusal_log_ = now;
  ROS_WARN_STREAM(what << " (" << refused_commands_ << " commands refused since the start)");
}

long NavigationNode::refusedCommands() const {
  std::lock_guard<std::mutex> lock(refusal_mutex_);
  return refused_commands_;
}

void NavigationNode::onCommand(const endovascular_sim::DeviceCommand& msg) {
  if (msg.mode == endovascular_sim::DeviceCommand::DETACH) {
    const std::string why = loop_.detach(msg.device);
    if (why.empty())
      ROS_INFO_STREAM("'" << msg.device << "' detached");
    else
      ROS_WARN_STREAM("detach refused for '" << msg.device << "': " << why);
    return;
  }
  if (msg.mode != endovascular_sim::DeviceCommand::VELOCITY &&
      msg.mode != endovascular_sim::DeviceCommand::POSITION) {
    logRefusal("command refused: mode " + std::to_string(int(msg.mode)) +
               " is neither VELOCITY (0), POSITION (1) nor DETACH (2)");
    return;
  }
  DriveCommand cmd;
  cmd.mode = msg.mode == endovascular_sim::DeviceCommand::POSITION ? DriveCommand::Mode::kPosition
                                                                   : DriveCommand::Mode::kVelocity;
  cmd.insertion = msg.insertion;
  cmd.rotation = msg.rotation;
  const std::string why = loop_.setCommand(msg.device, cmd);
  if (!why.empty()) logRefusal("command refused for '" + msg.device + "': " + why);
}

void NavigationNode::onJoy(const sensor_msgs::Joy& msg) {
  const auto model = loop_.model();
  const int n = static_cast<int>(model->devices.size());
  JoystickOutcome out;
  {
    std::lock_guard<std::mutex> lock(publisher_mutex_);  // (a scene swap resets the state)
    out = mapJoystick(joystick_, msg.axes, msg.buttons, n, &joystick_state_);
  }
  if (!out.problem.empty()) {
    ROS_WARN_STREAM_THROTTLE(5.0, "joy message ignored: " << out.problem);
    return;
  }
  if (out.switched)
    ROS_INFO_STREAM("joystick drives '" << model->devices[joystick_state_.device].name << "'");
  for (const auto& [device, command] : out.commands) {
    const DeviceModel& d = model->devices[device];
    const std::string why = loop_.setCommand(d.name, clampToLimits(command, d));
    if (!why.empty()) logRefusal("joystick command refused: " + why);
  }
}

NavigationNode::SceneRequest NavigationNode::requestFor(const std::string& scene) const {
  SceneRequest r;
  r.scene = scene;
  r.units = params_.units;
  r.radius_array = params_.radius_array;
  r.base = params_.centerline_base;
  r.frame = params_.anatomical_frame;
  return r;
}

bool NavigationNode::onLoadScene(endovascular_sim::LoadScene::Request& req,
                                 endovascular_sim::LoadScene::Response& res) {
  std::lock_guard<std::mutex> one_at_a_time(load_mutex_);
  // A centreline given here takes its units from ~units, read now.
  SceneRequest r = requestFor(req.scene);
  private_nh_.getParam("units", r.units);
  res.success = loadSceneNamed(r, &res.message, /*from_request=*/true);
  return true;
}

bool NavigationNode::onLoadCenterline(endovascular_sim::LoadCenterline::Request& req,
                                      endovascular_sim::LoadCenterline::Response& res) {
  std::lock_guard<std::mutex> one_at_a_time(load_mutex_);
  SceneRequest r;
  r.scene = req.centerline;
  r.units = req.units;
  r.radius_array = req.radius_array.empty() ? params_.radius_array : req.radius_array;
  r.base = req.base_scene.empty() ? params_.centerline_base : req.base_scene;
  r.frame = req.frame.empty() ? params_.anatomical_frame : req.frame;
  for (const std::string& entry : req.names) {
    std::string why;
    if (!parseBranchName(entry, &r.names, &why)) {
      res.success = false;
      res.message = "cannot load centreline '" + req.centerline + "': names: " + why;
      ROS_ERROR_STREAM(res.message);
      return true;
    }
  }
  if (!isCenterlinePath(r.scene)) {
    res.success = false;
    res.message = "cannot load centreline: '" + r.scene + "' is not a .vtp, .vtk or .swc file";
    ROS_ERROR_STREAM(res.message);
    return true;
  }
  res.success = loadSceneNamed(r, &res.message, /*from_request=*/true);
  return true;
}

bool NavigationNode::onListScenes(endovascular_sim::ListScenes::Request&,
                                  endovascular_sim::ListScenes::Response& res) {
  res.scenes = shippedScenes();
  return true;
}

bool NavigationNode::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  loop_.reset();
  {
    std::lock_guard<std::mutex> lock(publisher_mutex_);
    publisher_.restartClock();
  }
  joystick_state_.moving = false;
  res.success = true;
  res.message = "scene '" + loop_.model()->name + "' back to its initial state";
  ROS_INFO_STREAM(res.message);
  return true;
}

bool NavigationNode::onPause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
  loop_.setPaused(req.data);
  res.success = true;
  res.message = req.data ? "paused" : "running";
  ROS_INFO_STREAM("simulation " << res.message);
  return true;
}

void NavigationNode::onReconfigure(endovascular_sim::SolverConfig& config, uint32_t) {
  const auto model = loop_.model();
  ContactOptions o = model->contact;
  std::string why;
  try {
    o.lcp.solver = lcpSolverFromName(config.solver);
  } catch (const std::exception& e) {
    why = e.what();
  }
  o.lcp.tolerance = config.lcp_tolerance;
  o.lcp.max_iterations = config.lcp_max_iterations;
  o.max_activation_loops = config.max_activation_loops;
  o.max_subdivisions = config.max_subdivisions;
  o.penetration_tolerance = config.penetration_tolerance;
  if (why.empty()) why = loop_.setContactOptions(o);
  if (!why.empty()) {
    ROS_WARN_STREAM("solver options refused: " << why);
    o = model->contact;  // show what is in force
  } else {
    ROS_INFO_STREAM("solver options: " << config.solver << ", tolerance " << o.lcp.tolerance << ", "
                                       << o.max_activation_loops << " loops, " << o.max_subdivisions
                                       << " subdivisions");
  }
  writeConfig(o, &config);
}

void NavigationNode::showContactOptions(const ContactOptions& options) {
  endovascular_sim::SolverConfig config = endovascular_sim::SolverConfig::__getDefault__();
  writeConfig(options, &config);
  reconfigure_->updateConfig(config);
}

}  // namespace evsim
