// `evsim bench SCENE --windows N`: a paired comparison on the scene's hard
// stretch. One run of the scene saves its state at N steps spread over the
// measured stretch; from each, the scene and every `--variant` (a scene
// file with the same devices: other contact options, another tolerance)
// step `--window-steps` steps. A window is short enough that a chaotic
// path (a coil whipping round a dome) has not yet left the run's, so the
// loops, rows and halvings of two variants count the same steps' work, and
// the scene's own windows repeat the run's steps to the bit (the state
// file is exact): the output says whether they did.
#include "bench_windows.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <vector>

#include "commands.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/state_file.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

/// What a scene's windows cost, summed over all of them.
struct WindowTotals {
  std::vector<double> ms;  // every step's wall time [ms]
  long extra_loops{0};     // activation loops after the first
  LateRows late;           // rows found after the first LCP, by kind
  long rows{0};            // rows of the steps' last LCPs
  int halved{0};           // steps halved at least once
  double deepest{0.0};     // [m] the deepest penetration a step ended with
  std::vector<int> loops;  // every step's loops (for the comparison with the run)
};

/// Steps `model` from the saved state for `count` steps, adding to *t.
/// False (the reason on stderr) when a step fails.
bool runWindow(const SceneModel& model, const std::string& state, long count, bool strict,
               WindowTotals* t) {
  SimData data = makeData(model);
  try {
    loadState(model, state, &data);
  } catch (const std::exception& e) {  // (written by this run: not expected)
    std::cerr << "evsim: " << model.name << ": a window's state: " << e.what() << "\n";
    return false;
  }
  for (long k = 0; k < count; ++k) {
    bool recovered = false;
    const StepStatus status = strict ? step(model, &data) : stepOrRecover(model, &data, &recovered);
    if (status != StepStatus::kOk) {
      std::cerr << "evsim: " << model.name << ": window from " << state << ": step "
                << data.step + 1 << " at t = " << data.time << " s failed: " << data.last_error
                << "\n";
      return false;
    }
    const StepStats& s = data.stats;
    const ContactStats& c = s.contact;
    t->ms.push_back(s.wall_ms);
    t->extra_loops += std::max(c.activation_loops - 1, 0);
    t->late += c.late_rows;
    t->rows += c.contacts;
    t->halved += s.subdivisions > 0;
    t->deepest = std::max(t->deepest, c.max_penetration_m);
    t->loops.push_back(c.activation_loops);
  }
  return true;
}

double quantileOf(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * v.size()))];
}

void printTotals(const std::string& label, const WindowTotals& t) {
  double total = 0.0;
  for (double x : t.ms) total += x;
  std::printf("  %-28s %8ld %6d %6d %6d %7.1f %6d %8.2f %8.3f %8.3f %8.3f\n", label.c_str(),
              t.extra_loops, t.late.wall, t.late.pair, t.late.lumen,
              static_cast<double>(t.rows) / t.ms.size(), t.halved, t.deepest * 1e6,
              quantileOf(t.ms, 0.5), total / t.ms.size(), quantileOf(t.ms, 0.99));
}

/// A temporary folder for the windows' states, removed when done (where it
/// cannot be made, saving the first state says so).
class StateFolder {
 public:
  StateFolder() {
    std::error_code ec;
    path_ = fs::temp_directory_path(ec);
    if (ec) path_ = "/tmp";
    path_ /= "evsim_windows_" + std::to_string(static_cast<long>(::getpid()));
    fs::create_directories(path_, ec);
  }
  ~StateFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  StateFolder(const StateFolder&) = delete;
  StateFolder& operator=(const StateFolder&) = delete;
  std::string file(int i) const { return (path_ / ("window_" + std::to_string(i))).string(); }

 private:
  fs::path path_;
};

}  // namespace

std::string loadVariants(const SceneModel& model, const std::vector<std::string>& files,
                         std::vector<SceneModel>* variants) {
  for (const std::string& file : files) {
    try {
      variants->push_back(buildSceneModel(loadSceneFile(resolveScenePath(file))));
    } catch (const std::exception& e) {
      return "--variant " + file + ": " + e.what();
    }
    SceneModel& v = variants->back();
    bool same = v.devices.size() == model.devices.size();
    for (size_t d = 0; same && d < v.devices.size(); ++d)
      same = v.devices[d].name == model.devices[d].name &&
             v.devices[d].num_nodes == model.devices[d].num_nodes;
    if (!same)
      return "--variant " + file + ": its devices differ from scene " + model.name +
             "'s (names and node counts): its windows cannot start from the scene's states";
    v.name = model.name;  // (the states are the scene's)
  }
  return "";
}

int benchWindows(const SceneModel& model, const std::vector<SceneModel>& variants,
                 const BenchWindows& o, long warmup, long steps, bool strict) {
  // Window i starts after step warmup + i (steps - K) / (N - 1).
  const int n = o.count;
  std::vector<long> starts(n);
  for (int i = 0; i < n; ++i) starts[i] = warmup + (n > 1 ? i * (steps - o.steps) / (n - 1) : 0);
  const StateFolder folder;
  WindowTotals run;  // the run's own steps in the windows
  {
    SimData data = makeData(model);
    int next = 0;
    std::vector<char> inside(warmup + steps + 1, 0);
    for (long s : starts)
      for (long k = s; k < s + o.steps; ++k) inside[k] = 1;
    for (long k = 0; k < warmup + steps && next <= n; ++k) {
      while (next < n && starts[next] == k) {
        if (!saveState(model, data, folder.file(next))) {
          std::cerr << "evsim bench: cannot write a window's state to " << folder.file(next)
                    << "\n";
          return kExitFailure;
        }
        ++next;
      }
      if (next == n && k >= starts[n - 1] + o.steps) break;
      bool recovered = false;
      const StepStatus status =
          strict ? step(model, &data) : stepOrRecover(model, &data, &recovered);
      if (status != StepStatus::kOk) {
        std::cerr << "evsim: " << model.name << ": step " << data.step + 1
                  << " at t = " << data.time << " s failed: " << data.last_error << "\n";
        return kExitFailure;
      }
      if (inside[k]) run.loops.push_back(data.stats.contact.activation_loops);
    }
  }
  std::printf(
      "windows: %d states from t = %.3f to %.3f s, %ld steps from each (the run's states; a "
      "paired comparison)\n",
      n, starts.front() * model.time_step, starts.back() * model.time_step, o.steps);
  std::printf("  %-28s %8s %6s %6s %6s %7s %6s %8s %8s %8s %8s\n", "scene", "loops>1", "wall",
              "pair", "lumen", "rows", "halved", "deep[um]", "median", "mean", "p99 [ms]");
  std::vector<const SceneModel*> all{&model};
  for (const SceneModel& v : variants) all.push_back(&v);
  for (size_t m = 0; m < all.size(); ++m) {
    WindowTotals t;
    for (int i = 0; i < n; ++i)
      if (!runWindow(*all[m], folder.file(i), o.steps, strict, &t)) return kExitFailure;
    printTotals(
        m == 0 ? model.name + " (the scene)" : fs::path(o.variants[m - 1]).filename().string(), t);
    if (m == 0)
      std::printf("  the scene's windows repeat the run's loops step for step: %s\n",
                  t.loops == run.loops ? "yes" : "no");
  }
  return kExitOk;
}

}  // namespace evsim
