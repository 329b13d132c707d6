// `evsim bench`: step-time statistics of a scene, by default over its whole
// scripted procedure (the scene's `duration`), overall and per phase:
//
//   free      before the first contact
//   contact   in contact while a drive moves a device
//   inserted  in contact with every drive at rest (fully inserted, or its
//             command ended): what a device resting in the vessels costs
//
// Each line gives the median, p99 and worst step and the real-time factor
// (simulated time / wall time) of the phase.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <vector>

#include "bench_windows.h"
#include "commands.h"
#include "endovascular_sim/sim/simulation.h"
#include "scene_variants.h"

namespace evsim {
namespace {

enum class Phase { kFree, kContact, kInserted };
constexpr const char* kPhaseNames[] = {"free", "contact", "inserted"};

/// One measured step.
struct BenchStep {
  double ms;        // wall time of the step [ms]
  int rows;         // rows of its last LCP (detected contacts)
  int forces;       // contacts with a positive force
  int loops;        // activation loops
  bool subdivided;  // the step was halved at least once
  bool asleep;      // the scene slept through it
  Phase phase;
  LateRows late;  // rows its loops found after the first LCP, by kind
};

/// The p-th quantile (element p n of the sorted values; the median at 0.5).
template <typename T>
T quantile(std::vector<T> values, double p) {
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(p * values.size()))];
}

/// One line: steps, median, p99, worst [ms], real-time factor.
void printTimes(const char* label, const std::vector<BenchStep>& steps, double dt) {
  std::vector<double> ms;
  double total = 0.0;
  for (const BenchStep& b : steps) {
    ms.push_back(b.ms);
    total += b.ms;
  }
  if (ms.empty()) {
    std::printf("  %-9s %7d\n", label, 0);
    return;
  }
  std::printf("  %-9s %7zu %9.3f %9.3f %9.3f %9.3f %8.2f\n", label, ms.size(), quantile(ms, 0.5),
              total / ms.size(), quantile(ms, 0.99), quantile(ms, 1.0),
              ms.size() * dt * 1e3 / total);
}

void printContacts(const std::vector<BenchStep>& steps) {
  std::vector<int> rows, forces;
  int subdivided = 0, max_loops = 0, asleep = 0, extra_loops = 0;
  LateRows late;
  for (const BenchStep& b : steps) {
    extra_loops += std::max(b.loops - 1, 0);
    late += b.late;
    rows.push_back(b.rows);
    forces.push_back(b.forces);
    subdivided += b.subdivided;
    asleep += b.asleep;
    max_loops = std::max(max_loops, b.loops);
  }
  std::printf(
      "active contacts: median %d  max %d;  LCP rows: median %d  max %d;  steps subdivided %d;  "
      "most activation loops %d;  steps asleep %d\n",
      quantile(forces, 0.5), quantile(forces, 1.0), quantile(rows, 0.5), quantile(rows, 1.0),
      subdivided, max_loops, asleep);
  std::printf("loops after the first %d, for the rows found late: wall %d, pair %d, lumen %d\n",
              extra_loops, late.wall, late.pair, late.lumen);
}

/// Every phase and the whole stretch.
void printSummary(const std::vector<BenchStep>& steps, double dt) {
  std::printf("  %-9s %7s %9s %9s %9s %9s %8s\n", "phase", "steps", "median", "mean", "p99",
              "worst", "RTF");
  for (int p = 0; p < 3; ++p) {
    std::vector<BenchStep> part;
    for (const BenchStep& b : steps)
      if (static_cast<int>(b.phase) == p) part.push_back(b);
    printTimes(kPhaseNames[p], part, dt);
  }
  printTimes("whole", steps, dt);
  printContacts(steps);
}

/// True when any device's drive moved it in the last step.
bool driveMoved(const std::vector<DeviceState>& before, const std::vector<DeviceState>& after) {
  for (size_t i = 0; i < before.size(); ++i)
    if (before[i].inserted_length != after[i].inserted_length ||
        before[i].rotation_angle != after[i].rotation_angle)
      return true;
  return false;
}

