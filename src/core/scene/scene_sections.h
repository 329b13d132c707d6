// The readers of a scene file's sections shared by its source files
// (internal to the scene layer): scene_file.cpp reads the file,
// vessels_section.cpp its `vessels:` and the vessel tree built from it,
// xray_section.cpp its `xray:`.
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/scene/yaml_reader.h"

namespace evsim {

/// The introducer's frame: x along `direction` (into the body), z toward `up`.
Mat3 introducerFrame(const Vec3& direction, const Vec3& up);

/// The `vessels:` map; relative paths against the scene's folder.
VesselSpec readVessels(const YamlReader& r, const YAML::Node& n,
                       const std::filesystem::path& scene_dir);

/// The `xray:` map (scene/xray_spec.h).
XraySpec readXray(const YamlReader& r, const YAML::Node& n);

}  // namespace evsim
