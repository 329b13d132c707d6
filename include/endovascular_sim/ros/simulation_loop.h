// The fixed-step simulation loop of the node (ROS-free): a thread that runs
// frames of a fixed number of steps (1 / (rate dt), as the scene's time step
// asks) paced by the wall clock. Simulated time only ever advances by whole
// steps, never by wall-clock differences; a frame that ends more than one
// period late is counted as an overrun and the schedule restarts from now
// (no burst of catch-up frames). Everything here is safe to call from other
// threads while the loop runs.
//
// A step that the scene's options cannot solve is solved at once with the
// recovery options, as every runner does (stepOrRecover, sim/simulation.h);
// if even that fails, the loop pauses with an error at the last good
// state. Each recovery and failure is told in notices.
//
// The loop can run the core's autopilot (sim/autopilot.h) to a named
// vessel: it sets the drive commands before every step and watches each
// step's outcome. A manual command, a reset or a new scene pre-empts it.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "endovascular_sim/ros/frame_snapshot.h"
#include "endovascular_sim/sim/autopilot.h"

namespace evsim {

/// The autopilot's state as the NavigateTo action reports it.
struct NavigationStatus {
  long id{0};  // of the navigation started last (0: none yet)
  bool active{false};
  bool done{false};    // ended: reached, failed or pre-empted
  std::string phase;   // the autopilot's phase (phaseName)
  std::string vessel;  // the vessel the tip is in
  std::string target;
  double remaining_path{0.0};       // [m] along the centrelines
  AutopilotReport report;           // when done
  std::vector<std::string> events;  // phase lines since the last navigation() call
};

class SimulationLoop {
 public:
  /// rate: frames per second [Hz].
  explicit SimulationLoop(double rate_hz);
  ~SimulationLoop();
  SimulationLoop(const SimulationLoop&) = delete;
  SimulationLoop& operator=(const SimulationLoop&) = delete;

  void start();
  void stop();

  /// Replaces the scene (fresh data at its initial state). With use_script
  /// false the scene's scripted commands are skipped.
  void setScene(std::shared_ptr<const SceneModel> model, bool use_script);
  /// Back to the scene's initial state (commands cleared, time 0).
  void reset();
  void setPaused(bool paused);
  /// Sets a device's command; returns why it was refused ("" when accepted).
  std::string setCommand(const std::string& device, const DriveCommand& command);
  /// Detaches a device's section (a coil from its pusher) at the current
  /// state; returns why it was refused ("" when done, state kept if not).
  std::string detach(const std::string& device);
  /// Replaces the contact options (validated; returns why refused, "" if not).
  std::string setContactOptions(const ContactOptions& options);

  /// Starts the autopilot toward `target` (a vessel name) with `device`'s
  /// tip ("": the innermost device); the rest of the scene's script is
  /// skipped. Returns why it was refused ("" when started; *id its id).
  std::string startNavigation(const std::string& target, const std::string& device,
                              const AutopilotOptions& options, long* id);
  /// Ends the running navigation with `why` as its reason, devices stopped.
  void stopNavigation(const std::string& why);
  /// The navigation's status; takes its phase lines since the last call.
  NavigationStatus navigation();

  std::shared_ptr<const SceneModel> model() const;
  FrameSnapshot snapshot() const;
  LoopTiming timing() const;
  /// Why the last rejected step was rejected ("" once a step succeeds again).
  std::string lastError() const;
  /// What happened since the last call (rejections, recoveries, refused
  /// script commands, drives stopped at their limits), oldest first.
  std::vector<std::string> takeNotices();

  /// Every step's drive wrenches since the last call, per device, oldest
  /// first (the node publishes them at the simulation's rate). With a
  /// cutoff [Hz] > 0 (setWrenchCutoff) they are low-passed step by step.
  /// At most kMaxWrenchSamples a device are kept between two calls.
  std::vector<std::vector<WrenchSample>> takeWrenches();
  /// 0: the raw wrench; else the low-pass cutoff [Hz] (reset by a new scene).
  void setWrenchCutoff(double cutoff_hz);
  static constexpr size_t kMaxWrenchSamples = 100000;

 private:
  void run();
  /// The lock for callers other than the loop: they announce themselves so
  /// that the loop lets them in before its next step (a plain mutex would let
  /// the stepping thread take it again and again).
  std::unique_lock<std::mutex> lockForCaller() const;
  /// Runs one frame's steps; returns the simulated time [s].
  double runFrame();

  /// Copies what the publisher shows into latest_ (mutex_ held).
  void shareState();
  /// A step was solved only with the recovery options (mutex_ held): tells it.
  void onRecoveredStep();
  /// A step failed even with them (mutex_ held): pauses with the error.
  void onFailedStep();
  void notice(const std::string& text);  // (status_mutex_ not held)
  /// Ends the autopilot (mutex_ held): its report kept (`why` the reason
  /// when it had not ended by itself), the devices stopped.
  void endNavigation(const std::string& why);
  /// Shares the autopilot's status (mutex_ held).
  void shareNavigation(const std::string& event);
  /// Appends the last step's wrenches (mutex_ held).
  void recordWrenches();

  const double period_s_;
  mutable std::mutex mutex_;  // the simulation: held for a whole step
  std::shared_ptr<const SceneModel> model_;
  SimData data_;
  bool use_script_{true};
  bool paused_{false};

  mutable std::mutex status_mutex_;  // what others read: held only to copy
  FrameSnapshot latest_;             // the state after the last step
  LoopTiming timing_;
  std::string last_error_;
  std::vector<std::string> notices_;
  std::unique_ptr<Autopilot> pilot_;                       // the running navigation (mutex_)
  NavigationStatus navigation_;                            // (status_mutex_)
  double wrench_cutoff_hz_{0.0};                           // (mutex_)
  std::vector<WrenchLowPass> wrench_filters_;              // per device (mutex_)
  std::vector<std::vector<WrenchSample>> wrench_samples_;  // (status_mutex_)

  mutable std::atomic<int> waiters_{0};
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace evsim