/// Steps `model` from its start: `warmup` steps, then `steps` recorded;
/// *tips (when given): each device's tip at the end [m]. False (the reason
/// on stderr) when a step fails.
bool measure(const SceneModel& model, long warmup, long steps, bool strict,
             std::vector<BenchStep>* record, int* recoveries, std::vector<Vec3>* tips = nullptr) {
  SimData data = makeData(model);
  bool touched = false;  // a contact so far
  record->reserve(steps);
  for (long k = 0; k < warmup + steps; ++k) {
    const std::vector<DeviceState> before = data.devices;
    bool recovered = false;
    const StepStatus status = strict ? step(model, &data) : stepOrRecover(model, &data, &recovered);
    *recoveries += recovered;
    if (status != StepStatus::kOk) {
      std::cerr << "evsim: " << model.name << ": step " << data.step + 1 << " at t = " << data.time
                << " s failed: " << data.last_error << "\n";
      return false;
    }
    const StepStats& s = data.stats;
    touched = touched || s.contact.contacts > 0;
    if (k < warmup) continue;
    const Phase phase = !touched                           ? Phase::kFree
                        : driveMoved(before, data.devices) ? Phase::kContact
                                                           : Phase::kInserted;
    record->push_back({s.wall_ms, s.contact.contacts, s.contact.active_contacts,
                       s.contact.activation_loops, s.subdivisions > 0, s.asleep, phase,
                       s.contact.late_rows});
  }
  if (tips) {
    tips->clear();
    for (const DeviceState& d : data.devices) tips->push_back(d.position.back());
  }
  return true;
}

/// The p-th quantile of the steps' times [ms].
double quantileMs(const std::vector<BenchStep>& steps, double p) {
  std::vector<double> ms;
  for (const BenchStep& b : steps) ms.push_back(b.ms);
  return quantile(ms, p);
}
double medianMs(const std::vector<BenchStep>& steps) { return quantileMs(steps, 0.5); }

/// The scene's copies whose script speeds differ by k 1e-9 (k = 1..copies):
/// each one's median, p99, worst step, extra loops and halved steps, and
/// how far its tips end from the scene's; then the range over all. A coil's
/// path is chaotic: its p99 moves as much between such copies as between
/// builds that differ by round-off. False when a step fails.
bool benchCopies(const SceneSpec& spec, const BenchOptions& o, long steps,
                 const std::vector<BenchStep>& record, const std::vector<Vec3>& tips) {
  std::printf("copies (the script's speeds x (1 + k 1e-9)):\n");
  double median_low = medianMs(record), median_high = median_low;
  double p99_low = quantileMs(record, 0.99), p99_high = p99_low;
  for (int k = 1; k <= o.copies; ++k) {
    SceneSpec copy = spec;
    perturbScript(&copy, 1e-9 * k);
    const SceneModel model = buildSceneModel(copy);
    std::vector<BenchStep> copy_record;
    std::vector<Vec3> copy_tips;
    int recoveries = 0;
    if (!measure(model, o.warmup, steps, o.strict, &copy_record, &recoveries, &copy_tips))
      return false;
    int extra_loops = 0, halved = 0;
    double worst = 0.0;
    for (const BenchStep& b : copy_record) {
      extra_loops += std::max(b.loops - 1, 0);
      halved += b.subdivided;
      worst = std::max(worst, b.ms);
    }
    double apart = 0.0;  // [m] the farthest tip from the scene's
    for (size_t d = 0; d < tips.size() && d < copy_tips.size(); ++d)
      apart = std::max(apart, (copy_tips[d] - tips[d]).norm());
    const double median = medianMs(copy_record), p99 = quantileMs(copy_record, 0.99);
    std::printf(
        "  copy %d: median %.3f  p99 %.3f  worst %.3f ms;  loops after the first %d;  steps "
        "subdivided %d;  tips %.3g mm from the scene's\n",
        k, median, p99, worst, extra_loops, halved, apart * 1e3);
    median_low = std::min(median_low, median);
    median_high = std::max(median_high, median);
    p99_low = std::min(p99_low, p99);
    p99_high = std::max(p99_high, p99);
  }
  std::printf("  the scene and its %d copies: median %.3f-%.3f ms, p99 %.3f-%.3f ms\n", o.copies,
              median_low, median_high, p99_low, p99_high);
  return true;
}

}  // namespace

