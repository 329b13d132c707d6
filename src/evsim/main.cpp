// evsim: command-line runner on the core library (no ROS).
//
//   evsim run SCENE [--steps N] [--json] [--dump-lcp DIR] [--load-state F] [--save-state F]
//                                          step a scene, print progress or JSON;
//                                          write each step's last LCP to DIR;
//                                          start from a saved state, save the last
//                                          good one (also after a failed step)
//   evsim mesh SCENE --out FILE [--spacing M] [--device-radius M]
//                                          vessel surface as PLY or STL
//   evsim bench SCENE [--steps N] [--warmup N] [--elements E] [--effects A,B]
//                     [--min-rows R]
//                                          step-time statistics (median, p99, Hz);
//                                          --effects replaces the scene's effects;
//                                          --min-rows adds the same over the steps
//                                          whose LCP has at least R rows
//   evsim bench accuracy SCENE|beam|root [--duration S] [--csv FILE]
//                                          accuracy knobs against their cost
//   evsim list                             shipped scenes
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>

#include "accuracy_sweep.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/surface_mesh.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/simulation.h"
#include "endovascular_sim/sim/state_file.h"
#include "scene_variants.h"
#include "step_json.h"

namespace evsim {
namespace {

int usage(const char* why = nullptr) {
  if (why) std::cerr << "evsim: " << why << "\n";
  std::cerr << "usage:\n"
               "  evsim run SCENE [--steps N] [--json] [--dump-lcp DIR] [--load-state FILE]\n"
               "                  [--save-state FILE]\n"
               "                                         SCENE: a path or a shipped scene name\n"
               "  evsim mesh SCENE --out FILE.ply|.stl [--spacing M] [--device-radius M]\n"
               "  evsim bench SCENE [--steps N] [--warmup N] [--elements E] [--effects A,B]\n"
               "                    [--min-rows R]\n"
               "  evsim bench accuracy SCENE|beam|root [--duration S] [--csv FILE]\n"
               "  evsim list                             the shipped scenes\n";
  return 2;
}

int runCommand(int argc, char** argv) {
  if (argc < 1) return usage("run needs a SCENE");
  const std::string scene = argv[0];
  long steps = 1000;
  bool json = false;
  std::string dump_dir, load_path, save_path;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--json")) {
      json = true;
    } else if (!std::strcmp(argv[i], "--load-state") && i + 1 < argc) {
      load_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--save-state") && i + 1 < argc) {
      save_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--dump-lcp") && i + 1 < argc) {
      dump_dir = argv[++i];
    } else if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) {
      char* end = nullptr;
      steps = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || steps < 0) return usage("--steps needs a whole number >= 0");
    } else {
      return usage((std::string("unknown argument ") + argv[i]).c_str());
    }
  }
  const SceneModel model = loadScene(scene);
  SimData data = makeData(model);
  if (!load_path.empty()) loadState(model, load_path, &data);  // LoadError: main prints it
  auto save = [&]() {
    if (save_path.empty() || saveState(model, data, save_path)) return true;
    std::cerr << "evsim: cannot write " << save_path << "\n";
    return false;
  };
  if (!dump_dir.empty()) {
    std::filesystem::create_directories(dump_dir);
    data.record_lcp = true;
  }
  const long report_every = std::max(1L, static_cast<long>(0.1 / model.time_step + 0.5));
  double wall_ms = 0.0;
  for (long k = 0; k < steps; ++k) {
    if (step(model, &data) != StepStatus::kOk) {
      std::cerr << "evsim: step " << data.step + 1 << " failed: " << data.last_error << "\n";
      save();  // the last good state, to study the failing step from
      return 1;
    }
    for (const std::string& notice : data.notices) std::cerr << "evsim: " << notice << "\n";
    data.notices.clear();
    wall_ms += data.stats.wall_ms;
    if (!dump_dir.empty() && data.lcp.q.size() > 0) {
      char name[64];
      std::snprintf(name, sizeof(name), "/step_%07ld.lcp", data.step);
      if (!writeLcpRecord(data.lcp, dump_dir + name)) {
        std::cerr << "evsim: cannot write " << dump_dir + name << "\n";
        return 1;
      }
    }
    if (json) {
      std::cout << stepJson(model, data) << "\n";
    } else if (data.step % report_every == 0 || k + 1 == steps) {
      const DeviceState& d = data.devices.front();
      const Vec3& tip = d.position.back();
      std::cout << "t=" << data.time << " s  " << model.devices.front().name
                << " inserted=" << d.inserted_length * 1e3 << " mm  tip=(" << tip.x() * 1e3 << ", "
                << tip.y() * 1e3 << ", " << tip.z() * 1e3
                << ") mm  contacts=" << data.stats.contacts << "  mean step " << wall_ms / (k + 1)
                << " ms\n";
    }
  }
  return save() ? 0 : 1;
}

