// The fixed-step simulation loop of the node (ROS-free): a thread that runs
// frames of a fixed number of steps (1 / (rate dt), as the scene's time step
// asks) paced by the wall clock. Declared and documented in
// endovascular_sim/ros/simulation_loop.h.
#include "endovascular_sim/ros/simulation_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace evsim {
namespace {

using Clock = std::chrono::steady_clock;

int stepsPerFrame(double period_s, double time_step) {
  return std::max(1, static_cast<int>(std::lround(period_s / time_step)));
}

}  // namespace

SimulationLoop::SimulationLoop(double rate_hz) : period_s_(1.0 / rate_hz) {}

SimulationLoop::~SimulationLoop() { stop(); }

std::unique_lock<std::mutex> SimulationLoop::lockForCaller() const {
  ++waiters_;
  std::unique_lock<std::mutex> lock(mutex_);
  --waiters_;
  return lock;
}

void SimulationLoop::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread(&SimulationLoop::run, this);
}

void SimulationLoop::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

void SimulationLoop::setScene(std::shared_ptr<const SceneModel> model, bool use_script) {
  const auto lock = lockForCaller();
  endNavigation("pre-empted by a new scene");
  model_ = std::move(model);
  use_script_ = use_script;
  data_ = makeData(*model_);
  if (!use_script_) data_.next_script_entry = model_->script.size();
  wrench_filters_.clear();
  {
    std::lock_guard<std::mutex> status(status_mutex_);
    timing_ = LoopTiming{};
    timing_.steps_per_frame = stepsPerFrame(period_s_, model_->time_step);
    last_error_.clear();
    wrench_samples_.clear();  // (another scene's devices)
  }
  shareState();
}

void SimulationLoop::reset() {
  const auto lock = lockForCaller();
  if (!model_) return;
  endNavigation("pre-empted by a reset");
  data_ = makeData(*model_);
  if (!use_script_) data_.next_script_entry = model_->script.size();
  wrench_filters_.clear();
  {
    std::lock_guard<std::mutex> status(status_mutex_);
    last_error_.clear();
    for (auto& samples : wrench_samples_) samples.clear();  // (the clock restarts)
  }
  shareState();
}

void SimulationLoop::setPaused(bool paused) {
  const auto lock = lockForCaller();
  paused_ = paused;
  shareState();
}

std::string SimulationLoop::setCommand(const std::string& device, const DriveCommand& command) {
  const auto lock = lockForCaller();
  if (!model_) return "no scene loaded";
  const std::string why = evsim::setCommand(*model_, &data_, device, command);
  if (why.empty() && pilot_) endNavigation("pre-empted by a manual command for '" + device + "'");
  return why;
}

std::string SimulationLoop::startNavigation(const std::string& target, const std::string& device,
                                            const AutopilotOptions& options, long* id) {
  const auto lock = lockForCaller();
  if (!model_) return "no scene loaded";
  std::unique_ptr<Autopilot> pilot;
  try {
    pilot = std::make_unique<Autopilot>(*model_, data_, target, device, options);
  } catch (const std::exception& e) {  // LoadError: unknown, unconnected or closed target
    return e.what();
  }
  endNavigation("pre-empted by a new navigation goal");
  pilot_ = std::move(pilot);
  data_.next_script_entry = model_->script.size();  // the autopilot drives from now on
  {
    std::lock_guard<std::mutex> status(status_mutex_);
    const long next = navigation_.id + 1;
    navigation_ = NavigationStatus{};
    navigation_.id = next;
    navigation_.active = true;
    navigation_.target = target;
    if (id) *id = next;
  }
  shareNavigation("");
  return "";
}

void SimulationLoop::stopNavigation(const std::string& why) {
  const auto lock = lockForCaller();
  endNavigation(why);
}

NavigationStatus SimulationLoop::navigation() {
  std::lock_guard<std::mutex> status(status_mutex_);
  NavigationStatus out = navigation_;
  navigation_.events.clear();
  return out;
}

