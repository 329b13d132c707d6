// The NavigateTo action (action/NavigateTo.action) of the node. Declared and
// documented in endovascular_sim/ros/navigate_action.h.
#include "endovascular_sim/ros/navigate_action.h"

#include <cmath>

namespace evsim {
namespace {

endovascular_sim::NavigateToResult resultOf(const NavigationStatus& s) {
  endovascular_sim::NavigateToResult r;
  r.reached = s.report.reached;
  r.reason = s.report.reason;
  r.time = s.report.time;
  r.retries = s.report.retries;
  r.peak_wall_force = s.report.peak_wall_force;
  r.failed_steps = s.report.failed_steps;
  r.remaining_path = s.remaining_path;
  r.final_vessel = s.vessel;
  return r;
}

}  // namespace

NavigateActionServer::NavigateActionServer(ros::NodeHandle nh, SimulationLoop* loop)
    : loop_(loop),
      server_(
          nh, "navigate_to", [this](const auto& goal) { execute(goal); },
          /*auto_start=*/false) {
  server_.start();
}

NavigateActionServer::~NavigateActionServer() { server_.shutdown(); }

void NavigateActionServer::execute(const endovascular_sim::NavigateToGoalConstPtr& goal) {
  AutopilotOptions options;
  if (!(std::isfinite(goal->timeout) && goal->timeout >= 0.0 && goal->timeout <= 3600.0)) {
    endovascular_sim::NavigateToResult r;
    r.reason = "timeout must lie in [0, 3600] s (0: the default, 90 s)";
    ROS_WARN_STREAM("navigate_to refused: " << r.reason);
    server_.setAborted(r, r.reason);
    return;
  }
  if (goal->timeout > 0.0) options.timeout = goal->timeout;
  long id = 0;
  const std::string why = loop_->startNavigation(goal->target, goal->device, options, &id);
  if (!why.empty()) {
    endovascular_sim::NavigateToResult r;
    r.reason = why;
    ROS_WARN_STREAM("navigate_to refused: " << why);
    server_.setAborted(r, why);
    return;
  }
  ROS_INFO_STREAM("navigate_to '" << goal->target << "' started");
  ros::WallRate rate(kFeedbackRateHz);
  while (ros::ok()) {
    const NavigationStatus s = loop_->navigation();
    if (s.id != id) {  // another goal took over (it pre-empted this one)
      server_.setPreempted(endovascular_sim::NavigateToResult{}, "pre-empted by a new goal");
      return;
    }
    for (const std::string& e : s.events) ROS_INFO_STREAM("navigate_to: " << e);
    if (s.done) {
      const auto result = resultOf(s);
      if (result.reached)
        server_.setSucceeded(result, "reached " + goal->target);
      else
        server_.setAborted(result, result.reason);
      return;
    }
    if (server_.isPreemptRequested()) {
      loop_->stopNavigation("cancelled by the client");
      server_.setPreempted(resultOf(loop_->navigation()), "cancelled");
      return;
    }
    endovascular_sim::NavigateToFeedback f;
    f.vessel = s.vessel;
    f.remaining_path = s.remaining_path;
    f.phase = s.phase;
    f.event = s.events.empty() ? "" : s.events.back();
    server_.publishFeedback(f);
    rate.sleep();
  }
  loop_->stopNavigation("the node is shutting down");
  server_.setAborted(endovascular_sim::NavigateToResult{}, "the node is shutting down");
}

}  // namespace evsim