/// One measured step of `evsim bench`.
struct BenchStep {
  double ms;        // wall time of the step [ms]
  int rows;         // rows of its last LCP (detected contacts)
  int forces;       // contacts with a positive force
  int loops;        // activation loops
  bool subdivided;  // the step was halved at least once
};

/// Median (element n/2 of the sorted values) and the p-th quantile.
template <typename T>
T quantile(std::vector<T> values, double p) {
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(p * values.size()))];
}

/// Prints step time, rows, forces, subdivisions and loops of `steps` (non-empty).
void printBenchSummary(const std::vector<BenchStep>& steps) {
  std::vector<double> ms;
  std::vector<int> rows, forces;
  int subdivided = 0, max_loops = 0;
  double mean = 0.0;
  for (const BenchStep& b : steps) {
    ms.push_back(b.ms);
    rows.push_back(b.rows);
    forces.push_back(b.forces);
    subdivided += b.subdivided;
    max_loops = std::max(max_loops, b.loops);
    mean += b.ms / steps.size();
  }
  const double median = quantile(ms, 0.5);
  std::printf(
      "step [ms]: median %.3f  mean %.3f  p90 %.3f  p99 %.3f  max %.3f  -> %.0f Hz at the median\n",
      median, mean, quantile(ms, 0.9), quantile(ms, 0.99), quantile(ms, 1.0), 1e3 / median);
  std::printf(
      "active contacts: median %d  max %d;  LCP rows: median %d  max %d;  steps subdivided %d;  "
      "most activation loops %d\n",
      quantile(forces, 0.5), quantile(forces, 1.0), quantile(rows, 0.5), quantile(rows, 1.0),
      subdivided, max_loops);
}

int benchCommand(int argc, char** argv) {
  if (argc < 1) return usage("bench needs a SCENE");
  if (!std::strcmp(argv[0], "accuracy")) return accuracyCommand(argc - 1, argv + 1);
  long steps = 3000, warmup = 0;
  int elements = 0;
  long min_rows = 0;    // --min-rows R: also the steps whose LCP has >= R rows (0: not asked)
  std::string effects;  // --effects a,b,c replaces the scene's list ("" = none)
  bool have_effects = false;
  for (int i = 1; i < argc; ++i) {
    char* end = nullptr;
    if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) {
      steps = std::strtol(argv[++i], &end, 10);
    } else if (!std::strcmp(argv[i], "--warmup") && i + 1 < argc) {
      warmup = std::strtol(argv[++i], &end, 10);
    } else if (!std::strcmp(argv[i], "--elements") && i + 1 < argc) {
      elements = static_cast<int>(std::strtol(argv[++i], &end, 10));
    } else if (!std::strcmp(argv[i], "--min-rows") && i + 1 < argc) {
      min_rows = std::strtol(argv[++i], &end, 10);
    } else if (!std::strcmp(argv[i], "--effects") && i + 1 < argc) {
      effects = argv[++i];
      have_effects = true;
      continue;
    } else {
      return usage((std::string("unknown argument ") + argv[i]).c_str());
    }
    if (*end != '\0' || steps < 1 || warmup < 0 || elements < 0 || min_rows < 0)
      return usage("bench options need whole numbers (steps >= 1)");
  }
  SceneSpec spec = loadSceneFile(resolveScenePath(argv[0]));
  if (elements > 0) setElementCount(&spec, elements);
  if (have_effects) {
    const std::string why = setEffects(&spec, effects);
    if (!why.empty()) return usage(why.c_str());
  }
  const SceneModel model = buildSceneModel(spec);
  SimData data = makeData(model);
  for (long k = 0; k < warmup; ++k)
    if (step(model, &data) != StepStatus::kOk) {
      std::cerr << "evsim: warm-up step failed: " << data.last_error << "\n";
      return 1;
    }
  std::vector<BenchStep> record;
  record.reserve(steps);
  for (long k = 0; k < steps; ++k) {
    if (step(model, &data) != StepStatus::kOk) {
      std::cerr << "evsim: step failed: " << data.last_error << "\n";
      return 1;
    }
    const StepStats& s = data.stats;
    record.push_back(
        {s.wall_ms, s.contacts, s.active_contacts, s.activation_loops, s.subdivisions > 0});
  }
  int nodes = 0;
  for (const auto& d : model.devices) nodes += d.num_nodes - 1;
  std::string effect_list;
  for (const auto& e : spec.effects) effect_list += (effect_list.empty() ? "" : ",") + e;
  std::printf("scene %s: %zu device(s), %d elements, effects [%s], %ld steps after %ld warm-up\n",
              model.name.c_str(), model.devices.size(), nodes, effect_list.c_str(), steps, warmup);
  printBenchSummary(record);
  if (min_rows > 0) {
    std::vector<BenchStep> large;
    for (const BenchStep& b : record)
      if (b.rows >= min_rows) large.push_back(b);
    std::printf("steps with >= %ld LCP rows: %zu of %ld\n", min_rows, large.size(), steps);
    if (!large.empty()) printBenchSummary(large);
  }
  return 0;
}

