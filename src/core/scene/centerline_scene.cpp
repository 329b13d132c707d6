#include "endovascular_sim/scene/centerline_scene.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "endovascular_sim/core/file_path.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/geometry/centerline.h"
#include "endovascular_sim/geometry/patient_frame.h"
#include "endovascular_sim/scene/centerline_vtk.h"

namespace evsim {

namespace fs = std::filesystem;

bool parseBranchName(const std::string& entry, std::map<int, std::string>* names,
                     std::string* why) {
  const size_t colon = entry.find(':');
  auto trim = [](std::string s) {
    const size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
    return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
  };
  const std::string id_text = trim(entry.substr(0, colon));
  const std::string name = colon == std::string::npos ? "" : trim(entry.substr(colon + 1));
  char* end = nullptr;
  const long id = std::strtol(id_text.c_str(), &end, 10);
  if (colon == std::string::npos || id_text.empty() || *end != '\0' || id < 0 || id > 1000000) {
    *why = "'" + entry + "' is not 'ID: NAME' (ID a branch id >= 0, as evsim vessels lists)";
    return false;
  }
  if (!isVesselName(name)) {
    *why = "'" + name + "' is not a vessel name ([a-z][a-z0-9_]*)";
    return false;
  }
  if (!names->emplace(static_cast<int>(id), name).second) {
    *why = "branch " + id_text + " is named twice";
    return false;
  }
  return true;
}

bool isCenterlinePath(const std::string& path) {
  return isVtkCenterlinePath(path) || lowerCaseExtension(path) == ".swc";
}

double lengthUnit(const std::string& name) {
  if (name == "m") return 1.0;
  if (name == "cm") return 1e-2;
  if (name == "mm") return 1e-3;
  if (name == "um") return 1e-6;
  return 0.0;
}

SceneSpec centerlineScene(const SceneSpec& base, const CenterlineSceneRequest& r) {
  const std::string& path = r.centerline;
  if (!fs::is_regular_file(path)) throw LoadError(path, 0, "scene", "no such centreline file");
  const bool vtk = isVtkCenterlinePath(path);
  VesselSpec v;
  v.present = true;
  v.centerline_file = fs::absolute(path).lexically_normal().string();
  v.field = base.vessels.field;
  if (vtk && r.units.empty())
    throw LoadError(path, 0, "units",
                    "a VTK centreline needs its units declared (m, cm, mm or um): SimVascular "
                    "models are in cm, most VMTK output in mm");
  if (!r.units.empty()) {
    v.units = lengthUnit(r.units);
    if (v.units == 0.0)
      throw LoadError(path, 0, "units", "'" + r.units + "': must be m, cm, mm or um");
  }
  if (vtk && r.radius_array.empty())
    throw LoadError(path, 0, "radius_array", "the radius array's name is empty");
  if (!r.radius_array.empty()) v.radius_array = r.radius_array;
  if (!r.frame.empty()) {
    const std::string why = frameCodeProblem(r.frame);
    if (!why.empty()) throw LoadError(path, 0, "frame", why);
    v.frame = r.frame;
  }
  if (!r.names.empty() && !vtk)
    throw LoadError(path, 0, "names",
                    "names apply to a VTK centreline; an SWC file names its vessels itself");
  for (const auto& [id, name] : r.names) {
    if (id < 0) throw LoadError(path, 0, "names", "branch ids are >= 0");
    if (!isVesselName(name))
      throw LoadError(path, 0, "names." + std::to_string(id),
                      "'" + name + "' is not a vessel name ([a-z][a-z0-9_]*)");
  }
  v.tree.names = r.names;

  SceneSpec s = base;
  s.file = v.centerline_file;
  s.name = fs::path(path).stem().string();
  s.description =
      "the centreline " + fs::path(path).filename().string() + " with the devices of " + base.name;
  s.vessels = v;
  // The base's vessel motion moved its own vessels: not these.
  s.effects.erase(std::remove(s.effects.begin(), s.effects.end(), "vessel_motion"),
                  s.effects.end());
  s.targets.clear();
  for (DevicePlacementSpec& d : s.devices)
    if (d.outer < 0) d.at_inlet = true, d.access_point_line = 0;
  return s;
}

}  // namespace evsim