void SimulationLoop::endNavigation(const std::string& why) {
  if (!pilot_) return;
  const bool preempted = !pilot_->done();
  for (size_t i = 0; model_ && i < data_.commands.size(); ++i)
    applyCommand(&data_, static_cast<int>(i), DriveCommand{});  // the drives stop where they are
  std::string event;
  if (preempted) event = why;
  shareNavigation(event);
  {
    std::lock_guard<std::mutex> status(status_mutex_);
    navigation_.active = false;
    navigation_.done = true;
    if (preempted) {
      navigation_.report.reached = false;
      navigation_.report.reason = event;
    }
  }
  pilot_.reset();
}

void SimulationLoop::shareNavigation(const std::string& event) {
  if (!pilot_) return;
  const VesselAtlas& atlas = *model_->atlas;
  const int vessel = pilot_->currentVessel();
  std::lock_guard<std::mutex> status(status_mutex_);
  navigation_.phase = phaseName(pilot_->phase());
  navigation_.vessel = vessel >= 0 ? atlas.vessels()[vessel].name : "";
  navigation_.remaining_path = pilot_->remainingPath();
  navigation_.report = pilot_->report();
  if (!event.empty() && navigation_.events.size() < 100) navigation_.events.push_back(event);
}

std::string SimulationLoop::detach(const std::string& device) {
  const auto lock = lockForCaller();
  if (!model_) return "no scene loaded";
  const std::string why = detachDevice(*model_, &data_, device);
  if (why.empty()) shareState();
  return why;
}

std::string SimulationLoop::setContactOptions(const ContactOptions& options) {
  const std::string why = validateContactOptions(options);
  if (!why.empty()) return why;
  const auto lock = lockForCaller();
  if (!model_) return "no scene loaded";
  auto model = std::make_shared<SceneModel>(*model_);  // models are immutable: swap a copy
  model->contact = options;
  model_ = std::move(model);
  wake(&data_);  // the rest was found with the old options
  shareState();
  return "";
}

void SimulationLoop::shareState() {
  FrameSnapshot f;
  f.model = model_;
  f.time = data_.time;
  f.step = data_.step;
  f.paused = paused_;
  f.devices = data_.devices;
  f.contacts = data_.contacts;
  f.stats = data_.stats;
  f.tips = data_.tips;
  f.targets = data_.targets;
  f.drives = data_.drives;
  f.tip_forces = data_.tip_forces;
  f.stalls = data_.stalls;
  std::lock_guard<std::mutex> status(status_mutex_);
  latest_ = std::move(f);
}

std::shared_ptr<const SceneModel> SimulationLoop::model() const {
  std::lock_guard<std::mutex> status(status_mutex_);
  return latest_.model;
}

FrameSnapshot SimulationLoop::snapshot() const {
  FrameSnapshot f;
  {
    std::lock_guard<std::mutex> status(status_mutex_);
    f = latest_;
  }
  if (f.model && f.model->surface) f.motion = f.model->surface->motionAt(f.time);
  return f;
}

LoopTiming SimulationLoop::timing() const {
  std::lock_guard<std::mutex> status(status_mutex_);
  return timing_;
}

std::string SimulationLoop::lastError() const {
  std::lock_guard<std::mutex> status(status_mutex_);
  return last_error_;
}

std::vector<std::string> SimulationLoop::takeNotices() {
  std::lock_guard<std::mutex> status(status_mutex_);
  std::vector<std::string> out;
  out.swap(notices_);
  return out;
}

void SimulationLoop::notice(const std::string& text) {
  std::lock_guard<std::mutex> status(status_mutex_);
  if (notices_.size() < 100) notices_.push_back(text);  // nobody reading: keep the first
}

void SimulationLoop::onRecoveredStep() {
  const SceneModel recovery = evsim::recoveryModel(*model_);
  notice("step at t = " + std::to_string(data_.time - model_->time_step) + " s rejected: " +
         data_.last_error + "; recovered: this step solved with the status method, " +
         std::to_string(recovery.contact.max_activation_loops) + " activation loops and " +
         std::to_string(recovery.contact.max_subdivisions) +
         " halvings; the scene's options apply again from the next step");
}