bool parseLength(const char* text, double* out) {
  char* end = nullptr;
  *out = std::strtod(text, &end);
  return *end == '\0' && std::isfinite(*out) && *out >= 0.0;
}

int meshCommand(int argc, char** argv) {
  if (argc < 1) return usage("mesh needs a SCENE");
  std::string out;
  double spacing = 0.0, radius = 0.0;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--out") && i + 1 < argc) {
      out = argv[++i];
    } else if (!std::strcmp(argv[i], "--spacing") && i + 1 < argc) {
      if (!parseLength(argv[++i], &spacing)) return usage("--spacing needs a length [m] >= 0");
    } else if (!std::strcmp(argv[i], "--device-radius") && i + 1 < argc) {
      if (!parseLength(argv[++i], &radius)) return usage("--device-radius needs a length [m] >= 0");
    } else {
      return usage((std::string("unknown argument ") + argv[i]).c_str());
    }
  }
  if (out.empty()) return usage("mesh needs --out FILE");
  const SceneSpec spec = loadSceneFile(resolveScenePath(argv[0]));
  if (!spec.vessels.present) {
    std::cerr << "evsim: scene '" << spec.name << "' has no vessels\n";
    return 1;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const VesselField field = buildVesselField(spec.vessels, false);
  const SurfaceMesh mesh = meshVesselSurface(field, spacing, radius);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::string why;
  if (!writeMesh(mesh, out, &why)) {
    std::cerr << "evsim: " << why << "\n";
    return 1;
  }
  std::cout << out << ": " << mesh.vertices.size() << " vertices, " << mesh.triangles.size()
            << " triangles from " << field.numSegments() << " segments in " << s << " s\n";
  return 0;
}

}  // namespace
}  // namespace evsim

int main(int argc, char** argv) {
  if (argc < 2) return evsim::usage();
  const std::string command = argv[1];
  try {
    if (command == "run") return evsim::runCommand(argc - 2, argv + 2);
    if (command == "mesh") return evsim::meshCommand(argc - 2, argv + 2);
    if (command == "bench") return evsim::benchCommand(argc - 2, argv + 2);
    if (command == "list") {
      for (const auto& s : evsim::shippedScenes()) std::cout << s << "\n";
      return 0;
    }
  } catch (const evsim::LoadError& e) {
    std::cerr << "evsim: " << e.what() << "\n";
    return 1;
  }
  return evsim::usage(("unknown command " + command).c_str());
}