int benchScene(const BenchOptions& o) {
  SceneSpec spec = loadSceneFile(resolveScenePath(o.scene));
  if (o.elements > 0) setElementCount(&spec, o.elements);
  if (o.effects) {
    const std::string why = setEffects(&spec, *o.effects);
    if (!why.empty()) {
      std::cerr << "evsim: --effects: " << why << "\n";
      return kExitBadInput;
    }
  }
  if (o.no_sleep) spec.sleep.enabled = false;
  const SceneModel model = buildSceneModel(spec);
  const long whole = std::max(1L, std::lround(model.duration / model.time_step));
  const long steps = o.steps > 0 ? o.steps : std::max(1L, whole - o.warmup);
  std::vector<SceneModel> variants;  // --windows: checked before anything runs
  if (!o.variants.empty() && o.windows == 0) {
    std::cerr << "evsim bench: --variant needs --windows\n";
    return kExitBadInput;
  }
  if (o.windows > 0 && steps < o.window_steps) {
    std::cerr << "evsim bench: --windows needs at least --window-steps (" << o.window_steps
              << ") measured steps, not " << steps << "\n";
    return kExitBadInput;
  }
  const std::string why = loadVariants(model, o.variants, &variants);
  if (!why.empty()) {
    std::cerr << "evsim bench: " << why << "\n";
    return kExitBadInput;
  }
  int recoveries = 0;  // steps solved with the recovery options
  std::vector<BenchStep> record;
  std::vector<Vec3> tips;
  if (!measure(model, o.warmup, steps, o.strict, &record, &recoveries, &tips)) return kExitFailure;
  int elements = 0;
  for (const auto& d : model.devices) elements += d.num_nodes - 1;
  std::string effect_list;
  for (const auto& e : spec.effects) effect_list += (effect_list.empty() ? "" : ",") + e;
  std::printf(
      "scene %s: %zu device(s), %d elements, effects [%s]; %ld steps of %g ms (t = %.3f to %.3f "
      "s)\n",
      model.name.c_str(), model.devices.size(), elements, effect_list.c_str(), steps,
      model.time_step * 1e3, o.warmup * model.time_step, (o.warmup + steps) * model.time_step);
  if (recoveries > 0)
    std::printf("steps solved with the recovery options (sim/simulation.h): %d\n", recoveries);
  std::printf("step [ms] and real-time factor:\n");
  printSummary(record, model.time_step);
  double large_median = 0.0;  // of the steps with >= o.min_rows rows [ms]
  if (o.min_rows > 0) {
    std::vector<BenchStep> large;
    for (const BenchStep& b : record)
      if (b.rows >= o.min_rows) large.push_back(b);
    std::printf("steps with >= %ld LCP rows: %zu of %ld\n", o.min_rows, large.size(), steps);
    if (!large.empty()) printSummary(large, model.time_step);
    large_median = large.empty() ? 0.0 : medianMs(large);
  }
  if (o.copies > 0 && !benchCopies(spec, o, steps, record, tips)) return kExitFailure;
  if (o.windows > 0) {
    const int code = benchWindows(model, variants, {o.windows, o.window_steps, o.variants},
                                  o.warmup, steps, o.strict);
    if (code != kExitOk) return code;
  }
  if (!o.against.empty()) {  // a second scene's whole procedure in the same run
    const SceneModel other = buildSceneModel(loadSceneFile(resolveScenePath(o.against)));
    const long other_steps = std::max(1L, std::lround(other.duration / other.time_step));
    std::vector<BenchStep> other_record;
    int other_recoveries = 0;
    if (!measure(other, 0, other_steps, o.strict, &other_record, &other_recoveries))
      return kExitFailure;
    const double base = medianMs(other_record);
    std::printf("against %s (its whole procedure, %ld steps, in this run): median %.3f ms\n",
                other.name.c_str(), other_steps, base);
    std::printf("  %s whole: median %.3f ms = %.1fx\n", model.name.c_str(), medianMs(record),
                medianMs(record) / base);
    if (large_median > 0.0)
      std::printf("  %s steps with >= %ld LCP rows: median %.3f ms = %.1fx\n", model.name.c_str(),
                  o.min_rows, large_median, large_median / base);
  }
  return kExitOk;
}

}  // namespace evsim
