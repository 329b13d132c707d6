#include "endovascular_sim/scene/centerline_scene.h"

#include <algorithm>
#include <filesystem>

#include "endovascular_sim/core/file_path.h"
#include "endovascular_sim/core/load_error.h"
#include "endovascular_sim/scene/centerline_vtk.h"

namespace evsim {

namespace fs = std::filesystem;

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
