// The NavigateTo action (action/NavigateTo.action) of the node: a goal
// names a vessel; the SimulationLoop's autopilot drives the devices there
// while this server relays its feedback (the tip's vessel, the path left,
// phase lines) and its result. A cancel or a new goal pre-empts the goal; a
// manual command, a reset or a new scene aborts it with the reason.
#pragma once

#include <actionlib/server/simple_action_server.h>
#include <ros/ros.h>

#include <memory>

#include "endovascular_sim/NavigateToAction.h"
#include "endovascular_sim/ros/simulation_loop.h"

namespace evsim {

class NavigateActionServer {
 public:
  /// Serves `navigate_to` in `nh`'s namespace for the loop's scene.
  NavigateActionServer(ros::NodeHandle nh, SimulationLoop* loop);
  ~NavigateActionServer();

  /// Feedback rate [Hz] (wall clock).
  static constexpr double kFeedbackRateHz = 5.0;

 private:
  void execute(const endovascular_sim::NavigateToGoalConstPtr& goal);

  SimulationLoop* loop_;
  actionlib::SimpleActionServer<endovascular_sim::NavigateToAction> server_;
};

}  // namespace evsim