void SimulationLoop::onFailedStep() {
  paused_ = true;
  const std::string error = "paused at t = " + std::to_string(data_.time) +
                            " s: the step cannot be solved even with the recovery options (" +
                            data_.last_error +
                            "); reset the scene, load another, or change the solver options "
                            "and unpause";
  {
    std::lock_guard<std::mutex> status(status_mutex_);
    last_error_ = error;
  }
  notice(error);
}

double SimulationLoop::runFrame() {
  const int steps = timing().steps_per_frame;
  double simulated = 0.0;
  for (int k = 0; k < steps && running_; ++k) {
    // The state lock is taken per step and handed to waiting callers between
    // steps (commands and services wait at most one step); the publisher
    // reads the state shared after each step and never waits for one.
    while (waiters_ > 0) std::this_thread::yield();
    std::lock_guard<std::mutex> lock(mutex_);
    if (paused_ || !model_) break;
    if (pilot_) shareNavigation(pilot_->control(*model_, &data_));
    bool recovered = false;
    if (stepOrRecover(*model_, &data_, &recovered) != StepStatus::kOk) {
      onFailedStep();
      if (pilot_) {  // the recovery failed too: the navigation ends
        pilot_->observe(data_, /*step_failed=*/true);
        endNavigation("the simulation paused: " + lastError());
      }
      shareState();  // (paused, or the same state)
      break;
    }
    if (recovered) onRecoveredStep();
    if (pilot_) {
      pilot_->observe(data_, /*step_failed=*/false);
      if (pilot_->done()) endNavigation("");
    }
    {
      std::lock_guard<std::mutex> status(status_mutex_);
      last_error_.clear();  // steps succeed again
      for (std::string& n : data_.notices) notices_.push_back(std::move(n));
    }
    data_.notices.clear();
    simulated += model_->time_step;
    recordWrenches();
    shareState();
  }
  return simulated;
}

void SimulationLoop::recordWrenches() {
  const size_t n = data_.drives.size();
  if (wrench_cutoff_hz_ > 0.0 && wrench_filters_.size() != n)
    wrench_filters_.assign(n, WrenchLowPass(wrench_cutoff_hz_));
  std::lock_guard<std::mutex> status(status_mutex_);
  wrench_samples_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const DriveWrench& w = wrench_cutoff_hz_ > 0.0
                               ? wrench_filters_[i].update(data_.drives[i], model_->time_step)
                               : data_.drives[i];
    auto& samples = wrench_samples_[i];
    if (samples.size() >= kMaxWrenchSamples) samples.erase(samples.begin());
    samples.push_back({data_.time, w});
  }
}

std::vector<std::vector<WrenchSample>> SimulationLoop::takeWrenches() {
  std::lock_guard<std::mutex> status(status_mutex_);
  std::vector<std::vector<WrenchSample>> taken(wrench_samples_.size());
  std::swap(taken, wrench_samples_);
  wrench_samples_.resize(taken.size());
  return taken;
}

void SimulationLoop::setWrenchCutoff(double cutoff_hz) {
  auto lock = lockForCaller();
  wrench_cutoff_hz_ = cutoff_hz;
  wrench_filters_.clear();
}

void SimulationLoop::run() {
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period_s_));
  auto deadline = Clock::now();
  auto window_start = deadline;
  double window_sim_s = 0.0;
  while (running_) {
    const auto frame_start = Clock::now();
    const double simulated = runFrame();
    const auto now = Clock::now();
    deadline += period;
    {
      std::lock_guard<std::mutex> status(status_mutex_);
      timing_.frame_ms = std::chrono::duration<double, std::milli>(now - frame_start).count();
      ++timing_.frames;
      window_sim_s += simulated;
      const double window_s = std::chrono::duration<double>(now - window_start).count();
      if (window_s >= 1.0 || timing_.frames * period_s_ < 1.0) {  // first second: so far
        timing_.real_time_factor = window_sim_s / window_s;
      }
      if (window_s >= 1.0) {
        window_start = now;
        window_sim_s = 0.0;
      }
      if (now > deadline + period) {
        ++timing_.overruns;
        deadline = now;  // restart the schedule rather than bursting to catch up
      }
    }
    std::this_thread::sleep_until(deadline);
  }
}

}  // namespace evsim
