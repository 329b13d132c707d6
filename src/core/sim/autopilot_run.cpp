// The autopilot run headless (sim/autopilot.h): what `evsim navigate`,
// `evsim bench navigation` and the tests step.
#include <sstream>

#include "endovascular_sim/sim/autopilot.h"

namespace evsim {

AutopilotReport runAutopilot(const SceneModel& model, SimData* data, const std::string& target,
                             const std::string& device, const AutopilotOptions& options,
                             const std::function<void(const std::string&)>& on_line,
                             const std::function<void(const SimData&)>& on_step) {
  Autopilot pilot(model, *data, target, device, options);
  // A bounded number of steps: the autopilot ends by its timeout before.
  const long max_steps = static_cast<long>((options.timeout + 1.0) / model.time_step);
  std::string failure;
  for (long k = 0; k < max_steps && !pilot.done(); ++k) {
    const std::string line = pilot.control(model, data);
    if (!line.empty() && on_line) on_line(line);
    bool recovered = false;
    const StepStatus status = stepOrRecover(model, data, &recovered);
    if (recovered && on_line) {
      std::ostringstream m;
      m << "step at t = " << data->time << " s recovered with the recovery options";
      on_line(m.str());
    }
    pilot.observe(*data, status != StepStatus::kOk);
    if (on_step) on_step(*data);
    data->notices.clear();
    if (status != StepStatus::kOk) {
      failure = "a step failed even with the recovery options: " + data->last_error;
      if (on_line) on_line(failure);
      break;
    }
  }
  AutopilotReport report = pilot.report();
  if (!report.reached && report.reason.empty())
    report.reason = failure.empty() ? "out of steps" : failure;
  return report;
}

}  // namespace evsim
