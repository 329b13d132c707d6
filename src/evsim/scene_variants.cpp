// Variants of a scene for benchmarks and sweeps: the same scene with another
// discretisation, other effects, or its script's speeds perturbed. Declared and documented in
// scene_variants.h.
#include "scene_variants.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace evsim {

void setElementCount(SceneSpec* spec, int elements) {
  for (auto& d : spec->devices) {
    int total = 0;
    for (const auto& sec : d.device.sections) total += sec.elements;
    for (auto& sec : d.device.sections)
      sec.elements =
          std::max(1, static_cast<int>(std::lround(1.0 * sec.elements * elements / total)));
  }
}

void perturbScript(SceneSpec* spec, double relative) {
  for (ScriptedCommand& c : spec->script) {
    if (c.detach || c.command.mode != DriveCommand::Mode::kVelocity) continue;
    c.command.insertion *= 1.0 + relative;
    c.command.rotation *= 1.0 + relative;
  }
}

std::string setEffects(SceneSpec* spec, const std::string& list) {
  std::vector<std::string> effects;
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');) {
    if (name.empty()) continue;
    const auto& known = knownEffects();
    if (std::find(known.begin(), known.end(), name) == known.end())
      return "unknown effect '" + name + "'";
    if (name == "vessel_motion" && spec->vessels.motion.empty())
      return "vessel_motion needs a scene with motion regions";
    effects.push_back(name);
  }
  spec->effects = effects;
  return "";
}

int elementCount(const SceneSpec& spec) {
  int total = 0;
  if (!spec.devices.empty())
    for (const auto& sec : spec.devices[0].device.sections) total += sec.elements;
  return total;
}

}  // namespace evsim
