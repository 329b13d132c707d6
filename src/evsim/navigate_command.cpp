// `evsim navigate`: the autopilot (sim/autopilot.h) headless: a line per
// phase, then the summary as one JSON object, on stdout.
#include <algorithm>
#include <fstream>
#include <iostream>

#include "commands.h"
#include "endovascular_sim/sim/autopilot.h"
#include "output_paths.h"
#include "endovascular_sim/sim/step_json.h"

namespace evsim {

int navigateScene(const NavigateOptions& o) {
  std::ofstream steps;
  if (!o.steps_json.empty()) {
    const std::string why = checkWritableFile(o.steps_json);
    if (!why.empty()) {
      std::cerr << "evsim: --steps-json: " << why << "\n";
      return kExitBadInput;
    }
    steps.open(o.steps_json);
  }
  const SceneModel model = loadScene(o.scene);  // LoadError: main reports it
  // Without --target: the scene's first target (a procedure scene has one).
  std::string target = o.target, device = o.device;
  if (target.empty()) {
    const auto vessel_target = std::find_if(model.targets.begin(), model.targets.end(),
                                            [](const Target& t) { return t.spec.aneurysm < 0; });
    if (vessel_target == model.targets.end()) {
      std::cerr << "evsim: navigate: scene '" << model.name
                << "' names no targets: give one with --target NAME (evsim vessels " << o.scene
                << " lists its vessels)\n";
      return kExitBadInput;
    }
    target = vessel_target->spec.vessel;
    if (device.empty()) device = vessel_target->spec.device;
  }
  SimData data = makeData(model);
  AutopilotOptions options;
  options.timeout = o.timeout;
  Autopilot pilot(model, data, target, device, options);  // LoadError: main reports it
  const VesselAtlas& atlas = *model.atlas;
  if (!o.json_only) {
    std::string plan;
    for (int v : atlas.path(data.tips[pilot.device()].vessel, pilot.target()))
      plan += (plan.empty() ? "" : " -> ") + atlas.vessels()[v].name;
    std::cout << "navigate " << model.name << ": " << model.devices[pilot.device()].name << " to "
              << atlas.vessels()[pilot.target()].name << " (" << plan << ")\n";
  }
  // (pilot: the plan and names; the run steps its own from the same state)
  const AutopilotReport r = runAutopilot(
      model, &data, target, device, options,
      [&](const std::string& line) {
        if (!o.json_only) std::cout << line << "\n";
      },
      [&](const SimData& stepped) {
        if (steps.is_open()) steps << stepJson(model, stepped) << "\n";
      });
  std::cout << autopilotJson(model, data, pilot.target(), pilot.device(), r) << "\n";
  return r.reached ? kExitOk : kExitFailure;
}

}  // namespace evsim
