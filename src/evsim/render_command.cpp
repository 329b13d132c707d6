// `evsim render`: runs a scene (its script, or the autopilot to a vessel)
// and writes its virtual fluoroscopy as PNG frames (xray_recorder.h).
#include <cmath>
#include <iostream>
#include <stdexcept>

#include "commands.h"
#include "endovascular_sim/sim/autopilot.h"
#include "output_paths.h"
#include "xray_recorder.h"

namespace evsim {

int renderScene(const RenderOptions& o) {
  const std::string bad_folder = prepareOutputFolder(o.out);
  if (!bad_folder.empty()) {
    std::cerr << "evsim: --out: " << bad_folder << "\n";
    return kExitBadInput;
  }
  const SceneModel model = loadScene(o.scene);  // LoadError: main reports it
  XrayRecorderOptions ro;
  ro.out = o.out;
  ro.rate = o.rate;
  ro.lao = o.lao;
  ro.cranial = o.cranial;
  ro.pixels = o.pixels;
  ro.inject = o.inject;
  ro.inject_device = o.inject_device;
  ro.inject_vessel = o.inject_vessel;
  ro.roadmap = o.roadmap;
  std::unique_ptr<XrayRecorder> recorder;
  try {
    recorder = std::make_unique<XrayRecorder>(model, ro);
  } catch (const std::invalid_argument& e) {
    std::cerr << "evsim: render: " << e.what() << "\n";
    return kExitBadInput;
  }
  SimData data = makeData(model);
  std::string why;
  if (!recorder->start(data, &why)) {
    std::cerr << "evsim: " << why << "\n";
    return kExitFailure;
  }
  bool written = true;
  double end = o.duration > 0.0 ? o.duration : model.duration;
  if (!o.navigate.empty()) {
    AutopilotOptions options;
    if (o.duration > 0.0) options.timeout = o.duration;
    const AutopilotReport r = runAutopilot(
        model, &data, o.navigate, "", options,
        [](const std::string& line) { std::cout << line << "\n"; },
        [&](const SimData& stepped) {
          if (written && !recorder->onStep(stepped, &why)) written = false;
        });
    std::cout << (r.reached ? "reached " : "not reached ") << o.navigate << " at t = " << r.time
              << " s\n";
    // The devices held where the autopilot left them, to --duration.
    for (DriveCommand& c : data.commands) c = DriveCommand{};
    if (o.duration <= 0.0) end = data.time;
  }
  const long steps = std::lround(std::max(0.0, end - data.time) / model.time_step);
  for (long k = 0; k < steps && written; ++k) {
    bool recovered = false;
    if (stepOrRecover(model, &data, &recovered) != StepStatus::kOk) {
      std::cerr << "evsim: step " << data.step + 1 << " failed: " << data.last_error << "\n";
      return kExitFailure;
    }
    data.notices.clear();
    written = recorder->onStep(data, &why);
  }
  if (!written) {
    std::cerr << "evsim: " << why << "\n";
    return kExitFailure;
  }
  std::cout << recorder->summary() << "\n";
  return kExitOk;
}

}  // namespace evsim
