#include "scene_variants.h"

#include <algorithm>
#include <cmath>

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

int elementCount(const SceneSpec& spec) {
  int total = 0;
  if (!spec.devices.empty())
    for (const auto& sec : spec.devices[0].device.sections) total += sec.elements;
  return total;
}

}  // namespace evsim
