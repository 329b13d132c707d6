// `evsim run`: steps a scene headless and prints progress or one JSON
// object per step; optionally dumps each step's LCP and saves the last
// good state.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "endovascular_sim/sim/simulation.h"
#include "endovascular_sim/sim/state_file.h"
#include "endovascular_sim/sim/step_json.h"
#include "output_paths.h"
#include "scene_source.h"
#include "vtk_output.h"

namespace evsim {

namespace {

/// The output paths checked before the run (a bad one is refused before
/// any step, not after the whole run): "" or what is wrong.
std::string checkOutputs(const RunOptions& o) {
  if (!o.save_state.empty()) {
    const std::string why = checkWritableFile(o.save_state);
    if (!why.empty()) return "--save-state: " + why;
  }
  for (const auto& [flag, folder] : {std::pair{"--dump-lcp", &o.dump_lcp}, {"--vtk", &o.vtk}}) {
    if (folder->empty()) continue;
    const std::string why = prepareOutputFolder(*folder);
    if (!why.empty()) return std::string(flag) + ": " + why;
  }
  return "";
}

/// The progress line: the first device's insertion and tip, every tip's
/// vessel, the contacts and the mean step time.
void printProgress(const SceneModel& model, const SimData& data, double mean_step_ms) {
  const DeviceState& d = data.devices.front();
  const Vec3& tip = d.position.back();
  std::cout << "t=" << data.time << " s  " << model.devices.front().name
            << " inserted=" << d.inserted_length * 1e3 << " mm  tip=(" << tip.x() * 1e3 << ", "
            << tip.y() * 1e3 << ", " << tip.z() * 1e3 << ") mm";
  if (model.atlas)
    for (size_t i = 0; i < data.tips.size(); ++i)
      std::cout << "  " << model.devices[i].name << " in "
                << model.atlas->vessels()[data.tips[i].vessel].name << " at "
                << data.tips[i].depth * 1e3 << " mm";
  std::cout << "  contacts=" << data.stats.contact.contacts << "  mean step " << mean_step_ms
            << " ms" << (data.stats.asleep ? "  asleep" : "") << "\n";
}

/// The step's LCP written to the --dump-lcp folder; false when it cannot be.
bool dumpLcp(const RunOptions& o, const SimData& data) {
  if (!data.record_lcp || data.lcp.q.size() == 0) return true;
  char name[64];
  std::snprintf(name, sizeof(name), "/step_%07ld.lcp", data.step);
  if (writeLcpRecord(data.lcp, o.dump_lcp + name)) return true;
  std::cerr << "evsim: cannot write " << o.dump_lcp + name << "\n";
  return false;
}

}  // namespace

int runScene(const RunOptions& o) {
  const std::string bad_output = checkOutputs(o);
  if (!bad_output.empty()) {
    std::cerr << "evsim: " << bad_output << "\n";
    return kExitBadInput;
  }
  const SceneModel model =
      buildSceneModel(sceneSpecOf(o.scene, o.centerline));  // LoadError: main reports it
  SimData data = makeData(model);
  if (!o.load_state.empty()) loadState(model, o.load_state, &data);
  const long steps = o.steps >= 0
                         ? o.steps
                         : std::lround(std::max(0.0, model.duration - data.time) / model.time_step);
  auto save = [&]() {
    if (o.save_state.empty() || saveState(model, data, o.save_state)) return true;
    std::cerr << "evsim: cannot write " << o.save_state << "\n";
    return false;
  };
  data.record_lcp = !o.dump_lcp.empty();
  VtkSeries frames(o.vtk);
  const long frame_every = std::max(1L, std::lround(1.0 / (o.vtk_rate * model.time_step)));
  auto frame = [&]() {
    std::string why;
    if (o.vtk.empty() || frames.write(model, data, &why)) return true;
    std::cerr << "evsim: --vtk: " << why << "\n";
    return false;
  };
  if (!frame()) return kExitFailure;  // the start
  const long report_every = std::max(1L, static_cast<long>(0.1 / model.time_step + 0.5));
  double wall_ms = 0.0;
  for (long k = 0; k < steps; ++k) {
    bool recovered = false;
    const StepStatus status =
        o.strict ? step(model, &data) : stepOrRecover(model, &data, &recovered);
    if (recovered)
      std::cerr << "evsim: step " << data.step << " at t = " << data.time
                << " s solved with the recovery options\n";
    if (status != StepStatus::kOk) {
      std::cerr << "evsim: step " << data.step + 1 << " failed: " << data.last_error << "\n";
      save();  // the last good state, to study the failing step from
      return kExitFailure;
    }
    for (const std::string& notice : data.notices) std::cerr << "evsim: " << notice << "\n";
    data.notices.clear();
    wall_ms += data.stats.wall_ms;
    if (data.step % frame_every == 0 && !frame()) return kExitFailure;
    if (!dumpLcp(o, data)) return kExitFailure;
    if (o.json)
      std::cout << stepJson(model, data) << "\n";
    else if (data.step % report_every == 0 || k + 1 == steps)
      printProgress(model, data, wall_ms / (k + 1));
  }
  std::string why;
  if (!o.vtk.empty() && !frames.finish(&why)) {
    std::cerr << "evsim: --vtk: " << why << "\n";
    return kExitFailure;
  }
  return save() ? kExitOk : kExitFailure;
}

}  // namespace evsim
