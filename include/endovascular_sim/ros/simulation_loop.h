// The fixed-step simulation loop of the node (ROS-free): a thread that runs
// frames of a fixed number of steps (1 / (rate dt), as the scene's time step
// asks) paced by the wall clock. Simulated time only ever advances by whole
// steps, never by wall-clock differences; a frame that ends more than one
// period late is counted as an overrun and the schedule restarts from now
// (no burst of catch-up frames). Everything here is safe to call from other
// threads while the loop runs.
//
// A step that cannot be solved keeps the state and is tried again next
// frame. After kRejectionsBeforeRecovery rejections of the same state the
// loop applies its recovery for that one step (the status method, more
// activation loops, halving on: recoveryOptions); if even that fails, it
// pauses with an error. Each rejection and recovery is told in notices.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "endovascular_sim/ros/frame_snapshot.h"

namespace evsim {

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

  std::shared_ptr<const SceneModel> model() const;
  FrameSnapshot snapshot() const;
  LoopTiming timing() const;
  /// Why the last rejected step was rejected ("" once a step succeeds again).
  std::string lastError() const;
  /// What happened since the last call (rejections, recoveries, refused
  /// script commands, drives stopped at their limits), oldest first.
  std::vector<std::string> takeNotices();

  /// Rejections of one state before the recovery step (with
  /// evsim::recoveryModel, sim/simulation.h).
  static constexpr int kRejectionsBeforeRecovery = 3;

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
  /// A step was rejected (mutex_ held): counts it, recovers or pauses.
  /// Returns true when the recovery step succeeded.
  bool onRejectedStep();
  void notice(const std::string& text);  // (status_mutex_ not held)

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
  int rejections_{0};  // of the current state (mutex_)

  mutable std::atomic<int> waiters_{0};
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace evsim
