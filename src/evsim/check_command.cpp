// `evsim check FILE...`: validates scene, device, vessel and state files
// without running them, each as its loader does (the scene with its
// devices, vessels, access points and targets built), and prints a line per
// file: `FILE: ok (...)`, or the error naming the file, the line and the
// key (`file:line:column: key: what`); every problem at once where the
// loader collects them (a scene against its schema, a device's sections,
// an SWC file's lines), a line each. Every file is checked, whatever the others gave; exit 0 when
// all are valid, 2 otherwise.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "endovascular_sim/core/file_path.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/vessel_field.h"
#include "endovascular_sim/scene/centerline_scene.h"
#include "endovascular_sim/scene/centerline_vtk.h"
#include "endovascular_sim/scene/device_file.h"
#include "endovascular_sim/sim/simulation.h"
#include "endovascular_sim/sim/state_file.h"

namespace evsim {
namespace {

namespace fs = std::filesystem;

bool isStateFile(const std::string& path) {
  std::ifstream in(path);
  std::string word;
  return static_cast<bool>(in >> word) && word == "evsim_state";
}

double unitOf(const std::string& units) {
  const double unit = lengthUnit(units);
  if (unit > 0.0) return unit;
  throw LoadError("", 0, "--units", "must be m, cm, mm or um, got '" + units + "'");
}

/// What the file holds when valid; throws LoadError otherwise.
std::string checkOne(const CheckOptions& o, const std::string& path) {
  if (!fs::is_regular_file(path)) throw LoadError(path, 0, "", "no such file");
  const std::string ext = lowerCaseExtension(path);
  if (ext == ".urdf" || ext == ".xml") {
    const DeviceSpec spec = loadDeviceFile(path);
    const DeviceModel m = buildDeviceModel(spec);
    std::ostringstream out;
    out << "device " << m.name << ", " << m.num_nodes - 1 << " elements, " << m.length * 1e3
        << " mm";
    return out.str();
  }
  if (ext == ".swc") {
    const Centerline c = loadCenterlineFile(path, o.units.empty() ? 1e-3 : unitOf(o.units));
    const VesselField field(c, {}, {}, {});
    return "centreline of " + std::to_string(c.numPoints()) + " points, " +
           std::to_string(c.vessel_names.size()) + " named vessels";
  }
  if (isVtkCenterlinePath(path)) {
    if (o.units.empty())
      throw LoadError(path, 0, "--units",
                      "a VTK centreline needs its units declared (m, cm, mm or um)");
    VtkCenterlineOptions v;
    v.unit = unitOf(o.units);
    CenterlineTreeReport report;
    const Centerline c = loadVtkCenterline(path, v, &report);
    std::string out = "centreline of " + std::to_string(report.file_points) + " points -> " +
                      std::to_string(report.branches) + " branches, " +
                      std::to_string(c.numPoints()) + " points";
    for (const std::string& w : report.warnings) out += "; warning: " + w;
    return out;
  }
  if (isStateFile(path)) {
    if (o.scene.empty())
      throw LoadError(path, 0, "--scene", "a state file is checked against its scene: --scene S");
    const SceneModel model = loadScene(o.scene);
    SimData data = makeData(model);
    loadState(model, path, &data);
    std::ostringstream out;
    out << "state of scene " << model.name << " at t = " << data.time << " s";
    return out.str();
  }
  if (ext == ".yaml" || ext == ".yml") {
    const SceneModel model = buildSceneModel(loadSceneFile(path));
    std::string out =
        "scene " + model.name + ", " + std::to_string(model.devices.size()) + " device(s)" +
        (model.atlas ? ", " + std::to_string(model.atlas->vessels().size()) + " named vessels"
                     : std::string(", no vessels"));
    for (const std::string& w : model.warnings) out += "; warning: " + w;
    return out;
  }
  throw LoadError(path, 0, "",
                  "not a file evsim reads (a scene .yaml, a device .urdf, a centreline .swc, "
                  ".vtp or .vtk, or a state file)");
}

}  // namespace

int checkFiles(const CheckOptions& o) {
  int bad = 0;
  for (const std::string& path : o.files) {
    try {
      const std::string what = checkOne(o, path);
      std::cout << path << ": ok (" << what << ")\n";
    } catch (const LoadErrors& e) {  // every problem the loader found, a line each
      for (const LoadError& one : e.all()) std::cout << one.what() << "\n";
      ++bad;
    } catch (const LoadError& e) {
      std::cout << e.what() << "\n";
      ++bad;
    } catch (const std::exception& e) {  // a loader that failed without a LoadError: a bug
      std::cout << path << ": internal error: " << e.what() << "\n";
      ++bad;
    }
  }
  if (o.files.size() > 1)
    std::cout << o.files.size() - bad << " valid, " << bad << " with errors\n";
  return bad == 0 ? kExitOk : kExitBadInput;
}

}  // namespace evsim
