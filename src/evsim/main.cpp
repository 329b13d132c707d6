// evsim: command-line runner on the core library (no ROS).
//
//   evsim run SCENE [--steps N] [--json] [--dump-lcp DIR]
//                                          step a scene, print progress or JSON;
//                                          write each step's last LCP to DIR
//   evsim mesh SCENE --out FILE [--spacing M] [--device-radius M]
//                                          vessel surface as PLY or STL
//   evsim list                             shipped scenes
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>

#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/surface_mesh.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/simulation.h"
#include "step_json.h"

namespace evsim {
namespace {

int usage(const char* why = nullptr) {
  if (why) std::cerr << "evsim: " << why << "\n";
  std::cerr << "usage:\n"
               "  evsim run SCENE [--steps N] [--json] [--dump-lcp DIR]\n"
               "                                         SCENE: a path or a shipped scene name\n"
               "  evsim mesh SCENE --out FILE.ply|.stl [--spacing M] [--device-radius M]\n"
               "  evsim list                             the shipped scenes\n";
  return 2;
}

int runCommand(int argc, char** argv) {
  if (argc < 1) return usage("run needs a SCENE");
  const std::string scene = argv[0];
  long steps = 1000;
  bool json = false;
  std::string dump_dir;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--json")) {
      json = true;
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
  if (!dump_dir.empty()) {
    std::filesystem::create_directories(dump_dir);
    data.record_lcp = true;
  }
  const long report_every = std::max(1L, static_cast<long>(0.1 / model.time_step + 0.5));
  double wall_ms = 0.0;
  for (long k = 0; k < steps; ++k) {
    if (step(model, &data) != StepStatus::kOk) {
      std::cerr << "evsim: step " << data.step + 1 << " failed: " << data.last_error << "\n";
      return 1;
    }
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
                << ") mm  contacts=" << data.stats.contacts << "  mean step " << wall_ms / data.step
                << " ms\n";
    }
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
