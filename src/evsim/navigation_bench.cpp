// `evsim bench navigation`: the autopilot on every target of the arch
// scenes from the femoral access, and on targets drawn with a fixed seed
// 3-6 bifurcations deep in the 4,000-vessel network; a line per run, a
// summary per group (success rate, time to target, peak wall force) and a
// CSV of every run.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <random>
#include <thread>

#include "commands.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/scene/arch_scene.h"
#include "endovascular_sim/sim/autopilot.h"

namespace evsim {
namespace {

struct Case {
  std::string group;  // "arch", "network" or "anatomy"
  std::string scene;
  std::string target;
  std::string device;
  int branchings{0};    // bifurcations passed from the access to the target
  std::string variant;  // a generated arch's: "type II", "type I, bovine", ...
};

struct Outcome {
  AutopilotReport report;
  double wall_s{0.0};
};

/// Branches entered (parent into child) along the atlas path from a to b.
int branchingsAlong(const VesselAtlas& atlas, int from, int to) {
  const std::vector<int> path = atlas.path(from, to);
  int n = 0;
  for (size_t i = 0; i + 1 < path.size(); ++i) n += atlas.vessels()[path[i + 1]].parent == path[i];
  return n;
}

/// The network's targets: every vessel `min..max` bifurcations from where
/// the innermost device's tip starts, wide enough for that tip; `count` of
/// them drawn with the seed (in vessel order, then shuffled).
std::vector<Case> networkCases(const NavigationBenchOptions& o) {
  const SceneModel model = loadScene(o.network_scene);
  if (!model.atlas) throw LoadError(model.file, 0, "vessels", "the scene has no vessels");
  const SimData data = makeData(model);
  const Autopilot probe(model, data, model.atlas->vessels().front().name);  // its device choice
  const int device = probe.device();
  const int entry = data.tips[device].vessel;
  const double tip_radius = model.devices[device].node_radius.back();
  std::vector<Case> all;
  const auto& vessels = model.atlas->vessels();
  const int trunk = model.atlas->find("brachiocephalic_trunk");
  for (size_t v = 0; v < vessels.size(); ++v) {
    const int n = branchingsAlong(*model.atlas, entry, static_cast<int>(v));
    if (n < o.min_branchings || n > o.max_branchings || vessels[v].radius <= 1.5 * tip_radius)
      continue;
    // As in the arch procedures, the catheter for the target's side: the
    // Headhunter curve engages the brachiocephalic trunk, the 45 degree
    // catheter does not.
    const std::vector<int> path = model.atlas->path(entry, static_cast<int>(v));
    const bool beyond_trunk =
        trunk >= 0 && std::find(path.begin(), path.end(), trunk) != path.end();
    all.push_back(
        {"network",
         beyond_trunk && !o.network_scene_trunk.empty() ? o.network_scene_trunk : o.network_scene,
         vessels[v].name, "", n, ""});
  }
  std::mt19937 random(o.seed);
  std::shuffle(all.begin(), all.end(), random);
  if (static_cast<int>(all.size()) > o.network_targets) all.resize(o.network_targets);
  return all;
}

std::vector<Case> archCases(const NavigationBenchOptions& o) {
  std::vector<Case> cases;
  for (const std::string& scene : o.arch_scenes) {
    if (scene.empty()) continue;  // (--arch-scenes "": the network alone)
    const SceneModel model = loadScene(scene);
    if (model.targets.empty())
      throw LoadError(model.file, 0, "targets", "the scene names no targets to navigate to");
    const SimData data = makeData(model);
    for (const Target& t : model.targets) {
      if (t.spec.aneurysm >= 0) continue;  // (a coil's target: not the autopilot's)
      const int d = t.device >= 0 ? t.device : 0;
      cases.push_back({"arch", scene, t.spec.vessel, t.spec.device,
                       branchingsAlong(*model.atlas, data.tips[d].vessel, t.vessel), ""});
    }
  }
  return cases;
}

/// Generated arches (evsim arch), seeds seed .. seed + anatomies - 1, each
/// to its targets with the catheter a clinician takes for each.
std::vector<Case> anatomyCases(const NavigationBenchOptions& o) {
  const std::string dir = o.anatomy_dir.empty()
                              ? (std::filesystem::temp_directory_path() /
                                 ("evsim_arches_" + std::to_string(o.seed)))
                                    .string()
                              : o.anatomy_dir;
  std::vector<Case> cases;
  for (int k = 0; k < o.anatomies; ++k) {
    const ArchParameters p = drawArch(o.seed + k);
    const ArchScenes files = writeArchScenes(p, dir);
    std::string variant = p.type == ArchType::kI    ? "type I"
                          : p.type == ArchType::kII ? "type II"
                                                    : "type III";
    if (p.bovine) variant += ", bovine";
    if (p.aberrant_rsa) variant += ", aberrant RSA";
    for (const std::string& target : archTargets(p))
      cases.push_back({"anatomy", files.target_scene.at(target), target, "guidewire", 0, variant});
  }
  return cases;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// A summary line of the runs `pick` selects, headed `label`.
template <typename Pick>
void printSummary(const std::string& label, const std::vector<Case>& cases,
                  const std::vector<Outcome>& out, Pick pick) {
  std::vector<double> times, forces;
  int runs = 0, reached = 0;
  long failed_steps = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    if (!pick(cases[i])) continue;
    ++runs;
    failed_steps += out[i].report.failed_steps;
    forces.push_back(out[i].report.peak_wall_force);
    if (!out[i].report.reached) continue;
    ++reached;
    times.push_back(out[i].report.time);
  }
  if (runs == 0) return;
  std::printf("%-8s reached %d of %d (%.0f %%)", label.c_str(), reached, runs,
              100.0 * reached / runs);
  if (!times.empty())
    std::printf("; time to target median %.2f s, worst %.2f s", median(times),
                *std::max_element(times.begin(), times.end()));
  std::printf("; peak wall force median %.3g N, max %.3g N; failed steps %ld\n", median(forces),
              *std::max_element(forces.begin(), forces.end()), failed_steps);
}

void printSummary(const std::string& group, const std::vector<Case>& cases,
                  const std::vector<Outcome>& out) {
  printSummary(group, cases, out, [&](const Case& c) { return c.group == group; });
}

/// The generated arches' runs per target and per variant, and every failure
/// with its reason.
void printAnatomySummary(const std::vector<Case>& cases, const std::vector<Outcome>& out) {
  std::vector<std::string> targets, variants;
  for (const Case& c : cases) {
    if (c.group != "anatomy") continue;
    if (std::find(targets.begin(), targets.end(), c.target) == targets.end())
      targets.push_back(c.target);
    const std::string type = c.variant.substr(0, c.variant.find(','));
    for (const std::string& v : {type, c.variant})
      if (std::find(variants.begin(), variants.end(), v) == variants.end()) variants.push_back(v);
  }
  if (targets.empty()) return;
  printSummary("anatomy", cases, out);
  for (const std::string& t : targets)
    printSummary("  " + t, cases, out,
                 [&](const Case& c) { return c.group == "anatomy" && c.target == t; });
  std::sort(variants.begin(), variants.end());
  for (const std::string& v : variants)
    printSummary("  " + v, cases, out, [&](const Case& c) {
      return c.group == "anatomy" &&
             (c.variant == v || c.variant.substr(0, c.variant.find(',')) == v);
    });
  for (size_t i = 0; i < cases.size(); ++i)
    if (cases[i].group == "anatomy" && !out[i].report.reached)
      std::printf("  failed: %s (%s) %s: %s\n", cases[i].scene.c_str(), cases[i].variant.c_str(),
                  cases[i].target.c_str(), out[i].report.reason.c_str());
}

}  // namespace

int benchNavigation(const NavigationBenchOptions& o) {
  std::vector<Case> cases = archCases(o);  // LoadError: main reports it (exit 2)
  if (o.network_targets > 0) {
    const std::vector<Case> network = networkCases(o);
    cases.insert(cases.end(), network.begin(), network.end());
  }
  if (o.anatomies > 0) {
    const std::vector<Case> anatomy = anatomyCases(o);
    cases.insert(cases.end(), anatomy.begin(), anatomy.end());
  }
  std::ofstream csv;
  if (!o.csv.empty()) {
    csv.open(o.csv);
    if (!csv) {
      std::cerr << "evsim: cannot write " << o.csv << "\n";
      return kExitBadInput;
    }
  }
  std::printf("navigation benchmark: %zu runs, %d job(s), timeout %.0f s simulated each\n",
              cases.size(), o.jobs, o.timeout);
  std::vector<Outcome> out(cases.size());
  std::atomic<size_t> next{0};
  std::mutex print;
  auto worker = [&]() {
    for (size_t i = next++; i < cases.size(); i = next++) {
      const Case& c = cases[i];
      const auto t0 = std::chrono::steady_clock::now();
      AutopilotOptions options;
      options.timeout = o.timeout;
      try {  // (a scene refused is that run's reason: the benchmark goes on)
        const SceneModel model = loadScene(c.scene);  // its own: nothing shared between jobs
        SimData data = makeData(model);
        out[i].report = runAutopilot(model, &data, c.target, c.device, options);
      } catch (const LoadError& e) {
        out[i].report.reason = std::string("refused: ") + e.what();
      }
      out[i].wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const AutopilotReport& r = out[i].report;
      std::lock_guard<std::mutex> lock(print);
      std::printf("%-8s %-28s %-34s %d  %s  %6.2f s  %2d retries  %.3g N  (%.0f s wall)%s%s\n",
                  c.group.c_str(), c.scene.c_str(), c.target.c_str(), c.branchings,
                  r.reached ? "reached" : "NOT    ", r.time, r.retries, r.peak_wall_force,
                  out[i].wall_s, r.reached ? "" : ": ", r.reached ? "" : r.reason.c_str());
      std::fflush(stdout);
    }
  };
  std::vector<std::thread> threads;
  for (int j = 0; j < std::max(1, o.jobs); ++j) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();

  printSummary("arch", cases, out);
  printSummary("network", cases, out);
  printAnatomySummary(cases, out);
  if (csv) {
    csv << "group,scene,target,branchings,reached,reason,time_s,retries,peak_wall_force_N,"
           "failed_steps,wall_s,variant\n";
    for (size_t i = 0; i < cases.size(); ++i) {
      const AutopilotReport& r = out[i].report;
      std::string reason = r.reason;
      std::replace(reason.begin(), reason.end(), '"', '\'');
      csv << cases[i].group << ',' << cases[i].scene << ',' << cases[i].target << ','
          << cases[i].branchings << ',' << (r.reached ? 1 : 0) << ",\"" << reason << "\"," << r.time
          << ',' << r.retries << ',' << r.peak_wall_force << ',' << r.failed_steps << ','
          << out[i].wall_s << ",\"" << cases[i].variant << "\"\n";
    }
  }
  return kExitOk;
}

}  // namespace evsim
